"""Input checks shared by the closed-form motions (plain numerics, below both of them)."""

from __future__ import annotations

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError


def finite_array(field: str, values: ArrayLike) -> FloatArray:
    """``values`` as a float array, refused unless every element is finite.

    Parameters
    ----------
    field : str
        The name the error message gives the input.
    values : array_like
        Times, rates or angles [any unit], any shape.

    Returns
    -------
    ndarray
        ``np.asarray(values, dtype=float)``.

    Raises
    ------
    ParameterError
        An element is NaN or infinite.
    """
    arr = np.asarray(values, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{field} must be finite")
    return arr
