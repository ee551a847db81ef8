"""Volosov's averaged equations (2.2)–(2.3) of the nonlinear-moment model (§7): in the
energy H or a turning point θext besides z = (R, G, a, b), with their averages in closed
form or by the general engine, the start corrected to first order, and the equations of
order 2 in mean variables.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Literal

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging.nutation import (
    AVERAGE_RTOL,
    NutationSystem,
    Perturbation,
    numeric_averages,
    nutation_generator,
    potential_gradient,
)
from tumble.averaging.second_order import MeanSystem
from tumble.errors import IntegrationError, ParameterError
from tumble.kernels import (
    EVENT_NONE,
    EVENT_NUTATION_SEPARATRIX,
    KIND_NUTATION_AVERAGED,
    KIND_NUTATION_ENGINE,
    Kernel,
)
from tumble.kernels.nutation import evaluate_separatrix_distance, evaluate_well, nutation_columns
from tumble.models.base import AveragedForm, AveragingOptions, Breakpoint
from tumble.models.inputs.nonlinear_moment import Params, State, orbit_of
from tumble.models.nonlinear_moment.full import full_kernel
from tumble.models.nonlinear_moment.perturbation import (
    _builtin_averages,
    builtin_perturbation,
    damping_torque,
    engine_perturbation,
)
from tumble.unperturbed.symmetric_body import NutationOrbit, effective_potential, potential_slope

# ---------------------------------------------------------------------------------------------
# Averaged equations (2.2)–(2.3).


def barrier_energies(R: float, G: float, a: float, b: float) -> FloatArray:
    """Energies of the local maxima of W(θ) in (0, π): the separatrix levels of (1.6).

    F = W'(θ) = 0 is, times sin³θ, the quintic (G − Ru)(R − Gu) − (1 − u²)²(a + 2bu) = 0 in
    u = cos θ; a maximum of W is a root in (−1, 1) where F changes sign from + to − in θ.

    Parameters
    ----------
    R, G : float
        Reduced momenta [1/t].
    a, b : float
        Moment coefficients [1/t²].

    Returns
    -------
    ndarray
        The barrier energies [1/t²] (empty for a single well).
    """
    # (G − Ru)(R − Gu) = GR − (G² + R²)u + GR u²; (1 − u²)²(a + 2bu), highest power first.
    quartic = np.array([1.0, 0.0, -2.0, 0.0, 1.0])
    poly = -np.polymul(quartic, [2.0 * b, a])
    poly[-3:] += [G * R, -(G * G + R * R), G * R]
    out = []
    for r in np.roots(poly):
        if abs(r.imag) > 1e-9 or not -1.0 < r.real < 1.0:
            continue
        theta = math.acos(r.real)
        h = 1e-6 * min(theta, math.pi - theta)
        if potential_slope(theta - h, R, G, a, b) > 0.0 > potential_slope(theta + h, R, G, a, b):
            out.append(float(effective_potential(theta, R, G, a, b)))
    return np.array(out)


def _orbit_or_raise(build: Callable[[], NutationOrbit], t: float) -> NutationOrbit:
    try:
        return build()
    except ParameterError as exc:
        raise IntegrationError(
            f"averaged equations (2.2) at t = {t:.6g}: {exc} — averaging breaks down there "
            "(§11); do not average across a separatrix"
        ) from None


def averaged_rhs(
    t: float,
    y: FloatArray,
    p: Params,
    *,
    form: Literal["energy", "theta_max", "theta_min"] = "energy",
    u_hint: float = 0.0,
    perturbation: Perturbation | None = None,
) -> FloatArray:
    """Volosov's averaged equations (2.2)–(2.3) of §7.

    ``form = "energy"``: y = [H, R, G, a, b], H' = ε(⟨Φθθ'⟩ + ⟨Φz·W^z⟩), z' = ε⟨Φz⟩ (the
    better-conditioned form; the well is the allowed interval nearest ``u_hint``).
    ``form = "theta_max"`` or ``"theta_min"``: y = [θext, R, G, a, b] and (2.2),
    θext' = ε(⟨Φθθ'⟩ + ⟨Φz·W^z⟩ − ⟨Φz⟩·W^z(θext))/F(θext, z).

    The reference implementation: the orbit by :class:`NutationOrbit` (the quartic's roots,
    scipy's Legendre integrals), independent of the compiled energy form
    (:func:`tumble.kernels.nutation.nutation_averaged`, Carlson's integrals), which an
    averaged run integrates where it can and which the tests hold against this one. The
    θext forms and a perturbation without a compiled program run this one.

    Parameters
    ----------
    t : float
        Time [t].
    y : ndarray, shape (5,)
        ``[H, R, G, a, b]`` [1/t², 1/t, 1/t, 1/t², 1/t²], or θext [rad] in place of H.
    p : Params
        μ and ε, and the damping d, ν and the pressure of the built-in perturbation.
    form : {"energy", "theta_max", "theta_min"}
        The slow variable besides z: the energy H or a turning point θext.
    u_hint : float
        cos θ inside the tracked well (energy form).
    perturbation : Perturbation, optional
        Default: the built-in one of §9, averaged in closed form (§8); any other is
        averaged numerically (:func:`numeric_averages`).

    Returns
    -------
    ndarray, shape (5,)

    Raises
    ------
    IntegrationError
        Near a separatrix (1 − k² below ``SEPARATRIX_TOL``), or at zero amplitude in a θext
        form (F(θext) = 0: use the energy form).
    """
    x, R, G, a, b = y.tolist()
    tau = p.eps * t
    if form == "energy":
        orbit = _orbit_or_raise(
            lambda: NutationOrbit.from_energy(p.mu, a, b, R, G, x, u_hint=u_hint), t
        )
    else:
        orbit = _orbit_or_raise(lambda: NutationOrbit.from_turning_point(p.mu, a, b, R, G, x), t)
    if perturbation is None:
        g, phi_z = _builtin_averages(orbit, p, tau)
    else:
        g, phi_z = numeric_averages(orbit, perturbation, tau)
    if form == "energy":
        rate = g
    else:
        u_e = math.cos(x)
        F = float(potential_slope(x, R, G, a, b))
        if F == 0.0:
            raise IntegrationError(
                f"averaged equations (2.2) at t = {t:.6g}: F(θext) = 0 (zero nutation "
                'amplitude or an unstable equilibrium); use averaged_form = "energy"'
            )
        w_e = potential_gradient(np.array([u_e]), np.array([R, G, a, b]))[:, 0]
        rate = (g - float(phi_z @ w_e)) / F
    return p.eps * np.array([rate, *phi_z.tolist()])


def averaged_initial(
    p: Params,
    st: State,
    perturbation: Perturbation | None = None,
    start: Literal["exact", "corrected"] = "exact",
) -> tuple[float, FloatArray, NutationOrbit]:
    """The averaged initial state H̄(0), z̄(0) of §7 and §14 (``[run] averaged_init``).

    ``start = "exact"``: H̄ = H(0), z̄ = z(0) (the paper's). ``"corrected"``: the first-order
    mean state H̄ = H(0) − ε u₁_H, z̄ = z(0) − ε u₁_z, u₁ the generator of the general
    mean ↔ osculating map at the initial state (:func:`tumble.averaging.nutation
    .nutation_generator`); for the perturbations of the paper it equals
    ∫_{t*}^0 (g − ⟨g⟩)dt, ∫_{t*}^0 (Φz − ⟨Φz⟩)dt along the frozen orbit, t* ≤ 0 its last
    turning point, g = Φθθ' + W^z·Φz (measured to 1e-16).

    Parameters
    ----------
    p : Params
    st : State
    perturbation : Perturbation, optional
        Default: the built-in one.
    start : {"exact", "corrected"}
        The paper's start, or the one corrected to first order.

    Returns
    -------
    H : float
        H̄(0) [1/t²].
    z : ndarray, shape (4,)
        z̄(0) = (R, G, a, b).
    orbit : NutationOrbit
        The unperturbed orbit of (H̄(0), z̄(0)) in the initial well.
    """
    a0, b0 = (float(v) for v in p.ab(0.0))
    orbit = orbit_of(p, st)
    H = orbit.E
    z = np.array([st.R, st.G, a0, b0])
    if start == "corrected" and p.perturbed:
        # The first-order generator of the general map at the initial state: for this
        # paper's perturbations it is the integral from the last turning point (Serov 1991).
        pert = builtin_perturbation(p) if perturbation is None else perturbation
        u_H, u_z = nutation_generator(orbit, pert, 0.0)
        if u_H != 0.0 or np.any(u_z):
            H -= p.eps * u_H
            z = z - p.eps * u_z
            orbit = NutationOrbit.from_energy(
                p.mu, z[2], z[3], z[0], z[1], H, u_hint=0.5 * (orbit.u1 + orbit.u2)
            )
    return H, z, orbit


AveragedCoordinates = Literal["energy", "theta_max", "theta_min"]
_COORDINATES: dict[str, AveragedCoordinates] = {
    "energy": "energy",
    "theta_max": "theta_max",
    "theta_min": "theta_min",
}


def _compiled_start(p: Params, st: State) -> tuple[float, FloatArray, float] | None:
    """The paper's start H̄(0) = H(0), z̄(0) = z(0) and the middle of its well from the
    compiled well (:func:`tumble.kernels.nutation.well_averages`) instead of a Python orbit;
    None where that has no answer (a pole, a separatrix: the Python orbit then says why)."""
    if not 0.0 < st.theta < math.pi:
        return None
    a0, b0 = (float(v) for v in p.ab(0.0))
    u = math.cos(st.theta)
    H = 0.5 * st.theta_dot**2 + (st.G - st.R * u) ** 2 / (2.0 * math.sin(st.theta) ** 2)
    H += a0 * u + b0 * u * u  # (1.6)
    well = evaluate_well(st.R, st.G, a0, b0, H, u)
    if well[0] == 0.0 or not well[2] <= u <= well[1]:
        return None
    return H, np.array([st.R, st.G, a0, b0]), 0.5 * float(well[1] + well[2])


def nutation_phase(p: Params, st: State) -> float:
    """The nutation's angle variable of the state ``st`` on its own orbit: 2πt/T from the
    turning point θmax (the origin of :class:`tumble.averaging.nutation.NutationSystem`)
    [rad]."""
    orbit = orbit_of(p, st)
    if orbit.kind == "steady":
        return 0.0
    t_last = orbit.turning_time("last")
    at_max = abs(float(orbit.theta(t_last)) - orbit.theta_max) <= abs(
        float(orbit.theta(t_last)) - orbit.theta_min
    )
    return 2.0 * math.pi * (-t_last) / orbit.period + (0.0 if at_max else math.pi)


_MEAN_SLOW = ("H", "R", "G", "a", "b", "w")


_ORBIT_COLUMNS = ("theta_max", "theta_min", "k2", "period", "root_case", "E")


def _orbit_table(
    X: FloatArray,
    u_hint: float,
    orbit: Callable[[FloatArray], NutationOrbit],
    compiled: bool = True,
) -> FloatArray:
    """θmax, θmin [rad], k² [1], period [t], root case and energy [1/t²] of the orbits of the
    rows of ``X`` (:data:`_ORBIT_COLUMNS`), shape (n, 6).

    Where ``compiled`` (rows ``[H, R, G, a, b]``), from the compiled well
    (:func:`tumble.kernels.nutation.nutation_columns`) about cos θ = ``u_hint``, and from the
    Python orbit ``orbit(row)`` for a row it has no answer for; otherwise from the Python
    orbit for every row.
    """
    if compiled:
        table = nutation_columns(np.ascontiguousarray(X, dtype=float), u_hint)
        rows = np.flatnonzero(np.isnan(table[:, 0])).tolist()
    else:
        table = np.empty((X.shape[0], len(_ORBIT_COLUMNS)))
        rows = list(range(X.shape[0]))
    for i in rows:
        o = orbit(X[i])
        table[i] = o.theta_max, o.theta_min, o.k2, o.period, o.root_case, o.E
    return table


def _mean_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """The averaged equations of order 2 in mean variables (H̄, z̄) and the mean nutation
    phase w̄ (:class:`tumble.averaging.nutation.NutationSystem`), started from the mean state
    of the given one (``options.initial = "osculating"``) or from it; the envelope and z
    columns are those of the osculating orbit rebuilt at every time asked for (at an
    extremum of the full motion its θ is that orbit's turning point)."""
    perturbation = engine_perturbation(p) if options.averaging == "numeric" else None
    pert = builtin_perturbation(p) if perturbation is None else perturbation
    orbit0 = orbit_of(p, st)
    system = NutationSystem(p.mu, pert, p.eps, 0.5 * (orbit0.u1 + orbit0.u2))
    mean = MeanSystem(system.terms, 1, options.order)
    guarded = mean.guarded()
    a0, b0 = (float(v) for v in p.ab(0.0))
    x0 = np.array([orbit0.E, st.R, st.G, a0, b0])
    w0 = nutation_phase(p, st)

    def initial_state(p: Params, st: State) -> FloatArray:
        if options.initial == "mean":
            return np.array([*x0, w0])
        return mean.start(0.0, x0, [w0])

    def to_columns(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
        Y = np.atleast_2d(Y)
        X, _ = mean.osculating(t, Y)
        # The osculating orbit's turning points and the mean orbit's k², period, root case:
        # the compiled well, the Python orbit for a row it has no answer for.
        osc, avg = (_orbit_table(rows, system.u_hint, system.orbit) for rows in (X, Y[:, :5]))
        cols = {"theta_max": osc[:, 0], "theta_min": osc[:, 1], "k2": avg[:, 2],
                "period": avg[:, 3], "root_case": avg[:, 4], "E": Y[:, 0].copy()}  # fmt: skip
        for j, name in enumerate(("R", "G", "a", "b")):
            cols[name] = X[:, j + 1]
        cols |= {f"{name}_mean": Y[:, j] for j, name in enumerate(_MEAN_SLOW)}
        return cols

    return AveragedForm(
        name=f"mean_order{options.order}",
        equation=f"(2.1) averaged to order {options.order} in mean variables (tumble.averaging)",
        slow=tuple(f"{name}_mean" for name in _MEAN_SLOW),
        rhs=lambda t, y, p: guarded(t, y),
        initial_state=initial_state,
        to_columns=to_columns,
        breakpoints=_pressure_knots(p),
    )


def _pressure_knots(p: Params) -> tuple[Breakpoint, ...]:
    """Breakpoints at the times t = τ/ε where dQ/dτ jumps (a pressure table's inner knots, a
    function's breaks): an averaged run stops and restarts there so no step straddles one."""
    return tuple(Breakpoint.at_time(tk / p.eps) for tk in p.pressure.knots() if tk > 0.0)


def _averaged_start(
    p: Params,
    st: State,
    options: AveragingOptions,
    form: AveragedCoordinates,
    engine: Perturbation | None,
    compiled: bool,
) -> tuple[FloatArray, float]:
    """The initial state ``[x, R, G, a, b]`` of the averaged equations in the coordinates
    ``form`` (x: H [1/t²] or a turning point [rad]) and the cos θ [1] inside the well they
    track: the paper's start from the compiled well where the form is compiled and the well
    has an answer, else from the Python orbit (:func:`averaged_initial`)."""
    start = _compiled_start(p, st) if compiled and options.start == "exact" else None
    if start is not None:
        H, z, u_hint = start
        return np.array([H, *z.tolist()]), u_hint
    H, z, orbit = averaged_initial(p, st, engine, options.start)
    u_hint = 0.5 * (orbit.u1 + orbit.u2)
    if form == "energy":
        return np.array([H, *z.tolist()]), u_hint
    x0 = orbit.theta_max if form == "theta_max" else orbit.theta_min
    return np.array([x0, *z.tolist()]), u_hint


def _separatrix(form: AveragedCoordinates, compiled: bool) -> Breakpoint:
    """The separatrix (§11) as a breakpoint that stops the averaged run with an
    IntegrationError: the energy crossing a barrier between two wells of W, which one step
    could otherwise jump over unseen (compiled: the kernel's event function)."""

    def energy_of(y: FloatArray) -> float:
        x, R, G, a, b = (float(v) for v in y)
        return x if form == "energy" else float(effective_potential(x, R, G, a, b))

    def below_barriers(t: float, y: FloatArray) -> float:
        # > 0 while H is below every barrier of W, < 0 while above one: a sign change is a
        # separatrix crossing (§11), which one step could otherwise jump over unseen.
        if compiled:  # the same sign, without the roots of the quintic
            return float(evaluate_separatrix_distance(np.asarray(y, dtype=float)))
        barriers = barrier_energies(*(float(v) for v in y[1:]))
        return float(np.min(barriers) - energy_of(y)) if barriers.size else 1.0

    def refuse(t: float, y: FloatArray) -> FloatArray:
        raise IntegrationError(
            f"averaged equations (2.2): the motion reaches a separatrix at t = {t:.6g} (the "
            "energy crosses the barrier between two wells of W); averaging is not valid across "
            "it (§11): run the full model there"
        )

    return Breakpoint(
        below_barriers, refuse, event=EVENT_NUTATION_SEPARATRIX if compiled else EVENT_NONE
    )


def _averaged_kernel(
    full: Kernel | None, program: FloatArray | None, u_hint: float
) -> Callable[[Params], Kernel | None]:
    """The energy form compiled from the full kernel ``full``: with the closed-form averages
    (``program`` None), or the general engine on the damping as the torque ``program`` (a
    moment of the body rate); ``u_hint`` picks the well."""

    def kernel(p: Params) -> Kernel | None:
        if full is None:
            return None
        if program is None:  # the closed-form averages: the full kernel's, and the well's hint
            params = np.append(full.params, u_hint)
            return replace(full, kind=KIND_NUTATION_AVERAGED, params=params, event=EVENT_NONE)
        params = np.concatenate([full.params, [u_hint, AVERAGE_RTOL], program])
        return replace(full, kind=KIND_NUTATION_ENGINE, params=params, event=EVENT_NONE)

    return kernel


def _averaged_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """Volosov's equations (2.2)–(2.3) in the energy H (default) or a turning point besides z,
    their averages in closed form (§8–§9: K, E, Π) or by the general engine
    (:mod:`tumble.averaging.nutation`, ``averaging = "numeric"``), from the exact or the
    corrected start. The energy form with the closed-form averages is also compiled
    (:mod:`tumble.kernels.nutation`)."""
    if options.order == 2:
        return _mean_form(p, st, options)
    engine = engine_perturbation(p) if options.averaging == "numeric" else None
    form = _COORDINATES[options.coordinates or "energy"]
    full = full_kernel(p)
    program = damping_torque(p).program if engine is not None else None
    compiled = form == "energy" and full is not None and (engine is None or program is not None)
    y0, u_hint = _averaged_start(p, st, options, form, engine, compiled)

    failures: list[str] = []

    def rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
        try:
            return averaged_rhs(t, y, p, form=form, u_hint=u_hint, perturbation=engine)
        except IntegrationError as exc:
            # A trial stage of a too-long step may leave the domain of the averaged system
            # (no motion with that energy). NaN makes the solver reject the step and retry a
            # shorter one; if the true solution leaves the domain, the step size collapses and
            # the last message is reported (``failure``).
            failures.append(str(exc))
            return np.full(5, np.nan)

    def to_columns(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
        return _averaged_columns(Y, p, form, u_hint, compiled)

    return AveragedForm(
        name=form,
        equation="(2.2)-(2.3)" + (", energy form of §7" if form == "energy" else ""),
        slow=("H" if form == "energy" else form, "R", "G", "a", "b"),
        rhs=rhs,
        initial_state=lambda p, st: y0,
        to_columns=to_columns,
        breakpoints=(*_pressure_knots(p), _separatrix(form, compiled)),
        failure=lambda: failures[-1] if failures else None,
        kernel=_averaged_kernel(full, program, u_hint) if compiled else None,
    )


def _slow_orbit(y: FloatArray, p: Params, form: str, u_hint: float) -> NutationOrbit:
    x, R, G, a, b = (float(v) for v in y)
    if form == "energy":
        return NutationOrbit.from_energy(p.mu, a, b, R, G, x, u_hint=u_hint)
    return NutationOrbit.from_turning_point(p.mu, a, b, R, G, x)


def _averaged_columns(
    Y: FloatArray, p: Params, form: str, u_hint: float, compiled: bool = False
) -> dict[str, FloatArray]:
    table = _orbit_table(Y, u_hint, lambda y: _slow_orbit(y, p, form, u_hint), compiled)
    out = {k: table[:, j].copy() for j, k in enumerate(_ORBIT_COLUMNS)}
    if form == "theta_max":  # the integrated variable itself, not its round trip
        out["theta_max"] = Y[:, 0].copy()
    elif form == "theta_min":
        out["theta_min"] = Y[:, 0].copy()
    for i, name in enumerate(("R", "G", "a", "b")):
        out[name] = Y[:, i + 1].copy()
    return out
