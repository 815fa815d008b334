"""The robot-rate study (issue 19, docs/findings/robot_rate.md): the multi-rate loop (100 Hz
whole body over 1 kHz joint torque loops) on the paper's tracking, with and without the online
stiffness identification.

Writes into OUT (default out/robot_rate):

- robustness_map.png: outcome and CoM error of 10 s runs over stiffness estimate x damping
  estimate, without and with identification, with the period map's eigenvalue boundary along
  the stiffness axis (damping estimate x1) drawn;
- push_table.md / push_table.json: the largest push recovered per direction on two feet
  (``sea-sim push``), beside the capture-point bound and the rigid robot under the rigid
  controller at 100 Hz; pushed at 1 s, and (``PUSH_CONVERGED``) at 3 s, when the stiffness
  identification has converged; (``PUSH_EXCITED``) at 4 s, without and with the legs (and the
  torso) excited for the identification in the first 3 s (``LEGS_EXCITED``,
  ``LEGS_AND_TORSO_EXCITED``); and (``PUSH_PARTS``) with one
  part of the design changed per row (the push not observed, the stiff CoM gains, the paper's
  QP, ...);
- model_errors.md: tracking with every link's mass in the controller's model off by a draw
  from [-10 %, +10 %] (``MASS_DRAWS`` seeded draws) and with stiffness estimates x0.5 / x2,
  for each way of taking what the model misses (``MODEL_ERROR_SETUPS``: nothing, the
  centroidal observer, the generalized disturbance observer, the identification, both);
- noise.md: the tracking with noisy encoders (``NOISE``, seeds 0-7) from stiffness estimates
  x0.5, x1, x2, with the identification alone and with the design that holds model errors
  (``NOISE_SETUPS``);
- robot_rate.json: every figure of the above;
- with ``--outcomes FILE`` (the main job's outcomes.md): its section "At the robot's rate"
  written (replaced when it is there).

Usage: python scripts/robot_rate.py [OUT] [--sea-sim PATH] [--outcomes FILE]
"""

from __future__ import annotations

import argparse
import json
import pathlib
import random
import subprocess
import sys
import textwrap
import xml.etree.ElementTree as ET
from typing import Any

import numpy as np

import sea_momentum as sm

ROOT = pathlib.Path(__file__).resolve().parent.parent
TRACKING = ROOT / "scenarios" / "robot_rate" / "tracking_multi_rate.toml"
PUSH = ROOT / "scenarios" / "robot_rate" / "push_two_feet.toml"
STIFFNESS = [0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 1.0, 1.05, 1.1, 1.25, 1.5, 2.0]
DAMPING = [0.2, 0.5, 1.0, 2.0, 3.0]
IDENTIFICATION = "controller.stiffness_identification"
#: The shipped robot-rate scenarios run the identification; every table here starts from the
#: fixed estimates (the rows that identify set it on), so that each row changes one part.
FIXED: dict[str, Any] = {IDENTIFICATION: False}
#: The design that holds model errors (docs/findings/model_errors.md).
ROBUST: dict[str, Any] = {
    IDENTIFICATION: True,
    "controller.external_wrench": "generalized",
    "controller.identification_prior_deflection_rad": 5e-3,
}
#: The push scenario is the robot-rate design (multi-rate, the push observed, compliant CoM
#: gains, the feet on the ground with joint stops); the rows override it. The rigid robot under the rigid
#: controller at 100 Hz (zero-order hold), the same controller settings, is each table's
#: reference ("% of rigid").
RIGID_100_HZ = [
    "actuators.kind=rigid",
    "controller.kind=rigid",
    "controller.sampling=zero_order_hold",
    "controller.rate_hz=100",
]
PUSH_SETUPS = {
    "rigid robot, rigid controller, 100 Hz": RIGID_100_HZ,
    "SEA, multi-rate": [],
    "SEA, multi-rate, identification from x0.5": [f"{IDENTIFICATION}=true", "controller.stiffness_estimate_scale=0.5"],
    "SEA, multi-rate, identification from x2": [f"{IDENTIFICATION}=true", "controller.stiffness_estimate_scale=2.0"],
}


