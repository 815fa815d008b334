"""The feet's planned normal forces against the delivered ones in a walking scenario.

Runs SCENARIO (step adjustment on, every whole-body tick recorded; `key=value` arguments are
more overrides, values as Python literals) and prints, from the record's `planned_wrenches`
(what the controller's QP asked each foot for) and `contact_wrenches` (what the plant
delivered), the episodes where a foot is planned a load the plant does not give it ("air";
at a touchdown, the plan loading a foot still in the air) and where a foot planned no load
is loaded ("strike"; a sole striking the ground before its touchdown, or a leaving foot
still touching once its planned share reached zero). "Loaded" is a normal force above 5 % of
the weight, "no load" under 1 N. A sample's delivered wrench is that of its first plant
step, against a plan held for the whole-body period: an episode shorter than the period
between two samples can be missed, and durations are whole periods.

    python scripts/planned_vs_delivered.py scenarios/walking/walk_push.toml
    python scripts/planned_vs_delivered.py scenarios/walking/walk_fast.toml walking.swing_height=0.04
"""

import ast
import sys

import numpy as np

import sea_momentum as sm


def episodes(mask, force, time, period):
    """(start [s], contact, duration [ms], peak force [N]) of each run of `mask` per contact."""
    found = []
    for c in range(mask.shape[1]):
        k = 0
        while k < len(mask):
            if not mask[k, c]:
                k += 1
                continue
            end = k
            while end < len(mask) and mask[end, c]:
                end += 1
            found.append((time[k], c, (end - k) * period * 1e3, force[k:end, c].max()))
            k = end
    return sorted(found)


#: The overrides of every run: the step adjustment on, every whole-body tick recorded.
DEFAULTS = {"walking.step_adjustment": True, "simulation.record_every": 1}


def measure(path, overrides):
    """Runs `path` with `overrides`; the run and, per case ("air": a foot planned a load the
    plant does not give it; "strike": a foot loaded with no load planned), its episodes
    ([`episodes`]; the planned force's peak for "air", the delivered one's for "strike")."""
    run = sm.run_scenario(path, overrides)
    if len(run.time) < 2:
        raise SystemExit(f"{path}: {len(run.time)} recorded sample(s), too few for episodes")
    planned, delivered = run.planned_wrenches[:, :, 2], run.contact_wrenches[:, :, 2]
    weight = np.median(delivered.sum(axis=1))
    period = run.time[1] - run.time[0]
    air = (planned > 0.05 * weight) & (delivered < 0.05 * weight)
    strike = (planned < 1.0) & (delivered > 0.05 * weight)
    return run, {
        "air": episodes(air, planned, run.time, period),
        "strike": episodes(strike, delivered, run.time, period),
    }


def main(argv):
    if not argv:
        sys.exit(__doc__)
    extra = {k: ast.literal_eval(v) for k, v in (a.split("=", 1) for a in argv[1:])}
    overrides = {**DEFAULTS, **extra}
    run, found = measure(argv[0], overrides)
    print(f"{argv[0]} {extra}: {run.status} at {run.time[-1]:.2f} s")
    names = {"air": "load planned on a foot in the air", "strike": "a foot loaded with no load planned"}
    for case, name in names.items():
        if not found[case]:
            print(f"  {name}: none")
            continue
        durations, peaks = [e[2] for e in found[case]], [e[3] for e in found[case]]
        print(
            f"  {name}: {len(durations)} episodes, {sum(durations):.0f} ms in all, "
            f"median {np.median(durations):.0f} ms and {np.median(peaks):.0f} N"
        )
        shown = found[case][:8]
        print("   ", " ".join(f"{t:.2f} s {run.contacts[c]} {d:.0f} ms {p:.0f} N" for t, c, d, p in shown))
    planned, delivered = run.planned_wrenches[:, :, 2], run.contact_wrenches[:, :, 2]
    gap = np.abs(planned - delivered).sum(axis=1)
    print(
        f"  |planned - delivered| normal force over the feet: median {np.median(gap):.1f} N, "
        f"90th percentile {np.percentile(gap, 90):.1f} N"
    )


if __name__ == "__main__":
    main(sys.argv[1:])
