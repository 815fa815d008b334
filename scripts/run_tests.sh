#!/usr/bin/env bash
# Creates the project virtual environment .venv (once), installs sea-momentum (built for this
# CPU) with the test extras into it, then runs all tests: cargo tests of every Rust crate (sea_py
# included, linked against libpython), the API docs' links (scripts/check_rustdoc.py), then
# pytest (which also checks the stub against the module with mypy's stubtest, and installs a
# wheel of the same build into a fresh environment with numpy alone: python_tests/test_wheel.py).
# A failed import of sea_momentum fails the run.
#
# `SEA_INSTALL=wheel bash scripts/run_tests.sh` tests the distributable wheel instead
# (scripts/build_wheel.sh: baseline and x86-64-v3 modules, two more full builds of the
# extension; about 40 minutes on 2 cores): installed into .venv, and test_wheel.py checks both
# modules, the choice between them and, where qemu-x86_64 is installed, older CPUs.
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/setup_env.sh
ensure_libpython

echo "== cargo tests"
cargo test --release --workspace
# The walks of robots from example-robot-data (installed with the test extras, found through
# VIRTUAL_ENV); ignored by a plain `cargo test`, where the models may be missing.
cargo test --release -p sea_scenario --test integration -- --ignored talos_walks

echo "== rustdoc: no broken or private links (units in brackets allowed)"
python3 scripts/check_rustdoc.py

echo "== pytest"
python -m pytest python_tests -q -p no:cacheprovider

print_activation_hint