#: Pushed at 3 s (5 s runs): three identification time constants after the start, where the
#: identification from a wrong estimate has converged; the rigid robot first, as the reference.
PUSH_CONVERGED = {
    "rigid robot, rigid controller, 100 Hz, pushed at 3 s": PUSH_SETUPS["rigid robot, rigid controller, 100 Hz"],
    "SEA, multi-rate, identification from x0.5, pushed at 3 s": PUSH_SETUPS["SEA, multi-rate, identification from x0.5"],
    "SEA, multi-rate, identification from x2, pushed at 3 s": PUSH_SETUPS["SEA, multi-rate, identification from x2"],
}
PUSHED_AT_3_S = ["--start", "3", "--set", "simulation.duration_s=5"]

#: The identification excitation (``sea_ctrl::excitation``): 1 Nm at 1 Hz for the first 3 s on
#: the legs' roll and yaw joints, which carry almost no torque on two feet at rest, the same
#: sign on both legs (internal torques: the feet take them, the CoM does not move).
LEGS = "l_ankle_roll=1.0, r_ankle_roll=1.0, l_hip_roll=1.0, r_hip_roll=1.0, l_hip_yaw=1.0, r_hip_yaw=1.0"
#: The torso's roll and yaw carry no torque upright either: 0.1 Nm each, at the same rate (the
#: CoM moves 0.07 mm; 0.25 Nm, 0.18 mm, identifies as well but lowers the sideways push, docs/findings/pushes.md).
TORSO = "torso_roll=0.1, torso_yaw=0.1"


def excitation(joints: str) -> list[str]:
    """The ``--set`` values of an excitation of ``joints`` (``name=amplitude, ...``), 1 Hz, 0-3 s."""
    return [
        f"controller.identification_excitation_nm={{{joints}}}",
        "controller.identification_excitation_hz=1.0",
        "controller.identification_excitation_s=3.0",
    ]


LEGS_EXCITED = excitation(LEGS)
LEGS_AND_TORSO_EXCITED = excitation(f"{LEGS}, {TORSO}")
_FROM_HALF = PUSH_SETUPS["SEA, multi-rate, identification from x0.5"]
_FROM_TWICE = PUSH_SETUPS["SEA, multi-rate, identification from x2"]
#: Pushed at 4 s (6 s runs), 1 s after the excitation: the identification from a wrong
#: estimate without and with it; the rigid robot first, as the reference.
PUSH_EXCITED = {
    "rigid robot, rigid controller, 100 Hz, pushed at 4 s": PUSH_SETUPS["rigid robot, rigid controller, 100 Hz"],
    "SEA, multi-rate, identification from x0.5, pushed at 4 s": _FROM_HALF,
    "SEA, multi-rate, identification from x0.5, legs excited 0-3 s, pushed at 4 s": _FROM_HALF + LEGS_EXCITED,
    "SEA, multi-rate, identification from x0.5, legs and torso excited 0-3 s, pushed at 4 s": _FROM_HALF + LEGS_AND_TORSO_EXCITED,
    "SEA, multi-rate, identification from x2, pushed at 4 s": _FROM_TWICE,
    "SEA, multi-rate, identification from x2, legs excited 0-3 s, pushed at 4 s": _FROM_TWICE + LEGS_EXCITED,
    "SEA, multi-rate, identification from x2, legs and torso excited 0-3 s, pushed at 4 s": _FROM_TWICE + LEGS_AND_TORSO_EXCITED,
}
PUSHED_AT_4_S = ["--start", "4", "--set", "simulation.duration_s=6"]

