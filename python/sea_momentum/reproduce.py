"""Reproduces the paper's three experiments (section "Simulation results") on the iCub, in the
paper's setting, and explains every outcome with the closed loop's linearisation.

The paper's setting is continuous control: its controller runs inside ode15s's right-hand side,
so the scenarios of ``scenarios/paper`` use ``controller.sampling = "continuous"``. Every
experiment is also run with the controller sampled at 1 kHz with zero-order hold (one 1 ms
plant step per tick, the setting of the earlier results), and the stability map covers the
sampled-data loop from 100 Hz to 10 kHz.

Writes to ``out``:

- ``figure1_tracking_damping.png``: lateral CoM error for controller damping estimates x1.0,
  x1.45, x1.6, x0.4 (continuous);
- ``figure2_rigid_vs_sea.png``: joint error norm after the 1 degree upper-body step, rigid and
  SEA controllers (continuous);
- ``figure3_saturation.png``: stance ankle roll motor velocity with the springs at rest at the
  start, with and without the 0.34 Nm limit (continuous);
- ``stability_map.png``: damping estimate scale against control rate (and continuous): stable
  or not and the CoM error from a sweep, with the eigenvalue boundary drawn over it;
- ``growth_rate_damping.png``: growth rate of the least stable mode against the damping
  estimate scale (continuous, and 1 kHz for contrast), the paper's x0.4, x1.45, x1.6 marked;
- one MCAP log per paper scenario, ``summary.json`` and ``outcomes.md`` (each experiment: the
  paper's outcome, ours in the paper's setting and at 1 kHz, and the evidence for every
  disagreement, all computed by this run).
"""

from __future__ import annotations

import dataclasses
import json
import pathlib
import sys
import time as clock
from typing import Any

import numpy as np

from .analysis import Linearization, linearize, stability_margin
from .scenario import ScenarioResult, run_scenario
from .sweep import sweep

#: Damping estimate scales of the paper's Figure 1, the nominal first.
DAMPING_SCALES = (1.0, 1.45, 1.6, 0.4)
#: The sampled-data setting of the earlier results: 1 kHz zero-order hold, 1 ms plant step.
SAMPLED_1KHZ = {"controller.sampling": "zero_order_hold", "controller.rate_hz": 1000.0, "plant.dt": 1e-3}
#: Zero-order hold at the scenario's own (accurate) plant step: the stability map's setting.
ZERO_ORDER_HOLD = {"controller.sampling": "zero_order_hold"}
#: Stability map axes: damping estimate scales and control rates [Hz] (log spaced).
MAP_SCALES = tuple(float(v) for v in np.geomspace(0.2, 3.0, 8))
MAP_RATES_HZ = tuple(float(v) for v in np.geomspace(100.0, 10_000.0, 7))
#: Simulated time of one stability-map run [s]: unstable settings diverge well before.
MAP_DURATION_S = 3.0
#: Damping estimate scales of the growth-rate curve.
GROWTH_SCALES = tuple(sorted({*(float(v) for v in np.geomspace(0.2, 3.0, 17)), 0.4, 1.0, 1.45, 1.6}))
#: The stance ankle roll and its motor torque limit of the saturation experiment [Nm].
SATURATED_JOINT = "l_ankle_roll"
TORQUE_LIMIT_NM = 0.34
#: A mode whose angular frequency exceeds this [rad/s] is an SEA mode (the balancing modes
#: are slower than 10 rad/s, the SEA modes faster than 280 rad/s for scales up to 3).
SEA_MODE_MIN_FREQUENCY = 200.0
#: The paper's outcomes, by experiment.
PAPER = {
    "tracking x1.0": "stable, CoM error a few mm",
    "tracking x1.45": "stable (error does not grow)",
    "tracking x1.6": "unstable",
    "tracking x0.4": "stable",
    "step, rigid controller": "unstable",
    "step, SEA controller": "converges",
    "saturation 0.34 Nm": "stable, ~50 rad/s initial motor velocity peak, slower convergence",
}


def _log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def _stable(result: ScenarioResult) -> bool:
    return result.status == "completed"


def _outcome(result: ScenarioResult) -> str:
    """``completed`` or ``diverged at T s``."""
    s = result.summary
    return s.status + ("" if s.diverged_at_s is None else f" at {s.diverged_at_s:.2f} s")


