"""The iCub with series elastic actuators in MuJoCo, modelled the MuJoCo way.

Per joint of ``urdf/icub25.urdf`` (compiled as in ``mujoco_icub.py``), the series elastic
actuator of the paper (eq:motors, eq:alpha: ``I_m thetaddot = tau_m - Gamma tau``,
``tau = K_S (Gamma theta - s) + K_D (Gamma thetadot - sdot)``) is built from MuJoCo elements
(MuJoCo XML reference: ``joint/@armature``, ``tendon/fixed``, ``tendon/@stiffness``,
``tendon/@damping``, ``actuator/general`` with ``gear``):

- a **rotor body** ``<joint>_rotor`` on the joint's parent link, at the joint's pose, with a
  hinge ``<joint>_rotor`` about the joint's axis: the rotor angle on the joint side,
  ``phi = Gamma theta``. Its ``armature`` is the motor inertia reflected, ``I_m / Gamma^2``
  (armature adds to the hinge's diagonal of the mass matrix only: the rotor's kinetic energy
  ``I_m thetadot^2 / 2`` without the gyroscopic coupling to the link's motion, as in the
  paper's model, Spong's reduced model). The body itself has a negligible mass (``ROTOR_MASS``) and
  no geometry (MuJoCo needs a moving body to have a mass);
- the **spring-damper**: a fixed tendon ``<joint>_spring`` of length ``L = s - phi`` (joint
  coefficient 1, rotor coefficient -1) with ``stiffness = K_S``, ``damping = K_D`` and spring
  length 0: MuJoCo's passive tendon force ``F = -K_S L - K_D Ldot`` acts on each joint of the
  tendon times its coefficient, so the link feels ``+F = K_S (phi - s) + K_D (phidot - sdot)
  = tau`` (eq:alpha) and the rotor ``-tau``;
- the **motor**: an actuator ``<joint>_motor`` on the rotor hinge with ``gear = 1 / Gamma``, so
  its control is the motor torque ``tau_m`` [N m, motor side] and the rotor feels
  ``tau_m / Gamma``: with the armature, ``(I_m / Gamma^2) phiddot = tau_m / Gamma - tau``, which
  is eq:motors multiplied by ``1 / Gamma``;
- optionally (``motor_velocity_gain``) the motor boards' **velocity loop** (eq:tauMotors,
  ``tau_m = -I_m K_m (thetadot - thetadot_d) + Gamma tau``) as a velocity actuator
  ``<joint>_velocity`` on the rotor (``gear = 1 / Gamma``, so its length rate is ``thetadot``;
  ``kv = I_m K_m``; its control is ``thetadot_d``), which MuJoCo's ``implicitfast`` integrator
  treats implicitly, plus the feed-forward ``Gamma tau`` through ``<joint>_motor``, set by the
  caller at every MuJoCo step from the spring's torque (``MotorBoards.feed_forward``): the
  torque sensor's reading, sampled at the MuJoCo step;
- optionally (``torque_limits``) the motor torque limit ``|tau_m| <= L``: the rotor hinge's
  ``actfrcrange`` (``joint/@actuatorfrcrange``, which clamps the sum of the actuators' forces
  on the joint), ``+-L / Gamma``, the limit seen through the gear.

Our state ``x = [q, theta, nu, thetadot]`` maps to MuJoCo's: the link joints' ``qpos``/``qvel``
are ``s``, ``sdot``; the rotors' are ``Gamma theta``, ``Gamma thetadot``; the free joint as in
``mujoco_icub.StateMap``.

Why not a rotor body in series (rotor hinge, then the link on a spring hinge with joint
``stiffness``/``damping``): it is the same dynamics in other coordinates (``s = phi + delta``),
but it moves every link body one level down the tree and makes the link angle a sum of two
joints; the tendon keeps the URDF's tree and joints, so the rigid example's state map holds.
"""

from __future__ import annotations

import dataclasses
import pathlib
import sys
from typing import Mapping