#: What each part of the design brings (SEA, multi-rate, one part changed per row): without
#: the observer (the push unknown), with the robot description's stiff CoM gains and postural
#: scale (K_i 40, 45 N/m per kg horizontally hold the CoM), both (the design of the previous
#: push tables), the paper's QP, and a 40 Hz torque loop. Rigid robot first, as the reference.
STIFF_COM = ["controller.momentum_integral=[40.0, 45.0, 40.0, 1.0, 5.0, 1.0]", "controller.postural_scale=0.2"]
NO_OBSERVER = ["controller.external_wrench=none"]
PUSH_PARTS = {
    "rigid robot, rigid controller, 100 Hz": RIGID_100_HZ,
    "SEA, multi-rate, push not observed": NO_OBSERVER,
    "SEA, multi-rate, stiff CoM gains": STIFF_COM,
    "SEA, multi-rate, push not observed, stiff CoM gains": NO_OBSERVER + STIFF_COM,
    "SEA, multi-rate, the paper's QP": [
        "controller.momentum_relaxation=none",
        "controller.qp_moment_regularization=0",
        "controller.contact.cop_margin=0",
    ],
    "SEA, multi-rate, 40 Hz torque loop": ["controller.torque_bandwidth_hz=40"],
    "rigid robot, rigid controller, 100 Hz, a joint at its limit ending the run": RIGID_100_HZ
    + ["simulation.stop_at_joint_limits=true"],
}


#: The proxy the push tables were measured with before the feet could leave the ground: the
#: feet welded (bilateral contacts), a fall when a foot's wrench leaves what a unilateral
#: contact with friction could carry, a joint past its URDF limit ending the run, the default
#: error bounds.
PROXY = [
    "plant.contact_model=bilateral",
    "simulation.stop_at_joint_limits=true",
    "simulation.divergence_joint_error_rad=1.0",
    "simulation.divergence_com_error_m=0.1",
]
PROXY_ROWS = ["rigid robot, rigid controller, 100 Hz", "SEA, multi-rate", "SEA, multi-rate, identification from x0.5"]
PUSH_PROXY = {label: PUSH_SETUPS[label] + PROXY for label in PROXY_ROWS}


def log(message: str) -> None:
    """A progress line on stderr."""
    print(f"[robot_rate] {message}", file=sys.stderr, flush=True)


#: The robustness maps: (title, overrides of the tracking scenario, whether the period map is
#: linearised: not with an observer, whose estimate is no state of the map).
MAPS: dict[str, tuple[str, dict[str, Any], bool]] = {
    "without": ("without identification", {IDENTIFICATION: False}, True),
    "with": ("with identification", {IDENTIFICATION: True}, True),
    "with_observer": ("identification (prior 5 mrad) + generalized observer", ROBUST, False),
}


def robustness_map(overrides: dict[str, Any]) -> dict[str, Any]:
    """10 s runs over ``STIFFNESS`` x ``DAMPING`` (grid order: damping fastest)."""
    result = sm.sweep(
        TRACKING,
        {
            "controller.stiffness_estimate_scale": STIFFNESS,
            "controller.damping_estimate_scale": DAMPING,
        },
        overrides={**FIXED, **overrides},
    )
    shape = (len(STIFFNESS), len(DAMPING))
    return {
        "status": np.asarray(result["status"]).reshape(shape).tolist(),
        "com_error_rms_m": np.asarray(result["com_error_rms_m"]).reshape(shape).tolist(),
        "joint_error_norm_final_rad": np.asarray(result["joint_error_norm_final_rad"])
        .reshape(shape)
        .tolist(),
    }


#: The period map is linearised with the feet welded: on the ground its equilibrium does not
#: converge (the regularised friction lets a loaded sole creep) and a near-neutral mode hides
#: the controller's (growth +0.011 1/s against -0.144 welded at the nominal stiffness,
#: docs/findings/contacts.md).
WELDED_FEET = {"plant.contact_model": "bilateral"}


def growth_rates(setup: dict[str, Any]) -> list[dict[str, Any]]:
    """The period map's growth rate along ``STIFFNESS`` (damping estimate x1) with the
    overrides ``setup``, the feet welded (``WELDED_FEET``)."""
    rows = []
    for scale in STIFFNESS:
        overrides = {**FIXED, **setup, **WELDED_FEET, "controller.stiffness_estimate_scale": scale}
        lin = sm.linearize(TRACKING, overrides=overrides)
        rows.append(
            {
                "stiffness_scale": scale,
                "growth_rate": lin.growth_rate,
                "equilibrium_converged": bool(lin.converged),
                "dominant_state": lin.dominant_states[0][0] if lin.dominant_states else "",
            }
        )
    return rows


