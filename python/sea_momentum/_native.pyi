"""Typed stub of the native module ``sea_momentum._native``.

Conventions: ``q = [p_B (3, world), quaternion (w, x, y, z), s (n)]`` (``nq = 7 + n``);
``nu = [pdot_B (3, world), omega_B (3, world axes), sdot (n)]`` (``nv = 6 + n``); spatial vectors
linear part first; ``M(q) nudot + h(q, nu) = B tau + sum_k J_k^T f_k``; gravity -9.81 m/s^2 along
world z. Arrays are float64; array-likes are accepted and converted.
"""

from os import PathLike
from typing import Mapping, Sequence

import numpy as np
import numpy.typing as npt

__version__: str
ICUB25_JOINTS: tuple[str, ...]
"""The paper's 25 iCub joints in the original study's order (defined once, in Rust)."""

ArrayLike = npt.ArrayLike
Vector = npt.NDArray[np.float64]
Matrix = npt.NDArray[np.float64]

class ModelError(ValueError):
    """A robot description problem; the message names the URDF element and the condition."""

class Model:
    """A floating-base robot model loaded from URDF, with the buffers of its algorithms.

    Not thread-safe: use one Model per thread.
    """

    @staticmethod
    def from_urdf(
        path: str | PathLike[str],
        joints: Sequence[str] | None = None,
        locked: Mapping[str, float] | None = None,
    ) -> Model:
        """Load a URDF file.

        ``joints`` lists the moving joints in coordinate order (default: every revolute,
        continuous and prismatic joint, depth-first tree order); every other movable joint is
        locked at ``locked[name]`` (default 0). Raises ModelError naming the bad element.
        """
    @property
    def nq(self) -> int:
        """Configuration size, 7 + n."""
    @property
    def nv(self) -> int:
        """Velocity size, 6 + n."""
    @property
    def n_joints(self) -> int:
        """Number of moving joints n."""
    @property
    def joint_names(self) -> list[str]:
        """Moving joint names in coordinate order."""
    @property
    def frame_names(self) -> list[str]:
        """Every URDF link name (addressable frames), root first."""
    @property
    def base_link(self) -> str:
        """Name of the root link (the floating base)."""
    @property
    def total_mass(self) -> float:
        """Total mass [kg]."""
    def neutral(self) -> Vector:
        """Neutral configuration (nq,): base at the origin, identity orientation, joints at 0."""
    def mass_matrix(self, q: ArrayLike) -> Matrix:
        """Joint-space inertia matrix M(q), (nv, nv), symmetric."""
    def bias_forces(self, q: ArrayLike, nu: ArrayLike) -> Vector:
        """h(q, nu) = C(q, nu) nu + G(q), (nv,)."""
    def gravity_forces(self, q: ArrayLike) -> Vector:
        """G(q), (nv,)."""
    def inverse_dynamics(self, q: ArrayLike, nu: ArrayLike, nudot: ArrayLike) -> Vector:
        """M(q) nudot + h(q, nu), (nv,)."""
    def frame_pose(self, q: ArrayLike, frame: str) -> Matrix:
        """world_H_frame, (4, 4)."""
    def frame_jacobian(self, q: ArrayLike, frame: str) -> Matrix:
        """J_F(q), (6, nv): nu -> [velocity of the frame origin; angular velocity], world axes."""
    def frame_jacobian_dot_v(self, q: ArrayLike, nu: ArrayLike, frame: str) -> Vector:
        """Jdot_F nu, (6,): the frame's classical acceleration at nudot = 0, world axes."""
    def com(self, q: ArrayLike) -> Vector:
        """Centre of mass in world, (3,)."""
    def com_jacobian(self, q: ArrayLike) -> Matrix:
        """CoM Jacobian, (3, nv), world axes."""
    def centroidal_momentum_matrix(self, q: ArrayLike) -> Matrix:
        """A_G(q), (6, nv): H = [m pdot_com; L_com] = A_G nu, world axes, about the CoM."""
    def centroidal_momentum(self, q: ArrayLike, nu: ArrayLike) -> Vector:
        """H = [m pdot_com; L_com], (6,)."""
    def centroidal_momentum_bias(self, q: ArrayLike, nu: ArrayLike) -> Vector:
        """Adot_G nu, (6,): rate of the centroidal momentum at nudot = 0."""

ActuatorSpec = str | Mapping[str, float | None]

