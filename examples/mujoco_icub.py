"""The iCub of sea-momentum in MuJoCo: the model, the state conversion and the feet's wrenches.

Shared by ``examples/mujoco_balance.py``, ``benchmarks/mujoco_push.py`` and
``benchmarks/peers.py``: the same URDF (urdf/icub25.urdf) compiled by MuJoCo, with a free base,
soft frictional contacts between two foot boxes and a floor plane, and torque actuators on the
25 joints.

Conventions converted (MuJoCo docs, "Floating objects" / mjData.qvel):
- free joint ``qpos = [x y z qw qx qy qz]`` (base position, world; quaternion w first) equals our
  ``q[:7]`` (docs/reference/conventions.md: ``[p_B, quaternion (w, x, y, z)]``);
- free joint ``qvel = [v (world), omega (base frame)]``; ours is ``[pdot_B (world), omega_B
  (world)]``, so ``omega_world = R_B omega_body``;
- joints by name (``model.joint(name).qposadr / dofadr``), in our joint order.

What MuJoCo's URDF import makes of the file (checked with MuJoCo 4.0): the compiler's
``autolimits`` is on by default, so every revolute joint with a ``<limit>`` is ``limited`` with
the URDF's ``[lower, upper]`` as its range (joint stops); each ``effort`` becomes the joint's
``actuatorfrcrange`` (the actuator torque is clamped to it), unless ``effort_limits=False``.
"""

from __future__ import annotations

import dataclasses
import pathlib
import xml.etree.ElementTree as ET

import mujoco
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
URDF = ROOT / "urdf" / "icub25.urdf"
#: Any iCub scenario: its build gives the model and the initial configuration (overridden to
#: two feet, the "two_feet" posture of the original study, rigid joints).
SCENARIO = ROOT / "scenarios" / "paper" / "tracking.toml"
FEET = ["l_sole", "r_sole"]
#: The foot rectangle in the sole frame [m]: the MuJoCo foot box and the controller's CoP
#: constraint (controller.contact.foot_x / foot_y) are the same rectangle.
FOOT_X = (-0.05, 0.10)
FOOT_Y = (-0.025, 0.025)
#: Half thickness of the foot box [m]; its bottom face is the sole plane.
FOOT_HALF_THICKNESS = 0.005
#: MuJoCo step [s].
TIMESTEP = 1e-3
#: Gravity [m/s^2], MuJoCo's default and ours (docs/reference/conventions.md).
GRAVITY = (0.0, 0.0, -9.81)
#: Collision bits: the floor collides with the foot boxes (bit 1) and with the body shapes
#: (bit 2); body shapes do not collide with each other nor with the foot boxes.
FOOT_BIT, BODY_BIT = 1, 2


@dataclasses.dataclass(frozen=True)
class ModelOptions:
    """How the URDF is compiled (the defaults are ``examples/mujoco_balance.py``'s model)."""

    #: ``armature`` on every actuated joint [kg m^2] (our plant's
    #: ``joint_inertia_regularization`` adds the same to the joint diagonal of M).
    armature: float = 0.0
    #: Keep the URDF's ``effort`` as each joint's ``actuatorfrcrange`` (MuJoCo's import does).
    effort_limits: bool = True
    #: Elliptic friction cones instead of MuJoCo's default pyramidal ones.
    elliptic: bool = False
    #: The URDF's visual boxes (equivalent inertia boxes) as massless shapes colliding with the
    #: floor only, so that a body touching the floor shows as a contact (the feet's are left out).
    body_shapes: bool = False
    #: MuJoCo's ``fusestatic``: static bodies (the sole frames, the neck, the wrists) fused into
    #: their parents, as a user compiling the URDF would; the foot boxes then sit on the foot
    #: links at the sole's pose.
    fusestatic: bool = False


