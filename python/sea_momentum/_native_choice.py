"""Chooses the compiled module at import: the distributable wheel (``scripts/build_wheel.sh``)
ships two builds of the same Rust extension, ``_native`` for any x86-64 CPU (or the building
machine's, for ``pip install .``) and ``_native_v3`` for x86-64-v3 (AVX2, FMA, BMI2: the
kernels' fused multiply-adds and wider vectors). The second is used where the CPU has those
features (the baseline module checks them, with the operating system's support of the AVX
registers), unless the environment variable ``SEA_MOMENTUM_NATIVE=baseline`` asks for the first.

The chosen module is registered as ``sea_momentum._native``, so every import of that name, the
stub ``_native.pyi`` and pickling (its classes' ``__module__``) see the one module in use.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import sys
from types import ModuleType

ENVIRONMENT_VARIABLE = "SEA_MOMENTUM_NATIVE"
"""Environment variable choosing the compiled module: ``auto`` (default) or ``baseline``."""

CHOICES = ("auto", "baseline")
"""The values ``SEA_MOMENTUM_NATIVE`` may take."""

BASELINE = "sea_momentum._native"
"""The module every build ships."""

X86_64_V3 = "sea_momentum._native_v3"
"""The module built for x86-64-v3, shipped by the wheel on x86-64 only."""


def _requested() -> str:
    """The value of ``SEA_MOMENTUM_NATIVE`` (``auto`` when unset); an error names the allowed ones."""
    requested = os.environ.get(ENVIRONMENT_VARIABLE, "auto").strip().lower() or "auto"
    if requested not in CHOICES:
        raise ImportError(
            f"{ENVIRONMENT_VARIABLE}={os.environ[ENVIRONMENT_VARIABLE]!r} is not one of {', '.join(CHOICES)}"
        )
    return requested


def choose_native_module() -> ModuleType:
    """Imports the baseline module, then the x86-64-v3 one where it is shipped, wanted and the
    CPU runs it; registers the chosen one as ``sea_momentum._native`` and returns it."""
    baseline = importlib.import_module(BASELINE)
    wanted = _requested() == "auto"
    if not (wanted and importlib.util.find_spec(X86_64_V3) is not None and baseline.cpu_supports_x86_64_v3()):
        return baseline
    chosen = importlib.import_module(X86_64_V3)
    sys.modules[BASELINE] = chosen
    package = sys.modules[__package__]
    package._native = chosen  # type: ignore[attr-defined]
    return chosen


NATIVE_MODULE: str = choose_native_module().__name__.rsplit(".", 1)[-1]
"""The compiled module in use: ``_native`` or ``_native_v3``."""
