"""Validation of pin_reference's convention conversion, independently of sea_momentum.

Each quantity produced by PinReference in our conventions is checked against either a
different Pinocchio entry point (frame velocity, kinetic energy, centroidal momentum, per-body
momenta) or against finite differences along the exact constant-nu motion of our conventions
(p += pdot t, R <- exp(omega t) R in world axes, s += sdot t), computed with this file's own
quaternion algebra.
"""

from __future__ import annotations

import pathlib

import numpy as np
import pinocchio as pin
import pytest

from pin_reference import (  # a helper beside the tests (see conftest.py)
    GRAVITY,
    HAND_JOINTS_FILE_ORDER,
    HAND_URDF,
    ICUB25_JOINTS,
    PinReference,
    integrate_constant_nu,
    quat_wxyz_to_rot,
    random_state,
    rot_to_quat_wxyz,
    so3_exp,
    so3_log,
    urdf_depth_first_joints,
)

import icub_models  # noqa: E402  (a test dependency: missing means failed, not skipped)

ICUB25 = ICUB25_JOINTS
ICUB_LOCKED = {"neck_pitch": 0.3, "l_wrist_pitch": -0.4, "r_wrist_yaw": 0.25}



@pytest.fixture(scope="module")
def hand_urdf(tmp_path_factory) -> pathlib.Path:
    path = tmp_path_factory.mktemp("urdf") / "hand_made.urdf"
    path.write_text(HAND_URDF)
    return path


@pytest.fixture(scope="module")
def icub_urdf() -> pathlib.Path:
    return pathlib.Path(icub_models.get_model_file("iCubGenova04"))


_CACHE: dict = {}


def _ref(kind: str, hand_urdf, icub_urdf) -> PinReference:
    if kind not in _CACHE:
        if kind == "hand":
            _CACHE[kind] = PinReference(hand_urdf)
        elif kind == "hand_permuted":
            _CACHE[kind] = PinReference(hand_urdf, joints=["gamma_rev", "zeta_rev", "beta_cont"],
                                        locked={"alpha_pris": 0.12})
        elif kind == "icub32":
            _CACHE[kind] = PinReference(icub_urdf)
        elif kind == "icub25":
            _CACHE[kind] = PinReference(icub_urdf, joints=ICUB25, locked=ICUB_LOCKED)
        elif kind.startswith("random"):
            import urdf_gen
            seed = int(kind.split("-")[1])
            path = urdf_gen.write_random_urdf(hand_urdf.parent, seed, 10)
            _CACHE[kind] = PinReference(path)
        else:
            raise KeyError(kind)
    return _CACHE[kind]


MODELS = ["hand", "hand_permuted", "icub32", "icub25", "random-0", "random-1", "random-2"]
SEEDS = [0, 1, 2]


@pytest.fixture(params=MODELS)
def ref(request, hand_urdf, icub_urdf) -> PinReference:
    return _ref(request.param, hand_urdf, icub_urdf)


def _frames(ref: PinReference) -> list[str]:
    preferred = ["l_sole", "r_sole", "root_link", "l_hand", "r_hand", "head", "chest",
                 "sole", "l_cont", "l_last", "l_tool", "base"]
    out = [f for f in preferred if f in ref.frame_ids]
    return out or list(ref.frame_names)


def _state(ref: PinReference, seed: int, speed: float = 1.0):
    rng = np.random.default_rng(1000 + seed)
    return random_state(rng, ref.n_joints, box=1.0, angle=1.5, speed=speed)


def close(a, b, rtol: float, what: str = "") -> None:
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    assert a.shape == b.shape, (what, a.shape, b.shape)
    err = np.linalg.norm(a - b)
    scale = max(1.0, np.linalg.norm(b))
    assert err <= rtol * scale, f"{what}: |diff| = {err:.3e}, |ref| = {np.linalg.norm(b):.3e}"


EXACT = 1e-10  # different Pinocchio entry points, same model: agreement to rounding
FD = 1e-6  # central differences, eps = 1e-6
EPS = 1e-6


def _fd(fun, q, nu, eps: float = EPS):
    """Central difference of fun along the constant-nu motion through q."""
    return (fun(integrate_constant_nu(q, nu, eps)) - fun(integrate_constant_nu(q, nu, -eps))) / (
        2 * eps
    )