def urdf_text(urdf: pathlib.Path, joints: list[str], options: ModelOptions) -> str:
    """The URDF for MuJoCo: joint damping and friction dropped (our rigid model has none), the
    joints not in ``joints`` locked (as in our reduced model), and a ``<mujoco><compiler>``."""
    robot = ET.parse(urdf).getroot()
    for dynamics in robot.iter("dynamics"):
        dynamics.attrib.pop("damping", None)
        dynamics.attrib.pop("friction", None)
    for joint in robot.findall("joint"):
        if joint.get("type") != "fixed" and joint.get("name") not in joints:
            joint.set("type", "fixed")
    compiler = ET.SubElement(ET.SubElement(robot, "mujoco"), "compiler")
    compiler.attrib.update(
        {
            "fusestatic": str(options.fusestatic).lower(),
            "discardvisual": str(not options.body_shapes).lower(),
            "balanceinertia": "false",
        }
    )
    if options.body_shapes:
        # The visual boxes must not add mass: the URDF's <inertial> stay the only masses.
        compiler.set("inertiafromgeom", "false")
    return ET.tostring(robot, encoding="unicode")


def sole_pose_in_parent(urdf: pathlib.Path, sole: str) -> tuple[str, np.ndarray, np.ndarray]:
    """The parent link of the fixed joint holding ``sole`` and the sole's position and
    quaternion (w, x, y, z) in that link, from the joint's ``<origin xyz rpy>``."""
    for joint in ET.parse(urdf).getroot().findall("joint"):
        if joint.find("child").get("link") != sole:
            continue
        origin = joint.find("origin")
        xyz = np.array([float(v) for v in origin.get("xyz", "0 0 0").split()])
        roll, pitch, yaw = (float(v) for v in origin.get("rpy", "0 0 0").split())
        # URDF: R = Rz(yaw) Ry(pitch) Rx(roll).
        quat = np.empty(4)
        mujoco.mju_euler2Quat(quat, np.array([roll, pitch, yaw]), "XYZ")
        return joint.find("parent").get("link"), xyz, quat
    raise ValueError(f"no joint has {sole} as its child")


def add_foot_boxes(spec: mujoco.MjSpec, urdf: pathlib.Path, fused: bool) -> None:
    """Massless foot boxes of the foot rectangle, bottom face on the sole plane, on the sole
    bodies (or, ``fused``, on their parent links at the sole's pose)."""
    half = [(FOOT_X[1] - FOOT_X[0]) / 2, (FOOT_Y[1] - FOOT_Y[0]) / 2, FOOT_HALF_THICKNESS]
    centre = np.array([(FOOT_X[1] + FOOT_X[0]) / 2, (FOOT_Y[1] + FOOT_Y[0]) / 2, FOOT_HALF_THICKNESS])
    for foot in FEET:
        body, pos, quat = foot, centre, np.array([1.0, 0.0, 0.0, 0.0])
        if fused:
            body, sole_pos, quat = sole_pose_in_parent(urdf, foot)
            rotation = np.empty(9)
            mujoco.mju_quat2Mat(rotation, quat)
            pos = sole_pos + rotation.reshape(3, 3) @ centre
        # Massless: a contact surface, not a body (the URDF's masses stay the only ones).
        spec.body(body).add_geom(
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=half,
            pos=list(pos),
            quat=list(quat),
            name=f"{foot}_box",
            density=0.0,
            contype=FOOT_BIT,
            conaffinity=FOOT_BIT,
        )


def mujoco_model(urdf: pathlib.Path, joints: list[str], options: ModelOptions | None = None) -> mujoco.MjModel:
    """The URDF in MuJoCo (see ``urdf_text`` and ``ModelOptions``): a free base, foot boxes, a
    floor plane and one torque actuator per joint of ``joints``; 1 ms steps, implicitfast."""
    options = options or ModelOptions()
    spec = mujoco.MjSpec.from_string(urdf_text(urdf, joints, options))
    spec.option.timestep = TIMESTEP
    spec.option.gravity = GRAVITY
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    if options.elliptic:
        spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.worldbody.first_body().add_freejoint()
    spec.worldbody.add_geom(
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[2.0, 2.0, 0.1],
        name="floor",
        contype=FOOT_BIT,
        conaffinity=FOOT_BIT | BODY_BIT,
    )
    add_foot_boxes(spec, urdf, options.fusestatic)
    for name in joints:
        joint = spec.joint(name)
        joint.armature = options.armature
        if not options.effort_limits:
            joint.actfrclimited = mujoco.mjtLimited.mjLIMITED_FALSE
        actuator = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        actuator.gainprm[0] = 1.0  # a motor: force = ctrl [N m]
    model = spec.compile()
    if options.body_shapes:
        enable_body_shapes(model)
    return model


