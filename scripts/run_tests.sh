#!/usr/bin/env bash
# Creates the project virtual environment .venv (once), installs sea-momentum and the test
# dependencies into it, then runs all tests: cargo tests of every Rust crate (sea_py included,
# linked against libpython), then pytest (which also checks the stub against the module with
# mypy's stubtest). A failed import of sea_momentum fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/setup_env.sh
ensure_libpython

echo "== cargo tests"
cargo test --release --workspace

echo "== pytest"
python -m pytest python_tests -q -p no:cacheprovider

print_activation_hint