import mujoco
import numpy as np
import sea_momentum as sm

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from mujoco_icub import (  # noqa: E402  (the rigid model's pieces, shared)
    FOOT_BIT,
    GRAVITY,
    ModelOptions,
    StateMap,
    add_foot_boxes,
    urdf_text,
)

#: Mass of a rotor body [kg] and its principal inertia [kg m^2]: negligible (MuJoCo refuses a
#: moving body without mass); the rotor's inertia is the hinge's armature.
ROTOR_MASS = 1e-9
ROTOR_INERTIA = 1e-12


@dataclasses.dataclass(frozen=True)
class Sea:
    """One series elastic actuator's parameters (the paper's iCub SEA by default, as
    ``sea_dyn::ElasticParameters::paper_icub``, the scenarios' ``[actuators]`` default;
    ``motor_torque_limits`` checks a scenario's against them, and ``mujoco_sea_check.py``'s
    welded check, equal to 2e-8 rad, fails if these differ from our plant's)."""

    ratio: float = 0.01  #: Gamma (joint angle per motor angle)
    motor_inertia: float = 1e-5  #: I_m [kg m^2, motor side]
    stiffness: float = 350.0  #: K_S [N m/rad]
    damping: float = 0.25  #: K_D [N m s/rad]

    @property
    def reflected_inertia(self) -> float:
        """``I_m / Gamma^2`` [kg m^2]: the rotor hinge's armature."""
        return self.motor_inertia / self.ratio**2


@dataclasses.dataclass(frozen=True)
class SeaModelOptions:
    """How the SEA model is built."""

    #: ``None``: the motor torque is the control (``<joint>_motor``); a gain ``K_m`` [1/s]:
    #: the motor velocity loop (``<joint>_velocity``, implicit) plus the feed-forward.
    motor_velocity_gain: float | None = None
    #: ``armature`` of the link joints [kg m^2]: the plant's ``joint_inertia_regularization``
    #: (the scenario's ``plant.joint_inertia_regularization``), so both are the same robot.
    joint_armature: float = 0.0
    #: ``None``: a free base on a floor with the foot boxes; a pose ``[x y z qw qx qy qz]``:
    #: the base welded there (no free joint, no floor), the contact-free check.
    fixed_base: np.ndarray | None = None
    #: Motor torque limits ``L`` [N m, motor side] by joint name (the scenario's
    #: ``torque_limit``s, ``motor_torque_limits``); a joint not named is unlimited.
    torque_limits: Mapping[str, float] = dataclasses.field(default_factory=dict)
    #: MuJoCo's step [s] and integrator.
    timestep: float = 2.5e-4
    integrator: int = mujoco.mjtIntegrator.mjINT_IMPLICITFAST


def add_rotor(spec: mujoco.MjSpec, name: str, sea: Sea, options: SeaModelOptions) -> None:
    """The rotor body, its hinge, the spring tendon and the actuators of joint ``name``."""
    joint = spec.joint(name)
    link = joint.parent
    rotor = link.parent.add_body(
        name=f"{name}_rotor",
        pos=list(link.pos),
        quat=list(link.quat),
        mass=ROTOR_MASS,
        inertia=[ROTOR_INERTIA] * 3,
        explicitinertial=True,
    )
    rotor.add_joint(
        name=f"{name}_rotor",
        type=mujoco.mjtJoint.mjJNT_HINGE,
        pos=list(joint.pos),
        axis=list(joint.axis),
        armature=sea.reflected_inertia,
        limited=mujoco.mjtLimited.mjLIMITED_FALSE,
    )
    limit = options.torque_limits.get(name)
    if limit is not None:
        hinge = spec.joint(f"{name}_rotor")
        hinge.actfrclimited = mujoco.mjtLimited.mjLIMITED_TRUE
        hinge.actfrcrange = [-limit / sea.ratio, limit / sea.ratio]
    spring = spec.add_tendon(name=f"{name}_spring")
    spring.stiffness = [sea.stiffness, 0.0, 0.0]
    spring.damping = [sea.damping, 0.0, 0.0]
    spring.springlength = [0.0, 0.0]
    spring.wrap_joint(name, 1.0)
    spring.wrap_joint(f"{name}_rotor", -1.0)
    motor = spec.add_actuator(name=f"{name}_motor", target=f"{name}_rotor", trntype=mujoco.mjtTrn.mjTRN_JOINT)
    motor.gear[0] = 1.0 / sea.ratio
    motor.gainprm[0] = 1.0  # force = ctrl: the motor torque [N m]
    if options.motor_velocity_gain is not None:
        kv = sea.motor_inertia * options.motor_velocity_gain
        velocity = spec.add_actuator(
            name=f"{name}_velocity", target=f"{name}_rotor", trntype=mujoco.mjtTrn.mjTRN_JOINT
        )
        velocity.gear[0] = 1.0 / sea.ratio
        velocity.gainprm[0] = kv  # force = kv (ctrl - thetadot): ctrl is thetadot_d
        velocity.biastype = mujoco.mjtBias.mjBIAS_AFFINE
        velocity.biasprm[2] = -kv