def foot_fixed_bodies(model: mujoco.MjModel) -> set[int]:
    """The bodies welded to a foot (the foot links, the sole frames): no joint between them."""
    welds = {int(model.body_weldid[model.body(foot).id]) for foot in FEET if _has_body(model, foot)}
    return {b for b in range(model.nbody) if int(model.body_weldid[b]) in welds}


def enable_body_shapes(model: mujoco.MjModel) -> None:
    """The visual geoms of the bodies not fixed to a foot collide with the floor (only)."""
    feet = foot_fixed_bodies(model)
    for geom in range(model.ngeom):
        body = int(model.geom_bodyid[geom])
        if body == 0 or model.geom_group[geom] != 1:
            continue  # the floor; the foot boxes (group 0)
        model.geom_contype[geom] = 0 if body in feet else BODY_BIT
        model.geom_conaffinity[geom] = 0


def _has_body(model: mujoco.MjModel, name: str) -> bool:
    return mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name) >= 0


@dataclasses.dataclass
class StateMap:
    """Where our state's entries are in MuJoCo's qpos/qvel."""

    base_qpos: int  #: free joint's qpos address
    base_dof: int  #: free joint's dof address
    joint_qpos: np.ndarray  #: qpos address of each of our joints, in our order
    joint_dof: np.ndarray  #: dof address of each of our joints

    @classmethod
    def of(cls, mj: mujoco.MjModel, joints: list[str]) -> StateMap:
        """The addresses in ``mj`` of the free joint and of ``joints``."""
        free = next(j for j in range(mj.njnt) if mj.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE)
        return cls(
            int(mj.jnt_qposadr[free]),
            int(mj.jnt_dofadr[free]),
            np.array([mj.joint(name).qposadr[0] for name in joints]),
            np.array([mj.joint(name).dofadr[0] for name in joints]),
        )

    def to_ours(self, data: mujoco.MjData) -> np.ndarray:
        """Our rigid state ``x = [q, nu]`` from MuJoCo's ``qpos``, ``qvel``."""
        pose = data.qpos[self.base_qpos : self.base_qpos + 7]
        velocity = data.qvel[self.base_dof : self.base_dof + 6]
        rotation = np.empty(9)
        mujoco.mju_quat2Mat(rotation, pose[3:7])
        omega_world = rotation.reshape(3, 3) @ velocity[3:6]
        q = np.concatenate([pose, data.qpos[self.joint_qpos]])
        nu = np.concatenate([velocity[:3], omega_world, data.qvel[self.joint_dof]])
        return np.concatenate([q, nu])

    def set_from_ours(self, data: mujoco.MjData, q: np.ndarray) -> None:
        """MuJoCo's ``qpos`` at our configuration ``q`` (velocities zero)."""
        data.qpos[self.base_qpos : self.base_qpos + 7] = q[:7]
        data.qpos[self.joint_qpos] = q[7:]
        data.qvel[:] = 0.0


def foot_wrenches(mj: mujoco.MjModel, data: mujoco.MjData, feet: list[str]) -> np.ndarray:
    """MuJoCo's contact wrenches on each foot, ``[force; torque about the sole origin]`` in world
    axes (n_feet, 6), from ``mj_contactForce`` (a contact's frame: normal then tangents, as
    rows; the force acts on geom2 along +normal, on geom1 opposite)."""
    wrenches = np.zeros((len(feet), 6))
    bodies = [mj.body(foot).id for foot in feet]
    local = np.zeros(6)
    for i in range(data.ncon):
        contact = data.contact[i]
        mujoco.mj_contactForce(mj, data, i, local)
        force = contact.frame.reshape(3, 3).T @ local[:3]
        for k, body in enumerate(bodies):
            if mj.geom_bodyid[contact.geom2] == body:
                on_foot = force
            elif mj.geom_bodyid[contact.geom1] == body:
                on_foot = -force
            else:
                continue
            sole = data.xpos[body]
            wrenches[k, :3] += on_foot
            wrenches[k, 3:] += np.cross(contact.pos - sole, on_foot)
    return wrenches
