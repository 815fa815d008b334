"""Pinocchio reference for sea_momentum, in sea_momentum's conventions.

This module is test infrastructure: it builds a Pinocchio model from a URDF (a free-flyer base,
reduced to a joint list if one is given) and evaluates the dynamics quantities of the Python API
of the package from *our* state (q, nu, nudot), converting to and from Pinocchio's conventions.

Our conventions (docs/reference/conventions.md):
    q  = [p_B (3, world), quaternion (w, x, y, z), s (n)]
    nu = [pdot_B (3, world), omega_B (3, world axes), sdot (n)]
    spatial vectors linear first; frame Jacobians map nu to [origin velocity; angular velocity]
    in world axes; Jdot_nu is the classical acceleration at nudot = 0; H = [m pdot_com; L_com]
    (world axes), H = A_G nu; M nudot + h = tau; gravity -9.81 along world z.

Pinocchio's conventions (free flyer from ``pin.buildModelFromUrdf(path, JointModelFreeFlyer())``):
    q_pin = [p_B, quaternion (x, y, z, w), joint coordinates in Pinocchio's joint order]
            (continuous joints take two coordinates, (cos s, sin s))
    v_pin = [R^T pdot_B, R^T omega_B, sdot in Pinocchio's order]   (base velocity in base axes)

Conversion. With R = world_R_base and P the permutation taking our joint order to Pinocchio's,
T = blockdiag(R^T, R^T, P) gives v_pin = T nu. Differentiating along a motion (Rdot = R [w_b]x,
w_b = R^T omega, v_b = R^T pdot):
    d/dt (R^T pdot)  = R^T pddot - w_b x v_b
    d/dt (R^T omega) = R^T omegadot - w_b x w_b = R^T omegadot
so a_pin = T nudot + c with c = [-(w_b x v_b); 0; 0].
Power is invariant (tau_ours . nu = tau_pin . v_pin), so tau_ours = T^T tau_pin, hence
    M_ours = T^T M_pin T,  h_ours = T^T rnea_pin(q, v_pin, c),  g_ours = T^T g_pin,
    rnea_ours(q, nu, nudot) = T^T rnea_pin(q, v_pin, T nudot + c),
and every map from velocities (LOCAL_WORLD_ALIGNED frame Jacobian, CoM Jacobian, centroidal
map, which already produce world-axes outputs) is post-multiplied by T.
Jdot_nu is Pinocchio's classical frame acceleration (LOCAL_WORLD_ALIGNED) after
forwardKinematics(q_pin, v_pin, c), i.e. the acceleration at nudot = 0.

Pinocchio pitfalls this module takes care of:
- the quaternion is stored (x, y, z, w) in q_pin, ours is (w, x, y, z);
- ``pin.Quaternion(w, x, y, z)`` takes w first but ``.coeffs()`` returns (x, y, z, w): this
  module does not use pin.Quaternion at all (own formulas below);
- Pinocchio's joint order is depth-first but siblings come in urdfdom's order (its joints are
  kept in a std::map, so siblings end up sorted by joint name), not in file order: always map
  joints by name;
- a continuous URDF joint is a 2-coordinate (cos, sin) joint in Pinocchio (nq = 2, nv = 1);
- ``pin.buildReducedModel`` keeps the remaining joints in the original relative order and
  turns each locked joint into a FIXED_JOINT frame with the joint's name; a URDF link is always
  a BODY frame, and a link and a joint may share a name, so frames are looked up by
  (name, BODY);
- Pinocchio returns views into ``data``: everything returned here is copied;
- ``pin.crba`` historically fills only the upper triangle: symmetrised here.
"""

from __future__ import annotations

import pathlib
from typing import Mapping, Sequence

import numpy as np
import pinocchio as pin
import sea_momentum

GRAVITY = 9.81

