"""Typed stub of the native module ``sea_momentum._native``.

Conventions: ``q = [p_B (3, world), quaternion (w, x, y, z), s (n)]`` (``nq = 7 + n``);
``nu = [pdot_B (3, world), omega_B (3, world axes), sdot (n)]`` (``nv = 6 + n``); spatial vectors
linear part first; ``M(q) nudot + h(q, nu) = B tau + sum_k J_k^T f_k``; gravity -9.81 m/s^2 along
world z. Arrays are float64; array-likes are accepted and converted.
"""

import pathlib
from os import PathLike
from typing import Mapping, Sequence, final

import numpy as np
from numpy.typing import ArrayLike, NDArray

# Not re-exported: float64 arrays (shapes in each docstring) and the typed results.
from .arrays import FloatArray
from .results import PlantOutputs, SimulationResult
from .controller import ControlOutput

# The names the module defines (pyo3 fills the module's __all__ as items are added).
__all__ = [
    "SeaError",
    "ModelError",
    "ScenarioError",
    "SolverError",
    "SeaIOError",
    "Model",
    "Plant",
    "Controller",
    "Scenario",
    "run_scenario_native",
    "scenario_urdf",
    "linearize_native",
    "stability_margin_native",
    "push_table_native",
    "template_push_native",
    "sweep_grid",
    "sweep",
    "sweep_batch",
    "init_scenario",
    "link_meshes",
    "cpu_supports_x86_64_v3",
    "__version__",
    "ICUB25_JOINTS",
    "PICTURE_TRIANGLE_BUDGET",
    "MAX_SWEEP_WORKERS",
]

__version__: str
ICUB25_JOINTS: tuple[str, ...]
"""The paper's 25 iCub joints in the original study's order (defined once, in Rust)."""
PICTURE_TRIANGLE_BUDGET: int
"""Default triangles of all the robot's meshes in a picture (``link_meshes``)."""
MAX_SWEEP_WORKERS: int
"""The most threads a local sweep takes (``sweep``'s ``workers``; each is an operating-system
thread)."""

class SeaError(Exception):
    """Base of every sea_momentum error (MCAP logging failures other than I/O raise it as is)."""

class ModelError(SeaError, ValueError):
    """The robot description is unusable: the message names the URDF file, the element and the
    condition, or the file (and line, when known) of a parse failure; also an unknown frame name."""

    element: str
    """The element, e.g. ``"joint 'r_knee'"`` or the unknown frame (not set for parse errors)."""
    filename: str | None
    """The URDF file of an unusable element, ``None`` when the description was given as text (not
    set for parse errors and unknown frames)."""

class ScenarioError(SeaError, ValueError):
    """A scenario value or controller setting breaks a rule (the message names the dotted key,
    the rule and the value, after the file and the key's line when they are known), or a
    scenario file is malformed TOML (file and line)."""

    key: str
    """The dotted key, e.g. ``"controller.postural_scale"`` (not set for TOML syntax errors)."""

class SolverError(SeaError, RuntimeError):
    """A numerical failure on well-formed input: a mass matrix that is not positive definite,
    degenerate contact constraints, a failed factorisation in the implicit step."""

    operation: str
    """What was being computed, e.g. ``"factorising the mass matrix"``."""

class SeaIOError(SeaError, OSError):
    """Reading or writing a file failed; ``errno``, ``strerror`` (e.g. ``"No space left on
    device"``) and ``filename`` are set."""

