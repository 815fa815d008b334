"""Shared set-up of the Python tests: the test helpers beside them.

The helpers are plain modules in this folder, imported by name from any test file:

- ``pin_reference.py``: Pinocchio in sea_momentum's conventions (validated by
  ``test_pin_reference.py``), the reference of the dynamics comparisons;
- ``urdf_gen.py``: random URDF trees for those comparisons (checked by ``test_urdf_gen.py``);
- ``load_file.py``: a script, example or benchmark of the repository imported as a module;
- ``bench_vs_pinocchio.py``: a script (the Python benchmark), not a test.

pytest puts this folder on ``sys.path`` when it loads this conftest (in its default "prepend"
import mode: the folder is not a package), before any test module is collected; the line below
does the same in the other import modes, so no test file touches ``sys.path``.
"""

from __future__ import annotations

import pathlib
import sys

#: This folder, where the helpers are.
HELPERS = pathlib.Path(__file__).resolve().parent

if str(HELPERS) not in sys.path:
    sys.path.insert(0, str(HELPERS))
