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
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.errors import IntegrationError, ParameterError

__all__ = ["AVERAGE_RTOL", "AveragingError", "BatchedTorque", "torus_mean"]

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


class BatchedTorque:
    """A torque evaluated at n states at once: ``(t, q (n, 4), omega (n, 3)) -> (n, 3)``.

    Batched calling convention: ``torque(t, q, omega)`` with q of shape (n, 4) and omega of
    shape (n, 3) must return shape (n, 3), or (3,) for a moment that depends on neither (every
    built-in of :mod:`tumble.torques` does). With ``batched=None`` the first call tries this
    and compares two nodes with one-state calls (a one-state ``B @ omega`` could broadcast into
    something wrong); a torque that raises, returns another shape or disagrees is from then on
    called one state at a time (one that works on batches only is trusted). ``batched=False``
    always calls one state at a time (the reference in tests); ``batched=True`` insists.

    Parameters
    ----------
    torque : callable
        ``torque(t, q, omega) -> body moment``.
    batched : bool or None
        The calling convention (None: detect on the first call).
    where : str
        The unperturbed motion, for the message when the torque is not finite there.
    """

    def __init__(self, torque: Any, batched: bool | None = None, where: str = "") -> None:
        self.torque, self.batched, self.where = torque, batched, where

    def _one(self, t: float, q: FloatArray, w: FloatArray) -> FloatArray:
        m = np.asarray(self.torque(t, q, w), dtype=float)
        if m.shape != (3,):
            raise ParameterError(
                f"torque returned shape {m.shape} for one state; it must return the 3 body "
                "components of the moment"
            )
        return m

    def _many(self, t: float, q: FloatArray, w: FloatArray) -> FloatArray | None:
        """The batched call, or None if the torque does not follow the batched convention."""
        n = q.shape[0]
        try:
            m = np.asarray(self.torque(t, q, w), dtype=float)
        except Exception:  # a one-state callable fails on arrays in many ways
            if self.batched:
                raise
            return None
        if m.shape == (3,):
            m = np.broadcast_to(m, (n, 3))
        if m.shape != (n, 3):
            if self.batched:
                raise ParameterError(
                    f"torque returned shape {m.shape} for {n} states; with batched=True it "
                    f"must return ({n}, 3) or (3,)"
                )
            return None
        if self.batched is None:
            # Not node 0: a symmetric grid often makes a rate component vanish there.
            probe = [1 % n, (n // 2 + 3) % n]
            try:
                one = np.array([self._one(t, q[i], w[i]) for i in probe])
            except Exception:  # written for batches only: nothing to compare with
                self.batched = True
                return m
            scale = float(np.max(np.abs(one))) + 1e-300
            self.batched = bool(np.all(np.abs(m[probe] - one) <= 1e-12 * scale))
            if not self.batched:
                return None
        return m

    def __call__(self, t: float, q: FloatArray, w: FloatArray) -> FloatArray:
        m = None if self.batched is False else self._many(t, q, w)
        if m is None:
            self.batched = False
            m = np.array([self._one(t, q[i], w[i]) for i in range(q.shape[0])])
        if not np.all(np.isfinite(m)):
            raise AveragingError(
                f"the torque returned non-finite values on {self.where or 'the motion'}: no "
                "average can be formed"
            )
        return m