def boundaries(rows: list[dict[str, Any]]) -> list[float]:
    """Stiffness scales where the growth rate changes sign (linear interpolation), between
    points whose equilibria converged."""
    found = []
    for a, b in zip(rows, rows[1:]):
        if not (a["equilibrium_converged"] and b["equilibrium_converged"]):
            continue
        ga, gb = a["growth_rate"], b["growth_rate"]
        if (ga < 0) != (gb < 0):
            t = ga / (ga - gb)
            found.append(a["stiffness_scale"] + t * (b["stiffness_scale"] - a["stiffness_scale"]))
    return found


#: Model errors (tracking, multi-rate): how many seeded per-link mass draws, their spread, and
#: the setups compared (overrides of the tracking scenario).
MASS_DRAWS = 8
MASS_SPREAD = 0.1
MODEL_ERROR_SETUPS: dict[str, dict[str, Any]] = {
    "nothing (the paper's dynamics)": {},
    "centroidal observer": {"controller.external_wrench": "observed"},
    "generalized disturbance observer": {"controller.external_wrench": "generalized"},
    "stiffness identification": {IDENTIFICATION: True},
    "identification + generalized observer": {IDENTIFICATION: True, "controller.external_wrench": "generalized"},
    "identification (prior 5 mrad) + generalized observer": ROBUST,
}
MODEL_ERROR_STIFFNESS = [0.5, 2.0]

#: Noisy encoders (every encoder 1e-4 rad, every velocity 1e-2 rad/s; the identification told
#: the deflection's noise), seeds ``NOISE_SEEDS``, from the stiffness estimates ``NOISE_STIFFNESS``.
NOISE = {
    "sensing.joint_position_noise_rad": 1e-4,
    "sensing.motor_position_noise_rad": 1e-4,
    "sensing.joint_velocity_noise_rad_s": 1e-2,
    "sensing.motor_velocity_noise_rad_s": 1e-2,
    "controller.identification_deflection_noise_rad": 1e-4,
}
NOISE_SEEDS = list(range(8))
NOISE_STIFFNESS = [0.5, 1.0, 2.0]
NOISE_SETUPS: dict[str, dict[str, Any]] = {
    "identification": {IDENTIFICATION: True},
    "identification (prior 5 mrad) + generalized observer": ROBUST,
}


def noise_table() -> dict[str, Any]:
    """Per setup of ``NOISE_SETUPS``: the outcome of each (stiffness estimate, seed) run."""
    table: dict[str, Any] = {}
    for label, setup in NOISE_SETUPS.items():
        log(f"encoder noise: {label} ({len(NOISE_STIFFNESS) * len(NOISE_SEEDS)} runs)")
        table[label] = [
            {
                "stiffness_scale": scale,
                "seed": seed,
                **outcome(
                    sm.run_scenario(
                        TRACKING,
                        overrides={
                            **FIXED,
                            **setup,
                            **NOISE,
                            "controller.stiffness_estimate_scale": scale,
                            "sensing.seed": seed,
                        },
                    )
                ),
            }
            for scale in NOISE_STIFFNESS
            for seed in NOISE_SEEDS
        ]
    return table


def noise_markdown(table: dict[str, Any]) -> list[str]:
    """The noise table as markdown: runs completed, CoM rms and final joint error (median /
    max over the completed ones)."""
    lines = [
        "| noisy encoders, stiffness x0.5 / x1 / x2, 8 seeds | completed | CoM rms median / max [mm] "
        "| final joint error median / max [rad] | not completed |",
        "| --- | --- | --- | --- | --- |",
    ]
    for label, runs in table.items():
        done = [r for r in runs if r["status"] == "completed"]
        rms = [1e3 * r["com_error_rms_m"] for r in done] or [float("nan")]
        joint = [r["joint_error_norm_final_rad"] for r in done] or [float("nan")]
        failed = ", ".join(
            f"x{r['stiffness_scale']:g} seed {r['seed']} {r['status']} at {r['at_s']:.2f} s"
            for r in runs
            if r["status"] != "completed"
        )
        lines.append(
            f"| {label} | {len(done)} of {len(runs)} | {np.median(rms):.2f} / {max(rms):.2f} "
            f"| {np.median(joint):.3f} / {max(joint):.3f} | {failed or '-'} |"
        )
    return lines