__all__ = [
    "GRAVITY",
    "HAND_URDF",
    "HAND_JOINTS_FILE_ORDER",
    "ICUB25_JOINTS",
    "urdf_depth_first_joints",
    "PinReference",
    "quat_wxyz_to_rot",
    "rot_to_quat_wxyz",
    "quat_mul_wxyz",
    "so3_exp",
    "so3_log",
    "skew",
    "integrate_constant_nu",
    "random_state",
]


# Siblings deliberately not in alphabetical order in the file (zeta_rev before alpha_pris),
# a non-unit revolute axis, a prismatic and a continuous joint, a fixed joint to a massive link
# (merged by Pinocchio) and a fixed joint to a massless link.
HAND_URDF = """<?xml version="1.0"?>
<robot name="hand_made">
  <link name="base">
    <inertial>
      <origin xyz="0.01 -0.02 0.03" rpy="0.1 0.2 -0.3"/>
      <mass value="3.0"/>
      <inertia ixx="0.05" ixy="0.002" ixz="-0.001" iyy="0.06" iyz="0.003" izz="0.04"/>
    </inertial>
  </link>
  <joint name="zeta_rev" type="revolute">
    <parent link="base"/>
    <child link="l_rev"/>
    <origin xyz="0.1 0.05 0.2" rpy="0.3 -0.2 0.1"/>
    <axis xyz="0 1.2 -1.6"/>
    <limit lower="-2" upper="2" effort="10" velocity="5"/>
  </joint>
  <link name="l_rev">
    <inertial>
      <origin xyz="0.0 0.0 0.15" rpy="0 0.4 0"/>
      <mass value="1.2"/>
      <inertia ixx="0.011" ixy="0.0005" ixz="0" iyy="0.012" iyz="0" izz="0.004"/>
    </inertial>
  </link>
  <joint name="mid_fixed" type="fixed">
    <parent link="l_rev"/>
    <child link="l_tool"/>
    <origin xyz="0 0 0.3" rpy="0.5 0 0.2"/>
  </joint>
  <link name="l_tool">
    <inertial>
      <origin xyz="0.02 0 0.01"/>
      <mass value="0.5"/>
      <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.003" iyz="0" izz="0.0025"/>
    </inertial>
  </link>
  <joint name="beta_cont" type="continuous">
    <parent link="l_tool"/>
    <child link="l_cont"/>
    <origin xyz="0.05 0.0 0.1" rpy="0 0 0.7"/>
    <axis xyz="1 1 0"/>
  </joint>
  <link name="l_cont">
    <inertial>
      <origin xyz="0.1 0.0 0.0"/>
      <mass value="0.7"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.004" iyz="0" izz="0.004"/>
    </inertial>
  </link>
  <joint name="alpha_pris" type="prismatic">
    <parent link="base"/>
    <child link="l_pris"/>
    <origin xyz="-0.1 0.0 -0.2" rpy="0 0.3 0"/>
    <axis xyz="1 2 3"/>
    <limit lower="-0.5" upper="0.5" effort="100" velocity="1"/>
  </joint>
  <link name="l_pris">
    <inertial>
      <origin xyz="0 0 -0.1"/>
      <mass value="2.0"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.01"/>
    </inertial>
  </link>
  <joint name="sole_fixed" type="fixed">
    <parent link="l_pris"/>
    <child link="sole"/>
    <origin xyz="0.03 0.01 -0.25" rpy="0 0 0.1"/>
  </joint>
  <link name="sole"/>
  <joint name="gamma_rev" type="revolute">
    <parent link="l_pris"/>
    <child link="l_last"/>
    <origin xyz="0 0.1 -0.1" rpy="0.2 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="5"/>
  </joint>
  <link name="l_last">
    <inertial>
      <origin xyz="0 0.05 0"/>
      <mass value="0.4"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/>
    </inertial>
  </link>
</robot>
"""
# The 25 joints of the paper's iCub, in the original study's order
# (docs/references.md#original-study-joints-and-contacts; defined once, in Rust:
# sea_sim's scenario presets, exposed by the native module).
ICUB25_JOINTS = list(sea_momentum.ICUB25_JOINTS)


