"""Second-order averaging and the mean ↔ osculating map, numerically, for any right-hand side.

The system is in the standard form of the method of averaging with slow variables x (m of them)
and fast phases φ on a d-torus,

    dx/dt = f(t, x, φ),    dφ/dt = ν(x) + g(t, x, φ),

where f and g are small (of order ε; tumble's models carry ε in them) and the frequencies ν are
not. A near-identity transformation to mean variables y and mean phases ψ,

    x = y + u(t, y, ψ),    φ = ψ + v(t, y, ψ),

with u and v zero-mean in ψ and of order ε, removes the phases from the equations up to terms
of order ε³ in the slow rates:

    dy/dt = F₁(y) + F₂(y),    dψ/dt = ν(y) + G₁(y),

with

    ν·∂u/∂ψ = f − ⟨f⟩,                       F₁ = ⟨f⟩,
    ν·∂v/∂ψ = g − ⟨g⟩ + (∂ν/∂x) u,           G₁ = ⟨g⟩,
    F₂ = ⟨(∂f/∂x) u + (∂f/∂φ) v⟩,

all at (t, y, ψ), ⟨·⟩ the mean over the torus (J. A. Sanders, F. Verhulst and J. Murdock,
*Averaging Methods in Nonlinear Dynamical Systems*, 2nd ed., Springer 2007, §2.9 and ch. 7;
the same second-order terms as the Lie-series form of A. Deprit, Celest. Mech. 1, 1969 and
H. Kamel, Celest. Mech. 1, 1970). The term (∂ν/∂x) u is the shear of the phases: a slow
variable displaced by u moves the frequencies, hence the phases, at first order. The mean phase
needs only G₁: an O(ε²) error of its rate shifts ψ by O(ε) over the slow time 1/ε, and u by
O(ε²).

The generator is u = u₁ + u₂ with u₁ the part of order ε above and u₂ that of order ε²,

    ν·∂u₂/∂ψ = (∂f/∂x) u₁ + (∂f/∂φ) v − (∂u₁/∂y) F₁ − (∂u₁/∂ψ) G₁ − F₂,

the balance of the terms of order ε² in dx/dt once F₂ is chosen (its right-hand side has zero
mean). v needs no second-order part: an O(ε²) error of the phases moves x by O(ε³).

Why second order. Started from the mean state of the physical (osculating) one, the solution of
the averaged equations with F₁ + F₂ stays within O(ε²) of the mean variables over times of
order 1/ε, and the osculating variables rebuilt by x = y + u(y, ψ) within O(ε²) of the true
ones; with F₁ alone both errors are O(ε). u₂ enters neither rate: without it the start and the
rebuilt values are off by O(ε²), the order kept, with it by O(ε³), so the error of a second-order
run is that of its rates alone.

How. At one slow state the functions f and g are evaluated on a uniform grid of the torus, u
and v follow by FFT (:func:`~tumble.averaging.generator.zero_mean_antiderivative`, small
divisors reported), ∂f/∂φ spectrally, the product (∂f/∂x) u as a central difference of f along
u at every node, and ∂ν/∂x by central differences. The grid is doubled along each phase until
the harmonics in its upper half are below ``GRID_RTOL`` of the largest: F₂ and u are corrections
of order ε, so a relative 1e-6 of them is far below what the averaging leaves (ε³ in the rates).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TypeVar

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.averaging.fourier import (
    _coefficients,
    _nodes,
    _padded,
    _phase_derivatives,
    _series,
    resolved,
    torus_values,
)
from tumble.averaging.generator import (
    DIVISOR_RTOL,
    SmallDivisorError,
    zero_mean_antiderivative,
)
from tumble.averaging.quadrature import AveragingError
from tumble.averaging.resonance_widths import (
    RESONANCE_WIDTHS,
    nearest_resonance,
    resonance_distance,
    resonance_table,
)
from tumble.errors import IntegrationError, ParameterError

__all__ = [
    "GRID_RTOL",
    "RESONANCE_WIDTHS",
    "FastRates",
    "Frequencies",
    "MeanMap",
    "MeanSystem",
    "SecondOrder",
    "generator_drift",
    "grid_terms",
    "nearest_resonance",
    "refine_grid",
    "resolved",
    "resonance_distance",
    "resonance_table",
    "resonances_at",
    "second_order",
    "torus_values",
]

FastRates = Callable[[float, FloatArray, Sequence[FloatArray]], tuple[FloatArray, FloatArray]]
"""``rates(t, x, phases) -> (f, g)``: ``x`` has shape (m, ...) and ``phases`` are d arrays,
all broadcasting to the grid's shape; f has shape (m, *grid), g shape (d, *grid)."""

