"""Averages over fast phases: the periodic trapezoidal rule, refined until it converges.

For a smooth 2π-periodic integrand the trapezoidal rule with n equally spaced nodes converges
geometrically (the error is the size of the integrand's Fourier coefficients of order n), so
doubling n until two results agree gives the average to round-off at a known cost. Doubling
reuses the previous nodes: the new nodes are the midpoints. An integrand that does not
converge (a near-singular one: a separatrix, a pole on the path) is reported, never returned.

A periodic integrand that is smooth except for kinks at nodes of every grid (such as
w ∘ |w| of the quadratic drag law, kinked where a component of w(φ) vanishes, at multiples of
π/2) converges only algebraically: each smooth piece contributes an Euler–Maclaurin series
in even powers of the step h, so the trapezoidal error falls like h⁴ (a jump in the third
derivative). Romberg (Richardson) extrapolation of the doubling sequence removes one even
power per level; ``torus_mean(..., extrapolate=True)`` runs it beside the plain test (see
there).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.errors import IntegrationError, ParameterError
from tumble.kernels.limits import AVERAGE_RTOL
from tumble.torques import (
    ConstantBodyTorque,
    InternalDissipation,
    LinearDrag,
    QuadraticDrag,
    ScaledTorque,
    TorqueSum,
    ZeroTorque,
)

__all__ = ["AVERAGE_RTOL", "AveragingError", "BatchedTorque", "rate_only", "torus_mean"]


class AveragingError(IntegrationError):
    """The average over the fast phases did not converge (exit code 3)."""


_ROMBERG_PREVIOUS = 1e3
"""How close the extrapolated value must already have been one level before it is accepted,
in units of the tolerance (see :func:`torus_mean`). A single small change can be a
coincidence; a second one within 10³·tol shows the sequence converging. For the quadratic law
of (1.2) the changes of the Romberg diagonal shrink 400–8000× per doubling near the
tolerance (measured), so the pair is met at the level of the single test or one later."""


@functools.cache
def _romberg_weights(levels: int) -> FloatArray:
    """W with R(j, j) = Σ_i W[j, i] T_i: the diagonal of the Romberg table of T_0 … T_{L−1},
    read-only and cached per number of levels.

    The recurrence R(j, m) = R(j, m−1) + (R(j, m−1) − R(j−1, m−1))/(4^m − 1), run on weight
    vectors (the rows of W sum to 1). Row j depends on j only, not on ``levels``.
    """
    rows = [np.eye(levels)[0]]
    weights = np.zeros((levels, levels))
    weights[0] = rows[0]
    for j in range(1, levels):
        fresh = [np.eye(levels)[j]]
        for m, coarse in enumerate(rows, start=1):
            fresh.append(fresh[-1] + (fresh[-1] - coarse) / (4.0**m - 1.0))
        weights[j], rows = fresh[-1], fresh
    weights.setflags(write=False)
    return weights


def _first_accepted(
    means: list[FloatArray], first: int, rtol: float, atol: float, extrapolate: bool
) -> tuple[int | None, FloatArray]:
    """The first level j ≥ ``first`` that passes the tests of :func:`torus_mean`, and its value.

    ``means`` are the trapezoidal means T_0, T_1, … (flat, one entry per component), and
    levels 1 … ``first`` − 1 have failed already. All levels are tested at once: one array
    operation per test instead of one per level.
    """
    # ufunc reductions, not np.max or np.diff: on a few numbers their Python wrappers cost more
    # than the arithmetic, and this runs at every level of every average.
    T = np.array(means)
    tol = atol + rtol * np.maximum.reduce(np.abs(T), axis=1, initial=0.0)
    # Entry j − 1 is level j (level 0 has nothing to compare with).
    ok = np.maximum.reduce(np.abs(T[1:] - T[:-1]), axis=1, initial=0.0) <= tol[1:]
    plain = ok
    D = T
    if extrapolate and len(T) > 2:
        D = _romberg_weights(len(T)) @ T
        change = np.maximum.reduce(np.abs(D[1:] - D[:-1]), axis=1, initial=0.0)
        ok = plain.copy()
        ok[1:] |= (change[1:] <= tol[2:]) & (change[:-1] <= _ROMBERG_PREVIOUS * tol[2:])
    hits = np.flatnonzero(ok[first - 1 :])
    if hits.size == 0:
        return None, T[-1]
    j = first + int(hits[0])
    # The plain test first: a smooth integrand gets its converged trapezoidal mean.
    return j, T[j] if plain[j - 1] else D[j]


def torus_mean(
    f: Callable[..., FloatArray],
    dims: int = 1,
    *,
    rtol: float = AVERAGE_RTOL,
    atol: float = 0.0,
    n_start: int = 8,
    n_max: int = 4096,
    what: str = "the average over the fast phases",
    extrapolate: bool = False,
    known: FloatArray | None = None,
) -> tuple[FloatArray, int]:
    """Mean of ``f`` over the torus [0, 2π)^dims by the periodic trapezoidal rule.

    The nodes (j + offset)·2π/n start at 0, and doubling keeps them: in one dimension each
    level adds the midpoints (every value is computed once); in two, the first call is on
    the grid of 2·``n_start`` nodes per phase, whose even nodes give the coarser mean, and
    each further level is one call on the doubled grid.

    With ``extrapolate`` (one phase only) the doubling sequence T_0, T_1, … also feeds a
    Romberg table, R(j, 0) = T_j, R(j, m) = R(j, m−1) + (R(j, m−1) − R(j−1, m−1))/(4^m − 1),
    whose diagonal D_j = R(j, j) removes the error terms h², h⁴, …, h^{2j} of the
    Euler–Maclaurin series. That series holds for an integrand that is smooth between kinks
    lying on nodes of every level (``n_start`` a multiple of 4 for kinks at multiples of
    π/2); then D_j converges much faster than T_j. Accepted at the first level that passes:
    T_j by the plain test below (checked first, so an analytic integrand, whose trapezoidal
    means converge first, gets the same result as without ``extrapolate``: checked on
    1/(a + cos φ) and exp(c cos φ)), or D_j when |D_j − D_{j−1}| ≤ tol and
    |D_{j−1} − D_{j−2}| ≤ 10³·tol in every component: one small change of D can be a
    coincidence, two successive ones that shrink are the series converging. An integrand
    whose error is not such a series (a kink between nodes, a cusp) does not pass the
    Romberg test and is refined, or reported, as before.

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
        ``tol = atol + rtol·max|mean|`` in every component.
    n_start, n_max : int
        First and largest number of nodes per phase.
    what : str
        Name of the average, for the error message.
    extrapolate : bool
        Also accept the Romberg extrapolation of the doubling sequence (``dims = 1``).
    known : ndarray, optional
        ``f`` already evaluated on the N nodes j·2π/N, shape (..., N), N = ``n_start``·2^p
        (``dims = 1``): every level up to N nodes is served from it. One call on many nodes
        costs about as much as one on a few when the cost is Python's, not the arithmetic's.

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
    _check_mode(dims, n_start, extrapolate, known)
    if dims == 1:
        found = _circle_mean(f, rtol, atol, n_start, n_max, extrapolate, known)
    else:
        found = _torus_mean_2(f, rtol, atol, n_start, n_max)
    if found is not None:
        return found
    raise AveragingError(
        f"{what} did not converge with {n_max} nodes per phase: the integrand is nearly "
        "singular on the unperturbed motion (a separatrix, a resonance, or a pole on the path)"
    )


