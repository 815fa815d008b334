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
