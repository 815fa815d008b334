#!/usr/bin/env bash
# Creates the project virtual environment .venv (once), builds the distributable wheel
# (scripts/build_wheel.sh: baseline and x86-64-v3 modules) and installs it with the test extras
# into it, then runs all tests: cargo tests of every Rust crate (native build, sea_py included,
# linked against libpython), then pytest on the installed wheel (which also checks the stub
# against the module with mypy's stubtest, and installs the same wheel, $SEA_WHEEL, into a fresh
# environment with numpy alone: python_tests/test_wheel.py). A failed import of sea_momentum
# fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."

export SEA_INSTALL=wheel
source scripts/setup_env.sh
ensure_libpython

echo "== cargo tests"
cargo test --release --workspace

echo "== pytest"
python -m pytest python_tests -q -p no:cacheprovider

print_activation_hint
