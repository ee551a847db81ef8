"""Averages over fast phases: the periodic trapezoidal rule, refined until it converges.

For a smooth 2π-periodic integrand the trapezoidal rule with n equally spaced nodes converges
geometrically (the error is the size of the integrand's Fourier coefficients of order n), so
doubling n until two results agree gives the average to round-off at a known cost. Doubling
reuses the previous nodes: the new nodes are the midpoints. An integrand that does not
converge (a near-singular one: a separatrix, a pole on the path) is reported, never returned.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from tumble._typing import FloatArray
from tumble.errors import IntegrationError

__all__ = ["AVERAGE_RTOL", "AveragingError", "torus_mean"]

AVERAGE_RTOL = 1e-12
"""Default relative tolerance of the averages (the engine's right-hand sides are then exact
to about this, far below any integration tolerance in use)."""


class AveragingError(IntegrationError):
    """The average over the fast phases did not converge (exit code 3)."""


def torus_mean(
    f: Callable[..., FloatArray],
    dims: int = 1,
    *,
    rtol: float = AVERAGE_RTOL,
    atol: float = 0.0,
    n_start: int = 8,
    n_max: int = 4096,
    what: str = "the average over the fast phases",
) -> tuple[FloatArray, int]:
    """Mean of ``f`` over the torus [0, 2π)^dims by the periodic trapezoidal rule.

    Parameters
    ----------
    f : callable
        ``f(*phases) -> array``; each phase is an array of nodes, broadcast against the others
        (shape (n,) for one phase, (n, 1) and (1, n) for two), and the result has the phases'
        broadcast shape in its last ``dims`` axes (leading axes are components).
    dims : {1, 2}
        Number of independent fast phases.
    rtol, atol : float
        Accept when two successive refinements differ by at most
        ``atol + rtol·max|mean|`` in every component.
    n_start, n_max : int
        First and largest number of nodes per phase.
    what : str
        Name of the average, for the error message.

    Returns
    -------
    mean : ndarray
        The average of each component.
    n : int
        Nodes per phase used.

    Raises
    ------
    AveragingError
        If the rule has not converged with ``n_max`` nodes per phase.
    """
    if dims not in (1, 2):
        raise ValueError("dims must be 1 or 2")

    def grid(n: int, offset: float) -> list[FloatArray]:
        nodes = np.asarray((np.arange(n) + offset) * (2.0 * math.pi / n), dtype=float)
        if dims == 1:
            return [nodes]
        return [nodes[:, None], nodes[None, :]]

    def mean_of(values: FloatArray) -> FloatArray:
        return np.asarray(values, dtype=float).mean(axis=tuple(range(-dims, 0)))

    n = n_start
    old = mean_of(f(*grid(n, 0.0)))
    while n < n_max:
        if dims == 1:
            # Doubling: the old nodes plus the midpoints.
            new = 0.5 * (old + mean_of(f(*grid(n, 0.5))))
        else:
            new = mean_of(f(*grid(2 * n, 0.0)))
        n *= 2
        scale = float(np.max(np.abs(new))) if np.size(new) else 0.0
        if np.all(np.abs(new - old) <= atol + rtol * scale):
            return new, n
        old = new
    raise AveragingError(
        f"{what} did not converge with {n_max} nodes per phase: the integrand is nearly "
        "singular on the unperturbed motion (a separatrix, a resonance, or a pole on the path)"
    )