@dataclasses.dataclass
class Session:
    """Where the scenarios are, where the outputs go, and the runs' common overrides."""

    scenario_dir: pathlib.Path
    out: pathlib.Path
    duration: float | None
    started: float = dataclasses.field(default_factory=clock.perf_counter)

    def path(self, name: str) -> pathlib.Path:
        return self.scenario_dir / f"{name}.toml"

    def say(self, message: str) -> None:
        _log(f"[{clock.perf_counter() - self.started:6.1f} s] {message}")

    def run(self, name: str, overrides: dict | None = None, mcap: str | None = None) -> ScenarioResult:
        """One scenario run; ``duration`` (if given) overrides every run's length."""
        merged = {**(overrides or {})}
        if self.duration is not None:
            merged["simulation.duration_s"] = self.duration
        self.say(f"{name} {merged or ''}")
        result = run_scenario(self.path(name), merged, mcap=None if mcap is None else self.out / mcap)
        s = result.summary
        _log(f"          -> {_outcome(result)} ({s.sampling}, CoM error rms {s.com_error_rms_m * 1e3:.2f} mm)")
        return result


# ---- Runs ----


def _damping(scale: float) -> dict:
    return {"controller.damping_estimate_scale": scale}


def run_experiments(session: Session, setting: dict, logs: bool) -> dict[str, ScenarioResult]:
    """The paper's experiments with ``setting`` on top of their files; MCAP logs if ``logs``."""
    runs: dict[str, ScenarioResult] = {}
    for scale in DAMPING_SCALES:
        mcap = "tracking.mcap" if logs and scale == 1.0 else None
        runs[f"tracking x{scale}"] = session.run("tracking", {**setting, **_damping(scale)}, mcap)
    for kind, label in (("rigid", "step, rigid controller"), ("sea", "step, SEA controller")):
        runs[label] = session.run(f"step_{kind}", setting, f"step_{kind}.mcap" if logs else None)
    # Every sample, so the short time at the limit is resolved.
    every = {**setting, "simulation.record_every": 1}
    runs["saturation 0.34 Nm"] = session.run("saturation", every, "saturation.mcap" if logs else None)
    return runs


def run_saturation_references(session: Session) -> dict[str, ScenarioResult]:
    """The saturation experiment's two references: springs at rest without the limit (the
    tracking scenario), and the limit with preloaded springs (where it never binds)."""
    every = {"simulation.record_every": 1}
    return {
        "at rest, no limit": session.run("tracking", {**every, "robot.initial_springs": "at_rest"}),
        "preloaded, 0.34 Nm": session.run("saturation", {**every, "robot.initial_springs": "preloaded"}),
    }


def saturation_figures(result: ScenarioResult) -> dict[str, float]:
    """Peak motor velocity, peak torque and time at the limit of the saturated joint."""
    k = result.motor(SATURATED_JOINT)
    torque = np.abs(result.motor_torques[:, k])
    at_limit = torque >= TORQUE_LIMIT_NM - 1e-9
    sample = float(result.time[1] - result.time[0])
    return {
        "peak_motor_velocity_rad_s": float(np.abs(result.thetadot[:, k]).max()),
        "peak_motor_torque_nm": float(torque.max()),
        "time_at_limit_s": float(at_limit.sum() * sample),
        "last_time_at_limit_s": float(result.time[at_limit][-1]) if at_limit.any() else None,
    }


#: Motor velocity [rad/s] below which the saturated joint's start transient counts as settled
#: (the CoM motion itself needs about 1 rad/s at the motor).
SETTLED_MOTOR_VELOCITY = 5.0


def settling_time(result: ScenarioResult) -> float:
    """Last time [s] the saturated joint's motor velocity exceeds ``SETTLED_MOTOR_VELOCITY``."""
    k = result.motor(SATURATED_JOINT)
    fast = np.abs(result.thetadot[:, k]) > SETTLED_MOTOR_VELOCITY
    return float(result.time[fast][-1]) if fast.any() else 0.0


# ---- Linearisation evidence ----


def sea_modes(lin: Linearization) -> np.ndarray:
    """The SEA modes of a continuous-time linearisation (one oscillatory pair per joint)."""
    rates = lin.eigenvalues if lin.sampling == "continuous" else np.log(lin.eigenvalues.astype(complex)) / lin.control_period
    return rates[np.abs(rates.imag) > SEA_MODE_MIN_FREQUENCY]


