#!/usr/bin/env python3
"""Benchmark sea_momentum against Pinocchio from Python, on the same model and random states.

Not a test (timings are reported, never asserted). Each side is called in its own conventions:
the states are generated in ours and converted once, outside the timed loops, to Pinocchio's
(q_pin, v_pin, a_pin) with pin_reference. Operations:

    rnea                        inverse_dynamics(q, nu, nudot)   vs pin.rnea
    crba                        mass_matrix(q)                   vs pin.crba
    centroidal_momentum_matrix  centroidal_momentum_matrix(q)    vs pin.computeCentroidalMap
    frame_jacobian              frame_jacobian(q, frame)         vs pin.computeFrameJacobian
                                                                    (LOCAL_WORLD_ALIGNED)
    frame_jacobian_dot_v        frame_jacobian_dot_v(q, nu, f)   vs pin.forwardKinematics(q, v, a0)
                                                                    + getFrameClassicalAcceleration

Timing: time.perf_counter_ns around batches of --batch calls (cycling through --states random
states), --repeat batches after a warm-up, garbage collector off; the figure is the median over
batches of the per-batch mean, in microseconds per call (Python call overhead included on both
sides). If the native benchmark binary exists (default target/release/sea-sim), its
`bench --urdf PATH --json` figures are shown next to the Python ones.

Examples:
    python python_tests/bench_vs_pinocchio.py
    python python_tests/bench_vs_pinocchio.py --urdf $(python -c "import icub_models;
        print(icub_models.get_model_file('iCubGenova04'))") --joints icub25 --json out.json
"""

from __future__ import annotations

import argparse
import gc
import json
import math
import pathlib
import platform
import statistics
import subprocess
import sys
import time

import numpy as np
import pinocchio as pin

HERE = pathlib.Path(__file__).resolve().parent
REPO = HERE.parent

# Run as a script, so its folder (python_tests/, with pin_reference.py) is on sys.path.
from pin_reference import ICUB25_JOINTS, PinReference, random_state  # noqa: E402

OPS = [
    "rnea",
    "crba",
    "centroidal_momentum_matrix",
    "frame_jacobian",
    "frame_jacobian_dot_v",
]
NATIVE_KEYS = {op: f"{op}_us" for op in OPS}


def parse_args(argv=None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--urdf", default=str(REPO / "urdf" / "icub25.urdf"),
                    help="URDF file (default: urdf/icub25.urdf of the repository)")
    ap.add_argument("--joints", default=None,
                    help="comma-separated joint list (reduced model, others locked at 0), or "
                         "'icub25' for the paper's 25 iCub joints; default: all joints")
    ap.add_argument("--frame", default=None,
                    help="frame for the Jacobian benchmarks (default: l_sole if present)")
    ap.add_argument("--repeat", type=int, default=50, help="number of timed batches")
    ap.add_argument("--batch", type=int, default=2000, help="calls per batch")
    ap.add_argument("--states", type=int, default=64, help="number of random states")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--native", default=str(REPO / "target" / "release" / "sea-sim"),
                    help="native benchmark binary (skipped if it does not exist)")
    ap.add_argument("--no-native", action="store_true", help="do not run the native benchmark")
    ap.add_argument("--json", metavar="FILE", default=None, help="also write results as JSON")
    return ap.parse_args(argv)


def time_calls(fn, arg_list, repeat: int, warmup_batches: int = 2) -> dict:
    """Median over batches of the mean time per call, in microseconds."""
    n = len(arg_list)
    for _ in range(warmup_batches):
        for a in arg_list:
            fn(*a)
    per_call = []
    gc_was_enabled = gc.isenabled()
    gc.disable()
    try:
        for _ in range(repeat):
            t0 = time.perf_counter_ns()
            for a in arg_list:
                fn(*a)
            t1 = time.perf_counter_ns()
            per_call.append((t1 - t0) / n / 1e3)
    finally:
        if gc_was_enabled:
            gc.enable()
    return {
        "median_us": statistics.median(per_call),
        "min_us": min(per_call),
        "max_us": max(per_call),
        "batches": repeat,
        "calls_per_batch": n,
    }


def empty_loop_us(arg_list, repeat: int) -> float:
    """Cost of the timing loop itself with a trivial callable (for reference)."""
    def nop(*_a):
        return None

    return time_calls(nop, arg_list, repeat)["median_us"]


def run_native(binary: str, urdf: str, timeout: float = 600.0) -> tuple[dict | None, str]:
    path = pathlib.Path(binary)
    if not path.exists():
        return None, f"{binary} not found"
    cmd = [str(path), "bench", "--urdf", urdf, "--json"]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return None, f"{' '.join(cmd)}: {exc}"
    if proc.returncode != 0:
        return None, f"{' '.join(cmd)} exited with {proc.returncode}: {proc.stderr.strip()[-500:]}"
    out = proc.stdout.strip()
    data = None
    try:
        data = json.loads(out)
    except json.JSONDecodeError:
        # tolerate log lines around the JSON object: take the last parsable {...} line/block
        start = out.rfind("\n{")
        candidates = [out[start + 1:]] if start >= 0 else []
        if out.find("{") >= 0:
            candidates.append(out[out.find("{"):])
        for c in candidates:
            try:
                data = json.loads(c)
                break
            except json.JSONDecodeError:
                continue
    if not isinstance(data, dict):
        return None, f"{' '.join(cmd)}: no JSON object in output: {out[:300]!r}"
    return data, " ".join(cmd)


def fmt(x) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return f"{x:.3f}"


