"""The paper application's entry point: :func:`reproduce` runs every experiment and analysis in
order and writes what :mod:`sea_momentum.paper` lists."""

from __future__ import annotations

import json
import pathlib
import time as clock
from typing import Any

from ..extras import require_plots
from . import evidence, experiments, figures, outcomes
from .session import Session
from .setting import SAMPLED_1KHZ
from .stability_map import StabilityMap, stability_map


def _map_summary(grid: StabilityMap) -> dict[str, Any]:
    """The stability map as summary.json holds it."""
    return {"scales": grid.scales, "rates_hz": grid.rates_hz, "stable": grid.stable.tolist(),
            "boundary_rate_hz": grid.boundary_rate_hz}


def reproduce(scenario_dir: pathlib.Path, out: pathlib.Path, duration: float | None = None) -> dict[str, Any]:
    """Runs every experiment and analysis; writes the figures, logs, ``summary.json`` and
    ``outcomes.md`` to ``out``; returns the summary. ``duration`` [s] (if given) overrides every
    run's length (and caps the stability map's)."""
    require_plots("reproduce")
    import matplotlib

    matplotlib.use("Agg")
    out.mkdir(parents=True, exist_ok=True)
    session = Session(scenario_dir, out, duration)
    paper_setting = experiments.run_experiments(session, {}, logs=True)
    sampled = experiments.run_experiments(session, SAMPLED_1KHZ, logs=False)
    saturation_runs = {**experiments.run_saturation_references(session),
                       "saturation 0.34 Nm": paper_setting["saturation 0.34 Nm"]}
    saturation = experiments.saturation_evidence(saturation_runs)
    figures.figure_tracking(paper_setting, out / "figure1_tracking_damping.png")
    figures.figure_step(paper_setting, out / "figure2_rigid_vs_sea.png")
    figures.figure_saturation(saturation_runs, out / "figure3_saturation.png")
    pictures = figures.robot_pictures(scenario_dir, out, paper_setting)
    linearizations = evidence.linearization_evidence(session)
    margins = evidence.margin_evidence(session)
    curve = evidence.growth_rate_curve(session)
    figures.figure_growth_rate(curve, out / "growth_rate_damping.png")
    grid = stability_map(session)
    figures.figure_stability_map(grid, out / "stability_map.png")
    table = outcomes.outcome_table(paper_setting, sampled)
    outcomes.write_outcomes(out / "outcomes.md", table,
                            outcomes.damping_evidence(linearizations, margins, curve)
                            + outcomes.other_evidence(linearizations, margins, saturation, grid))
    summary = outcomes.summary_json(paper_setting, sampled, {
        "linearizations": linearizations, "margins": margins, "growth_rate_curve": curve, "saturation": saturation,
        "stability_map": _map_summary(grid), "pictures": pictures,
        "wall_time_s": clock.perf_counter() - session.started,
    })
    (out / "summary.json").write_text(json.dumps(summary, indent=2, default=str))
    print("\n".join(table))
    session.say("done")
    return summary