def motor_torque_limits(plant: sm.Plant, sea: Sea) -> dict[str, float]:
    """The motor torque limits of ``plant``'s elastic joints by name (those with one), after
    checking that its other SEA parameters are ``sea``'s (the model has one ``Sea``)."""
    limits = {}
    for name, parameters in zip(plant.elastic_joints, plant.elastic_parameters):
        for key in ("ratio", "motor_inertia", "stiffness", "damping"):
            if parameters[key] != getattr(sea, key):
                raise ValueError(f"{name}: the scenario's {key} {parameters[key]} is not the MuJoCo model's {getattr(sea, key)}")
        if parameters["torque_limit"] is not None:
            limits[name] = parameters["torque_limit"]
    return limits


def sea_model(urdf: pathlib.Path, joints: list[str], sea: Sea, options: SeaModelOptions) -> mujoco.MjModel:
    """The URDF in MuJoCo with a SEA on every joint of ``joints`` (module doc)."""
    rigid = ModelOptions(armature=options.joint_armature, effort_limits=False)
    spec = mujoco.MjSpec.from_string(urdf_text(urdf, joints, rigid))
    spec.option.timestep = options.timestep
    spec.option.gravity = GRAVITY
    spec.option.integrator = options.integrator
    base = spec.worldbody.first_body()
    if options.fixed_base is None:
        base.add_freejoint()
        spec.worldbody.add_geom(
            type=mujoco.mjtGeom.mjGEOM_PLANE, size=[2.0, 2.0, 0.1], name="floor", contype=FOOT_BIT, conaffinity=FOOT_BIT
        )
        add_foot_boxes(spec, urdf, fused=False)
    else:
        base.pos = list(options.fixed_base[:3])
        base.quat = list(options.fixed_base[3:7])
    for name in joints:
        spec.joint(name).armature = options.joint_armature
        add_rotor(spec, name, sea, options)
    return spec.compile()


