"""Import a Python file of the repository that is not in a package (``scripts/``,
``examples/``, ``benchmarks/``) as a module, for the tests beside this one (see conftest.py)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

#: The repository's root.
ROOT = Path(__file__).resolve().parents[1]


def load_file(relative: str) -> ModuleType:
    """The file ``relative`` to the repository's root (e.g. ``"scripts/landing_impulse.py"``)
    imported as the module named by its stem, registered in ``sys.modules`` first (its
    dataclasses look their module up there while they are made)."""
    path = ROOT / relative
    spec = importlib.util.spec_from_file_location(path.stem, path)
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot import {path}")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module