@final
class Model:
    """A floating-base robot model loaded from URDF, with the buffers of its algorithms.

    The functions of ``nu`` raise ``SolverError`` when their result overflows float64 (e.g.
    ``bias_forces`` at finite velocities of 1e200), instead of returning inf or NaN. Not thread-safe: use one Model per
    thread.
    """

    @staticmethod
    def from_urdf(
        path: str | PathLike[str],
        joints: Sequence[str] | None = None,
        locked: Mapping[str, float] | None = None,
        strict: bool = False,
    ) -> Model:
        """Load a URDF file.

        ``joints`` lists the moving joints in coordinate order (default: every revolute,
        continuous and prismatic joint, depth-first tree order); every other movable joint is
        locked at ``locked[name]`` (default 0). Raises ModelError naming the bad element.
        Physically doubtful inertias (zero mass with inertia, a negative or zero principal
        moment, the triangle inequality violated), moving joints that carry no mass, limits
        with lower above upper (taken as none) and moving joints with a ``<mimic>`` (the
        coupling is not modelled: the joint moves on its own) load with one ``UserWarning``
        each, also kept in ``warnings``; ``strict=True`` raises
        ModelError for them instead.
        """
    @property
    def warnings(self) -> list[str]:
        """What loading found physically doubtful but computable, one message per finding
        naming the link or joint (empty for a clean description)."""
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
    def neutral(self) -> FloatArray:
        """Neutral configuration (nq,): base at the origin, identity orientation, joints at 0."""
    def mass_matrix(self, q: ArrayLike) -> FloatArray:
        """Joint-space inertia matrix M(q), (nv, nv), symmetric."""
    def bias_forces(self, q: ArrayLike, nu: ArrayLike) -> FloatArray:
        """h(q, nu) = C(q, nu) nu + G(q), (nv,)."""
    def gravity_forces(self, q: ArrayLike) -> FloatArray:
        """G(q), (nv,)."""
    def inverse_dynamics(self, q: ArrayLike, nu: ArrayLike, nudot: ArrayLike) -> FloatArray:
        """M(q) nudot + h(q, nu), (nv,)."""
    def frame_pose(self, q: ArrayLike, frame: str) -> FloatArray:
        """world_H_frame, (4, 4)."""
    def frame_jacobian(self, q: ArrayLike, frame: str) -> FloatArray:
        """J_F(q), (6, nv): nu -> [velocity of the frame origin; angular velocity], world axes."""
    def frame_jacobian_dot_v(self, q: ArrayLike, nu: ArrayLike, frame: str) -> FloatArray:
        """Jdot_F nu, (6,): the frame's classical acceleration at nudot = 0, world axes."""
    def com(self, q: ArrayLike) -> FloatArray:
        """Centre of mass in world, (3,)."""
    def com_jacobian(self, q: ArrayLike) -> FloatArray:
        """CoM Jacobian, (3, nv), world axes."""
    def centroidal_momentum_matrix(self, q: ArrayLike) -> FloatArray:
        """A_G(q), (6, nv): H = [m pdot_com; L_com] = A_G nu, world axes, about the CoM."""
    def centroidal_momentum(self, q: ArrayLike, nu: ArrayLike) -> FloatArray:
        """H = [m pdot_com; L_com], (6,)."""
    def centroidal_momentum_bias(self, q: ArrayLike, nu: ArrayLike) -> FloatArray:
        """Adot_G nu, (6,): rate of the centroidal momentum at nudot = 0."""

_ActuatorSpec = str | Mapping[str, float | None]

