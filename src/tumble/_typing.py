"""Type aliases shared by the package."""

from __future__ import annotations

from typing import Any, TypeAlias

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
"""A float64 array of any shape."""

ArrayLike = Any
"""Anything numpy can turn into a float array (scalar, sequence, array)."""

ComplexArray = NDArray[np.complex128]
"""A complex128 array (complex-step differentiation of the right-hand sides)."""

BoolArray = NDArray[np.bool_]
"""A boolean mask."""

IntArray = NDArray[np.int_]
"""An array of integers (indices, orders)."""

Json: TypeAlias = float | int | str | bool | list["Json"] | dict[str, "Json"] | None
"""A value a JSON or TOML file can hold."""