def mass_draws() -> list[dict[str, float]]:
    """``MASS_DRAWS`` seeded draws of a mass scale per link of the tracking robot (uniform in
    1 +- ``MASS_SPREAD``; the links with an inertial element of its URDF)."""
    urdf = (TRACKING.parent / "../../urdf/icub25.urdf").resolve()
    links = [link.get("name", "") for link in ET.parse(urdf).getroot().iter("link") if link.find("inertial") is not None]
    draws = []
    for seed in range(MASS_DRAWS):
        rng = random.Random(seed)
        draws.append({link: round(rng.uniform(1 - MASS_SPREAD, 1 + MASS_SPREAD), 4) for link in links})
    return draws


def outcome(result: Any) -> dict[str, Any]:
    """The figures of one run's summary that the model-error table shows."""
    s = result.summary
    horizontal = np.asarray(result.com)[:, :2] - np.asarray(result.com_reference)[:, :2]
    return {
        "status": s.status,
        "at_s": s.diverged_at_s if s.diverged_at_s is not None else s.fell_at_s,
        "com_error_rms_m": s.com_error_rms_m,
        "com_error_horizontal_rms_m": float(np.sqrt(np.mean(np.sum(horizontal**2, axis=1)))),
        "com_error_lateral_max_m": s.com_error_lateral_max_m,
        "joint_error_norm_final_rad": s.joint_error_norm_final_rad,
    }


def model_error_table() -> dict[str, Any]:
    """Per setup of ``MODEL_ERROR_SETUPS``: the outcome of each mass draw and of each stiffness
    estimate of ``MODEL_ERROR_STIFFNESS`` (10 s tracking runs)."""
    draws = mass_draws()
    table: dict[str, Any] = {}
    for label, setup in MODEL_ERROR_SETUPS.items():
        log(f"model errors: {label} ({len(draws)} mass draws, {len(MODEL_ERROR_STIFFNESS)} stiffness estimates)")
        masses = [
            outcome(sm.run_scenario(TRACKING, overrides={**FIXED, **setup, "controller.link_mass_estimate_scales": d}))
            for d in draws
        ]
        stiffness = {
            f"x{scale:g}": outcome(
                sm.run_scenario(TRACKING, overrides={**FIXED, **setup, "controller.stiffness_estimate_scale": scale})
            )
            for scale in MODEL_ERROR_STIFFNESS
        }
        table[label] = {"mass_draws": masses, "stiffness": stiffness}
    return table


def model_error_markdown(table: dict[str, Any]) -> list[str]:
    """The model-error table as markdown: draws completed, median and worst figures of the
    completed ones (the true CoM's error), and the stiffness estimates' outcomes."""
    scales = [f"x{s:g}" for s in MODEL_ERROR_STIFFNESS]
    lines = [
        "| what the controller takes of its model's errors | mass draws completed | CoM rms median / max [mm] "
        "| horizontal CoM rms median / max [mm] | lateral max median / max [mm] | final joint error median / max [rad] | "
        + " | ".join(f"stiffness estimate {s}" for s in scales)
        + " |",
        "| --- | --- | --- | --- | --- | --- |" + " --- |" * len(scales),
    ]
    for label, row in table.items():
        done = [r for r in row["mass_draws"] if r["status"] == "completed"]
        if done:
            rms = [1e3 * r["com_error_rms_m"] for r in done]
            horizontal = [1e3 * r["com_error_horizontal_rms_m"] for r in done]
            lateral = [1e3 * r["com_error_lateral_max_m"] for r in done]
            joint = [r["joint_error_norm_final_rad"] for r in done]
            figures = (
                f"{np.median(rms):.2f} / {max(rms):.2f} | {np.median(horizontal):.2f} / {max(horizontal):.2f} | "
                f"{np.median(lateral):.2f} / {max(lateral):.2f} | {np.median(joint):.3f} / {max(joint):.3f}"
            )
        else:
            figures = "- | - | - | -"
        cells = []
        for s in scales:
            r = row["stiffness"][s]
            if r["status"] == "completed":
                cells.append(f"completed, CoM rms {1e3 * r['com_error_rms_m']:.2f} mm, joint {r['joint_error_norm_final_rad']:.3f} rad")
            else:
                cells.append(f"{r['status']} at {r['at_s']:.2f} s")
        lines.append(f"| {label} | {len(done)} of {len(row['mass_draws'])} | {figures} | " + " | ".join(cells) + " |")
    return lines