def describe(lin: Linearization) -> dict[str, Any]:
    """What outcomes.md and summary.json say about one linearisation."""
    modes = sea_modes(lin)
    rate = lin.least_stable_rate
    return {
        "sampling": lin.sampling,
        "control_period_s": lin.control_period,
        "growth_rate_1_s": lin.growth_rate,
        "stable": lin.stable,
        "least_stable_frequency_rad_s": abs(rate.imag),
        "dominant_states": [(name, round(weight, 3)) for name, weight in lin.dominant_states[:4]],
        "sea_mode_real_min_max_1_s": [float(modes.real.min()), float(modes.real.max())] if modes.size else None,
        "sea_mode_frequency_min_max_rad_s": [float(np.abs(modes.imag).min()), float(np.abs(modes.imag).max())] if modes.size else None,
    }


def linearization_evidence(session: Session) -> dict[str, dict]:
    """The linearisations behind the outcomes: each Figure 1 scale in continuous time, x0.4 at
    1 kHz, and the rigid controller after the step (continuous)."""
    tracking = session.path("tracking")
    evidence = {}
    for scale in DAMPING_SCALES:
        session.say(f"linearize tracking x{scale}, continuous")
        evidence[f"continuous x{scale}"] = describe(linearize(tracking, overrides=_damping(scale)))
    session.say("linearize tracking x0.4, 1 kHz zero-order hold, dt 1 ms")
    evidence["1 kHz x0.4"] = describe(linearize(tracking, overrides={**SAMPLED_1KHZ, **_damping(0.4)}))
    session.say("linearize step_rigid after the step, continuous")
    evidence["rigid after the step"] = describe(linearize(session.path("step_rigid"), t=1.0))
    return evidence


def margin_evidence(session: Session) -> dict[str, list[float]]:
    """Eigenvalue stability boundaries: the damping estimate scale in continuous time and at
    1 kHz (1 ms and the scenario's 0.25 ms plant step), and the control rate at x1.0."""
    tracking = session.path("tracking")
    scale = "controller.damping_estimate_scale"
    cases = {
        "damping scale 0.2-3, continuous": (scale, 0.2, 3.0, {}),
        "damping scale 0.2-3, 1 kHz, dt 1 ms": (scale, 0.2, 3.0, SAMPLED_1KHZ),
        "damping scale 0.2-3, 1 kHz, dt 0.25 ms": (scale, 0.2, 3.0, {**ZERO_ORDER_HOLD, "controller.rate_hz": 1000.0}),
        "control rate 100 Hz-10 kHz at x1.0, dt 0.25 ms": ("controller.rate_hz", 100.0, 10_000.0, ZERO_ORDER_HOLD),
    }
    margins = {}
    for label, (key, lower, upper, overrides) in cases.items():
        session.say(f"stability margin: {label}")
        margins[label] = stability_margin(tracking, key, lower, upper, overrides, log_grid=True)
    return margins


def growth_rate_curve(session: Session) -> dict[str, list[float]]:
    """Growth rate of the least stable mode and the SEA modes' decay against the damping
    estimate scale, in continuous time and at 1 kHz (dt 0.25 ms)."""
    tracking = session.path("tracking")
    session.say(f"growth rate curve: {len(GROWTH_SCALES)} damping scales, continuous and 1 kHz")
    curve: dict[str, list[float]] = {"scale": list(GROWTH_SCALES), "continuous": [], "sea_decay": [], "1 kHz": []}
    for scale in GROWTH_SCALES:
        lin = linearize(tracking, overrides=_damping(scale))
        curve["continuous"].append(lin.growth_rate)
        curve["sea_decay"].append(float(sea_modes(lin).real.max()))
        held = linearize(tracking, overrides={**ZERO_ORDER_HOLD, "controller.rate_hz": 1000.0, **_damping(scale)})
        curve["1 kHz"].append(held.growth_rate)
    return curve


# ---- Stability map ----


@dataclasses.dataclass
class StabilityMap:
    """Sweep outcomes on the (damping scale, control rate) grid plus the continuous column,
    and the eigenvalue boundary rate at each scale (None: stable over the whole rate range)."""

    scales: tuple[float, ...]
    rates_hz: tuple[float, ...]
    stable: np.ndarray  # (scales, rates + 1): the last column is continuous
    com_error_rms_m: np.ndarray  # same shape, NaN where the run diverged
    boundary_rate_hz: list[float | None]
    diverged_at_s: np.ndarray  # same shape, NaN where the run completed
    duration_s: float
    wall_time_s: float