# ------------------------------------------------------------------ own helpers, sanity


def test_rotation_helpers_against_pinocchio():
    rng = np.random.default_rng(7)
    for _ in range(20):
        w = rng.normal(size=3)
        R = so3_exp(w)
        np.testing.assert_allclose(R, pin.exp3(w), atol=1e-13)
        if np.linalg.norm(w) < 3.0:
            np.testing.assert_allclose(so3_log(R), w, atol=1e-10)
        quat = rot_to_quat_wxyz(R)
        np.testing.assert_allclose(quat_wxyz_to_rot(quat), R, atol=1e-13)
        # pin.Quaternion's constructor takes (w, x, y, z); coeffs() are (x, y, z, w).
        pq = pin.Quaternion(quat[0], quat[1], quat[2], quat[3])
        np.testing.assert_allclose(pq.toRotationMatrix(), R, atol=1e-13)
        np.testing.assert_allclose(pq.coeffs(), np.r_[quat[1:], quat[0]], atol=1e-15)


def test_constant_nu_motion_is_exact_flow():
    """integrate_constant_nu composes: q(t1 + t2) == q(t2) after q(t1)."""
    rng = np.random.default_rng(3)
    q, nu, _ = random_state(rng, 4)
    a = integrate_constant_nu(integrate_constant_nu(q, nu, 0.3), nu, 0.45)
    b = integrate_constant_nu(q, nu, 0.75)
    qa, qb = a[3:7], b[3:7]
    if qa @ qb < 0:
        qb = -qb
    np.testing.assert_allclose(np.r_[a[:3], qa, a[7:]], np.r_[b[:3], qb, b[7:]], atol=1e-13)
    # the quaternion derivative is 0.5 * (0, omega_world) * quat
    eps = 1e-6
    dq = (integrate_constant_nu(q, nu, eps)[3:7] - integrate_constant_nu(q, nu, -eps)[3:7]) / (
        2 * eps
    )
    w, v = q[3], q[4:7]
    om = nu[3:6]
    expect = 0.5 * np.r_[-om @ v, w * om + np.cross(om, v)]
    np.testing.assert_allclose(dq, expect, atol=1e-8)


# ------------------------------------------------------------------ model structure


def test_joint_order_pinocchio_not_file_order(hand_urdf):
    ref = PinReference(hand_urdf)
    assert sorted(ref.joint_names) == sorted(HAND_JOINTS_FILE_ORDER)
    # Pinocchio (through urdfdom) orders siblings by name, not file order: the pitfall the
    # sea_momentum comparison must avoid by matching joints by name.
    assert ref.joint_names.index("alpha_pris") < ref.joint_names.index("zeta_rev")
    assert set(ref.frame_names) == {"base", "l_rev", "l_tool", "l_cont", "l_pris", "sole",
                                    "l_last"}
    assert ref.total_mass == pytest.approx(3.0 + 1.2 + 0.5 + 0.7 + 2.0 + 0.4)


def test_urdf_depth_first_joints(icub_urdf):
    assert urdf_depth_first_joints(HAND_URDF) == HAND_JOINTS_FILE_ORDER
    order = urdf_depth_first_joints(icub_urdf.read_text())
    assert len(order) == 32 and set(order) == set(_ref("icub32", None, icub_urdf).joint_names)
    assert set(ICUB25) <= set(order)


def test_icub_structure(icub_urdf):
    full = _ref("icub32", None, icub_urdf)
    assert full.n_joints == 32
    assert full.total_mass == pytest.approx(33.06, abs=0.01)
    red = _ref("icub25", None, icub_urdf)
    assert red.joint_names == ICUB25
    assert red.nq == 32 and red.nv == 31
    assert red.total_mass == pytest.approx(full.total_mass, rel=1e-12)
    for f in ["l_sole", "r_sole", "root_link", "head", "l_hand"]:
        assert f in full.frame_ids and f in red.frame_ids
    # links keep BODY frames in the reduced model; the locked joints become FIXED_JOINT frames
    assert red.model.frames[red.model.getFrameId("neck_pitch")].type == pin.FrameType.FIXED_JOINT


