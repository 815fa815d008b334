#!/usr/bin/env bash
# Installs everything the tests need (Rust crates via cargo, the Python package and its test
# dependencies via pip) and runs all tests: cargo tests of the Rust crates, then pytest.
set -euo pipefail
cd "$(dirname "$0")/.."

echo "== installing sea-momentum (release build) and test dependencies"
python3 -m pip install --quiet --disable-pip-version-check ".[test]"

echo "== cargo tests"
# sea_py is an extension module (no libpython to link a test binary against): tested by pytest.
cargo test --release --workspace --exclude sea_py

echo "== pytest"
python3 -m pytest python_tests -q -p no:cacheprovider