def push_table(sea_sim: pathlib.Path, setups: dict[str, list[str]], extra: list[str]) -> dict[str, Any]:
    """``sea-sim push`` (with the arguments ``extra``) for each of ``setups``: recovered
    impulse per direction."""
    table: dict[str, Any] = {}
    for label, overrides in setups.items():
        log(f"push: {label}")
        args = [str(sea_sim), "push", str(PUSH), *extra, "--set", f"{IDENTIFICATION}=false"]
        for value in overrides:
            args += ["--set", value]
        report = json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)
        table[label] = {
            d["direction"]: {
                "recovered_n_s": d["recovered_impulse_n_s"],
                "capture_point_n_s": d["capture_point_impulse_n_s"],
                "failed_status": d["failed_status"],
            }
            for d in report["directions"]
        }
    return table


def push_markdown(table: dict[str, Any]) -> list[str]:
    """The push table as markdown: recovered impulse, % of the capture-point bound and % of
    the rigid robot's."""
    labels = list(table)
    rigid = table[labels[0]]
    directions = list(rigid)
    head = "| setup | " + " | ".join(directions) + " |"
    lines = [head, "| --- |" + " --- |" * len(directions)]
    bound = [f"{rigid[d]['capture_point_n_s']:.2f}" for d in directions]
    lines.append("| capture-point bound [N s] | " + " | ".join(bound) + " |")
    for label in labels:
        cells = []
        for d in directions:
            value = table[label][d]["recovered_n_s"]
            share = 100 * value / table[label][d]["capture_point_n_s"]
            of_rigid = 100 * value / rigid[d]["recovered_n_s"]
            cells.append(f"{value:.2f} ({share:.0f} % of bound, {of_rigid:.0f} % of rigid)")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return lines


def proxy_markdown(physics: dict[str, Any], proxy: dict[str, Any]) -> list[str]:
    """Per setup of ``PROXY_ROWS`` and direction: the recovered impulse on the ground (unilateral
    contacts, joint stops) beside the proxy's (welded feet, wrench check, joint limits ending
    the run) and the capture-point bound [N s]."""
    directions = list(physics[PROXY_ROWS[0]])
    lines = ["| setup | " + " | ".join(directions) + " |", "| --- |" + " --- |" * len(directions)]
    bound = [f"{physics[PROXY_ROWS[0]][d]['capture_point_n_s']:.2f}" for d in directions]
    lines.append("| capture-point bound | " + " | ".join(bound) + " |")
    for label in PROXY_ROWS:
        cells = []
        for d in directions:
            ground, welded = physics[label][d], proxy[label][d]
            change = 100 * (ground["recovered_n_s"] / welded["recovered_n_s"] - 1)
            cells.append(
                f"{ground['recovered_n_s']:.2f} on the ground ({ground['failed_status']}), "
                f"{welded['recovered_n_s']:.2f} proxy ({welded['failed_status']}); {change:+.0f} %"
            )
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return lines