@final
class Plant:
    """A floating-base robot with series elastic (or rigid) actuators and rigid contacts.

    State ``x = [q (nq), theta (n_e), nu (nv), thetadot (n_e)]``; input ``u`` (n), per joint
    in coordinate order: the joint torque of a rigid joint; for an elastic joint the motor
    torque, or the desired motor velocity when ``motor_velocity_gain`` is set (the motor
    velocity loop ``tau_m = -I_m K_m (thetadot - u) + Gamma tau``, saturated at the torque limit).
    Elastic joint: ``tau = K_S (Gamma theta - s) + K_D (Gamma thetadot - sdot)``,
    ``I_m thetaddot = tau_m - Gamma tau`` (``Gamma``, ``I_m``, ``K_S``, ``K_D``: the actuator's
    ``ratio``, ``motor_inertia``, ``stiffness``, ``damping``). Contacts hold frames at their pose in ``contact_q``
    (Baumgarte ``K_p``, ``K_d``); wrenches are ``[force; moment about the frame origin]``,
    world axes. Not thread-safe: one Plant per thread.
    """

    def __new__(
        cls,
        model: Model,
        *,
        actuator: _ActuatorSpec | None = None,
        actuators: Mapping[str, _ActuatorSpec] | None = None,
        contacts: Sequence[str] | None = None,
        contact_q: ArrayLike | None = None,
        baumgarte_kp: float | None = None,
        baumgarte_kd: float | None = None,
        motor_velocity_gain: float | None = None,
        joint_inertia_regularization: float = 0.0,
        gravity: ArrayLike | None = None,
        friction: float | None = None,
        foot_x: ArrayLike | None = None,
        foot_y: ArrayLike | None = None,
    ) -> Plant:
        """``actuator``: default for every joint, "rigid" (default), "elastic" (the paper's
        iCub SEA: ratio 0.01, motor_inertia 1e-5, stiffness 350, damping 0.25) or a dict of
        those keys plus ``torque_limit`` and ``kind`` (a scenario's actuator table, read the
        same way; with kind "rigid" no other key); ``actuators``: per-joint overrides by name.
        ``contacts``: frame names held at their pose in ``contact_q`` (None: no contacts).
        ``baumgarte_kp``, ``baumgarte_kd``: contact stabilisation gains; None keeps the plant's
        default (the original study's K_p = 50 and K_d = 2 sqrt(K_p), its critical damping).
        ``friction``, ``foot_x``, ``foot_y`` (sole frame [m]): the sole's friction coefficient
        and rectangle for the wrench margins; None keeps the default contact surface (the
        original study's iCub sole: mu 1, x in [-0.05, 0.10], y in [-0.025, 0.025])."""
    @property
    def nx(self) -> int:
        """State size nq + nv + 2 n_e."""
    @property
    def nd(self) -> int:
        """Tangent size 2 nv + 2 n_e."""
    @property
    def nu_input(self) -> int:
        """Input size n, one per joint: the length of the input ``u`` of ``dynamics(x, u)``
        (``u`` for input; not the velocity ``nu``)."""
    @property
    def elastic_joints(self) -> list[str]:
        """Elastic joint names, in the order of theta."""
    @property
    def elastic_parameters(self) -> list[dict[str, float | None]]:
        """The parameters of each elastic joint, in the order of theta: dicts with the keys of
        an actuator table (``ratio``, ``motor_inertia``, ``stiffness``, ``damping``,
        ``torque_limit``, None for no limit), as the scenario resolved them."""
    @property
    def contact_frames(self) -> list[str]:
        """Contact frame names."""
    @property
    def contact_point_counts(self) -> list[int]:
        """The number of points of each contact, in ``contact_frames``' order: the rows of the
        outputs' ``contact_point_*`` arrays, contact by contact. Empty under bilateral
        contacts."""
    def make_state(
        self,
        q: ArrayLike,
        nu: ArrayLike | None = None,
        theta: ArrayLike | None = None,
        thetadot: ArrayLike | None = None,
        joint_torques: ArrayLike | None = None,
    ) -> FloatArray:
        """A state; velocities default to 0 and ``theta`` to the springs at rest (``s / Gamma``),
        or, given ``joint_torques`` (n,), to the preload holding them:
        ``theta = (s + tau / K_S) / Gamma`` per elastic joint."""
    def split_state(self, x: ArrayLike) -> dict[str, FloatArray]:
        """``{"q": (nq,), "theta": (n_e,), "nu": (nv,), "thetadot": (n_e,)}``, float64 copies."""
    def dynamics(self, x: ArrayLike, u: ArrayLike) -> FloatArray:
        """dx/dt (nx), quaternion rate included: the right-hand side for scipy. ``SolverError``
        when a finite but huge state or input (velocities of 1e200) overflows float64."""
    def outputs(self, x: ArrayLike, u: ArrayLike) -> PlantOutputs:
        """The outputs at (x, u), float64: ``contact_wrenches`` (n_contacts, 6), ``joint_torques``
        (n,), ``motor_torques`` (n_e,), ``drift_position`` [m] and ``drift_rotation`` [rad]
        (floats), ``normal_force``, ``friction_margin``, ``cop_margin`` (n_contacts,) each (sole
        frame, negative when violated); under unilateral contacts also each contact point's
        ``contact_point_positions``, ``contact_point_forces`` (n_points, 3) and
        ``contact_point_active`` (n_points,) bool; ``joint_stop_torques`` (n,). ``SolverError``
        as :meth:`dynamics`."""
    def step_outputs(self) -> PlantOutputs:
        """The outputs of the last :meth:`step`: those at its start, with
        ``step_contact_wrenches`` the wrenches the step delivered (under unilateral contacts a
        stiff contact's force follows a new input within the step, so this, not the start's
        ``contact_wrenches``, is what the feet's force/torque sensors read over the step).
        Raises ``RuntimeError`` before any step."""
    def step(
        self,
        x: ArrayLike,
        u: ArrayLike,
        dt: float,
        method: str = "ros2",
        external: Mapping[str, ArrayLike] | None = None,
    ) -> FloatArray:
        """One step: "ros2" (Rosenbrock-W, order 2, L-stable), "implicit_euler" or "rk4".
        A scenario's plant (``Scenario.plant``) lets ``plant.w_refresh_steps`` consecutive
        steps share the implicit step matrix ``W`` prepared at the first one's start (any ``W``
        keeps the order; the native run does the same, so a Python loop reproduces it); a
        plant built with ``Plant(...)`` prepares it at every step.

        ``external``: pushes acting during this step only, ``{link: force (3,) or wrench
        (6,) [force; moment]}`` [N, N m], world axes, at the link frame's origin: a scenario's
        ``[[disturbances]]`` convention, applied by the same code. A link not in the model or
        a wrench of another length or with a non-finite entry raises ``ValueError`` naming it
        (``external['l_hand']``)."""
    def simulate(
        self,
        x0: ArrayLike,
        u: ArrayLike,
        dt: float,
        n_steps: int,
        method: str = "ros2",
        record_every: int | None = None,
    ) -> SimulationResult:
        """Native loop with ``u`` held (GIL released), ``m`` recorded rows (the initial state,
        every ``record_every``-th step, the last one), float64: ``time`` (m,), ``x`` (m, nx),
        ``contact_wrenches`` (m, n_contacts, 6), ``motor_torques`` (m, n_e), ``drift_position``
        (m,), ``drift_rotation`` (m,); ``status`` ("completed" | "diverged" | "fell" | "interrupted"),
        ``diverged_at`` (float or None), ``message``. Data up to a divergence is kept.
        ``n_steps`` (>= 0), ``record_every`` (>= 1; None: every step) and the record's size are
        checked first (``ValueError`` naming the argument, of any size, and giving the memory
        it would need). Ctrl-C raises ``KeyboardInterrupt`` within a fraction of a second; its
        ``partial`` attribute is the result so far (status "interrupted")."""