def test_permutation_consistency(hand_urdf):
    """Reordering the joints permutes every output consistently."""
    a = PinReference(hand_urdf)
    order = list(reversed(HAND_JOINTS_FILE_ORDER))
    b = PinReference(hand_urdf, joints=order)
    idx = [a.joint_names.index(n) for n in order]  # b's joint i is a's joint idx[i]
    vperm = np.r_[0:6, 6 + np.array(idx)]
    qperm = np.r_[0:7, 7 + np.array(idx)]
    rng = np.random.default_rng(11)
    qa, nua, nudota = random_state(rng, a.n_joints)
    qb, nub, nudotb = qa[qperm], nua[vperm], nudota[vperm]
    close(b.mass_matrix(qb), a.mass_matrix(qa)[np.ix_(vperm, vperm)], EXACT, "M")
    close(b.bias_forces(qb, nub), a.bias_forces(qa, nua)[vperm], EXACT, "h")
    close(b.inverse_dynamics(qb, nub, nudotb), a.inverse_dynamics(qa, nua, nudota)[vperm],
          EXACT, "rnea")
    close(b.frame_jacobian(qb, "l_cont"), a.frame_jacobian(qa, "l_cont")[:, vperm], EXACT, "J")
    close(b.centroidal_momentum_matrix(qb), a.centroidal_momentum_matrix(qa)[:, vperm], EXACT,
          "A_G")
    close(b.frame_pose(qb, "sole"), a.frame_pose(qa, "sole"), EXACT, "pose")


@pytest.mark.parametrize("kind", ["hand_permuted", "icub25"])
@pytest.mark.parametrize("seed", SEEDS)
def test_reduced_equals_full_with_locked_values(kind, seed, hand_urdf, icub_urdf):
    """The reduced model equals the full model with the locked joints at their values and at
    rest (sub-blocks of M, h, rnea, Jacobians; identical poses, CoM, momentum)."""
    red = _ref(kind, hand_urdf, icub_urdf)
    full = PinReference(red.urdf_path, joints=red.joint_names + list(red.locked_values))
    n = red.n_joints
    q, nu, nudot = _state(red, seed)
    qf = np.r_[q, list(red.locked_values.values())]
    nuf = np.r_[nu, np.zeros(len(red.locked_values))]
    nudotf = np.r_[nudot, np.zeros(len(red.locked_values))]
    k = slice(0, 6 + n)
    close(red.mass_matrix(q), full.mass_matrix(qf)[k, k], EXACT, "M")
    close(red.bias_forces(q, nu), full.bias_forces(qf, nuf)[k], EXACT, "h")
    close(red.gravity_forces(q), full.gravity_forces(qf)[k], EXACT, "g")
    close(red.inverse_dynamics(q, nu, nudot), full.inverse_dynamics(qf, nuf, nudotf)[k],
          EXACT, "rnea")
    close(red.com(q), full.com(qf), EXACT, "com")
    close(red.centroidal_momentum_matrix(q), full.centroidal_momentum_matrix(qf)[:, k],
          EXACT, "A_G")
    for f in _frames(red):
        close(red.frame_pose(q, f), full.frame_pose(qf, f), EXACT, f"pose {f}")
        close(red.frame_jacobian(q, f), full.frame_jacobian(qf, f)[:, k], EXACT, f"J {f}")
        close(red.frame_jacobian_dot_v(q, nu, f), full.frame_jacobian_dot_v(qf, nuf, f),
              EXACT, f"Jdot_nu {f}")


# ------------------------------------------------------------------ conversions


@pytest.mark.parametrize("seed", SEEDS)
def test_base_pose_and_quaternion_order(ref, seed):
    q, _, _ = _state(ref, seed)
    R = quat_wxyz_to_rot(q[3:7])
    base = ref.model.frames[2].name  # the root link's BODY frame follows universe, root_joint
    assert ref.model.frames[2].type == pin.FrameType.BODY
    H = ref.frame_pose(q, base)
    np.testing.assert_allclose(H[:3, :3], R, atol=1e-14)
    np.testing.assert_allclose(H[:3, 3], q[:3], atol=1e-14)
    np.testing.assert_allclose(H[3], [0, 0, 0, 1])
    # and a base translation/rotation moves every frame rigidly
    f = _frames(ref)[0]
    q0 = q.copy()
    q0[:7] = [0, 0, 0, 1, 0, 0, 0]
    local = ref.frame_pose(q0, f)
    np.testing.assert_allclose(ref.frame_pose(q, f), H @ local, atol=1e-13)