def figure(maps: dict[str, Any], rates: dict[str, Any], path: pathlib.Path) -> None:
    """One panel per map of ``MAPS``: outcome colours, CoM rms in mm, the eigenvalue boundary
    along the stiffness axis where the period map is linearised."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colours = {"completed": 0, "fell": 1, "diverged": 2}
    fig, axes = plt.subplots(1, len(maps), figsize=(6 * len(maps), 5), sharey=True)
    cmap = matplotlib.colors.ListedColormap(["#7fc97f", "#fdc086", "#f0027f"])
    for ax, key in zip(axes, maps):
        title = MAPS[key][0]
        status = np.array(maps[key]["status"])
        rms = np.array(maps[key]["com_error_rms_m"]) * 1e3
        codes = np.vectorize(lambda s: colours.get(s, 2))(status)
        ax.imshow(codes.T, origin="lower", cmap=cmap, vmin=0, vmax=2, aspect="auto")
        for i in range(len(STIFFNESS)):
            for j in range(len(DAMPING)):
                text = f"{rms[i, j]:.1f}" if status[i, j] == "completed" else status[i, j][0]
                ax.text(i, j, text, ha="center", va="center", fontsize=7)
        found = boundaries(rates[key]) if key in rates else []
        for b in found:
            x = np.interp(b, STIFFNESS, np.arange(len(STIFFNESS)))
            ax.axvline(x, color="k", linestyle="--", linewidth=1)
        unconverged = [r["stiffness_scale"] for r in rates.get(key, []) if not r["equilibrium_converged"]]
        note = "" if found else "no eigenvalue boundary between converged equilibria"
        if key not in rates:
            note = "period map not linearised (the observer's estimate is no state of it)"
        if unconverged:
            note += f"; no equilibrium found at x{', x'.join(f'{u:g}' for u in unconverged)}"
        note = "\n".join(textwrap.wrap(note.strip("; "), 90))
        ax.set_xlabel(f"stiffness estimate / true\n{note}", fontsize=8)
        ax.set_xticks(range(len(STIFFNESS)), [f"{s:g}" for s in STIFFNESS])
        ax.set_yticks(range(len(DAMPING)), [f"{d:g}" for d in DAMPING])
        ax.set_title(f"100 Hz / 1 kHz, {title}\n(CoM rms [mm]; f fell, d diverged)")
    axes[0].set_ylabel("damping estimate / true")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


SECTION = "## At the robot's rate (100 Hz whole body / 1 kHz joint loops)"


def outcomes_section(report: dict[str, Any]) -> list[str]:
    """The outcomes.md section: the robustness maps' counts, growth rates and the push table."""
    lines = [SECTION, ""]
    total = len(STIFFNESS) * len(DAMPING)
    for key in report["maps"]:
        m = report["maps"][key]
        statuses = [s for row in m["status"] for s in row]
        rms = [r for row, srow in zip(m["com_error_rms_m"], m["status"]) for r, s in zip(row, srow) if s == "completed"]
        worst = f", CoM rms up to {1e3 * max(rms):.2f} mm" if rms else ""
        lines.append(
            f"- {MAPS[key][0]}: {statuses.count('completed')} of {total} runs "
            f"complete 10 s of tracking (stiffness estimate x{STIFFNESS[0]:g} to x{STIFFNESS[-1]:g}, "
            f"damping x{DAMPING[0]:g} to x{DAMPING[-1]:g}){worst}; fell {statuses.count('fell')}, "
            f"diverged {statuses.count('diverged')}."
        )
        if key not in report["growth_rates"]:
            continue
        rates = ", ".join(
            f"x{r['stiffness_scale']:g} {r['growth_rate']:+.3f}" + ("" if r["equilibrium_converged"] else " (no equilibrium)")
            for r in report["growth_rates"][key]
        )
        lines.append(f"  Period-map growth rates [1/s] (damping x1): {rates}.")
    lines += ["", "Largest 0.1 s push on the pelvis recovered on two feet [N s] (`sea-sim push`):", ""]
    lines += push_markdown(report["pushes"])
    lines += ["", "Pushed at 3 s, the identification converged:", ""]
    lines += push_markdown(report["pushes_converged"])
    lines += ["", "Pushed at 4 s, without and with the legs (and the torso) excited 0-3 s for the identification:", ""]
    lines += push_markdown(report["pushes_excited"])
    lines += ["", "What each part of the design brings (one part changed per row):", ""]
    lines += push_markdown(report["pushes_parts"])
    lines += ["", f"Model errors: every link's mass in the controller's model off by a seeded draw in "
              f"+-{100 * MASS_SPREAD:g} % ({MASS_DRAWS} draws; CoM errors of the true CoM), and stiffness "
              "estimates without their per-link draws, 10 s tracking at 100 Hz / 1 kHz:", ""]
    lines += model_error_markdown(report["model_errors"])
    lines += ["", "Noisy encoders (1e-4 rad, 1e-2 rad/s), 10 s tracking at 100 Hz / 1 kHz:", ""]
    lines += noise_markdown(report["noise"])
    lines += ["", "Figure: robot_rate/robustness_map.png. Mechanism and design: docs/findings/robot_rate.md.", ""]
    return lines


