"""The outcomes of the paper application: the table beside the paper's outcomes, the evidence
paragraphs (every number computed by the run), ``outcomes.md`` and ``summary.json``."""

from __future__ import annotations

import pathlib
from typing import Any, Mapping

import numpy as np

from ..scenario import ScenarioResult
from .experiments import SETTLED_MOTOR_VELOCITY
from .session import outcome, stable
from .setting import PAPER, PAPER_STABLE, SATURATED_JOINT, TORQUE_LIMIT_NM
from .stability_map import StabilityMap


def verdict(label: str, result: Any) -> str:
    """Whether a run (anything with a ``status``) agrees with the paper's outcome of ``label``."""
    return "agrees" if stable(result) == PAPER_STABLE[label] else "**disagrees**"


def outcome_table(paper_setting: Mapping[str, ScenarioResult], sampled: Mapping[str, ScenarioResult]) -> list[str]:
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
            f"| {label} | {paper} | {outcome(ours)} ({verdict(label, ours)}) | {outcome(held)} "
            f"({verdict(label, held)}) | {s.com_error_rms_m * 1e3:.2f} / {s.com_error_max_m * 1e3:.2f} "
            f"| {s.motor_velocity_peak_rad_s:.0f} |"
        )
    return lines


def _mode(d: Mapping[str, Any]) -> str:
    """A linearisation in one phrase: growth, frequency, dominant states."""
    states = ", ".join(f"{name} ({weight})" for name, weight in d["dominant_states"])
    frequency = d["least_stable_frequency_rad_s"]
    kind = "a real mode" if frequency < 1e-6 else f"{frequency:.1f} rad/s"
    return f"growth rate {d['growth_rate_1_s']:+.3f} 1/s ({kind}), dominated by {states}"


def _sea(d: Mapping[str, Any]) -> str:
    """The SEA modes of a linearisation in one phrase: real parts and frequencies."""
    low, high = d["sea_mode_real_min_max_1_s"]
    f_low, f_high = d["sea_mode_frequency_min_max_rad_s"]
    return f"SEA modes at Re {low:.1f} .. {high:.1f} 1/s, {f_low:.0f} .. {f_high:.0f} rad/s"


def _boundaries(values: list[float], unit: str = "") -> str:
    """Stability boundaries as text, or that there are none."""
    return "none (stability never changes)" if not values else ", ".join(f"{v:.3g}{unit}" for v in values)


def damping_evidence(evidence: Mapping[str, Any], margins: Mapping[str, list[float]],
                     curve: Mapping[str, list[float]]) -> list[str]:
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


def other_evidence(evidence: Mapping[str, Any], margins: Mapping[str, list[float]], saturation: Mapping[str, Any],
                   grid: StabilityMap) -> list[str]:
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


def summary_json(paper_setting: Mapping[str, ScenarioResult], sampled: Mapping[str, ScenarioResult],
                 extra: Mapping[str, Any]) -> dict[str, Any]:
    """summary.json: each experiment (the paper's outcome, our run summaries in both settings),
    then ``extra`` (the evidence)."""
    experiments = {
        label: {"paper": PAPER[label], "continuous": paper_setting[label].summary.to_dict(),
                "zero_order_hold_1khz": sampled[label].summary.to_dict()}
        for label in PAPER
    }
    return {"experiments": experiments, **extra}
