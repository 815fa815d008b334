"""The array types of the package, defined once: every array the package returns or holds is
annotated with one of these ``numpy.typing.NDArray`` aliases (shapes are in each docstring);
array arguments are ``numpy.typing.ArrayLike`` (converted to float64 by the native module).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

__all__ = ["AnyArray", "BoolArray", "ComplexArray", "FloatArray", "IntArray"]

#: float64 array: states, matrices, time series (SI units).
FloatArray = npt.NDArray[np.float64]
#: complex128 array: eigenvalues and eigenvectors.
ComplexArray = npt.NDArray[np.complex128]
#: int64 array: indices and counts.
IntArray = npt.NDArray[np.int64]
#: bool array: masks (e.g. which runs of a sweep completed).
BoolArray = npt.NDArray[np.bool_]
#: An array whose dtype depends on its content (a sweep's columns: float64, int64 or str).
AnyArray = npt.NDArray[Any]
