"""The typed stub ``python/sea_momentum/_native.pyi`` matches the compiled module: mypy's
stubtest imports ``sea_momentum._native`` and compares every class, function, property,
signature and default with the stub (both directions)."""

from __future__ import annotations

import subprocess
import sys

import mypy.stubtest  # noqa: F401  (a test dependency: missing means failed, not skipped)


def test_stub_matches_the_native_module(tmp_path):
    # Run from an empty directory so mypy's cache lands there and the installed package is used.
    result = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "sea_momentum._native"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stdout + result.stderr