@pytest.mark.parametrize("seed", SEEDS)
def test_a_jacobian_vs_frame_velocity(ref, seed):
    q, nu, _ = _state(ref, seed)
    for f in _frames(ref):
        close(ref.frame_jacobian(q, f) @ nu, ref.frame_velocity(q, nu, f), EXACT, f)


@pytest.mark.parametrize("seed", SEEDS)
def test_b_jacobian_vs_pose_finite_differences(ref, seed):
    q, nu, _ = _state(ref, seed)
    for f in _frames(ref):
        Hp = ref.frame_pose(integrate_constant_nu(q, nu, EPS), f)
        Hm = ref.frame_pose(integrate_constant_nu(q, nu, -EPS), f)
        v = (Hp[:3, 3] - Hm[:3, 3]) / (2 * EPS)
        w = so3_log(Hp[:3, :3] @ Hm[:3, :3].T) / (2 * EPS)
        close(ref.frame_jacobian(q, f) @ nu, np.r_[v, w], FD, f)
    close(ref.com_jacobian(q) @ nu, _fd(ref.com, q, nu), FD, "com")


@pytest.mark.parametrize("seed", SEEDS)
def test_c_jdot_nu_vs_finite_differences(ref, seed):
    q, nu, _ = _state(ref, seed)
    for f in _frames(ref):
        fd = _fd(lambda qq: ref.frame_jacobian(qq, f) @ nu, q, nu)
        close(ref.frame_jacobian_dot_v(q, nu, f), fd, FD, f)


@pytest.mark.parametrize("seed", SEEDS)
def test_c2_acceleration_is_affine_in_nudot(ref, seed):
    """a_F = J nudot + Jdot_nu: Pinocchio's classical acceleration at a_pin(nudot)."""
    q, nu, nudot = _state(ref, seed)
    for f in _frames(ref):
        fid = ref.frame_id(f)
        pin.forwardKinematics(ref.model, ref.data, ref.q_pin(q), ref.v_pin(q, nu),
                              ref.a_pin(q, nu, nudot))
        acc = pin.getFrameClassicalAcceleration(ref.model, ref.data, fid,
                                                pin.ReferenceFrame.LOCAL_WORLD_ALIGNED).vector
        close(ref.frame_jacobian(q, f) @ nudot + ref.frame_jacobian_dot_v(q, nu, f), acc,
              EXACT, f)
    # and by finite differences along a motion with that nudot (second order Taylor)
    f = _frames(ref)[0]
    dt = 1e-4

    def vel(t):
        # nu(t) = nu + t nudot; q(t) to second order: midpoint of the velocity
        qt = integrate_constant_nu(q, nu + 0.5 * t * nudot, t)
        return ref.frame_jacobian(qt, f) @ (nu + t * nudot)

    fd = (vel(dt) - vel(-dt)) / (2 * dt)
    expect = ref.frame_jacobian(q, f) @ nudot + ref.frame_jacobian_dot_v(q, nu, f)
    close(fd, expect, 1e-5, "fd acc")


@pytest.mark.parametrize("seed", SEEDS)
def test_d_mass_matrix_and_rnea(ref, seed):
    q, nu, nudot = _state(ref, seed)
    M = ref.mass_matrix(q)
    np.testing.assert_allclose(M, M.T, atol=1e-12 * np.abs(M).max())
    assert np.linalg.eigvalsh(M).min() > 0
    h = ref.bias_forces(q, nu)
    close(ref.inverse_dynamics(q, nu, nudot), M @ nudot + h, EXACT, "rnea = M nudot + h")
    close(ref.inverse_dynamics(q, np.zeros(ref.nv), np.zeros(ref.nv)), ref.gravity_forces(q),
          EXACT, "g = rnea(q, 0, 0)")
    # the base block of M: total mass and the mass moment about the base origin
    m = ref.total_mass
    np.testing.assert_allclose(M[:3, :3], m * np.eye(3), atol=1e-12 * m)
    c = ref.com(q) - q[:3]
    np.testing.assert_allclose(M[:3, 3:6], -m * np.array([[0, -c[2], c[1]], [c[2], 0, -c[0]],
                                                           [-c[1], c[0], 0]]), atol=1e-11 * m)