@dataclasses.dataclass
class SeaStateMap:
    """Where our SEA state ``[q, theta, nu, thetadot]`` is in MuJoCo's ``qpos``/``qvel``."""

    links: StateMap | None  #: the free base and the link joints (None: fixed base)
    joint_qpos: np.ndarray  #: the link joints' qpos addresses, our order
    joint_dof: np.ndarray
    rotor_qpos: np.ndarray  #: the rotors' qpos addresses, our order
    rotor_dof: np.ndarray
    ratio: float  #: Gamma

    @classmethod
    def of(cls, mj: mujoco.MjModel, joints: list[str], ratio: float) -> SeaStateMap:
        """The addresses in ``mj`` of the base (when free), ``joints`` and their rotors."""
        free = any(mj.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE for j in range(mj.njnt))
        address = lambda names, field: np.array([getattr(mj.joint(n), field)[0] for n in names])  # noqa: E731
        rotors = [f"{n}_rotor" for n in joints]
        return cls(
            StateMap.of(mj, joints) if free else None,
            address(joints, "qposadr"),
            address(joints, "dofadr"),
            address(rotors, "qposadr"),
            address(rotors, "dofadr"),
            ratio,
        )

    def to_ours(self, data: mujoco.MjData, base_pose: np.ndarray | None = None) -> np.ndarray:
        """Our state ``x = [q, theta, nu, thetadot]`` (a fixed base at ``base_pose``, at rest)."""
        if self.links is not None:
            rigid = self.links.to_ours(data)
            n = len(self.joint_qpos)
            q, nu = rigid[: 7 + n], rigid[7 + n :]
        else:
            q = np.concatenate([base_pose, data.qpos[self.joint_qpos]])
            nu = np.concatenate([np.zeros(6), data.qvel[self.joint_dof]])
        theta = data.qpos[self.rotor_qpos] / self.ratio
        thetadot = data.qvel[self.rotor_dof] / self.ratio
        return np.concatenate([q, theta, nu, thetadot])

    def set_from_ours(self, data: mujoco.MjData, x: np.ndarray) -> None:
        """MuJoCo's ``qpos``/``qvel`` at our state ``x`` (the base's velocity too)."""
        n = len(self.joint_qpos)
        q, theta = x[: 7 + n], x[7 + n : 7 + 2 * n]
        nu, thetadot = x[7 + 2 * n : 13 + 3 * n], x[13 + 3 * n :]
        if self.links is not None:
            self.links.set_from_ours(data, q)
            rotation = np.empty(9)
            mujoco.mju_quat2Mat(rotation, q[3:7])
            base = self.links.base_dof
            data.qvel[base : base + 3] = nu[:3]
            data.qvel[base + 3 : base + 6] = rotation.reshape(3, 3).T @ nu[3:6]  # body axes
        else:
            data.qpos[self.joint_qpos] = q[7:]
        data.qvel[self.joint_dof] = nu[6:]
        data.qpos[self.rotor_qpos] = self.ratio * theta
        data.qvel[self.rotor_dof] = self.ratio * thetadot


@dataclasses.dataclass
class MotorBoards:
    """The actuators of the SEAs in ``mj``, in our joint order, and the joint torque sensors."""

    motor: np.ndarray  #: ``<joint>_motor`` actuator ids
    velocity: np.ndarray | None  #: ``<joint>_velocity`` ids (with the velocity loop)
    spring: np.ndarray  #: ``<joint>_spring`` tendon ids
    ratio: float

    @classmethod
    def of(cls, mj: mujoco.MjModel, joints: list[str], ratio: float) -> MotorBoards:
        """The ids of ``joints``' actuators and springs in ``mj``."""
        ids = lambda suffix, kind: np.array([mujoco.mj_name2id(mj, kind, f"{n}{suffix}") for n in joints])  # noqa: E731
        velocity = ids("_velocity", mujoco.mjtObj.mjOBJ_ACTUATOR)
        return cls(
            ids("_motor", mujoco.mjtObj.mjOBJ_ACTUATOR),
            None if (velocity < 0).any() else velocity,
            ids("_spring", mujoco.mjtObj.mjOBJ_TENDON),
            ratio,
        )

    def joint_torques(self, mj: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
        """The springs' torques on the links, ``tau = -(K_S L + K_D Ldot)`` (n): the joint
        torque sensors (from ``ten_length``/``ten_velocity``, valid after ``mj_forward`` or a
        step's position stage)."""
        length, rate = data.ten_length[self.spring], data.ten_velocity[self.spring]
        return -(mj.tendon_stiffness[self.spring] * length + mj.tendon_damping[self.spring] * rate)

    def command(self, mj: mujoco.MjModel, data: mujoco.MjData, u: np.ndarray) -> None:
        """Our plant input ``u`` (n) on the motors: the motor torques, or with the velocity
        loop the desired motor velocities plus the feed-forward ``Gamma tau`` of the spring's
        torque now (call at every MuJoCo step: the motor boards' loop)."""
        if self.velocity is None:
            data.ctrl[self.motor] = u
            return
        data.ctrl[self.velocity] = u
        data.ctrl[self.motor] = self.ratio * self.joint_torques(mj, data)
