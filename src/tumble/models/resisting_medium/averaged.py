"""The averaged equations of the resisting-medium model: (2.2) in (k, ϑ), its W, V form
(2.3), the general engine's quadrature, and the equations of order 2 in mean variables
with the resonance bands a hybrid run crosses (§6, §8.4, §10.5 of
``docs/theory/resisting-medium.md``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging.quadrature import AVERAGE_RTOL
from tumble.averaging.second_order import RESONANCE_WIDTHS, MeanSystem, nearest_resonance
from tumble.averaging.spinner import SPINNER_GRID, spinner_average, spinner_system
from tumble.kernels import (
    EVENT_EQUATOR,
    KIND_MEDIUM_AVERAGED,
    KIND_SPINNER_AVERAGED,
    Kernel,
    evaluate_rhs,
)
from tumble.models.base import AveragedForm, AveragingOptions, Breakpoint, Crossing
from tumble.models.inputs.resisting_medium import Params, State
from tumble.models.resisting_medium.closed_forms import crossing_time, plane_columns
from tumble.models.resisting_medium.full import full_from_slow, slow_from_full
from tumble.models.resisting_medium.passage import Passage, mean_turn, passage

# ---------------------------------------------------------------------------------------------
# Averaged system (2.2) and its W, V form (2.3).


def plane_kernel(p: Params, form: int) -> Kernel:
    """The compiled averaged equations of the plane of k: (2.2) (``form`` 0) or (2.3) (``form``
    1), one code told apart by ``form`` (:func:`tumble.kernels.rhs.evaluate`,
    ``KIND_MEDIUM_AVERAGED``), with the parameters of ``p`` packed as it reads them.

    Parameters
    ----------
    p : Params
        Model parameters.
    form : int
        0 for (2.2) in ``[k, ϑ]``, 1 for (2.3) in ``[W, V]``.
    """
    phase_b, phase_s = mean_turn(p)
    packed = [p.eps, float(p.a[2]), p.alpha, p.beta, p.gamma, p.delta, float(form), p.kappa,
              phase_b, phase_s]  # fmt: skip
    return Kernel(KIND_MEDIUM_AVERAGED, np.array(packed))


def averaged_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    """Averaged equations (2.2) for (k, ϑ); ρ and σ are constant: the compiled code the
    integrator runs (:func:`plane_kernel`).

    The a3 term of the ϑ-equation is evaluated as a3 sin ϑ / k, regular at ϑ = π/2 (§6).

    Parameters
    ----------
    t : float
        Time τ [1].
    y : ndarray, shape (2,)
        ``[k, ϑ]`` [1, rad].
    p : Params
        Model parameters.
    """
    return evaluate_rhs(plane_kernel(p, 0), t, y)


def averaged_rhs_wv(t: float, y: FloatArray, p: Params) -> FloatArray:
    """W, V form (2.3): dW/dτ = ε(a3 − βW − δW|W|), dV/dτ = −ε(αV + γV²): the compiled code
    the integrator runs (:func:`plane_kernel`).

    Parameters
    ----------
    t : float
        Time τ [1].
    y : ndarray, shape (2,)
        ``[W, V]`` = ``[k cos ϑ, k sin ϑ]`` [1].
    p : Params
        Model parameters.
    """
    return evaluate_rhs(plane_kernel(p, 1), t, y)


def _columns_ktheta(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    Y = np.atleast_2d(Y)
    return plane_columns(st, Y[:, 0], Y[:, 1])


def _columns_wv(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    Y = np.atleast_2d(Y)
    return plane_columns(st, np.hypot(Y[:, 0], Y[:, 1]), np.arctan2(Y[:, 1], Y[:, 0]))


def _no_turning_angle(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    """The angle columns that turn: none, σ being constant in (2.2) and (2.3) (so that a
    compiled run does not build every column on every step to unwrap it)."""
    return {}


def _plane_form(
    form: int,
    name: str,
    equation: str,
    slow: tuple[str, str],
    rhs: Callable[[float, FloatArray, Params], FloatArray],
    to_columns: Callable[[Params, State, FloatArray, FloatArray], dict[str, FloatArray]],
) -> AveragedForm[Params, State]:
    """(2.2) (``form`` 0) or (2.3) (1) as an averaged form: the two slow variables ``slow``
    (attributes of :class:`State`), ρ and σ constant, and the compiled code ``rhs`` calls
    (:func:`plane_kernel`)."""
    return AveragedForm(
        name=name,
        equation=equation,
        slow=slow,
        rhs=rhs,
        initial_state=lambda p, st: np.array([getattr(st, v) for v in slow]),
        to_columns=to_columns,
        kernel=lambda p: plane_kernel(p, form),
        angles=_no_turning_angle,
    )


_AVERAGED_KTHETA = _plane_form(0, "k_theta", "(2.2)", ("k", "theta"), averaged_rhs, _columns_ktheta)
_AVERAGED_WV = _plane_form(1, "W_V", "(2.3)", ("W", "V"), averaged_rhs_wv, _columns_wv)


def _equator(p: Params, st: State) -> tuple[Breakpoint, ...]:
    """(2.2) and (2.3) hold |cos ϑ| and W|W|: not smooth at the equator, which W crosses at
    most once, at the time the closed form of W gives (§8.4): the run is split there."""
    tau1 = crossing_time(st.W, p)
    return () if math.isinf(tau1) else (Breakpoint.at_time(tau1),)


def averaged_rhs_numeric(t: float, y: FloatArray, p: Params) -> FloatArray:
    """The averaged equations from the general engine: the moment (1.2) averaged over ψ and φ
    of the standard form (1.3) by quadrature; equal to (2.2) to round-off. The Python engine
    (:func:`tumble.averaging.spinner_average`): the oracle (2.2) and the compiled spinner
    setting are tested against; an averaged run integrates the compiled one
    (:func:`spinner_kernel`) for a moment of the body rate only.

    Parameters
    ----------
    t : float
        Time τ [1].
    y : ndarray, shape (4,)
        ``[k, ρ, σ, ϑ]`` [1, rad, rad, rad].
    p : Params
    """
    k, rho, sigma, theta = (float(v) for v in y)
    return spinner_average(p.torque, p.kappa, 1.0, k, rho, sigma, theta, t=t)


def _averaged_columns_numeric(
    p: Params, st: State, t: FloatArray, Y: FloatArray
) -> dict[str, FloatArray]:
    Y = np.atleast_2d(Y)
    return {"k": Y[:, 0], "rho": Y[:, 1], "sigma": Y[:, 2], "theta": Y[:, 3]}


def spinner_kernel(p: Params) -> Kernel | None:
    """:func:`averaged_rhs_numeric` compiled (:mod:`tumble.kernels.spinner`) when the moment
    depends on the body rate alone (the law (1.2) and its built-in parts); None otherwise
    (an attitude-dependent or a Python torque: the Python engine)."""
    program = p.torque.program
    if program is None or not p.torque.rate_only or p.kappa == 0.0:
        return None
    return Kernel(KIND_SPINNER_AVERAGED, np.concatenate([[p.kappa, AVERAGE_RTOL], program]))


_AVERAGED_NUMERIC: AveragedForm[Params, State] = AveragedForm(
    name="numeric",
    equation="(1.3) averaged over ψ, φ by quadrature (tumble.averaging)",
    slow=("k", "rho", "sigma", "theta"),
    rhs=averaged_rhs_numeric,
    initial_state=lambda p, st: np.array([st.k, st.rho, st.sigma, st.theta]),
    to_columns=_averaged_columns_numeric,
    # the equator, as above; a moment of the body rate only runs compiled
    breakpoints=(Breakpoint(lambda t, y: math.cos(y[3]), event=EVENT_EQUATOR),),
    kernel=spinner_kernel,
)


_SLOW = ("k", "rho", "sigma", "theta")
_PHASES = ("psi", "phi")


def mean_system(p: Params, order: int, refuse: bool = True) -> MeanSystem:
    """The averaged equations of ``order`` in mean variables (k, ρ, σ, ϑ) and mean phases
    (ψ, φ), with the mean ↔ osculating map (:mod:`tumble.averaging.second_order` on the
    standard form (1.3)); F₁ by :func:`tumble.averaging.spinner_average`."""

    def first(t: float, y: FloatArray) -> FloatArray:
        k, rho, sigma, theta = (float(v) for v in y)
        return spinner_average(p.torque, p.kappa, 1.0, k, rho, sigma, theta, t=t)

    rates, frequencies = spinner_system(p.torque, p.kappa)
    return MeanSystem.of_rates(rates, frequencies, SPINNER_GRID, order, first, refuse=refuse)


def _mean_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """The averaged equations of order ``options.order`` in mean variables, started from the
    mean state of the given one (``options.initial = "osculating"``) or from it, with the
    osculating variables rebuilt at the samples (:func:`mean_system`)."""
    system = mean_system(p, options.order, refuse=not options.hybrid)
    guarded = system.guarded()

    def initial_state(p: Params, st: State) -> FloatArray:
        x = np.array([st.k, st.rho, st.sigma, st.theta])
        phases = np.array([st.psi, st.phi])
        if options.initial == "mean":
            return np.concatenate([x, phases])
        return system.start(0.0, x, phases)

    def mean_columns(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
        Y = np.atleast_2d(Y)
        cols = {name: Y[:, i] for i, name in enumerate(_SLOW)}
        cols |= {f"{name}_mean": Y[:, i] for i, name in enumerate(_SLOW + _PHASES)}
        return cols

    def osculating(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
        X, _ = system.osculating(t, Y)
        return {name: X[:, i] for i, name in enumerate(_SLOW)}

    return AveragedForm(
        crossing=_resonance_band(p, st, system) if options.hybrid else None,
        name=f"mean_order{options.order}",
        equation=f"(1.3) averaged to order {options.order} in mean variables (tumble.averaging)",
        slow=(*(f"{v}_mean" for v in _SLOW), *(f"{v}_mean" for v in _PHASES)),
        rhs=lambda t, y, p: guarded(t, y),
        initial_state=initial_state,
        to_columns=mean_columns,
        breakpoints=(Breakpoint(lambda t, y: math.cos(y[3])),),
        osculating=osculating,
    )


def _resonance_band(p: Params, st: State, system: MeanSystem) -> Crossing:
    """The bands where the mean state is within RESONANCE_WIDTHS widths of a resonance of
    the phases (:func:`tumble.averaging.second_order.resonance_distance`): about ϑ = π/2,
    where φ stops (the harmonic (0, 1)), and about the commensurabilities ψ̇ = j|φ̇| the
    moment's harmonics (±1, j) meet as ϑ drifts. A hybrid run crosses them on the full
    equations (Euler + quaternions)."""
    mapping = system.map()

    last: list[Any] = [None, {}]  # the last state's table: band and signed ask for it in turn

    def signed(x: FloatArray) -> dict[tuple[int, ...], float]:
        key = np.asarray(x[:4], dtype=float).tobytes()
        if last[0] != key:
            last[:] = [key, system.resonances(0.0, x[:4])]
        return dict(last[1])

    def distance(x: FloatArray) -> float:
        return nearest_resonance(signed(x))[0]

    def band(z: FloatArray) -> float:
        return distance(z) / RESONANCE_WIDTHS - 1.0

    def osculating(y: FloatArray) -> tuple[FloatArray, FloatArray]:
        cols = slow_from_full(p, np.zeros(1), np.asarray(y)[None, :])
        x = np.array([float(cols[name][0]) for name in _SLOW])
        return x, np.array([float(cols["psi"][0]), float(cols["phi"][0])])

    def band_full(y: FloatArray) -> float:
        return distance(osculating(y)[0]) / RESONANCE_WIDTHS - 1.0

    def to_full(t: float, z: FloatArray) -> FloatArray:
        x, phases = mapping.to_osculating(t, z[:4], z[4:])
        k, rho, sigma, theta = (float(v) for v in x)
        return full_from_slow(p, State(k, rho, sigma, float(phases[0]), theta, float(phases[1])))

    def to_mean(t: float, y: FloatArray, z_entry: FloatArray) -> FloatArray:
        x, phases = osculating(y)
        # σ on the branch of the mean σ at entry (the azimuth is continuous)
        x[2] += 2.0 * math.pi * round((float(z_entry[2]) - x[2]) / (2.0 * math.pi))
        y_mean, psi = mapping.to_mean(t, x, phases)
        return np.concatenate([y_mean, psi])

    chunk = 20.0 * 2.0 * math.pi / max(st.k, 1e-3)  # 20 turns of ψ at the initial spin
    return Crossing(band, band_full, to_full, to_mean, "a resonance of ψ and φ", chunk, signed)


def _averaged_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """(2.2), its W, V form (2.3), the general engine (``averaging = "numeric"``,
    :func:`tumble.averaging.spinner_average`: the moment (1.2) averaged over ψ and φ), or the
    equations of order 2 in mean variables (:func:`_mean_form`). (2.2) and (2.3) cross a
    passage of ϑ = π/2 by the asymptotic step
    (:mod:`~tumble.models.resisting_medium.passage`) unless ``options.averaged_only``."""
    if options.order == 2 or options.hybrid:
        return _mean_form(p, st, options)
    if options.averaging == "numeric":
        return _AVERAGED_NUMERIC
    # (2.2) is written in polar coordinates (k, ϑ): at V0 = 0 (ϑ0 = 0 or π) the solution may
    # pass through k = 0, the polar singularity; (2.3) is the same system and regular there.
    form = _AVERAGED_WV if abs(math.sin(st.theta)) < 1e-12 else _AVERAGED_KTHETA
    crossing = None if options.averaged_only else passage(p, st)
    if crossing is None:
        return replace(form, breakpoints=_equator(p, st))
    return _stepped_form(p, crossing, 1 if form is _AVERAGED_WV else 0, form)


def _stepped_form(
    p: Params, crossing: Passage, form: int, plain: AveragedForm[Params, State]
) -> AveragedForm[Params, State]:
    """(2.2) (``form`` 0) or (2.3) (1) with the mean phase φ̄ as a third variable, stepped
    across the passage ``crossing`` at its stationary time and split at τ1 (the kink), its
    columns with the inner solution added (:class:`~tumble.models.resisting_medium.passage.
    Passage`)."""
    kappa, eps = p.kappa, p.eps
    phase_b, phase_s = mean_turn(p)

    def plane(Y: FloatArray) -> tuple[FloatArray, FloatArray]:
        if form == 1:
            return Y[:, 0], Y[:, 1]
        return Y[:, 0] * np.cos(Y[:, 1]), Y[:, 0] * np.sin(Y[:, 1])

    def to_columns(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
        Y = np.atleast_2d(Y)
        W, V = plane(Y)
        omega = -kappa * W / (1.0 + kappa) + eps * (phase_b + phase_s * V)
        V = np.abs(V + crossing.correction(t, Y[:, 2], omega))
        return plane_columns(st, np.hypot(W, V), np.arctan2(V, W))

    def initial_state(p: Params, st: State) -> FloatArray:
        return np.append(plain.initial_state(p, st), st.phi)

    return replace(
        plain,
        equation=f"{plain.equation} with the passage of ϑ = π/2 stepped (stationary phase)",
        slow=(*plain.slow, "phi"),
        initial_state=initial_state,
        to_columns=to_columns,
        breakpoints=(
            Breakpoint.at_time(crossing.tau1),
            Breakpoint.at_time(crossing.tau_s, crossing.restart(form)),
        ),
        steps=(crossing.span,),
    )
