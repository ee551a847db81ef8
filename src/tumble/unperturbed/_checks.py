"""Input checks shared by the closed-form motions (plain numerics, below both of them)."""

from __future__ import annotations

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError, check_finite


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


def moments(inertia: ArrayLike) -> FloatArray:
    """``inertia`` as a float array of three moments, in the order given (no other check).

    Parameters
    ----------
    inertia : array_like
        Principal moments [inertia unit], any shape holding three values.

    Returns
    -------
    ndarray, shape (3,)
        The moments, flattened.

    Raises
    ------
    ParameterError
        ``inertia`` does not hold exactly three values.
    """
    arr = np.asarray(inertia, dtype=float).reshape(-1)
    if arr.shape != (3,):
        raise ParameterError(f"inertia must have 3 moments, got {arr.size}")
    return arr


def finite_vector(field: str, values: ArrayLike) -> FloatArray:
    """``values`` as a float array of three components, refused unless each is finite.

    Parameters
    ----------
    field : str
        The name the error message gives the input (``field[i]`` for a component).
    values : array_like
        A vector's components [any unit], any shape holding three values.

    Returns
    -------
    ndarray, shape (3,)
        The components, flattened.

    Raises
    ------
    ParameterError
        ``values`` does not hold exactly three values, or one is NaN or infinite.
    """
    arr = np.asarray(values, dtype=float).reshape(-1)
    if arr.shape != (3,):
        raise ParameterError(f"{field} must have 3 components, got {arr.size}")
    for i, value in enumerate(arr):
        check_finite(f"{field}[{i}]", float(value))
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