def _check_mode(dims: int, n_start: int, extrapolate: bool, known: FloatArray | None) -> None:
    """Refuse a combination of :func:`torus_mean`'s options it does not implement: ``dims``
    other than 1 or 2, ``extrapolate`` or ``known`` on two phases, or ``known`` values on a
    number of nodes other than ``n_start``·2^p (arguments as there).

    Raises
    ------
    ValueError
        Naming the option and what it needs.
    """
    if dims not in (1, 2):
        raise ValueError("dims must be 1 or 2")
    if (extrapolate or known is not None) and dims != 1:
        raise ValueError("extrapolate and known need dims = 1")
    stored = 0 if known is None else int(np.shape(known)[-1])
    if stored and (
        stored < n_start or stored % n_start or (stored // n_start) & (stored // n_start - 1)
    ):
        raise ValueError(f"known has {stored} nodes: it needs n_start·2^p")


def _grid(n: int, offset: float, dims: int) -> list[FloatArray]:
    """The nodes (j + offset)·2π/n of each phase, shaped to broadcast against each other."""
    nodes = np.asarray((np.arange(n) + offset) * (2.0 * math.pi / n), dtype=float)
    if dims == 1:
        return [nodes]
    return [nodes[:, None], nodes[None, :]]


def _circle_mean(
    f: Callable[..., FloatArray],
    rtol: float,
    atol: float,
    n_start: int,
    n_max: int,
    extrapolate: bool,
    known: FloatArray | None,
) -> tuple[FloatArray, int] | None:
    """:func:`torus_mean` over one phase (None: not converged with ``n_max`` nodes)."""
    n = n_start
    # Means are kept flat, one row per component: (components,).
    if known is not None and np.shape(known)[-1] > 0:
        stored = int(np.shape(known)[-1])
        table = np.asarray(known, dtype=float)
        lead, table = table.shape[:-1], table.reshape(-1, stored)
    else:
        start = np.asarray(f(*_grid(n, 0.0, 1)), dtype=float)
        lead, table = start.shape[:-1], start.reshape(-1, n)
        stored = n

    def level_mean(n: int, offset: float) -> FloatArray:
        """Mean of f at the nodes (j + offset)·2π/n, from ``table`` where it holds them."""
        if 2 * n <= stored:
            step = stored // n
            values = table[:, int(offset * step) :: step]
        elif offset == 0.0 and n == stored:
            values = table
        else:
            values = np.asarray(f(*_grid(n, offset, 1)), dtype=float).reshape(-1, n)
        return np.add.reduce(values, axis=-1) * (1.0 / n)

    means, nodes = [level_mean(n, 0.0)], [n]
    while nodes[-1] < n_max:
        # The levels held in ``table`` cost no call of f: take them all and test them at
        # once; beyond them, one doubling at a time (the old nodes plus the midpoints).
        tested = len(means)
        while True:
            means.append(0.5 * (means[-1] + level_mean(nodes[-1], 0.5)))
            nodes.append(2 * nodes[-1])
            if nodes[-1] >= n_max or 2 * nodes[-1] > stored:
                break
        level, value = _first_accepted(means, tested, rtol, atol, extrapolate)
        if level is not None:
            return value.reshape(lead), nodes[level]
    return None


def _torus_sum(values: FloatArray) -> FloatArray:
    """Sum over the last two axes: a ufunc reduction over the flattened grid (np.mean's
    wrapper costs more than the arithmetic on the small grids used here)."""
    return np.add.reduce(values.reshape(*values.shape[:-2], -1), axis=-1)


def _torus_mean_2(
    f: Callable[..., FloatArray], rtol: float, atol: float, n_start: int, n_max: int
) -> tuple[FloatArray, int] | None:
    """:func:`torus_mean` over two phases: the first call on 2·n_start nodes per phase, whose
    even nodes give the coarser mean; each further level one call on the doubled grid."""
    n = n_start
    if n >= n_max:
        return None
    values = np.asarray(f(*_grid(2 * n, 0.0, 2)), dtype=float)
    old = _torus_sum(np.ascontiguousarray(values[..., ::2, ::2])) * (1.0 / (n * n))
    new = _torus_sum(values) * (0.25 / (n * n))
    while True:
        n *= 2
        scale = float(np.max(np.abs(new))) if np.size(new) else 0.0
        if bool(np.all(np.abs(new - old) <= atol + rtol * scale)):
            return new, n
        if n >= n_max:
            return None
        old = new
        new = _torus_sum(np.asarray(f(*_grid(2 * n, 0.0, 2)), dtype=float)) * (0.25 / (n * n))


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


_RATE_TORQUES = (ConstantBodyTorque, LinearDrag, QuadraticDrag, InternalDissipation, ZeroTorque)
"""Built-in torques that are functions of the body rate alone (exact types: a subclass may
override ``__call__``)."""


def rate_only(torque: Any) -> bool:
    """Whether ``torque`` is a function of the body rate alone, known from its type.

    True for the built-in :class:`~tumble.torques.ConstantBodyTorque`,
    :class:`~tumble.torques.LinearDrag`, :class:`~tumble.torques.QuadraticDrag`,
    :class:`~tumble.torques.InternalDissipation` and :class:`~tumble.torques.ZeroTorque` (exact
    types) and for sums and multiples of them. Such
    a torque reads neither the attitude nor the time: the engines call it with ``q = None``
    and skip the averages over phases that enter only through the attitude.
    """
    kind = type(torque)
    if kind in _RATE_TORQUES:
        return True
    if kind is ScaledTorque:
        return rate_only(torque.torque)
    if kind is TorqueSum:
        return all(rate_only(term) for term in torque.terms)
    return False