def stability_map(session: Session) -> StabilityMap:
    """The sweeps (2 workers) and, per damping scale, the eigenvalue margin over the rate."""
    started = clock.perf_counter()
    tracking = session.path("tracking")
    duration = MAP_DURATION_S if session.duration is None else min(MAP_DURATION_S, session.duration)
    short = {"simulation.duration_s": duration}
    session.say(f"stability map: {len(MAP_SCALES)} x {len(MAP_RATES_HZ)} sampled + {len(MAP_SCALES)} continuous runs of {duration} s")
    held = sweep(tracking, {"controller.damping_estimate_scale": list(MAP_SCALES), "controller.rate_hz": list(MAP_RATES_HZ)},
                 overrides={**ZERO_ORDER_HOLD, **short}, workers=2)
    continuous = sweep(tracking, {"controller.damping_estimate_scale": list(MAP_SCALES)}, overrides=short, workers=2)
    shape = (len(MAP_SCALES), len(MAP_RATES_HZ))
    stable = np.column_stack([held.stable.reshape(shape), continuous.stable])
    error = np.column_stack([held["com_error_rms_m"].reshape(shape), continuous["com_error_rms_m"]])
    diverged_at = np.column_stack([held["diverged_at_s"].reshape(shape), continuous["diverged_at_s"]])
    boundaries: list[float | None] = []
    for scale in MAP_SCALES:
        found = stability_margin(tracking, "controller.rate_hz", MAP_RATES_HZ[0], MAP_RATES_HZ[-1],
                                 {**ZERO_ORDER_HOLD, **_damping(scale)}, grid_points=7, log_grid=True)
        boundaries.append(found[-1] if found else None)
    session.say(f"stability map done: boundaries {[None if b is None else round(b) for b in boundaries]} Hz")
    return StabilityMap(MAP_SCALES, MAP_RATES_HZ, stable, np.where(stable, error, np.nan), boundaries,
                        diverged_at, duration, clock.perf_counter() - started)


# ---- Figures ----


