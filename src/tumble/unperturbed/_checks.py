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


def whole_number(field: str, value: object, least: int) -> int:
    """``value`` as an int, refused unless it is an integer (Python or numpy) ≥ ``least``.

    Parameters
    ----------
    field : str
        The name the error message gives the input.
    value : object
        A count or a power [1].
    least : int
        Smallest allowed value [1].

    Returns
    -------
    int
        ``int(value)``.

    Raises
    ------
    ParameterError
        ``value`` is not an integer, or below ``least``.
    """
    if not isinstance(value, int | np.integer) or value < least:
        raise ParameterError(
            f"{field} = {value!r} is outside the allowed range: integers ≥ {least}"
        )
    return int(value)