Frequencies = Callable[[FloatArray], FloatArray]
"""``frequencies(x) -> ν``, shape (d,), for one slow state x of shape (m,)."""

GRID_RTOL = 1e-6
"""The torus grid resolves f when its harmonics above a quarter of the grid (the upper half of
those it holds) are below this fraction of the largest: u, v and F₂ are corrections of order ε
and need no more than this relative accuracy."""

GRID_MAX = 1 << 12
"""Most nodes along one phase."""

_Kept = TypeVar("_Kept")

_FD_STEP = 1e-5
"""Central differences along u and in x take steps of this size relative to the slow scale:
truncation (step²) and round-off (1e-16/step) of the difference both near 1e-10."""

MAP_TOL = 1e-13
"""The fixed-point iterations of the inverse map stop when a step changes the mean state by
less than this relative to its scale."""

MAP_NOISE = 1e-9
"""…or when a step no longer halves the change and it is below this: the noise of a generator
whose phase part comes from differences between neighbouring motions (the triaxial setting's
~1e-11 in the phases)."""

_MAP_ITERATIONS = 20


@dataclass(frozen=True, slots=True)
class SecondOrder:
    """The averaged rates and the generator at one slow state (module notes).

    Attributes
    ----------
    t : float
        The (frozen) time [time unit].
    x : ndarray, shape (m,)
        The mean slow state the terms are taken at.
    first : ndarray, shape (m,)
        F₁ = ⟨f⟩ [slow unit / time unit].
    second : ndarray, shape (m,)
        F₂ = ⟨(∂f/∂x) u + (∂f/∂φ) v⟩ [slow unit / time unit].
    frequencies : ndarray, shape (d,)
        ν(x) [rad / time unit].
    phase : ndarray, shape (d,)
        G₁ = ⟨g⟩, the first-order shift of the mean phases' rates [rad / time unit].
    u, v : ndarray, shapes (m, *grid) and (d, *grid)
        The generator's first-order parts u₁, v on the grid's nodes [slow unit], [rad].
    u2 : ndarray, shape (m, *grid), or None
        Its second-order part u₂ [slow unit], where asked for (``generator_order=2``).
    resonances : dict
        The signed distance k·ν/w_k of each harmonic from its resonance, in units of its
        width (:func:`resonance_table`).
    """

    t: float
    x: FloatArray
    first: FloatArray
    second: FloatArray
    frequencies: FloatArray
    phase: FloatArray
    u: FloatArray
    v: FloatArray
    u2: FloatArray | None = None
    resonances: dict[tuple[int, ...], float] = field(default_factory=dict)

    @property
    def resonance(self) -> tuple[float, tuple[int, ...]]:
        """The distance to the nearest resonance in units of its width, and its harmonic k
        (inf and () where no harmonic can resonate)."""
        return nearest_resonance(self.resonances)

    @property
    def grid(self) -> tuple[int, ...]:
        """Nodes along each phase."""
        return tuple(self.u.shape[1:])

    def generator(self, phases: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """u (u₁ + u₂ where it has u₂) and v at the mean phases ``phases`` (shape (d,) or
        (n, d)) by Fourier interpolation of the grid values: spectrally accurate, exact for the
        harmonics the grid resolves."""
        u = self.u if self.u2 is None else self.u + self.u2
        values = torus_values(np.concatenate([u, self.v]), phases)
        m = self.u.shape[0]
        return values[..., :m], values[..., m:]


def _evaluate(
    rates: FastRates, t: float, x: FloatArray, shape: tuple[int, ...]
) -> tuple[FloatArray, FloatArray]:
    d = len(shape)
    phases = _nodes(shape)
    m = x.shape[0]
    f, g = rates(t, x.reshape(m, *([1] * d)) if x.ndim == 1 else x, phases)
    f = np.broadcast_to(np.asarray(f, dtype=float), (m, *shape))
    g = np.broadcast_to(np.asarray(g, dtype=float), (len(shape), *shape))
    if not (np.all(np.isfinite(f)) and np.all(np.isfinite(g))):
        raise AveragingError(
            f"the fast right-hand side is not finite on the torus near x = "
            f"{x.reshape(m, -1)[:, 0].tolist()}: no "
            "average can be formed"
        )
    return f, g


def _jacobian(frequencies: Frequencies, x: FloatArray, scale: FloatArray) -> FloatArray:
    """∂ν/∂x by central differences, shape (d, m)."""
    columns = []
    for i in range(x.size):
        h = _FD_STEP * scale[i]
        up, down = x.copy(), x.copy()
        up[i] += h
        down[i] -= h
        columns.append((np.asarray(frequencies(up)) - np.asarray(frequencies(down))) / (2 * h))
    return np.stack(columns, -1)


def second_order(
    rates: FastRates,
    frequencies: Frequencies,
    t: float,
    x: ArrayLike,
    *,
    grid: Sequence[int],
    scale: ArrayLike | None = None,
    rtol: float = GRID_RTOL,
    divisor_rtol: float = DIVISOR_RTOL,
    generator_order: int = 1,
) -> SecondOrder:
    """The averaged rates to second order and the generator at one slow state (module notes).

    Parameters
    ----------
    rates : callable
        ``rates(t, x, phases) -> (f, g)`` (:data:`FastRates`), vectorised over the grid and
        over slow states that differ from node to node.
    frequencies : callable
        ``frequencies(x) -> ν`` (:data:`Frequencies`), the unperturbed rates of the phases.
    t : float
        Time, frozen [time unit].
    x : array_like, shape (m,)
        Slow state.
    grid : sequence of int
        Nodes along each phase to start from (doubled along a phase until it is resolved).
    scale : array_like, shape (m,), optional
        The size of each slow variable, for the finite-difference steps (default
        max(|x|, 1)).
    rtol : float
        Resolution test of the grid (:data:`GRID_RTOL`).
    divisor_rtol : float
        Small-divisor test of the generator
        (:func:`~tumble.averaging.generator.zero_mean_antiderivative`).
    generator_order : {1, 2}
        2: also the generator's second-order part u₂ (for the mean ↔ osculating map; two
        more evaluations of f on the grid).

    Returns
    -------
    SecondOrder

    Raises
    ------
    SmallDivisorError
        A harmonic of f or g at or near a resonance k·ν = 0.
    AveragingError
        The right-hand side is not finite on the torus, or the grid needs more than
        ``GRID_MAX`` nodes along a phase.
    """
    x, scale_, f, g, nu = _frozen_state(rates, frequencies, t, x, grid, scale, rtol)
    shape = f.shape[1:]

    def rates_at(y: FloatArray) -> tuple[FloatArray, FloatArray]:
        return _evaluate(rates, t, y, shape)[0], np.asarray(frequencies(y), dtype=float).ravel()

    def drift(first: FloatArray) -> FloatArray:
        return generator_drift(rates_at, x, first, _step(first, scale_), f, divisor_rtol)

    return grid_terms(
        t,
        x,
        f,
        g,
        nu,
        _jacobian(frequencies, x, scale_),
        _along(rates, t, x, f, scale_),
        drift if generator_order == 2 else None,
        divisor_rtol=divisor_rtol,
    )


def _frozen_state(
    rates: FastRates,
    frequencies: Frequencies,
    t: float,
    x: ArrayLike,
    grid: Sequence[int],
    scale: ArrayLike | None,
    rtol: float,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """What :func:`second_order` and :func:`resonances_at` start from (arguments as there).

    Returns
    -------
    x : ndarray, shape (m,)
        The slow state [slow unit].
    scale : ndarray, shape (m,)
        The size of each slow variable: ``scale``, or max(|x|, 1) [slow unit].
    f, g : ndarray, shapes (m, *grid), (d, *grid)
        The slow rates and the phases' perturbation on the resolved grid
        [slow unit / time unit], [rad / time unit].
    nu : ndarray, shape (d,)
        ν(x) [rad / time unit].
    """
    x = np.asarray(x, dtype=float).reshape(-1)
    scale_ = np.maximum(np.abs(x), 1.0) if scale is None else np.asarray(scale, dtype=float)
    f, g = _resolved(rates, t, x, grid, rtol)
    nu = np.asarray(frequencies(x), dtype=float).reshape(-1)
    return x, scale_, f, g, nu


def _along(
    rates: FastRates, t: float, x: FloatArray, f: FloatArray, scale: FloatArray
) -> Callable[[FloatArray], FloatArray]:
    """``along(u) -> (∂f/∂x) u`` at every node of the grid of ``f`` (shape (m, *grid)): a
    central difference of the slow rates along u about the slow state x, with the step of
    :func:`_step` for the slow scale ``scale`` [slow unit]; zeros for u = 0."""
    shape = f.shape[1:]
    x_grid = x.reshape(-1, *([1] * len(shape)))

    def along(u: FloatArray) -> FloatArray:
        h = _step(u, scale)
        if not h:
            return np.zeros_like(f)
        up = _evaluate(rates, t, x_grid + h * u, shape)[0]
        down = _evaluate(rates, t, x_grid - h * u, shape)[0]
        return (up - down) / (2.0 * h)

    return along


def refine_grid(
    evaluate: Callable[[tuple[int, ...]], tuple[FloatArray, _Kept]],
    grid: Sequence[int],
    rtol: float = GRID_RTOL,
) -> tuple[_Kept | None, tuple[int, ...]]:
    """Evaluate on a torus grid doubled along each phase that is not yet resolved.

    The resolution test is :func:`~tumble.averaging.fourier.resolved`; a phase stops doubling
    once resolved, and the search stops when a phase that is not has ``GRID_MAX`` nodes.

    Parameters
    ----------
    evaluate : callable
        ``evaluate(shape) -> (values, kept)``: the grid values the test reads, shape
        (c, *shape), and what the caller keeps of that grid.
    grid : sequence of int
        Nodes along each phase to start from.
    rtol : float
        Resolution test, as in :func:`second_order` [1].

    Returns
    -------
    kept : object or None
        ``kept`` of the first grid on which every phase is resolved; None when a phase with
        ``GRID_MAX`` nodes is still not (the caller raises, saying what is too fine).
    shape : tuple of int
        Nodes along each phase of the last grid evaluated.
    """
    shape = tuple(int(n) for n in grid)
    while True:
        values, kept = evaluate(shape)
        done = resolved(values, rtol)
        if all(done):
            return kept, shape
        if max(shape) >= GRID_MAX:
            return None, shape
        shape = tuple(n if ok else 2 * n for n, ok in zip(shape, done, strict=True))


def _resolved(
    rates: FastRates, t: float, x: FloatArray, grid: Sequence[int], rtol: float
) -> tuple[FloatArray, FloatArray]:
    """f and g on a grid doubled along each phase from ``grid`` until resolved."""

    def on(shape: tuple[int, ...]) -> tuple[FloatArray, tuple[FloatArray, FloatArray]]:
        f, g = _evaluate(rates, t, x, shape)
        return np.concatenate([f, g]), (f, g)

    found, _ = refine_grid(on, grid, rtol)
    if found is None:
        raise AveragingError(
            f"the fast right-hand side needs more than {GRID_MAX} nodes along a phase at "
            f"x = {x.tolist()}: it varies too fast (or is not smooth) on the torus"
        )
    return found


def resonances_at(
    rates: FastRates,
    frequencies: Frequencies,
    t: float,
    x: ArrayLike,
    *,
    grid: Sequence[int],
    scale: ArrayLike | None = None,
    rtol: float = GRID_RTOL,
) -> dict[tuple[int, ...], float]:
    """:func:`resonance_table` at one slow state, without the generator: defined at a
    resonance too, where :func:`second_order` meets a zero divisor (arguments as there)."""
    x, scale_, f, _, nu = _frozen_state(rates, frequencies, t, x, grid, scale, rtol)
    return resonance_table(
        f, nu, _jacobian(frequencies, x, scale_), f.mean(axis=tuple(range(1, f.ndim)))
    )


def grid_terms(
    t: float,
    x: FloatArray,
    f: FloatArray,
    g: FloatArray,
    nu: FloatArray,
    nu_jacobian: FloatArray,
    along: Callable[[FloatArray], FloatArray],
    drift: Callable[[FloatArray], FloatArray] | None = None,
    *,
    divisor_rtol: float = DIVISOR_RTOL,
) -> SecondOrder:
    """The terms of :func:`second_order` from the fast system's values on a resolved grid:
    the formulas of the module notes, for a system that knows its own derivatives.

    Parameters
    ----------
    t : float
        Time [time unit].
    x : ndarray, shape (m,)
        The slow state.
    f, g : ndarray, shapes (m, *grid), (d, *grid)
        The slow rates and the phases' perturbation at the nodes.
    nu : ndarray, shape (d,)
        ν(x).
    nu_jacobian : ndarray, shape (d, m)
        ∂ν/∂x.
    along : callable
        ``along(u) -> (∂f/∂x) u`` at every node, shape (m, *grid), for u of that shape.
    drift : callable, optional
        ``drift(F₁) -> (∂u₁/∂y) F₁`` at every node; given, the generator's u₂ is formed too.
    divisor_rtol : float
        Small-divisor test of the generator.
    """
    shape = f.shape[1:]
    axes = tuple(range(1, len(shape) + 1))
    u = zero_mean_antiderivative(f, nu, divisor_rtol=divisor_rtol)
    shear = np.tensordot(nu_jacobian, u, axes=(1, 0))  # (∂ν/∂x) u
    v = zero_mean_antiderivative(g + shear, nu, divisor_rtol=divisor_rtol)
    along_u = along(u)
    # (∂f/∂φ) v, spectrally.
    across = sum(d_f * v_j for d_f, v_j in zip(_phase_derivatives(f), v, strict=True))
    first, phase = f.mean(axis=axes), g.mean(axis=axes)
    second = (along_u + across).mean(axis=axes)
    u2 = None
    if drift is not None:
        turn = sum(d_u * g_j for d_u, g_j in zip(_phase_derivatives(u), phase, strict=True))
        rest = along_u + across - drift(first) - turn
        rest = rest - second.reshape(-1, *([1] * len(shape)))
        u2 = zero_mean_antiderivative(rest, nu, divisor_rtol=divisor_rtol)
    return SecondOrder(
        t=float(t),
        x=np.asarray(x, dtype=float),
        first=first,
        second=second,
        frequencies=np.asarray(nu, dtype=float),
        phase=phase,
        u=u,
        v=v,
        u2=u2,
        resonances=resonance_table(f, nu, nu_jacobian, first),
    )


def generator_drift(
    rates_at: Callable[[FloatArray], tuple[FloatArray, FloatArray]],
    x: FloatArray,
    first: FloatArray,
    h: float,
    like: FloatArray,
    divisor_rtol: float = DIVISOR_RTOL,
) -> FloatArray:
    """(∂u₁/∂y) F₁ on the grid, the drift of the first-order generator along the averaged
    flow, by a central difference: u₁ at x ± h F₁ (``rates_at(y) -> (f, ν)`` on the same
    grid); zeros of the shape of ``like`` for h = 0 (no drift)."""
    if not h:
        return np.zeros_like(like)
    up, down = (zero_mean_antiderivative(*rates_at(x + sign * h * first), divisor_rtol=divisor_rtol)
                for sign in (1.0, -1.0))  # fmt: skip
    return np.asarray((up - down) / (2.0 * h))


def _step(direction: FloatArray, scale: FloatArray) -> float:
    """The step h of a central difference along ``direction`` (shape (m, ...)): h·direction
    is ``_FD_STEP`` of the slow scale at its largest; 0 for a zero direction."""
    size = float(np.max(np.abs(direction) / scale.reshape(-1, *([1] * (direction.ndim - 1)))))
    return _FD_STEP / size if size > 0.0 else 0.0


@dataclass(frozen=True)
class MeanMap:
    """The near-identity map between osculating (x, φ) and mean (y, ψ) variables.

    ``terms(t, y)`` gives the :class:`SecondOrder` terms at a mean state (e.g.
    :func:`second_order` with the system's rates bound); the map is x = y + u(y, ψ),
    φ = ψ + v(y, ψ), accurate to O(ε²), and :meth:`to_mean` is its inverse, solved by
    fixed-point iteration so that the two are inverse to round-off.
    """

    terms: Callable[[float, FloatArray], SecondOrder]
    scale: FloatArray | None = None

    def to_osculating(
        self, t: float, y: ArrayLike, psi: ArrayLike
    ) -> tuple[FloatArray, FloatArray]:
        """(x, φ) from the mean (y, ψ) at time t."""
        y = np.asarray(y, dtype=float)
        psi = np.asarray(psi, dtype=float)
        u, v = self.terms(t, y).generator(psi)
        return y + u, psi + v

    def to_mean(self, t: float, x: ArrayLike, phi: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """(y, ψ) from the osculating (x, φ) at time t: x = y + u(y, ψ), φ = ψ + v(y, ψ)."""
        x = np.asarray(x, dtype=float)
        phi = np.asarray(phi, dtype=float)
        scale = np.maximum(np.abs(x), 1.0) if self.scale is None else self.scale
        y, psi = x.copy(), phi.copy()
        last = math.inf
        for _ in range(_MAP_ITERATIONS):
            u, v = self.terms(t, y).generator(psi)
            y_new, psi_new = x - u, phi - v
            change = max(
                float(np.max(np.abs(y_new - y) / scale)), float(np.max(np.abs(psi_new - psi)))
            )
            y, psi = y_new, psi_new
            # converged, or at the noise of a generator built from finite differences
            if change <= MAP_TOL or (change <= MAP_NOISE and change >= 0.5 * last):
                return y, psi
            last = change
        raise AveragingError(
            f"the osculating → mean map did not converge at x = {x.tolist()}: the generator is "
            "not small there (ε too large, or near a resonance or separatrix)"
        )


@dataclass(frozen=True)
class MeanSystem:
    """Averaged equations of order 1 or 2 in mean variables, with the maps to and from the
    osculating ones: what a model's averaged form needs from this module.

    The state integrated is z = (y, ψ): the m mean slow variables and the d mean phases
    (the phases are kept to rebuild the osculating variables at the output times).

    Parameters
    ----------
    terms_of : callable
        ``terms_of(t, y, generator_order) -> SecondOrder`` at a mean state: :func:`second_order`
        on a fast system's rates (:meth:`of_rates`), or a setting's own construction.
    phases : int
        d, the number of fast phases.
    order : {1, 2}
        Order of the averaged rates (F₁, or F₁ + F₂) and of the generator of the maps (u₁,
        or u₁ + u₂).
    first : callable, optional
        ``first(t, y) -> F₁``, the first-order averaged rates from a more accurate engine (a
        closed form, or an adaptive quadrature); default: the mean over the grid.
    scale : ndarray, optional
        Size of each slow variable (convergence of the inverse map).
    refuse : bool
        Whether the order-2 rates refuse a mean state within ``RESONANCE_WIDTHS`` of a
        resonance (SmallDivisorError); a hybrid run, which leaves such states to the full
        equations at the edge of the band, turns it off so that its steps may probe them.
    """

    terms_of: Callable[[float, FloatArray, int], SecondOrder]
    phases: int
    order: int = 2
    first: Callable[[float, FloatArray], FloatArray] | None = None
    scale: FloatArray | None = None
    refuse: bool = True
    resonances_of: Callable[[float, FloatArray], dict[tuple[int, ...], float]] | None = None

    def __post_init__(self) -> None:
        if self.order not in (1, 2):
            raise ParameterError(
                f"run.averaging_order = {self.order!r} is not an order of averaging (allowed: 1, 2)"
            )

    @classmethod
    def of_rates(
        cls,
        rates: FastRates,
        frequencies: Frequencies,
        grid: tuple[int, ...],
        order: int = 2,
        first: Callable[[float, FloatArray], FloatArray] | None = None,
        scale: FloatArray | None = None,
        refuse: bool = True,
    ) -> MeanSystem:
        """The mean system of a fast system given by its rates (:func:`second_order`, the
        grid the last state needed being the next one's start)."""
        last = [tuple(grid)]

        def terms_of(t: float, y: FloatArray, generator_order: int) -> SecondOrder:
            so = second_order(rates, frequencies, t, y, grid=last[0], scale=scale,
                              generator_order=generator_order)  # fmt: skip
            last[0] = so.grid
            return so

        def resonances_of(t: float, y: FloatArray) -> dict[tuple[int, ...], float]:
            return resonances_at(rates, frequencies, t, y, grid=last[0], scale=scale)

        return cls(terms_of, len(grid), order, first, scale, refuse, resonances_of)

    def terms(self, t: float, y: FloatArray, generator_order: int = 1) -> SecondOrder:
        """The terms at the mean state y."""
        return self.terms_of(t, np.asarray(y, dtype=float), generator_order)

    def resonances(self, t: float, y: FloatArray) -> dict[tuple[int, ...], float]:
        """The signed distances from the resonances at the mean state y
        (:func:`resonance_table`), defined at a resonance too where ``resonances_of`` is
        given (else from :meth:`terms`, which refuses a state there)."""
        y = np.asarray(y, dtype=float)
        if self.resonances_of is not None:
            return self.resonances_of(t, y)
        return self.terms(t, y).resonances

    def guarded(self) -> Callable[[float, FloatArray], FloatArray]:
        """:meth:`rhs` for an ODE solver: an AveragingError or ParameterError (a resonance, a
        small divisor, an orbit that does not exist) stops the run at once as an
        IntegrationError naming the time and the reason. (Returning NaN to make the solver
        try shorter steps would cost hundreds of refused evaluations of a few ms each before
        the step size collapses; the states refused are those the solution is about to reach,
        not a trial stage's overshoot.)"""

        def rhs(t: float, z: FloatArray) -> FloatArray:
            try:
                return self.rhs(t, z)
            except (AveragingError, ParameterError) as exc:  # no average, or no orbit, there
                raise IntegrationError(
                    f"the averaged equations of order {self.order} stop at t = {t:.6g}: {exc}"
                ) from None

        return rhs

    def rhs(self, t: float, z: FloatArray) -> FloatArray:
        """dz/dt of z = (y, ψ): (F₁ [+ F₂], ν + G₁)."""
        m = z.size - self.phases
        y = np.asarray(z[:m], dtype=float)
        so = self.terms(t, y)
        distance, k = so.resonance
        if self.refuse and self.order == 2 and distance < RESONANCE_WIDTHS:
            raise SmallDivisorError(
                f"the mean state at t = {t:.6g} is {distance:.3g} widths from the resonance "
                f"k·ν = 0, k = {k} (ν = {so.frequencies.tolist()}): the second-order "
                "generator is no longer small there (a hybrid run crosses it on the full "
                "equations)"
            )
        rate = so.first if self.first is None else np.asarray(self.first(t, y), dtype=float)
        if self.order == 2:
            rate = rate + so.second
        return np.concatenate([rate, so.frequencies + so.phase])

    def map(self) -> MeanMap:
        """The mean ↔ osculating map of this order."""
        return MeanMap(lambda t, y: self.terms(t, y, self.order), self.scale)

    def start(self, t: float, x: ArrayLike, phi: ArrayLike) -> FloatArray:
        """z(t) of the osculating state (x, φ)."""
        y, psi = self.map().to_mean(t, x, phi)
        return np.concatenate([y, psi])

    def osculating(self, t: ArrayLike, Z: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """The osculating slow variables and phases rebuilt along mean states.

        Parameters
        ----------
        t : array_like, shape (n,)
            Times [time unit].
        Z : array_like, shape (n, m + d)
            Mean states z = (y, ψ).

        Returns
        -------
        x : ndarray, shape (n, m)
        phi : ndarray, shape (n, d)
        """
        Z = np.atleast_2d(np.asarray(Z, dtype=float))
        times = np.asarray(np.broadcast_to(t, Z.shape[:1]), dtype=float)
        m = Z.shape[1] - self.phases
        n = Z.shape[0]
        anchors = _anchors(times)
        if anchors is None:  # few rows, or times not increasing: the generator at each
            mapping = self.map()
            x, phi = np.empty((n, m)), np.empty((n, self.phases))
            for i, (ti, zi) in enumerate(zip(times, Z, strict=True)):
                x[i], phi[i] = mapping.to_osculating(float(ti), zi[:m], zi[m:])
            return x, phi
        # The generator at anchor rows, its Fourier coefficients interpolated in time between
        # them: it varies on the slow time only (module notes of MeanSystem.osculating).
        coef = []
        for i in anchors:
            so = self.terms(float(times[i]), Z[i, :m], self.order)
            u = so.u if so.u2 is None else so.u + so.u2
            coef.append(_coefficients(np.concatenate([u, so.v])))
        shapes = {c.shape for c in coef}
        if len(shapes) > 1:  # the grid changed between anchors: bring all to the finest
            finest = max(shapes, key=lambda s: math.prod(s))
            coef = [_padded(c, finest) for c in coef]
        stack = np.stack(coef)  # (anchors, c, *grid)
        from scipy.interpolate import CubicSpline  # loaded where a run is rebuilt

        spline = CubicSpline(times[anchors], stack, axis=0)
        values = np.empty((n, m + self.phases))
        for start in range(0, n, 256):
            rows = slice(start, min(start + 256, n))
            values[rows] = _series(spline(times[rows]), Z[rows, m:])
        return Z[:, :m] + values[:, :m], Z[:, m:] + values[:, m:]


_ANCHORS = 33
"""Rows at which :meth:`MeanSystem.osculating` forms the generator when it is asked for more
rows than twice this many: its coefficients are then a cubic spline in time between them,
whose error (the slow variation over a sixteenth of the run, to the fourth power, times the
generator's O(ε)) is far below the O(ε³) the map keeps."""


def _anchors(times: FloatArray) -> FloatArray | None:
    """Indices of the anchor rows (evenly spread, first and last included, at distinct
    times), or None where there are too few rows or the times decrease somewhere."""
    n = times.size
    if n <= 2 * _ANCHORS or not np.all(np.diff(times) >= 0.0):
        return None
    chosen = np.unique(np.linspace(0, n - 1, _ANCHORS).round().astype(int))
    _, first = np.unique(times[chosen], return_index=True)  # a time given twice: once
    chosen = chosen[first]
    return chosen if chosen.size >= 4 else None
