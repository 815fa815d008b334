"""Self-consistency checks of the dynamics on random states (no reference library needed).

Each identity is measured as a norm-relative error ``|a - b| / max(1, |b|)``:

- ``M`` symmetric positive definite; ``M nudot + h = inverse_dynamics(q, nu, nudot)``;
- ``H = A_G nu``; linear momentum ``= m J_com nu``;
- frame Jacobian: ``J nu`` equals finite differences of the frame pose along
  ``q(t) = q (+) nu t``; ``J_com nu`` equals finite differences of the CoM.
"""

from __future__ import annotations

import pathlib

import numpy as np

from ._native import Model
from .arrays import FloatArray

TOLERANCE = 1e-6


def default_urdf() -> pathlib.Path:
    """The iCub model shipped in the repository, relative to its root (``urdf/icub25.urdf``)."""
    return pathlib.Path("urdf") / "icub25.urdf"


def integrate(model: Model, q: FloatArray, nu: FloatArray, dt: float) -> FloatArray:
    """``q (+) nu dt``: base translation, world-axes rotation on the left, joints."""
    out = q.copy()
    out[:3] += nu[:3] * dt
    phi = nu[3:6] * dt
    angle = np.linalg.norm(phi)
    half = 0.5 * angle
    axis_part = phi * (np.sin(half) / angle if angle > 1e-12 else 0.5)
    dq = np.array([np.cos(half), *axis_part])
    w0, x0, y0, z0 = dq
    w1, x1, y1, z1 = q[3:7]
    out[3:7] = [
        w0 * w1 - x0 * x1 - y0 * y1 - z0 * z1,
        w0 * x1 + x0 * w1 + y0 * z1 - z0 * y1,
        w0 * y1 - x0 * z1 + y0 * w1 + z0 * x1,
        w0 * z1 + x0 * y1 - y0 * x1 + z0 * w1,
    ]
    out[3:7] /= np.linalg.norm(out[3:7])
    out[7:] += nu[6:] * dt
    return out


def _relative(a: FloatArray, b: FloatArray) -> float:
    """``|a - b| / max(1, |b|)``."""
    return float(np.linalg.norm(a - b) / max(1.0, float(np.linalg.norm(b))))


def _rotation_log(r: FloatArray) -> FloatArray:
    """The rotation vector of the rotation matrix ``r`` (SO(3) logarithm)."""
    angle = np.arccos(np.clip((np.trace(r) - 1.0) / 2.0, -1.0, 1.0))
    w = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    return w * (0.5 if angle < 1e-12 else angle / (2.0 * np.sin(angle)))


def dynamics_check(urdf: str | pathlib.Path, n_states: int = 20, seed: int = 0) -> dict:
    """Runs every identity on ``n_states`` random states; returns a JSON-ready report."""
    model = Model.from_urdf(urdf)
    rng = np.random.default_rng(seed)
    errors: dict[str, float] = {}

    def record(name: str, value: float) -> None:
        errors[name] = max(errors.get(name, 0.0), value)

    frames: list[str] = [f for f in ("l_sole", "r_sole", "root_link") if f in model.frame_names]
    frames = frames or model.frame_names[-1:]
    eps = 1e-6
    for _ in range(n_states):
        quat = rng.normal(size=4)
        q = np.concatenate([rng.uniform(-1, 1, 3), quat / np.linalg.norm(quat),
                            rng.uniform(-1, 1, model.n_joints)])
        nu, nudot = rng.normal(size=model.nv), rng.normal(size=model.nv)
        mass = model.mass_matrix(q)
        record("mass_matrix_symmetry", _relative(mass, mass.T))
        record("mass_matrix_positive_definite", 0.0 if np.linalg.eigvalsh(mass).min() > 0 else 1.0)
        tau = model.inverse_dynamics(q, nu, nudot)
        record("inverse_dynamics", _relative(mass @ nudot + model.bias_forces(q, nu), tau))
        momentum = model.centroidal_momentum(q, nu)
        record("centroidal_momentum", _relative(model.centroidal_momentum_matrix(q) @ nu, momentum))
        record("linear_momentum", _relative(model.total_mass * model.com_jacobian(q) @ nu, momentum[:3]))
        q_plus, q_minus = integrate(model, q, nu, eps), integrate(model, q, nu, -eps)
        com_rate = (model.com(q_plus) - model.com(q_minus)) / (2 * eps)
        record("com_jacobian", _relative(model.com_jacobian(q) @ nu, com_rate))
        for frame in frames:
            plus, minus = model.frame_pose(q_plus, frame), model.frame_pose(q_minus, frame)
            velocity = np.concatenate([(plus[:3, 3] - minus[:3, 3]) / (2 * eps),
                                       _rotation_log(plus[:3, :3] @ minus[:3, :3].T) / (2 * eps)])
            record("frame_jacobian", _relative(model.frame_jacobian(q, frame) @ nu, velocity))
    failed = [k for k, v in errors.items() if not v <= TOLERANCE]
    return {
        "urdf": str(urdf),
        "nv": model.nv,
        "total_mass_kg": model.total_mass,
        "states": n_states,
        "tolerance": TOLERANCE,
        "max_relative_error": errors,
        "passed": len(errors) - len(failed),
        "failed": len(failed),
        "failures": failed,
    }