def main(argv=None) -> int:
    args = parse_args(argv)
    urdf = str(pathlib.Path(args.urdf).resolve())
    if args.joints is None:
        joints = None
    elif args.joints.strip().lower() == "icub25":
        joints = list(ICUB25_JOINTS)
    else:
        joints = [j.strip() for j in args.joints.split(",") if j.strip()]

    try:
        import sea_momentum as sm  # noqa: PLC0415
    except ImportError as exc:
        sm = None
        print(f"warning: sea_momentum not importable ({exc}); timing Pinocchio only",
              file=sys.stderr)

    ours = None
    if sm is not None:
        ours = sm.Model.from_urdf(urdf, joints=joints) if joints is not None else \
            sm.Model.from_urdf(urdf)
        ref_joints = list(ours.joint_names)
    else:
        ref_joints = joints
    ref = PinReference(urdf, joints=ref_joints)
    model, data = ref.model, ref.data

    frame = args.frame
    if frame is None:
        frame = "l_sole" if "l_sole" in ref.frame_ids else ref.frame_names[-1]
    fid = ref.frame_id(frame)
    LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

    rng = np.random.default_rng(args.seed)
    states = [random_state(rng, ref.n_joints) for _ in range(args.states)]
    zero = np.zeros(ref.nv)
    pin_states = [
        (ref.q_pin(q), ref.v_pin(q, nu), ref.a_pin(q, nu, nudot), ref.a_pin(q, nu, zero))
        for q, nu, nudot in states
    ]

    def cycle(items):
        return [items[i % len(items)] for i in range(args.batch)]

    pin_fk_acc = pin.getFrameClassicalAcceleration
    pin_fk = pin.forwardKinematics

    def pin_jdot(qp, vp, a0):
        pin_fk(model, data, qp, vp, a0)
        return pin_fk_acc(model, data, fid, LWA)

    pin_ops = {
        "rnea": (pin.rnea, cycle([(model, data, qp, vp, ap) for qp, vp, ap, _ in pin_states])),
        "crba": (pin.crba, cycle([(model, data, qp) for qp, _, _, _ in pin_states])),
        "centroidal_momentum_matrix": (
            pin.computeCentroidalMap, cycle([(model, data, qp) for qp, _, _, _ in pin_states])),
        "frame_jacobian": (
            pin.computeFrameJacobian,
            cycle([(model, data, qp, fid, LWA) for qp, _, _, _ in pin_states])),
        "frame_jacobian_dot_v": (pin_jdot, cycle([(qp, vp, a0) for qp, vp, _, a0 in pin_states])),
    }
    our_ops = {}
    if ours is not None:
        our_ops = {
            "rnea": (ours.inverse_dynamics, cycle([(q, nu, nd) for q, nu, nd in states])),
            "crba": (ours.mass_matrix, cycle([(q,) for q, _, _ in states])),
            "centroidal_momentum_matrix": (
                ours.centroidal_momentum_matrix, cycle([(q,) for q, _, _ in states])),
            "frame_jacobian": (ours.frame_jacobian, cycle([(q, frame) for q, _, _ in states])),
            "frame_jacobian_dot_v": (
                ours.frame_jacobian_dot_v, cycle([(q, nu, frame) for q, nu, _ in states])),
        }

    native, native_note = (None, "disabled")
    if not args.no_native:
        native, native_note = run_native(args.native, urdf)

    results = {}
    for op in OPS:
        row = {"pin_us": None, "ours_us": None, "ratio": None, "native_us": None}
        fn, al = pin_ops[op]
        row["pin"] = time_calls(fn, al, args.repeat)
        row["pin_us"] = row["pin"]["median_us"]
        if op in our_ops:
            fn, al = our_ops[op]
            row["ours"] = time_calls(fn, al, args.repeat)
            row["ours_us"] = row["ours"]["median_us"]
            row["ratio"] = row["ours_us"] / row["pin_us"]
        if native is not None:
            v = native.get(NATIVE_KEYS[op])
            row["native_us"] = float(v) if isinstance(v, (int, float)) else None
        results[op] = row
    loop_us = empty_loop_us(cycle([(q,) for q, _, _ in states]), args.repeat)

    print(f"model: {urdf}")
    print(f"joints: {ref.n_joints} ({'given list' if joints else 'all'}), nv = {ref.nv}, "
          f"frame: {frame}")
    print(f"pinocchio {pin.__version__}, python {platform.python_version()}, "
          f"{args.repeat} batches x {args.batch} calls, {args.states} states")
    print(f"native: {native_note}"
          + ("" if joints is None or native is None else
             " (native figures use the URDF's own joints, not --joints)"))
    print()
    header = (f"{'operation':<28} {'ours py [us]':>13} {'pin py [us]':>12} "
              f"{'ours/pin':>9} {'ours native [us]':>17}")
    print(header)
    print("-" * len(header))
    for op in OPS:
        r = results[op]
        print(f"{op:<28} {fmt(r['ours_us']):>13} {fmt(r['pin_us']):>12} "
              f"{fmt(r['ratio']):>9} {fmt(r['native_us']):>17}")
    print("-" * len(header))
    print(f"(empty timing loop: {loop_us:.3f} us per call, included in the Python figures)")

    if args.json:
        out = {
            "urdf": urdf,
            "joints": ref.joint_names,
            "nv": ref.nv,
            "frame": frame,
            "repeat": args.repeat,
            "batch": args.batch,
            "states": args.states,
            "seed": args.seed,
            "pinocchio_version": pin.__version__,
            "python_version": platform.python_version(),
            "sea_momentum_available": ours is not None,
            "empty_loop_us": loop_us,
            "results": results,
            "native": native,
            "native_note": native_note,
        }
        pathlib.Path(args.json).write_text(json.dumps(out, indent=2))
        print(f"wrote {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
