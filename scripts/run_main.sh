#!/usr/bin/env bash
# The main job: installs sea-momentum and reproduces the paper's three experiments on the iCub
# (figures, MCAP logs, outcome table beside the paper's), Talos balancing on two feet (a robot
# set up by `sea-sim init`), the iCub walking (natively, and from Python in MuJoCo with SEAs),
# then the dynamics check and the benchmarks. Everything goes under out/ (or the directory
# given as $1). Installs sea-momentum with the extra `main` (matplotlib, the robots' packages,
# Pinocchio, MuJoCo: what this job uses) into the project virtual environment .venv, created
# on the first run (see scripts/setup_env.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out}"
mkdir -p "$out"

export SEA_EXTRAS=main
source scripts/setup_env.sh
echo "== building sea-sim (reuses the crates compiled for the wheel)"
# --bin, not -p sea_sim: features are then resolved over the whole workspace, as for the wheel
# (sea_py depends on every crate), so no dependency is compiled a second time.
cargo build --release --bin sea-sim
sea_sim="${CARGO_TARGET_DIR:-target}/release/sea-sim"

echo "== the paper's experiments (python -m sea_momentum reproduce)"
python -m sea_momentum reproduce --out "$out"

echo "== sea-sim on the tracking scenario (native binary, MCAP + summary)"
"$sea_sim" run scenarios/paper/tracking.toml --mcap "$out/tracking_sea_sim.mcap" \
    --summary "$out/tracking_sea_sim_summary.json" --quiet > /dev/null

echo "== a robot set up by sea-sim init: Talos on two feet (example-robot-data, CoM sinusoid 1 cm / 0.2 Hz, 5 s)"
# The scenario names its URDF as package://example-robot-data/...: found in the share folder of
# the environment's cmeel prefix (example-robot-data, of the extra `robots`).
"$sea_sim" run scenarios/robots/talos_two_feet.toml --mcap "$out/talos_two_feet.mcap" \
    --summary "$out/talos_two_feet_summary.json" --quiet > /dev/null
# The CoM plot, and Talos drawn along the run (talos_two_feet_strip.png, talos_two_feet.gif)
# beside the iCub's pictures.
python scripts/plot_com.py scenarios/robots/talos_two_feet.toml "$out/talos_two_feet_com.png" \
    --pictures talos_two_feet

echo "== walking at the robot's rate: the iCub walks 50 steps at 0.3 m/s (and at 0.4 m/s, the stretch) and turns 90 degrees in place (MCAP: footsteps, capture point, swings)"
"$sea_sim" run scenarios/walking/walk_fast.toml --mcap "$out/walk_fast.mcap" \
    --summary "$out/walk_fast_summary.json" --quiet > /dev/null
"$sea_sim" run scenarios/walking/turn_in_place.toml --mcap "$out/turn_in_place.mcap" \
    --summary "$out/turn_in_place_summary.json" --quiet > /dev/null
# The stretch, 0.4 m/s (docs/findings/walking.md, "0.4 m/s: 100 steps, and MuJoCo"); its
# outcome is printed whatever it is.
status=0
"$sea_sim" run scenarios/walking/walk_04.toml --summary "$out/walk_04_summary.json" --quiet > /dev/null \
    || status=$?
# 3: the run ended early (a fall or a divergence), which this gait may do; anything else fails.
[ "$status" -eq 0 ] || [ "$status" -eq 3 ]
python3 -c 'import json, sys
d = json.load(open(sys.argv[1]))
print("walk_04, 0.4 m/s: {} after {} steps, {:.2f} m walked".format(
    d["status"], d["steps_taken"], d["distance_walked_m"]))' "$out/walk_04_summary.json"

echo "== our controller from Python walking MuJoCo's SEA iCub: 50 steps at 0.3 m/s, the stiffness estimate x0.7 identified (examples/mujoco_sea_icub.py)"
# The identification learns in single support too, with the central difference (with the
# shipped hold the walk needs 2 s of standing first: docs/findings/mujoco_sea.md).
python examples/mujoco_sea_icub.py --walk scenarios/walking/walk_fast.toml --duration 22 \
    --set controller.stiffness_estimate_scale=0.7 --set controller.stiffness_identification=true \
    --set controller.identification_acceleration=central --set walking.identification_single_support=0.1 \
    --figure "$out/mujoco_sea_walk.png" | tee "$out/mujoco_sea_walk.txt"
echo "== the same at 0.4 m/s (walk_04.toml), the true stiffness estimate: an edge in MuJoCo (docs/findings/walking.md)"
python examples/mujoco_sea_icub.py --walk scenarios/walking/walk_04.toml --duration 22 \
    --figure "$out/mujoco_sea_walk_04.png" | tee "$out/mujoco_sea_walk_04.txt"

echo "== at the robot's rate: robustness maps and pushes of the 100 Hz / 1 kHz loop (scripts/robot_rate.py)"
python scripts/robot_rate.py "$out/robot_rate" --sea-sim "$sea_sim" --outcomes "$out/outcomes.md"
# The push scenario as shipped (5 N s forward at 1 s, recovered): the push's arrow, the
# observer's estimate on /momentum and the recovery in Foxglove.
"$sea_sim" run scenarios/robot_rate/push_two_feet.toml --mcap "$out/robot_rate/push_two_feet.mcap" \
    --summary "$out/robot_rate/push_two_feet_summary.json" --quiet > /dev/null

echo "== dynamics check on urdf/icub25.urdf"
python -m sea_momentum check --urdf urdf/icub25.urdf --out "$out"

echo "== native benchmark (sea-sim bench)"
"$sea_sim" bench --urdf urdf/icub25.urdf --json | tee "$out/bench_native.json"

echo "== benchmark from Python beside Pinocchio"
python python_tests/bench_vs_pinocchio.py --urdf urdf/icub25.urdf --json "$out/bench_python.json"

echo "== done: figures, logs, outcomes.md and summary.json in $out/"
print_activation_hint