HAND_JOINTS_FILE_ORDER = ["zeta_rev", "beta_cont", "alpha_pris", "gamma_rev"]


def urdf_depth_first_joints(urdf_text: str) -> list[str]:
    """Movable joints of a URDF in depth-first tree order, children in file order (our default
    joint order, docs/reference/conventions.md), computed from the XML alone."""
    import xml.etree.ElementTree as ET

    root = ET.fromstring(urdf_text)
    links = [e.get("name") for e in root.findall("link")]
    children: dict[str, list[tuple[str, str, str]]] = {n: [] for n in links}
    child_links = set()
    for j in root.findall("joint"):
        parent = j.find("parent").get("link")
        child = j.find("child").get("link")
        children[parent].append((j.get("name"), j.get("type"), child))
        child_links.add(child)
    roots = [n for n in links if n not in child_links]
    assert len(roots) == 1, roots
    out: list[str] = []

    def visit(link: str) -> None:
        for name, typ, child in children[link]:
            if typ in ("revolute", "continuous", "prismatic"):
                out.append(name)
            visit(child)

    visit(roots[0])
    return out


# --------------------------------------------------------------------------------------------
# Small rotation helpers (own implementation, independent of Pinocchio and of sea_momentum)
# --------------------------------------------------------------------------------------------


