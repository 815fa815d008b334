#!/usr/bin/env bash
# The main job: installs sea-momentum and runs what exists today of the paper's pipeline:
# the dynamics check on the iCub and the benchmarks (native, and from Python beside Pinocchio).
# Writes everything under out/ (or the directory given as $1) and prints a summary.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out}"
mkdir -p "$out"

echo "== installing sea-momentum (release build), Pinocchio and the iCub models for comparison"
python3 -m pip install --quiet --disable-pip-version-check ".[test]"
cargo build --release -p sea_ctrl

echo "== dynamics check on urdf/icub25.urdf"
python3 -m sea_momentum check --urdf urdf/icub25.urdf --out "$out"

echo "== native benchmark (sea-sim bench)"
./target/release/sea-sim bench --urdf urdf/icub25.urdf --json | tee "$out/bench_native.json"

echo "== benchmark from Python beside Pinocchio"
python3 python_tests/bench_vs_pinocchio.py --urdf urdf/icub25.urdf --json "$out/bench_python.json"

echo "== done: results in $out/"