def _save(fig: Any, path: pathlib.Path) -> None:
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def figure_tracking(runs: dict[str, ScenarioResult], path: pathlib.Path) -> None:
    """Figure 1: lateral CoM error for each damping estimate (paper's setting)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    styles = {1.0: "-", 1.45: "--", 1.6: "-.", 0.4: ":"}
    for scale in DAMPING_SCALES:
        result = runs[f"tracking x{scale}"]
        error_mm = (result.com[:, 1] - result.com_reference[:, 1]) * 1e3
        suffix = "" if _stable(result) else f" (diverged at {result.summary.diverged_at_s:.2f} s)"
        ax.plot(result.time, error_mm, styles[scale], label=f"K_D estimate x{scale}{suffix}")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("lateral CoM error [mm]")
    ax.set_title("Figure 1: CoM tracking on one foot, damping mismatch (continuous control)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    _save(fig, path)


def figure_step(runs: dict[str, ScenarioResult], path: pathlib.Path) -> None:
    """Figure 2: joint error norm after the step, rigid and SEA controllers."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    for label in ("step, SEA controller", "step, rigid controller"):
        result = runs[label]
        ax.plot(result.time, result.joint_error_norm, label=f"{label.split(', ')[1]} ({_outcome(result)})")
    # The rigid controller's divergence ends far above: keep the converged level readable.
    ax.set_ylim(0.0, 3.0 * float(np.max(runs["step, SEA controller"].joint_error_norm)))
    ax.set_xlabel("time [s]")
    ax.set_ylabel("joint position error norm [rad]")
    ax.set_title("Figure 2: 1 degree step on torso and arms, SEA robot (continuous control)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    _save(fig, path)


def figure_saturation(runs: dict[str, ScenarioResult], path: pathlib.Path) -> None:
    """Figure 3: the saturated joint's motor velocity, whole run and the first 0.3 s."""
    import matplotlib.pyplot as plt

    fig, (whole, start) = plt.subplots(2, 1, figsize=(7, 6))
    curves = (
        ("at rest, no limit", "g--", "springs at rest, no limit"),
        ("saturation 0.34 Nm", "r-", f"springs at rest, |tau_m| <= {TORQUE_LIMIT_NM} Nm"),
        ("preloaded, 0.34 Nm", "b:", f"springs preloaded, |tau_m| <= {TORQUE_LIMIT_NM} Nm"),
    )
    for key, style, label in curves:
        result = runs[key]
        k = result.motor(SATURATED_JOINT)
        for ax in (whole, start):
            ax.plot(result.time, result.thetadot[:, k], style, lw=1.0, label=label)
    limited = runs["saturation 0.34 Nm"]
    k = limited.motor(SATURATED_JOINT)
    start.plot(limited.time, limited.thetadot_desired[:, k], "k-", lw=0.6, label="reference (limited run)")
    start.set_xlim(0.0, 0.1)
    peak = max(np.abs(runs[key].thetadot[:, runs[key].motor(SATURATED_JOINT)]).max() for key, _, _ in curves)
    start.set_ylim(-1.3 * peak, 1.3 * peak)  # the reference's first swing is larger: cut
    for ax in (whole, start):
        ax.set_xlabel("time [s]")
        ax.set_ylabel(f"{SATURATED_JOINT} motor velocity [rad/s]")
        ax.grid(True, alpha=0.3)
    whole.set_title("Figure 3: torque saturation of the stance ankle roll (continuous control)")
    start.set_title("the first 0.1 s: the springs load")
    start.legend(fontsize=8)
    _save(fig, path)


def _edges(centres: np.ndarray) -> np.ndarray:
    """Cell edges around equally spaced centres."""
    step = centres[1] - centres[0]
    return np.concatenate([centres - step / 2, [centres[-1] + step / 2]])


def figure_stability_map(grid: StabilityMap, path: pathlib.Path) -> None:
    """Stable or not and the CoM error on (control rate, damping scale), log10 axes, the
    continuous setting as the last column, the eigenvalue boundary rate drawn over it."""
    import matplotlib.pyplot as plt

    log_rates = np.log10(grid.rates_hz)
    x = np.append(log_rates, log_rates[-1] + (log_rates[1] - log_rates[0]))  # + continuous
    y = np.log10(grid.scales)
    fig, ax = plt.subplots(figsize=(8, 5))
    cmap = plt.get_cmap("viridis").with_extremes(bad="lightgrey")  # diverged runs
    error_mm = np.ma.masked_invalid(grid.com_error_rms_m * 1e3)
    mesh = ax.pcolormesh(_edges(x), _edges(y), error_mm, cmap=cmap, shading="flat")
    fig.colorbar(mesh, ax=ax, label="CoM error rms [mm] (stable runs)")
    for row, col in zip(*np.nonzero(~grid.stable)):
        ax.text(x[col], y[row], f"{grid.diverged_at_s[row, col]:.2f} s", ha="center", va="center", fontsize=7)
    found = [(np.log10(b), ys) for b, ys in zip(grid.boundary_rate_hz, y) if b is not None]
    if found:
        bx, by = zip(*found)
        ax.plot(bx, by, "-o", color="crimson", lw=2, ms=4, label="eigenvalue boundary rate (zero-order hold)")
    ax.axvline((x[-1] + x[-2]) / 2, color="k", lw=1)
    ax.set_xticks(x, [f"{r:.0f}" for r in grid.rates_hz] + ["contin-\nuous"])
    ax.set_yticks(y, [f"x{s:.2f}" for s in grid.scales])
    ax.set_xlabel("control rate [Hz] (zero-order hold, plant step <= 0.25 ms)")
    ax.set_ylabel("damping estimate scale")
    ax.set_title(f"Stability map of the SEA controller (tracking, {grid.duration_s:g} s runs;\n"
                 "grey: diverged, at the time written)")
    ax.legend(loc="lower right", fontsize=8, framealpha=0.9)
    _save(fig, path)


def matplotlib_null_formatter() -> Any:
    """No labels on minor ticks (the major ticks name the scales)."""
    from matplotlib.ticker import NullFormatter

    return NullFormatter()


def figure_growth_rate(curve: dict[str, list[float]], path: pathlib.Path) -> None:
    """Growth rate of the least stable mode against the damping scale; the paper's scales."""
    import matplotlib.pyplot as plt

    fig, (slow, fast) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    scale = np.array(curve["scale"])
    slow.plot(scale, curve["continuous"], "b-o", ms=3, label="continuous (the paper's setting)")
    slow.set_ylabel("growth rate [1/s]")
    slow.set_title("Least stable mode of the linearised closed loop (tracking)")
    fast.plot(scale, curve["sea_decay"], "g-s", ms=3, label="SEA modes' real part, continuous")
    fast.plot(scale, curve["1 kHz"], "r-^", ms=3, label="least stable mode, 1 kHz zero-order hold (dt 0.25 ms)")
    fast.set_ylabel("rate [1/s]")
    fast.set_xlabel("damping estimate scale")
    paper = {0.4: "stable", 1.45: "stable", 1.6: "unstable"}
    for ax in (slow, fast):
        ax.axhline(0.0, color="k", lw=0.8)
        for value, verdict in paper.items():
            ax.axvline(value, color="grey", ls="--", lw=0.8)
        ax.set_xscale("log")
        ax.set_xticks([0.2, 0.3, 0.4, 0.6, 1.0, 1.45, 2.0, 3.0], ["0.2", "0.3", "0.4", "0.6", "1", "1.45", "2", "3"])
        ax.xaxis.set_minor_formatter(matplotlib_null_formatter())
        ax.grid(True, alpha=0.3, which="both")
        ax.legend(fontsize=8)
    for value, verdict in paper.items():
        slow.annotate(f"x{value}: paper {verdict}", (value, 1.0), xycoords=("data", "axes fraction"),
                      rotation=90, va="top", ha="right", fontsize=8)
    _save(fig, path)


# ---- Outcomes ----

#: Whether the paper found each experiment stable (completed).
PAPER_STABLE = {
    "tracking x1.0": True,
    "tracking x1.45": True,
    "tracking x1.6": False,
    "tracking x0.4": True,
    "step, rigid controller": False,
    "step, SEA controller": True,
    "saturation 0.34 Nm": True,
}


def _verdict(label: str, result: ScenarioResult) -> str:
    return "agrees" if _stable(result) == PAPER_STABLE[label] else "**disagrees**"


def outcome_table(paper_setting: dict[str, ScenarioResult], sampled: dict[str, ScenarioResult]) -> list[str]:
    """One row per experiment: the paper, ours in both settings, whether they agree."""
    lines = [
        "| experiment | paper | ours, continuous (paper's setting) | ours, 1 kHz zero-order hold, dt 1 ms "
        "| CoM error rms / max [mm] (continuous) | motor velocity peak [rad/s] (continuous) |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for label, paper in PAPER.items():
        ours, held = paper_setting[label], sampled[label]
        s = ours.summary
        lines.append(
            f"| {label} | {paper} | {_outcome(ours)} ({_verdict(label, ours)}) | {_outcome(held)} "
            f"({_verdict(label, held)}) | {s.com_error_rms_m * 1e3:.2f} / {s.com_error_max_m * 1e3:.2f} "
            f"| {s.motor_velocity_peak_rad_s:.0f} |"
        )
    return lines


def _mode(d: dict) -> str:
    """A linearisation in one phrase: growth, frequency, dominant states."""
    states = ", ".join(f"{name} ({weight})" for name, weight in d["dominant_states"])
    frequency = d["least_stable_frequency_rad_s"]
    kind = "a real mode" if frequency < 1e-6 else f"{frequency:.1f} rad/s"
    return f"growth rate {d['growth_rate_1_s']:+.3f} 1/s ({kind}), dominated by {states}"


def _sea(d: dict) -> str:
    low, high = d["sea_mode_real_min_max_1_s"]
    f_low, f_high = d["sea_mode_frequency_min_max_rad_s"]
    return f"SEA modes at Re {low:.1f} .. {high:.1f} 1/s, {f_low:.0f} .. {f_high:.0f} rad/s"


def _boundaries(values: list[float], unit: str = "") -> str:
    return "none (stability never changes)" if not values else ", ".join(f"{v:.3g}{unit}" for v in values)


def damping_evidence(evidence: dict, margins: dict, curve: dict) -> list[str]:
    """The damping-mismatch paragraphs: x0.4 (sampling) and x1.6 (over-estimation)."""
    c04, c16, c10, h04 = (evidence[k] for k in ("continuous x0.4", "continuous x1.6", "continuous x1.0", "1 kHz x0.4"))
    rates = np.array(curve["continuous"])
    return [
        "### K_D estimate x0.4 (paper: stable)",
        "",
        f"- Continuous (paper's setting): stable. Least stable mode: {_mode(c04)}; {_sea(c04)}.",
        f"- 1 kHz zero-order hold, dt 1 ms: least stable mode {_mode(h04)}. The controller commands the "
        "spring deflection rate through its damping estimate (`Delta_dot ~ (tau* - K_S Delta) / K_D_hat`); "
        "held over a control period T this SEA mode is stable only while T is below roughly "
        "`2 K_D_hat / K_S` (shifted by the motor velocity loop): under-estimating K_D_hat shrinks the "
        "admissible period.",
        f"- Eigenvalue boundary of the damping scale at 1 kHz: {_boundaries(margins['damping scale 0.2-3, 1 kHz, dt 1 ms'])} "
        f"with dt 1 ms, {_boundaries(margins['damping scale 0.2-3, 1 kHz, dt 0.25 ms'])} with dt 0.25 ms (the "
        "L-stable ROS2 step of 1 ms damps the 500-1200 rad/s SEA modes numerically and shifts the boundary); "
        f"in continuous time: {_boundaries(margins['damping scale 0.2-3, continuous'])} over x0.2 .. x3.",
        "- Reading: " + ("our earlier \"x0.4 unstable\" was the sampling, not the model; in the paper's "
                         "setting x0.4 agrees with the paper."
                         if c04["stable"] and not h04["stable"] else
                         "the linearisation does not separate the settings here; see the table."),
        "",
        "### K_D estimate x1.6 (paper: unstable)",
        "",
        f"- Continuous: stable. Least stable mode: {_mode(c16)}; {_sea(c16)} (x1.0: {_sea(c10)}).",
        f"- Over x{curve['scale'][0]:.1f} .. x{curve['scale'][-1]:.1f} the continuous growth rate stays between "
        f"{rates.min():.3f} and {rates.max():.3f} 1/s (figure growth_rate_damping.png): a slow balancing mode, "
        "while the SEA modes keep their real part near -K_m / 2 (the motor velocity loop's gain) whatever the "
        "estimate. Over-estimating K_D only slows the applied torque's convergence (time constant "
        "K_D_hat / K_S, about a millisecond), far faster than the balancing modes; sampling makes "
        "over-estimation safer, not worse (stability map).",
        "- Reading: " + ("**a disagreement we cannot reproduce by any mechanism of this model** (rigid "
                         "contacts, ideal motor velocity loop, QP constraints inactive at the equilibrium). "
                         "Candidates outside it: the original code's velocity loop or solver tolerances, QP "
                         "constraint activity, or a different quantity being mis-scaled. This is a finding "
                         "about our model, not a proof about the paper's simulator."
                         if c16["stable"] else "x1.6 is unstable in our model too, as in the paper."),
        "",
    ]


def other_evidence(evidence: dict, margins: dict, saturation: dict, grid: StabilityMap) -> list[str]:
    """The step, the saturation and the sampled-data paragraphs."""
    rigid = evidence["rigid after the step"]
    limited, free, preloaded = (saturation[k] for k in ("saturation 0.34 Nm", "at rest, no limit", "preloaded, 0.34 Nm"))
    rate = margins["control rate 100 Hz-10 kHz at x1.0, dt 0.25 ms"]
    unstable_cells = int((~grid.stable).sum())
    return [
        "### Step: rigid controller on the SEA robot (paper: unstable)",
        "",
        f"- Linearised after the step (continuous): {_mode(rigid)}.",
        "",
        f"### Saturation ({TORQUE_LIMIT_NM} Nm on the {SATURATED_JOINT} motor, springs at rest at the start)",
        "",
        f"- Springs at rest, limited: motor velocity peak {limited['peak_motor_velocity_rad_s']:.1f} rad/s, "
        f"at the limit for {limited['time_at_limit_s'] * 1e3:.1f} ms (last at {limited['last_time_at_limit_s']:.4f} s), "
        f"transient settled (|thetadot| < {SETTLED_MOTOR_VELOCITY} rad/s) after {limited['settling_time_s']:.3f} s.",
        f"- Springs at rest, no limit: peak {free['peak_motor_velocity_rad_s']:.1f} rad/s, torque peak "
        f"{free['peak_motor_torque_nm']:.3f} Nm, settled after {free['settling_time_s']:.3f} s.",
        f"- Springs preloaded, limited: peak {preloaded['peak_motor_velocity_rad_s']:.1f} rad/s, torque peak "
        f"{preloaded['peak_motor_torque_nm']:.3f} Nm: the limit never binds.",
        "- Reading: starting with the springs at rest (the original study's start) is what makes the limit bind "
        "and produces the paper's large initial motor velocity peak; the loop stays stable. The limit binds "
        "only during the first milliseconds, so the transient settles "
        + ("later than" if limited["settling_time_s"] > free["settling_time_s"] else "no later than")
        + " without the limit in our model (paper: slower convergence).",
        "",
        "### Sampled-data control (stability map, stability_map.png)",
        "",
        f"- Eigenvalue boundary of the control rate at x1.0 (plant step 0.25 ms): {_boundaries(rate, ' Hz')}; "
        "below it the SEA controller diverges. The real iCub's whole-body controllers run at 100 Hz.",
        f"- Boundary rate per damping scale: "
        + ", ".join(f"x{s:.2f}: {'-' if b is None else f'{b:.0f} Hz'}" for s, b in zip(grid.scales, grid.boundary_rate_hz))
        + f". {unstable_cells} of {grid.stable.size} runs diverged within {grid.duration_s:g} s "
        f"(map wall time {grid.wall_time_s:.0f} s).",
        "",
    ]


def write_outcomes(path: pathlib.Path, table: list[str], evidence_lines: list[str]) -> None:
    """outcomes.md: the setting, the table, then the evidence of every disagreement."""
    lines = [
        "# The paper's experiments: outcomes",
        "",
        "Settings. **Continuous** (the paper's: the controller evaluated at every integrator stage, as "
        "inside ode15s's right-hand side; ROS2, plant step 0.25 ms) and **1 kHz zero-order hold** (the "
        "controller sampled at 1 kHz, its input held, one 1 ms plant step per tick). Every number below "
        "was computed by this run (`python -m sea_momentum reproduce`).",
        "",
        *table,
        "",
        "## Evidence (linearisation about the closed loop's equilibrium, references frozen)",
        "",
        *evidence_lines,
    ]
    path.write_text("\n".join(lines) + "\n")


# ---- Main ----


def _summary_json(paper_setting: dict, sampled: dict, extra: dict) -> dict:
    experiments = {
        label: {"paper": PAPER[label], "continuous": paper_setting[label].summary.to_dict(),
                "zero_order_hold_1khz": sampled[label].summary.to_dict()}
        for label in PAPER
    }
    return {"experiments": experiments, **extra}


def robot_pictures(scenario_dir: pathlib.Path, out: pathlib.Path, runs: dict[str, ScenarioResult]) -> list[str]:
    """The robot at chosen instants of each experiment (paper's setting): PNG strips and GIFs;
    returns the file names written."""
    from .pictures import experiment_pictures

    return experiment_pictures(scenario_dir, out, {
        "tracking": runs["tracking x1.0"],
        "step_sea": runs["step, SEA controller"],
        "step_rigid": runs["step, rigid controller"],
        "saturation": runs["saturation 0.34 Nm"],
    })


def reproduce(scenario_dir: pathlib.Path, out: pathlib.Path, duration: float | None = None) -> dict:
    """Runs every experiment and analysis; writes the figures, logs, ``summary.json`` and
    ``outcomes.md`` to ``out``; returns the summary."""
    import matplotlib

    matplotlib.use("Agg")
    out.mkdir(parents=True, exist_ok=True)
    session = Session(scenario_dir, out, duration)
    paper_setting = run_experiments(session, {}, logs=True)
    sampled = run_experiments(session, SAMPLED_1KHZ, logs=False)
    saturation_runs = {**run_saturation_references(session), "saturation 0.34 Nm": paper_setting["saturation 0.34 Nm"]}
    saturation = {key: {**saturation_figures(r), "settling_time_s": settling_time(r)} for key, r in saturation_runs.items()}
    figure_tracking(paper_setting, out / "figure1_tracking_damping.png")
    figure_step(paper_setting, out / "figure2_rigid_vs_sea.png")
    figure_saturation(saturation_runs, out / "figure3_saturation.png")
    pictures = robot_pictures(scenario_dir, out, paper_setting)
    evidence = linearization_evidence(session)
    margins = margin_evidence(session)
    curve = growth_rate_curve(session)
    figure_growth_rate(curve, out / "growth_rate_damping.png")
    grid = stability_map(session)
    figure_stability_map(grid, out / "stability_map.png")
    table = outcome_table(paper_setting, sampled)
    write_outcomes(out / "outcomes.md", table,
                   damping_evidence(evidence, margins, curve) + other_evidence(evidence, margins, saturation, grid))
    summary = _summary_json(paper_setting, sampled, {
        "linearizations": evidence, "margins": margins, "growth_rate_curve": curve, "saturation": saturation,
        "stability_map": {"scales": grid.scales, "rates_hz": grid.rates_hz, "stable": grid.stable.tolist(),
                          "boundary_rate_hz": grid.boundary_rate_hz},
        "pictures": pictures,
        "wall_time_s": clock.perf_counter() - session.started,
    })
    (out / "summary.json").write_text(json.dumps(summary, indent=2, default=str))
    print("\n".join(table))
    session.say("done")
    return summary
