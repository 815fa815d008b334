"""The iCub of sea-momentum balanced in MuJoCo by the rigid momentum controller.

A test against a simulator nobody here wrote: the same URDF (urdf/icub25.urdf) compiled by
MuJoCo, with a free base, soft frictional contacts between two foot boxes and a floor plane, and
torque actuators on the 25 joints; every millisecond the MuJoCo state is converted to our
conventions and handed to ``sea_momentum.Controller.tick`` (rigid controller, two feet), whose
joint torques drive the actuators.

Conventions converted (MuJoCo docs, "Floating objects" / mjData.qvel):
- free joint ``qpos = [x y z qw qx qy qz]`` (base position, world; quaternion w first) equals our
  ``q[:7]`` (docs/reference/conventions.md: ``[p_B, quaternion (w, x, y, z)]``);
- free joint ``qvel = [v (world), omega (base frame)]``; ours is ``[pdot_B (world), omega_B
  (world)]``, so ``omega_world = R_B omega_body``;
- joints by name (``model.joint(name).qposadr / dofadr``), in our joint order.

Run: ``python examples/mujoco_balance.py [--duration 10] [--amplitude 0.02]`` (needs
``pip install mujoco``, the ``examples`` extra). Prints the CoM error and the contact forces
measured by MuJoCo (``mj_contactForce``) against the QP's.
"""

from __future__ import annotations

import argparse
import dataclasses
import pathlib
import xml.etree.ElementTree as ET

import mujoco
import numpy as np

import sea_momentum as sm

ROOT = pathlib.Path(__file__).resolve().parents[1]
URDF = ROOT / "urdf" / "icub25.urdf"
#: Any iCub scenario: its build gives the model and the initial configuration (overridden below
#: to two feet, the "two_feet" posture of the original study, rigid joints).
SCENARIO = ROOT / "scenarios" / "paper" / "tracking.toml"
FEET = ["l_sole", "r_sole"]
#: The foot rectangle in the sole frame [m]: the MuJoCo foot box and the controller's CoP
#: constraint (controller.contact.foot_x / foot_y) are the same rectangle.
FOOT_X = (-0.05, 0.10)
FOOT_Y = (-0.025, 0.025)
#: Half thickness of the foot box [m]; its bottom face is the sole plane.
FOOT_HALF_THICKNESS = 0.005
#: MuJoCo step = control period [s] (the controller runs at every step).
TIMESTEP = 1e-3
#: Gravity [m/s^2], MuJoCo's default and ours (docs/reference/conventions.md).
GRAVITY = (0.0, 0.0, -9.81)


def mujoco_model(urdf: pathlib.Path, joints: list[str]) -> mujoco.MjModel:
    """The URDF in MuJoCo: static bodies kept (the sole frames), visuals discarded, joint
    damping dropped (our rigid model has none), a free base, foot boxes, a floor plane and one
    torque actuator per joint of ``joints``."""
    robot = ET.parse(urdf).getroot()
    for dynamics in robot.iter("dynamics"):
        dynamics.attrib.pop("damping", None)
        dynamics.attrib.pop("friction", None)
    for joint in robot.findall("joint"):
        if joint.get("type") != "fixed" and joint.get("name") not in joints:
            joint.set("type", "fixed")  # locked, as in our reduced model
    compiler = ET.SubElement(ET.SubElement(robot, "mujoco"), "compiler")
    compiler.attrib.update({"fusestatic": "false", "discardvisual": "true", "balanceinertia": "false"})
    spec = mujoco.MjSpec.from_string(ET.tostring(robot, encoding="unicode"))
    spec.option.timestep = TIMESTEP
    spec.option.gravity = GRAVITY
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    base = spec.worldbody.first_body()
    base.add_freejoint()
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[2.0, 2.0, 0.1], name="floor")
    half = [(FOOT_X[1] - FOOT_X[0]) / 2, (FOOT_Y[1] - FOOT_Y[0]) / 2, FOOT_HALF_THICKNESS]
    centre = [(FOOT_X[1] + FOOT_X[0]) / 2, (FOOT_Y[1] + FOOT_Y[0]) / 2, FOOT_HALF_THICKNESS]
    # Box centre h above the sole: its bottom face is the sole plane, so it touches the floor.
    for foot in FEET:
        # Massless: a contact surface, not a body (the URDF's masses stay the only ones).
        spec.body(foot).add_geom(
            type=mujoco.mjtGeom.mjGEOM_BOX, size=half, pos=centre, name=f"{foot}_box", density=0.0
        )
    for name in joints:
        actuator = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        actuator.gainprm[0] = 1.0  # a motor: force = ctrl [N m]
    return spec.compile()


@dataclasses.dataclass
class StateMap:
    """Where our state's entries are in MuJoCo's qpos/qvel."""

    base_qpos: int  #: free joint's qpos address
    base_dof: int  #: free joint's dof address
    joint_qpos: np.ndarray  #: qpos address of each of our joints, in our order
    joint_dof: np.ndarray  #: dof address of each of our joints

    @classmethod
    def of(cls, mj: mujoco.MjModel, joints: list[str]) -> StateMap:
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