def write_outcomes(path: pathlib.Path, lines: list[str]) -> None:
    """Writes the section into ``path``, replacing an earlier one (up to the next "## ")."""
    text = path.read_text() if path.exists() else ""
    if SECTION in text:
        head, rest = text.split(SECTION, 1)
        tail = rest[rest.find("\n## ") + 1:] if "\n## " in rest else ""
        text = head + tail
    path.write_text(text.rstrip("\n") + "\n\n" + "\n".join(lines))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="out/robot_rate")
    parser.add_argument("--sea-sim", default=str(ROOT / "target" / "release" / "sea-sim"))
    parser.add_argument("--outcomes", type=pathlib.Path, help="outcomes.md to write the section into")
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    maps, rates = {}, {}
    for key, (title, setup, linearised) in MAPS.items():
        log(f"robustness map, {title} ({len(STIFFNESS) * len(DAMPING)} runs of 10 s)")
        maps[key] = robustness_map(setup)
        if linearised:
            log(f"period-map growth rates, {title} ({len(STIFFNESS)} linearisations)")
            rates[key] = growth_rates(setup)
    figure(maps, rates, out / "robustness_map.png")
    sea_sim = pathlib.Path(args.sea_sim)
    pushes = push_table(sea_sim, PUSH_SETUPS, [])
    converged = push_table(sea_sim, PUSH_CONVERGED, PUSHED_AT_3_S)
    excited = push_table(sea_sim, PUSH_EXCITED, PUSHED_AT_4_S)
    parts = push_table(sea_sim, PUSH_PARTS, [])
    proxy = push_table(sea_sim, PUSH_PROXY, [])
    tables = {
        "pushed_at_1_s": pushes,
        "pushed_at_3_s": converged,
        "pushed_at_4_s_excited": excited,
        "parts": parts,
        "proxy": proxy,
    }
    (out / "push_table.json").write_text(json.dumps(tables, indent=2))
    markdown = push_markdown(pushes) + ["", "Pushed at 3 s:", ""] + push_markdown(converged)
    markdown += ["", "Pushed at 4 s, without and with the legs (and the torso) excited for the identification:", ""]
    markdown += push_markdown(excited)
    markdown += ["", "One part of the design changed per row:", ""] + push_markdown(parts)
    markdown += ["", "On the ground against the proxy (welded feet, the wrench check, joint limits ending the run):", ""]
    markdown += proxy_markdown(pushes, proxy)
    (out / "push_table.md").write_text("\n".join(markdown) + "\n")
    model_errors = model_error_table()
    (out / "model_errors.md").write_text("\n".join(model_error_markdown(model_errors)) + "\n")
    noise = noise_table()
    (out / "noise.md").write_text("\n".join(noise_markdown(noise)) + "\n")
    report = {
        "model_errors": model_errors,
        "noise": noise,
        "stiffness_scales": STIFFNESS,
        "damping_scales": DAMPING,
        "maps": maps,
        "growth_rates": rates,
        "eigenvalue_boundaries": {k: boundaries(v) for k, v in rates.items()},
        "pushes": pushes,
        "pushes_converged": converged,
        "pushes_excited": excited,
        "pushes_parts": parts,
        "pushes_proxy": proxy,
    }
    (out / "robot_rate.json").write_text(json.dumps(report, indent=2, allow_nan=True))
    if args.outcomes is not None:
        write_outcomes(args.outcomes, outcomes_section(report))
    completed = {k: sum(s == "completed" for row in m["status"] for s in row) for k, m in maps.items()}
    log(f"completed runs: {completed} of {len(STIFFNESS) * len(DAMPING)} each; wrote {out}/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