def run_scenario_native(
    path: str,
    overrides: Mapping[str, object] | None = None,
    mcap: str | None = None,
    progress: bool = False,
    package_dirs: Sequence[str] | None = None,
) -> dict[str, object]:
    """Runs a TOML scenario natively (GIL released); use ``sea_momentum.run_scenario``.
    ``package_dirs`` (existing folders: a missing one or a file raises ``ValueError`` naming
    ``package_dirs``) are searched first for the URDF's ``package://`` meshes of the log.
    ``mcap`` is written as ``.NAME.partial`` beside it and renamed over it when the run ends
    (completed, diverged or interrupted); an error leaves an earlier file untouched.

    Returns float64 arrays (m recorded ticks): ``time`` (m,), ``x`` (m, nx),
    ``thetadot_desired`` (m, n_e), ``com`` (m, 3), ``com_reference`` (m, 3), ``momentum``
    (m, 6), ``contact_wrenches`` (m, n_contacts, 6), ``planned_wrenches`` (m, n_contacts, 6:
    the QP's wrenches at each tick, as ``contact_wrenches``), ``motor_torques`` (m, n_e),
    ``joint_error_norm`` (m,), ``qp_solved`` (m,), ``disturbance_wrench`` (m, 6: the
    ``[[disturbances]]`` acting from each sample on, summed, ``[force; torque]`` world axes,
    each torque about its link's origin), ``external_wrench`` (m, 6: the external wrench the
    controller took, ``[force; moment about the CoM]``); ints ``nq``, ``nv``, ``ne``; name lists
    ``joint_names``, ``elastic_joints``, ``contacts``; under unilateral contacts the contact
    points: ``contact_points`` (list of the number of points of each contact; empty under
    bilateral contacts), ``contact_point_positions`` and ``contact_point_forces`` (m, n_points,
    3: world, the force on the foot), ``contact_point_active`` (m, n_points) bool,
    ``ground_normal`` (3,) the ground's unit normal or None under bilateral contacts;
    ``summary``, the keyword arguments of ``sea_momentum.results.RunSummary``. Ctrl-C stops
    the run at its next tick (the MCAP log is finished) and raises ``KeyboardInterrupt`` whose
    ``partial`` attribute is this dict so far (summary status "interrupted")."""