def run(duration: float, amplitude: float, frequency: float = 0.2) -> dict[str, np.ndarray]:
    """Balances for ``duration`` seconds with a lateral CoM sinusoid of ``amplitude`` [m];
    returns the time series (time, com, com_reference, qp_wrenches, mujoco_wrenches, qp_solved)
    and the robot's weight [N]."""
    overrides = {
        "robot.contacts": FEET,
        "robot.initial_posture": "two_feet",
        "actuators.kind": "rigid",
        "controller.kind": "rigid",
    }
    scenario = sm.Scenario.load(SCENARIO, overrides)
    model = scenario.model
    q0 = scenario.initial_state[: model.nq]
    mj = mujoco_model(URDF, model.joint_names)
    data = mujoco.MjData(mj)
    states = StateMap.of(mj, model.joint_names)
    states.set_from_ours(data, q0)
    controller = sm.Controller(
        model,
        FEET,
        q0,
        actuators={"kind": "rigid"},
        reference={
            "com_origin": "initial",
            "com_amplitude": amplitude,
            "com_frequency": frequency,
            "com_direction": [0.0, 1.0, 0.0],
        },
        kind="rigid",
        contact={"foot_x": list(FOOT_X), "foot_y": list(FOOT_Y)},
    )
    actuator_of_joint = np.array([mj.actuator(name).id for name in model.joint_names])
    ticks = int(round(duration / TIMESTEP))
    series: dict[str, list] = {k: [] for k in ("time", "com", "com_reference", "qp_wrenches", "mujoco_wrenches", "qp_solved")}
    for k in range(ticks + 1):
        t = k * TIMESTEP
        x = states.to_ours(data)
        out = controller.tick(t, x)
        data.ctrl[actuator_of_joint] = out.input
        # mj_step's forward pass at x (before its integration) leaves the contacts and their
        # forces of this state and this input in `data`.
        mujoco.mj_step(mj, data)
        for key, value in (
            ("time", t),
            ("com", out.com),
            ("com_reference", out.com_reference),
            ("qp_wrenches", out.wrenches),
            ("mujoco_wrenches", foot_wrenches(mj, data, FEET)),
            ("qp_solved", out.qp_status == "solved"),
        ):
            series[key].append(value)
    result = {key: np.array(values) for key, values in series.items()}
    result["weight"] = np.array(model.total_mass * np.linalg.norm(GRAVITY))
    return result


#: The first instants, where MuJoCo's soft contacts build up from zero penetration, are left
#: out of the force comparison (reported apart) [s].
CONTACT_SETTLING = 0.05


def report(series: dict[str, np.ndarray], weight: float) -> str:
    """CoM error and contact forces, MuJoCo's against the QP's; ``weight`` [N]."""
    error = np.linalg.norm(series["com"] - series["com_reference"], axis=1)
    settled = series["time"] >= CONTACT_SETTLING
    qp, measured = series["qp_wrenches"], series["mujoco_wrenches"]
    force_error = np.linalg.norm(qp[:, :, :3] - measured[:, :, :3], axis=2)
    torque_error = np.linalg.norm(qp[:, :, 3:] - measured[:, :, 3:], axis=2)
    rms = lambda v: float(np.sqrt(np.mean(v**2)))  # noqa: E731
    lines = [
        f"duration {series['time'][-1]:.2f} s, QP solved at {series['qp_solved'].mean() * 100:.1f} % of the ticks",
        f"CoM error: rms {rms(error) * 1e3:.2f} mm, max {error.max() * 1e3:.2f} mm, final {error[-1] * 1e3:.2f} mm; "
        f"CoM height {series['com'][0, 2]:.3f} -> {series['com'][-1, 2]:.3f} m",
        f"total normal force after {CONTACT_SETTLING} s (mean): QP {qp[settled, :, 2].sum(axis=1).mean():.1f} N, "
        f"MuJoCo {measured[settled, :, 2].sum(axis=1).mean():.1f} N (weight {weight:.1f} N)",
    ]
    for i, foot in enumerate(FEET):
        lines.append(
            f"{foot}: normal force QP {qp[settled, i, 2].mean():.1f} N, MuJoCo {measured[settled, i, 2].mean():.1f} N; "
            f"|f_QP - f_MuJoCo| rms {rms(force_error[settled, i]):.2f} N, max {force_error[settled, i].max():.2f} N; "
            f"torque difference rms {rms(torque_error[settled, i]):.3f} N m "
            f"(before {CONTACT_SETTLING} s: force difference up to {force_error[~settled, i].max():.1f} N)"
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=10.0, help="simulated time [s]")
    parser.add_argument("--amplitude", type=float, default=0.02, help="lateral CoM sinusoid [m]")
    args = parser.parse_args()
    series = run(args.duration, args.amplitude)
    print(report(series, weight=series["weight"]))


if __name__ == "__main__":
    main()