def skew(w: np.ndarray) -> np.ndarray:
    """[w]x such that skew(w) @ v == np.cross(w, v)."""
    x, y, z = w
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def quat_wxyz_to_rot(quat: np.ndarray) -> np.ndarray:
    """Rotation matrix of a unit quaternion (w, x, y, z) (Hamilton convention, active)."""
    w, x, y, z = quat
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def rot_to_quat_wxyz(R: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z), w >= 0, of a rotation matrix (Shepperd's method)."""
    t = np.trace(R)
    if t > 0:
        s = 2.0 * np.sqrt(1.0 + t)
        q = np.array([0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s,
                      (R[1, 0] - R[0, 1]) / s])
    elif R[0, 0] > R[1, 1] and R[0, 0] > R[2, 2]:
        s = 2.0 * np.sqrt(1.0 + R[0, 0] - R[1, 1] - R[2, 2])
        q = np.array([(R[2, 1] - R[1, 2]) / s, 0.25 * s, (R[0, 1] + R[1, 0]) / s,
                      (R[0, 2] + R[2, 0]) / s])
    elif R[1, 1] > R[2, 2]:
        s = 2.0 * np.sqrt(1.0 + R[1, 1] - R[0, 0] - R[2, 2])
        q = np.array([(R[0, 2] - R[2, 0]) / s, (R[0, 1] + R[1, 0]) / s, 0.25 * s,
                      (R[1, 2] + R[2, 1]) / s])
    else:
        s = 2.0 * np.sqrt(1.0 + R[2, 2] - R[0, 0] - R[1, 1])
        q = np.array([(R[1, 0] - R[0, 1]) / s, (R[0, 2] + R[2, 0]) / s,
                      (R[1, 2] + R[2, 1]) / s, 0.25 * s])
    q /= np.linalg.norm(q)
    return q if q[0] >= 0 else -q


def quat_mul_wxyz(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product a * b, both (w, x, y, z)."""
    aw, av = a[0], a[1:]
    bw, bv = b[0], b[1:]
    return np.concatenate(([aw * bw - av @ bv], aw * bv + bw * av + np.cross(av, bv)))


def so3_exp(w: np.ndarray) -> np.ndarray:
    """Rodrigues: exp([w]x)."""
    th = np.linalg.norm(w)
    K = skew(w)
    if th < 1e-8:
        return np.eye(3) + K + 0.5 * K @ K
    return np.eye(3) + np.sin(th) / th * K + (1 - np.cos(th)) / th**2 * K @ K


def so3_log(R: np.ndarray) -> np.ndarray:
    """Rotation vector w with so3_exp(w) == R (for angles away from pi)."""
    c = np.clip((np.trace(R) - 1.0) / 2.0, -1.0, 1.0)
    th = np.arccos(c)
    v = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    if th < 1e-8:
        return 0.5 * v
    return th / (2.0 * np.sin(th)) * v


def integrate_constant_nu(q: np.ndarray, nu: np.ndarray, t: float) -> np.ndarray:
    """Exact configuration reached from q after time t at constant nu (our conventions).

    p += pdot t; R <- exp([omega t]x) R (omega in world axes, left multiplication); s += sdot t.
    """
    q = np.asarray(q, dtype=float)
    nu = np.asarray(nu, dtype=float)
    out = q.copy()
    out[0:3] = q[0:3] + t * nu[0:3]
    w = t * nu[3:6]
    th = np.linalg.norm(w)
    if th < 1e-300:
        dq = np.array([1.0, 0.0, 0.0, 0.0])
    else:
        dq = np.concatenate(([np.cos(th / 2)], np.sin(th / 2) * w / th))
    quat = quat_mul_wxyz(dq, q[3:7])
    out[3:7] = quat / np.linalg.norm(quat)
    out[7:] = q[7:] + t * nu[6:]
    return out


def random_state(
    rng: np.random.Generator,
    n_joints: int,
    box: float = 1.0,
    angle: float = np.pi,
    speed: float = 2.0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Random (q, nu, nudot) in our conventions: unit quaternion, p in [-box, box]^3,
    joint coordinates in [-angle, angle], velocities and accelerations ~ N(0, speed^2)."""
    quat = rng.normal(size=4)
    quat /= np.linalg.norm(quat)
    q = np.concatenate(
        (rng.uniform(-box, box, 3), quat, rng.uniform(-angle, angle, n_joints))
    )
    nu = speed * rng.normal(size=6 + n_joints)
    nudot = speed * rng.normal(size=6 + n_joints)
    return q, nu, nudot


# --------------------------------------------------------------------------------------------
# The reference
# --------------------------------------------------------------------------------------------


class PinReference:
    """Pinocchio evaluated in sea_momentum's conventions.

    ``joints``: our joint order (and the movable set); every other movable joint is locked at
    ``locked.get(name, 0.0)``. With ``joints=None`` every movable joint is kept, in Pinocchio's
    own order (which is not necessarily the URDF file order: match by ``joint_names``).
    Method names mirror ``sea_momentum.Model``.
    """

    def __init__(
        self,
        urdf_path: str | pathlib.Path,
        joints: Sequence[str] | None = None,
        locked: Mapping[str, float] | None = None,
    ) -> None:
        self.urdf_path = str(urdf_path)
        full = pin.buildModelFromUrdf(self.urdf_path, pin.JointModelFreeFlyer())
        if full.njoints < 2 or full.joints[1].shortname() != "JointModelFreeFlyer":
            raise ValueError("expected a free-flyer root joint")
        self.full_model = full
        movable = [full.names[j] for j in range(2, full.njoints)]
        for j in range(2, full.njoints):
            if full.joints[j].nv != 1:
                raise ValueError(
                    f"joint {full.names[j]!r}: unsupported type {full.joints[j].shortname()}"
                )
        locked = dict(locked or {})

        if joints is None:
            joints = list(movable)
            if locked:
                raise ValueError("locked values need a joints list")
        else:
            joints = list(joints)
            unknown = [n for n in joints if n not in movable]
            if unknown:
                raise ValueError(f"unknown joints {unknown}")
            if len(set(joints)) != len(joints):
                raise ValueError("duplicate joint names in joints")
            bad = [n for n in locked if n not in movable or n in joints]
            if bad:
                raise ValueError(f"locked names that are not locked movable joints: {bad}")

        to_lock = [n for n in movable if n not in joints]
        self.locked_values = {n: float(locked.get(n, 0.0)) for n in to_lock}
        if to_lock:
            qref = pin.neutral(full)
            for n in to_lock:
                jm = full.joints[full.getJointId(n)]
                self._set_joint_q(jm, qref, self.locked_values[n])
            ids = [full.getJointId(n) for n in to_lock]
            model = pin.buildReducedModel(full, ids, qref)
        else:
            model = full
        self.model = model
        self.data = model.createData()

        self.joint_names: list[str] = joints
        self.n_joints = len(joints)
        self.nq = 7 + self.n_joints
        self.nv = 6 + self.n_joints
        assert model.nv == self.nv, (model.nv, self.nv)

        # Joint mapping (our index i -> Pinocchio joint model).
        self._jmodels = []
        perm = np.zeros((self.n_joints, self.n_joints))
        for i, n in enumerate(joints):
            jid = model.getJointId(n)
            assert jid < model.njoints and model.names[jid] == n
            jm = model.joints[jid]
            self._jmodels.append(jm)
            perm[jm.idx_v - 6, i] = 1.0
        self.P = perm  # sdot_pin = P sdot_ours

        # URDF links = BODY frames.
        self.frame_ids: dict[str, int] = {}
        for fid, fr in enumerate(model.frames):
            if fr.type == pin.FrameType.BODY:
                if fr.name in self.frame_ids:
                    raise ValueError(f"duplicate BODY frame {fr.name!r}")
                self.frame_ids[fr.name] = fid
        self.frame_names = list(self.frame_ids)
        self.total_mass = float(pin.computeTotalMass(model))

    # ---------------------------------------------------------------- conversions

    @staticmethod
    def _set_joint_q(jm, qp: np.ndarray, s: float) -> None:
        if jm.nq == 1:
            qp[jm.idx_q] = s
        elif jm.nq == 2:  # continuous joint: (cos, sin)
            qp[jm.idx_q] = np.cos(s)
            qp[jm.idx_q + 1] = np.sin(s)
        else:
            raise ValueError(f"unsupported joint {jm.shortname()}")

    def neutral(self) -> np.ndarray:
        q = np.zeros(self.nq)
        q[3] = 1.0
        return q

    def _check(self, name: str, x, size: int) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        if x.shape != (size,):
            raise ValueError(f"{name}: expected shape ({size},), got {x.shape}")
        return x

    def rotation(self, q) -> np.ndarray:
        q = self._check("q", q, self.nq)
        return quat_wxyz_to_rot(q[3:7])

    def q_pin(self, q) -> np.ndarray:
        q = self._check("q", q, self.nq)
        qp = np.zeros(self.model.nq)
        qp[0:3] = q[0:3]
        w, x, y, z = q[3:7]
        qp[3:7] = (x, y, z, w)
        for i, jm in enumerate(self._jmodels):
            self._set_joint_q(jm, qp, q[7 + i])
        return qp

    def T(self, q) -> np.ndarray:
        """v_pin = T nu."""
        R = self.rotation(q)
        T = np.zeros((self.nv, self.nv))
        T[0:3, 0:3] = R.T
        T[3:6, 3:6] = R.T
        T[6:, 6:] = self.P
        return T

    def v_pin(self, q, nu) -> np.ndarray:
        nu = self._check("nu", nu, self.nv)
        return self.T(q) @ nu

    def a_pin(self, q, nu, nudot) -> np.ndarray:
        """a_pin = T nudot + c, c = [-(w_b x v_b); 0; 0]."""
        nu = self._check("nu", nu, self.nv)
        nudot = self._check("nudot", nudot, self.nv)
        T = self.T(q)
        v = T @ nu
        a = T @ nudot
        a[0:3] -= np.cross(v[3:6], v[0:3])
        return a

    def frame_id(self, frame: str) -> int:
        try:
            return self.frame_ids[frame]
        except KeyError:
            raise KeyError(f"no BODY frame {frame!r}") from None

    # ---------------------------------------------------------------- dynamics

    def mass_matrix(self, q) -> np.ndarray:
        qp = self.q_pin(q)
        T = self.T(q)
        M = np.array(pin.crba(self.model, self.data, qp), copy=True)
        M = np.triu(M) + np.triu(M, 1).T
        M = T.T @ M @ T
        return 0.5 * (M + M.T)

    def bias_forces(self, q, nu) -> np.ndarray:
        qp = self.q_pin(q)
        T = self.T(q)
        a = self.a_pin(q, nu, np.zeros(self.nv))
        tau = pin.rnea(self.model, self.data, qp, T @ np.asarray(nu, float), a)
        return T.T @ np.array(tau, copy=True)

    def gravity_forces(self, q) -> np.ndarray:
        qp = self.q_pin(q)
        T = self.T(q)
        g = pin.computeGeneralizedGravity(self.model, self.data, qp)
        return T.T @ np.array(g, copy=True)

    def inverse_dynamics(self, q, nu, nudot) -> np.ndarray:
        qp = self.q_pin(q)
        T = self.T(q)
        a = self.a_pin(q, nu, nudot)
        tau = pin.rnea(self.model, self.data, qp, T @ np.asarray(nu, float), a)
        return T.T @ np.array(tau, copy=True)

    # ---------------------------------------------------------------- kinematics

    def frame_pose(self, q, frame: str) -> np.ndarray:
        fid = self.frame_id(frame)
        qp = self.q_pin(q)
        pin.forwardKinematics(self.model, self.data, qp)
        oMf = pin.updateFramePlacement(self.model, self.data, fid)
        return np.array(oMf.homogeneous, copy=True)

    def frame_jacobian(self, q, frame: str) -> np.ndarray:
        fid = self.frame_id(frame)
        qp = self.q_pin(q)
        J = pin.computeFrameJacobian(
            self.model, self.data, qp, fid, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        )
        return np.array(J, copy=True) @ self.T(q)

    def frame_jacobian_dot_v(self, q, nu, frame: str) -> np.ndarray:
        fid = self.frame_id(frame)
        qp = self.q_pin(q)
        v = self.v_pin(q, nu)
        a = self.a_pin(q, nu, np.zeros(self.nv))
        pin.forwardKinematics(self.model, self.data, qp, v, a)
        acc = pin.getFrameClassicalAcceleration(
            self.model, self.data, fid, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        )
        return np.array(acc.vector, copy=True)

    def frame_velocity(self, q, nu, frame: str) -> np.ndarray:
        """pin.getFrameVelocity LOCAL_WORLD_ALIGNED (for validating the Jacobian conversion)."""
        fid = self.frame_id(frame)
        pin.forwardKinematics(self.model, self.data, self.q_pin(q), self.v_pin(q, nu))
        vel = pin.getFrameVelocity(
            self.model, self.data, fid, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        )
        return np.array(vel.vector, copy=True)

    def com(self, q) -> np.ndarray:
        c = pin.centerOfMass(self.model, self.data, self.q_pin(q))
        return np.array(c, copy=True)

    def com_jacobian(self, q) -> np.ndarray:
        Jc = pin.jacobianCenterOfMass(self.model, self.data, self.q_pin(q))
        return np.array(Jc, copy=True) @ self.T(q)

    def centroidal_momentum_matrix(self, q) -> np.ndarray:
        Ag = pin.computeCentroidalMap(self.model, self.data, self.q_pin(q))
        return np.array(Ag, copy=True) @ self.T(q)

    def centroidal_momentum(self, q, nu) -> np.ndarray:
        hg = pin.computeCentroidalMomentum(
            self.model, self.data, self.q_pin(q), self.v_pin(q, nu)
        )
        return np.array(hg.vector, copy=True)

    def kinetic_energy_pin(self, q, nu) -> float:
        return float(
            pin.computeKineticEnergy(self.model, self.data, self.q_pin(q), self.v_pin(q, nu))
        )
