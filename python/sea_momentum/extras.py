"""The optional dependencies (extras of ``pyproject.toml``): the library itself needs numpy only.

=============  ====================================  ==============================================
extra          packages                              what needs them
=============  ====================================  ==============================================
``plots``      matplotlib                            figures and robot pictures (``pictures``,
                                                     ``contact_pictures``, ``reproduce``)
``robots``     icub-models, example-robot-data       the robots' URDFs and meshes (``package://``)
``check``      pin (Pinocchio)                       the dynamics checked against Pinocchio, its
                                                     benchmark
``cluster``    ray                                   ``sweep(..., backend="ray")``
``examples``   mujoco                                the MuJoCo example
``test``       all of the above and the test tools   ``scripts/run_tests.sh``
=============  ====================================  ==============================================
"""

from __future__ import annotations

import importlib.util

#: The extra that installs each optional top-level module.
EXTRA_OF_MODULE = {"matplotlib": "plots", "pinocchio": "check", "ray": "cluster", "mujoco": "examples"}

#: The PyPI package of each optional top-level module (where the names differ).
PACKAGE_OF_MODULE = {"pinocchio": "pin"}


def require(module: str, needed_by: str) -> None:
    """Raises an ImportError naming the extra to install when the top-level ``module`` (one of
    ``EXTRA_OF_MODULE``) is not installed; ``needed_by`` names what needs it."""
    if module not in EXTRA_OF_MODULE:
        raise ValueError(f"module {module!r} is not an optional dependency; known: {', '.join(EXTRA_OF_MODULE)}")
    if importlib.util.find_spec(module) is None:
        package = PACKAGE_OF_MODULE.get(module, module)
        raise ImportError(
            f"{needed_by} needs {module}, which is not installed: "
            f"pip install 'sea-momentum[{EXTRA_OF_MODULE[module]}]' (or pip install {package})",
            name=module,
        )


def require_plots(needed_by: str) -> None:
    """:func:`require` for matplotlib (the extra ``plots``)."""
    require("matplotlib", needed_by)