def scenario_urdf(path: str | PathLike[str], overrides: Mapping[str, object] | None = None) -> pathlib.Path:
    """The URDF file of the scenario file ``path`` with ``overrides``, found as
    ``run_scenario`` finds it: ``robot.urdf`` or the robot description's ``urdf``, a
    ``package://`` / ``file://`` URI resolved (the scenario's ``robot.package_dirs``, then the
    environment's), a relative path from the scenario's folder when it exists there. The robot
    is not built. Raises ScenarioError naming the key."""

def init_scenario(
    urdf: str | PathLike[str],
    contacts: tuple[str, str],
    out: str | PathLike[str],
    foot: tuple[float, float, float, float] | None = None,
    package_dirs: list[str | PathLike[str]] | None = None,
    walking: bool = False,
    walk_check: bool = True,
) -> dict[str, object]:
    """``sea-sim init`` from Python: writes a two-feet balancing scenario (with ``walking`` a
    walk, as ``sea-sim init --walking``) for the robot of
    ``urdf`` (a path or a ``package://`` / ``file://`` URI) standing on ``contacts`` (frame
    names or ``LINK:x,y,z``), the foot rectangle ``foot`` (x0, x1, y0, y1, contact frame, m)
    or measured on the collision geometry; returns ``out``, ``robot``, ``mass``, ``joints``,
    ``foot_x``, ``foot_y``, ``measured``, ``lowering_m``, ``residual``, ``com_offset_m``
    (how far the CoM stands beside the middle of the rectangles' centres: 0, or the lateral
    offset legs without a hip yaw cannot reach), ``feet_rank`` (the
    rank of the two feet's 12 contact constraints: 12 with legs of 6 joints, fewer with
    shorter legs, whose scenario then gets a larger ``controller.pinv_damping``),
    ``warnings``, ``walking_figures`` (``com_height``, ``feet_distance``, ``leg_length``,
    ``reach`` [m]: the standing figures the walking settings scale with) and ``walk_check``:
    ``None`` without ``walking`` or with ``walk_check=False``, else the runs of the written
    walk in order, each a dict of ``com_height``, ``status``, ``reason``, ``duration_s`` (where
    the walk does not complete at the standing CoM height, ``walking.com_height`` is lowered
    by 3 % of it per run, at most 12 %, and the first height that completes is written; the
    standing one when none does). Ctrl-C raises ``KeyboardInterrupt``: before the file is
    written nothing is, during the walk's runs the walk stays written at the standing CoM
    height. A bad ``foot``, a ``urdf`` that cannot be found or read, or ``walk_check=False``
    without ``walking`` raises ``ValueError`` with ``argument`` naming it; contacts the robot
    cannot stand on, or that name no frame or link, ``ScenarioError`` naming the element
    (nothing is written)."""

# --- The robot's meshes (sea_momentum.pictures) ---

def link_meshes(
    urdf: str | PathLike[str],
    package_dirs: Sequence[str | PathLike[str]] | None = None,
    triangle_budget: int = 4000,
    strict: bool = False,
) -> tuple[list[tuple[str, FloatArray, NDArray[np.int64], tuple[float, float, float, float]]], list[str]]:
    """The mesh visuals of a URDF file (STL, OBJ, DAE), decimated to about ``triangle_budget``
    triangles for the whole robot: ``(meshes, warnings)``, ``meshes`` a list of ``(link,
    vertices (n, 3) float64 in the link frame [m], triangles (m, 3) int64, rgba)``, ``warnings``
    one message per mesh not drawn (link, URI, why). ``package://`` URIs are looked up in
    ``package_dirs`` (existing folders, as ``run_scenario_native``'s), then ROS_PACKAGE_PATH,
    AMENT/CMAKE_PREFIX_PATH, the Python environment's cmeel prefix, then above the URDF; a
    mesh's origin or scale that is not finite is a warning. ``strict=True`` raises
    ``ModelError`` instead of warning; an unreadable URDF raises ``SeaIOError`` or
    ``ModelError``."""