@pytest.mark.parametrize("seed", SEEDS)
def test_f_kinetic_energy(ref, seed):
    q, nu, nudot = _state(ref, seed)
    M = ref.mass_matrix(q)
    for x in (nu, nudot, nu + nudot):
        close(0.5 * x @ M @ x, ref.kinetic_energy_pin(q, x), EXACT, "KE")
    # pinocchio's own quadratic form, for completeness
    qp, vp = ref.q_pin(q), ref.v_pin(q, nu)
    Mp = pin.crba(ref.model, ref.data, qp)
    Mp = np.triu(Mp) + np.triu(Mp, 1).T
    close(0.5 * nu @ M @ nu, 0.5 * vp @ Mp @ vp, EXACT, "KE pin")


@pytest.mark.parametrize("seed", SEEDS)
def test_e_centroidal_momentum(ref, seed):
    q, nu, _ = _state(ref, seed)
    A = ref.centroidal_momentum_matrix(q)
    H = ref.centroidal_momentum(q, nu)
    close(A @ nu, H, EXACT, "A_G nu vs computeCentroidalMomentum")
    close(A[:3], ref.total_mass * ref.com_jacobian(q), EXACT, "A_G linear = m J_com")
    # independent: sum of body momenta (Pinocchio per-body inertias and velocities)
    model, data = ref.model, ref.data
    pin.forwardKinematics(model, data, ref.q_pin(q), ref.v_pin(q, nu))
    P = np.zeros(3)
    Lo = np.zeros(3)
    for i in range(1, model.njoints):
        f = data.oMi[i].act(model.inertias[i] * data.v[i])
        P += f.linear
        Lo += f.angular
    c = ref.com(q)
    close(np.r_[P, Lo - np.cross(c, P)], H, EXACT, "sum of body momenta")


@pytest.mark.parametrize("seed", SEEDS)
def test_g_gravity_from_com_jacobian(ref, seed):
    q, _, _ = _state(ref, seed)
    g = ref.gravity_forces(q)
    close(g, ref.total_mass * GRAVITY * ref.com_jacobian(q)[2], EXACT, "G = m g J_com_z^T")
    np.testing.assert_allclose(ref.model.gravity.linear, [0, 0, -GRAVITY])


@pytest.mark.parametrize("seed", SEEDS)
def test_h_bias_forces_newton_euler_and_lagrange(ref, seed):
    """h is checked without Pinocchio's RNEA: base rows by Newton-Euler on the whole system
    (finite differences of H), joint rows by Lagrange's equations (finite differences of M)."""
    q, nu, _ = _state(ref, seed)
    h = ref.bias_forces(q, nu)
    m = ref.total_mass
    # base rows: h_lin = dP/dt + m g e_z; moment about p_B: h_ang + (p_B - c) x h_lin = dL_c/dt
    dH = _fd(lambda qq: ref.centroidal_momentum(qq, nu), q, nu)
    close(h[:3], dH[:3] + m * GRAVITY * np.array([0, 0, 1.0]), FD, "base force")
    c = ref.com(q)
    close(h[3:6] + np.cross(q[:3] - c, h[:3]), dH[3:6], FD, "base moment")
    # joint rows: h_s = (dM/dt nu)_s - 1/2 nu^T dM/ds nu + G_s
    Mdot_nu = _fd(lambda qq: ref.mass_matrix(qq) @ nu, q, nu)
    G = ref.gravity_forces(q)
    dKds = np.zeros(ref.n_joints)
    for k in range(ref.n_joints):
        qp, qm = q.copy(), q.copy()
        qp[7 + k] += EPS
        qm[7 + k] -= EPS
        dKds[k] = 0.5 * nu @ ((ref.mass_matrix(qp) - ref.mass_matrix(qm)) / (2 * EPS)) @ nu
    close(h[6:], Mdot_nu[6:] - dKds + G[6:], FD, "joint rows")
    # power: nu^T h = 1/2 nu^T Mdot nu + nu^T G (holds for every row set)
    close(nu @ h, 0.5 * nu @ Mdot_nu + nu @ G, FD, "power")
