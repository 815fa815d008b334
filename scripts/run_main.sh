#!/usr/bin/env bash
# The main job: installs sea-momentum and reproduces the paper's three experiments on the iCub
# (figures, MCAP logs, outcome table beside the paper's), then the dynamics check and the
# benchmarks. Everything goes under out/ (or the directory given as $1).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out}"
mkdir -p "$out"

echo "== installing sea-momentum (release build) with Pinocchio, iCub models, scipy, mcap"
python3 -m pip install --quiet --disable-pip-version-check ".[test]"
cargo build --release -p sea_sim

echo "== the paper's experiments (python -m sea_momentum reproduce)"
python3 -m sea_momentum reproduce --out "$out"

echo "== sea-sim on the tracking scenario (native binary, MCAP + summary)"
./target/release/sea-sim run scenarios/paper/tracking.toml --mcap "$out/tracking_sea_sim.mcap" \
    --summary "$out/tracking_sea_sim_summary.json" --quiet > /dev/null

echo "== dynamics check on urdf/icub25.urdf"
python3 -m sea_momentum check --urdf urdf/icub25.urdf --out "$out"

echo "== native benchmark (sea-sim bench)"
./target/release/sea-sim bench --urdf urdf/icub25.urdf --json | tee "$out/bench_native.json"

echo "== benchmark from Python beside Pinocchio"
python3 python_tests/bench_vs_pinocchio.py --urdf urdf/icub25.urdf --json "$out/bench_python.json"

echo "== done: figures, logs, outcomes.md and summary.json in $out/"