class Plant:
    """A floating-base robot with series elastic (or rigid) actuators and rigid contacts.

    State ``x = [q (nq), theta (n_e), nu (nv), thetadot (n_e)]``; input ``u`` (n), per joint
    in coordinate order: the joint torque of a rigid joint; for an elastic joint the motor
    torque, or the desired motor velocity when ``motor_velocity_gain`` is set (the motor
    velocity loop ``tau_m = -b K_m (thetadot - u) + eta tau``, saturated at the torque limit).
    Elastic joint: ``tau = k_s (eta theta - s) + k_d (eta thetadot - sdot)``,
    ``b thetaddot = tau_m - eta tau``. Contacts hold frames at their pose in ``contact_q``
    (Baumgarte ``K_p``, ``K_d``); wrenches are ``[force; moment about the frame origin]``,
    world axes. Not thread-safe: one Plant per thread.
    """

    def __init__(
        self,
        model: Model,
        *,
        actuator: ActuatorSpec | None = None,
        actuators: Mapping[str, ActuatorSpec] | None = None,
        contacts: Sequence[str] = (),
        contact_q: ArrayLike | None = None,
        baumgarte_kp: float | None = None,
        baumgarte_kd: float | None = None,
        motor_velocity_gain: float | None = None,
        joint_inertia_regularization: float = 0.0,
        gravity: tuple[float, float, float] | None = None,
        friction: float = 1.0,
        foot_x: tuple[float, float] = (-0.05, 0.10),
        foot_y: tuple[float, float] = (-0.025, 0.025),
    ) -> None:
        """``actuator``: default for every joint, "rigid" (default), "elastic" (the paper's
        iCub SEA: ratio 0.01, motor_inertia 1e-5, stiffness 350, damping 0.25) or a dict of
        those keys plus ``torque_limit``; ``actuators``: per-joint overrides by name."""
    @property
    def nx(self) -> int:
        """State size nq + nv + 2 n_e."""
    @property
    def nd(self) -> int:
        """Tangent size 2 nv + 2 n_e."""
    @property
    def nu_input(self) -> int:
        """Input size n."""
    @property
    def elastic_joints(self) -> list[str]:
        """Elastic joint names, in the order of theta."""
    @property
    def contact_frames(self) -> list[str]:
        """Contact frame names."""
    def make_state(
        self,
        q: ArrayLike,
        nu: ArrayLike | None = None,
        theta: ArrayLike | None = None,
        thetadot: ArrayLike | None = None,
        joint_torques: ArrayLike | None = None,
    ) -> Vector:
        """A state; velocities default to 0 and ``theta`` to the springs at rest (``s / eta``),
        or, given ``joint_torques`` (n,), to the preload holding them:
        ``theta = (s + tau / k_s) / eta`` per elastic joint."""
    def split_state(self, x: ArrayLike) -> dict[str, Vector]:
        """``{"q", "theta", "nu", "thetadot"}``."""
    def dynamics(self, x: ArrayLike, u: ArrayLike) -> Vector:
        """dx/dt (nx), quaternion rate included: the right-hand side for scipy."""
    def outputs(self, x: ArrayLike, u: ArrayLike) -> dict[str, Vector | float]:
        """Contact wrenches (n_contacts, 6), joint torques (n), motor torques (n_e),
        drift_position [m], drift_rotation [rad], normal_force, friction_margin, cop_margin
        (per contact, sole frame, negative when violated)."""
    def step(self, x: ArrayLike, u: ArrayLike, dt: float, method: str = "ros2") -> Vector:
        """One step: "ros2" (Rosenbrock-W, order 2, L-stable), "implicit_euler" or "rk4"."""
    def simulate(
        self,
        x0: ArrayLike,
        u: ArrayLike,
        dt: float,
        n_steps: int,
        method: str = "ros2",
        record_every: int = 1,
    ) -> dict[str, object]:
        """Native loop with ``u`` held (GIL released): time, x, contact_wrenches, motor_torques,
        drift_position, drift_rotation, status ("completed" | "diverged"), diverged_at, message.
        Data up to a divergence is kept."""

def run_scenario_native(
    path: str,
    overrides: Mapping[str, object] | None = None,
    mcap: str | None = None,
    progress: bool = False,
) -> dict[str, object]:
    """Runs a TOML scenario natively (GIL released); use ``sea_momentum.run_scenario``."""

# --- Stability analysis (sea_momentum.analysis) ---

def linearize_native(
    path: str,
    t: float | None = None,
    overrides: Mapping[str, object] | None = None,
    sampling: str | None = None,
) -> dict[str, object]:
    """Linearises a scenario's closed loop (GIL released); use ``sea_momentum.linearize``.

    Returns the fields of ``sea_momentum.analysis.Linearization``, complex arrays split into
    ``eigenvalues_re``/``eigenvalues_im`` and ``mode_re``/``mode_im`` (float64, (nd,)),
    ``matrix`` (nd, nd), ``least_stable_rate`` as (re, im)."""

def stability_margin_native(
    path: str,
    parameter: str,
    lower: float,
    upper: float,
    overrides: Mapping[str, object] | None = None,
    method: str = "eigen",
    sampling: str | None = None,
    grid_points: int = 9,
    log_grid: bool = False,
) -> dict[str, object]:
    """Stability boundaries of a scenario key (GIL released); use
    ``sea_momentum.stability_margin``. Returns ``parameter``, ``boundaries`` (ascending),
    ``method``, ``evaluations`` and ``samples`` (list of (value, stable, growth_rate or None))."""

# --- Sweeps (sea_momentum.sweep, sea_momentum.ray_backend) ---

def sweep_grid(
    path: str,
    grid: Sequence[str],
    overrides: Mapping[str, object] | None = None,
) -> dict[str, object]:
    """Parses and checks grid specifications (``KEY=V1,V2,...`` or
    ``KEY=START:STOP:COUNT[:log]``) on a scenario. Returns ``keys`` (list[str]), ``points``
    (list[list[float]], the last key varying fastest) and ``columns`` (the row fields in
    order). Raises ScenarioError naming the key and the value."""

def sweep(
    path: str,
    grid: Sequence[str],
    overrides: Mapping[str, object] | None = None,
    workers: int | None = None,
    progress: bool = False,
) -> dict[str, object]:
    """Runs every point of a grid on ``workers`` threads (None: every core), GIL released;
    use ``sea_momentum.sweep``. Returns ``keys``, ``columns``, ``rows`` (list of dicts in grid
    order: ``index``, the grid values by key, ``status``, ``message``, the summary fields),
    ``total`` and ``interrupted`` (Ctrl-C: the rows done)."""

def sweep_batch(
    path: str,
    keys: Sequence[str],
    points: Sequence[tuple[int, Sequence[float]]],
    overrides: Mapping[str, object] | None = None,
    workers: int | None = 1,
) -> list[dict[str, object]]:
    """Runs the points ``(grid index, values)`` on ``workers`` threads, GIL released (one Ray
    task of ``sea_momentum.ray_backend``). Returns the rows as ``sweep`` does, in the order
    given."""