def cpu_supports_x86_64_v3() -> bool:
    """Whether this CPU and operating system run the x86-64-v3 build (AVX, AVX2, BMI1/2, F16C,
    FMA, LZCNT, MOVBE, XSAVE and the SSE levels below); always false on other architectures.
    ``sea_momentum`` imports the ``_native_v3`` module where it holds."""

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
    ``integer`` (the key takes whole numbers: each boundary halfway between two),
    ``conclusion`` ("boundaries" | "stable_over_range" | "unstable_over_range"), ``own_value``
    (the scenario's value, or None), ``own_value_stable``, ``stable_island`` ((low, high)
    containing the own value, or None), ``method``, ``evaluations`` and ``samples`` (list of
    (value, stable, growth_rate or None)), ``no_equilibrium`` (list of (value, residual): the
    eigen evaluations where Newton's method found no equilibrium, residual above 1e-3) and
    ``boundaries_beside_no_equilibrium`` (the boundaries next to one of those), and
    ``growth_unchanged`` (the growth rate the same at every one of three or more eigen
    evaluations: the parameter does not enter the linearisation). Ctrl-C stops the scan and
    raises ``KeyboardInterrupt``."""

def push_table_native(
    path: str,
    directions: list[str],
    overrides: Mapping[str, object] | None = None,
    impulses: list[float] | None = None,
    link: str = "root_link",
    start_s: float | None = None,
    duration_s: float = 0.1,
    tolerance_n_s: float = 0.1,
    phase: float | None = None,
    step: int | None = None,
) -> dict[str, object]:
    """The push study (GIL released); use ``sea_momentum.push_table``. Returns ``start_s``
    (the push's start: ``start_s``, 1.0 by default, or the time at ``phase`` of step ``step``'s
    swing, 3 by default), ``rows`` (one
    dict per direction: ``direction``, ``capture_point_impulse_n_s``,
    ``recovered_impulse_n_s``, ``failed_impulse_n_s``, ``pushes`` (list of (impulse, status)),
    ``interrupted``) and ``interrupted``. Ctrl-C returns the rows done."""

def template_push_native(
    path: str,
    directions: list[str],
    phase: float,
    step: int | None = None,
    overrides: Mapping[str, object] | None = None,
    impulses: list[float] | None = None,
    duration_s: float = 0.1,
    tolerance_n_s: float = 0.01,
) -> dict[str, object]:
    """Pushes on a walk's template (GIL released); use ``sea_momentum.template_push_table``
    (``step`` None: the fourth, 3, or the plan's last when it has fewer). Returns ``start_s`` and ``rows`` (one dict per direction: ``direction``,
    ``recovered_impulse_n_s``, ``pushes`` (list of (impulse, recovered); empty when
    bisected))."""

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

# --- The controller and the scenario as objects (sea_momentum.controller) ---

@final
class Controller:
    """The robot's controller stack: the momentum controller with its CoM and postural
    references, and with the scenario's ``[controller]`` keys the joint torque loops
    (``multi_rate``), the stiffness identification and its excitation, and the observers.
    Per period: ``tick(t, x)`` at the measured state ``x = [q, theta, nu, thetadot]``
    (``theta``, ``thetadot``: elastic joints only; a rigid robot has ``x = [q, nu]``), then
    ``inner_tick(x)`` at each joint-loop tick of the period (``multi_rate``), then
    ``end_period(...)`` with the period's force readings. The native loop runs the same stack.
    Not thread-safe."""

    def __new__(
        cls,
        model: Model,
        contacts: Sequence[str],
        q0: ArrayLike,
        *,
        actuators: Mapping[str, object] | None = None,
        reference: Mapping[str, object] | None = None,
        walking: Mapping[str, object] | None = None,
        **settings: object,
    ) -> Controller:
        """A controller for ``model`` on ``contacts`` (stance foot first) held at their pose in
        ``q0`` (nq); postural reference ``q0``'s joints. ``settings``: the keys of a scenario's
        ``[controller]`` table; ``actuators``: the ``[actuators]`` table (default: the paper's
        SEA; ``{"kind": "rigid"}`` for torque control); ``reference``: the ``[reference]``
        table; ``walking``: the ``[walking]`` table (two contacts, the feet; the gait planned
        from their pose in ``q0``, defaults as in a scenario file without
        ``robot.description``: the paper's iCub's, so another robot gives its own keys, e.g.
        those ``sea-sim init`` writes; a command the step limits clip is a ``UserWarning``).
        Checked as in a scenario file (ScenarioError names the key)."""
    @staticmethod
    def from_table(
        model: Model,
        table: Mapping[str, object],
        q0: ArrayLike,
        contacts: Sequence[str],
        actuators: Mapping[str, object] | None = None,
        reference: Mapping[str, object] | None = None,
        walking: Mapping[str, object] | None = None,
    ) -> Controller:
        """``Controller(model, contacts, q0, actuators=..., reference=..., walking=...,
        **table)``."""
    def tick(self, t: float, x: ArrayLike) -> ControlOutput:
        """One whole-body tick at time ``t`` [s] and measured state ``x`` (nx). With
        ``multi_rate`` sampling the joint loops hold the tick's torques (and the
        identification's excitation) and ``input`` is their first inner tick's. A failed tick
        raises ``SolverError``; ``command`` keeps the last command.

        Bad input (docs/guide/robot_rate.md, the per-tick contract): a ``t`` negative or not
        finite, an
        ``x`` of another length, with a NaN or infinite entry or a base quaternion ``x[3:7]``
        not of unit norm raises ``ValueError`` naming it (``x[12]``) and changes nothing. The
        clock is not checked (``t`` is the references' time): a tick called twice at the same
        ``(t, x)`` returns the same command; a late tick evaluates at its own ``t`` and state,
        the estimators skipping the missed periods. A command with a non-finite entry (e.g.
        from an external wrench of 1e308 N) raises ``SolverError`` instead of being returned
        (``multi_rate``: the joint loops keep the last torques, ``command`` the last
        command)."""
    def inner_tick(self, x: ArrayLike) -> FloatArray:
        """``multi_rate`` only: one joint torque loop tick at state ``x`` (nx) between two
        ticks, the plant input (n); ``ValueError`` for another sampling or a bad ``x``,
        ``RuntimeError`` before the first ``tick``."""
    def end_period(
        self,
        start_wrenches: ArrayLike,
        start_joint_torques: ArrayLike,
        end_wrenches: ArrayLike,
        end_joint_torques: ArrayLike,
        *,
        mean_wrenches: ArrayLike | None = None,
    ) -> None:
        """After the period that began at the last ``tick``, before the next: the feet's
        wrenches ((n_contacts, 6) or flat) and the joint torques (n,) at the period's start
        (``Plant.outputs`` at the tick's state and input) and at its end (at the start of the
        period's last plant step). The stiffness identification and the observers update
        from them, acting from the next ``tick``; without them it does nothing.
        ``mean_wrenches``: the feet's wrenches averaged over the period (read at every plant
        step or joint tick), which the external wrench observer then takes instead of the
        two instants (a foot bouncing within the period aliases them).
        ``ValueError`` names a reading of another shape or with a non-finite value (nothing is
        updated); once per period: a second call before the next ``tick``, or one before any
        tick, raises ``RuntimeError``."""
    @property
    def command(self) -> FloatArray:
        """The plant input (n) of the last ``tick`` or ``inner_tick``."""
    @property
    def stiffness_estimates(self) -> dict[str, float]:
        """Stiffness estimates [Nm/rad] by elastic joint: the joint loops' (identified with
        ``controller.stiffness_identification``), or the controller's without joint loops."""
    def set_external_wrench(self, wrench: ArrayLike) -> None:
        """The external wrench (6,: force, moment about the CoM; world axes) [N, Nm] the
        controller's dynamics take as acting on the base from the next ``tick`` on, e.g. an
        estimate of a push; zeros: none. ``ValueError`` for another shape or a non-finite
        value. With the scenario's observer (``controller.external_wrench = "observed"``),
        ``end_period`` replaces it."""
    def set_generalized_disturbance(self, disturbance: ArrayLike) -> None:
        """The generalized disturbance (nv,: base rows force and moment about the base origin
        in world axes, then one per joint) [N, Nm] that the controller's dynamics take from
        the next ``tick`` on (bias forces ``h - d``, its wrench carried by the contacts), e.g.
        an observer's estimate of what the model misses; zeros: none. ``ValueError`` for
        another shape or a non-finite value. With the scenario's observer
        (``controller.external_wrench = "generalized"``), ``end_period`` replaces it."""
    def set_com_offset(self, offset: ArrayLike) -> None:
        """The robot's CoM less the model's (3,: world) [m] that the CoM position error of the
        next ``tick``s takes (the momentum and its map stay the model's), e.g. an observer's
        estimate of where the robot's CoM is when the model's masses are off; zeros: none.
        ``ValueError`` for another shape or a non-finite value. With the scenario's observer
        (``controller.external_wrench = "generalized"``), ``end_period`` replaces it."""
    def com_reference(self, t: float) -> FloatArray:
        """The CoM reference at ``t`` [s], (3,) world [m]; ``ValueError`` for a ``t`` negative
        or not finite."""
    @property
    def kind(self) -> str:
        """"sea" or "rigid": ``controller.kind``. On a robot whose every joint is rigid
        (``actuators={"kind": "rigid"}``) both laws give the same command: the SEA law's
        additions act on elastic joints only."""
    @property
    def contacts(self) -> list[str]:
        """Contact frames, the rows of ``ControlOutput.wrenches``."""
    @property
    def joint_names(self) -> list[str]:
        """Joint names in coordinate order."""
    @property
    def nx(self) -> int:
        """Size of the state ``tick`` reads."""
    @property
    def qp_failures(self) -> int:
        """QP solves so far that fell back to the unconstrained solution."""

@final
class Scenario:
    """A scenario file built as ``run_scenario`` builds it. With zero-order-hold sampling, the
    run is ``out = controller.tick(k * control_period, x)`` then ``steps_per_tick`` times
    ``x = plant.step(x, out.input, plant_dt, method)``, from ``initial_state``; with
    ``multi_rate`` the input is renewed by ``controller.inner_tick(x)`` before every step ``j > 0``
    of the period with ``j % steps_per_inner_tick == 0``; after the period,
    ``controller.end_period`` with ``plant.outputs`` at the first and the last step's start
    runs the identification and the observers."""

    @staticmethod
    def load(path: str | PathLike[str], overrides: Mapping[str, object] | None = None) -> Scenario:
        """Builds the scenario file ``path`` with ``overrides`` ({"controller.kind": "rigid"}).
        A walking command the step limits clip is a ``UserWarning`` naming the keys, and so is
        each URDF element the model doubts (as ``Model.from_urdf`` warns, not point masses)."""
    @property
    def name(self) -> str:
        """The scenario's name."""
    @property
    def model(self) -> Model:
        """The robot model."""
    @property
    def plant(self) -> Plant:
        """The plant, configured as the scenario says (its steps share ``W`` as
        ``plant.w_refresh_steps`` says, counted from its first step)."""
    @property
    def controller(self) -> Controller:
        """The controller with the scenario's references."""
    @property
    def initial_state(self) -> FloatArray:
        """(nx,) initial state: at rest, springs preloaded."""
    @property
    def plant_dt(self) -> float:
        """Plant step [s]."""
    @property
    def control_period(self) -> float:
        """Time between two ticks [s]."""
    @property
    def steps_per_tick(self) -> int:
        """Plant steps per tick."""
    @property
    def steps_per_inner_tick(self) -> int:
        """Plant steps per joint-loop tick (``multi_rate``; else ``steps_per_tick``)."""
    @property
    def last_tick(self) -> int:
        """Index of the last tick (duration / control_period)."""
    @property
    def sampling(self) -> str:
        """"zero_order_hold", "continuous" or "multi_rate" (``Controller.inner_tick`` runs its
        joint loops; the stiffness identification and its excitation run in the native run
        only)."""
    @property
    def method(self) -> str:
        """The plant's integrator (``Plant.step``'s ``method``)."""
    @property
    def duration(self) -> float:
        """``simulation.duration_s`` [s]."""
