"""The entry-capsule application of the nonlinear-moment paper (docs/theory/nonlinear-moment.md
§9–§10).

A ballistic descent (:mod:`tumble.entry`) gives the dynamic pressure q(t); the capsule's
modified-Newtonian moment, fitted as Cm ≈ c1 sinα + c2 sin2α, gives
a(t) = q(t) S D c1 / A and b(t) = q(t) S D c2 / A of (1.5). The attitude motion about the
velocity direction (θ the total angle of attack) is then integrated in full and by Volosov's
averaged equations, and their envelopes compared.

Modelling assumptions (the paper's): the attitude does not affect the trajectory (zero lift,
constant drag coefficient), the rotation of the velocity vector is neglected (e_z fixed), and
aerodynamic damping is left out (d = ν = 0), so the envelope changes only through q(t).

Usable from a notebook::

    from tumble.analysis.capsule import capsule_attitude
    run = capsule_attitude()
    print(run.envelope["max_relative"], run.cost_ratio)
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from scipy.interpolate import make_interp_spline
from scipy.optimize import brentq

from tumble._typing import FloatArray
from tumble.entry import (
    SOYUZ_CLASS,
    STANDARD,
    AtmosphereModel,
    Capsule,
    Descent,
    MomentFit,
    descend,
    fit_moment,
)
from tumble.errors import ParameterError, check_range
from tumble.integrate import Trajectory, simulate
from tumble.models import nonlinear_moment as nm
from tumble.models.base import AveragingOptions

__all__ = ["Q_SPACING", "CapsuleAttitude", "capsule_attitude", "capsule_study", "descent_eps"]

Q_SPACING = 0.25
"""Largest node spacing of the dynamic-pressure splines [s]."""


@dataclass(frozen=True)
class CapsuleAttitude:
    """Full and averaged attitude motion of a capsule along its descent.

    Times ``t`` of the trajectories count from ``t_start`` of the descent [s].

    Attributes
    ----------
    capsule : Capsule
        The capsule (inertias possibly scaled).
    fit : MomentFit
        Its moment fit c1, c2 (1.5).
    descent : Descent
        The trajectory.
    t_start, t_end : float
        Window of the descent the attitude is integrated over [s].
    params : nonlinear_moment.Params
        The model: a, b at t_start [1/s²], ε = 1/(t_end − t_start) [1/s], Q(τ) = q/q(t_start).
    initial : nonlinear_moment.State
        Initial attitude state.
    trajectories : dict
        Method → Trajectory (``full``, ``averaged``).
    extrema : list
        Every θ extremum of the full motion, rows (kind, k, t, θ, R, G).
    envelope : dict
        :func:`~tumble.models.nonlinear_moment.envelope_discrepancy` of the averaged envelope.
    eps_descent : float
        The descent's true small parameter: max over the window of T(t)·|q'(t)|/q(t), the
        relative change of the dynamic pressure per small-amplitude nutation period [1].
    """

    capsule: Capsule
    fit: MomentFit
    descent: Descent
    t_start: float
    t_end: float
    params: nm.Params
    initial: nm.State
    trajectories: dict[str, Trajectory] = field(repr=False)
    extrema: list[tuple[str, int, float, float, float, float]] = field(repr=False)
    envelope: dict[str, Any]
    eps_descent: float

    @property
    def wall_time(self) -> dict[str, float]:
        """Seconds spent by each method [s]."""
        return {m: t.wall_time for m, t in self.trajectories.items()}

    @property
    def cost_ratio(self) -> float | None:
        """Wall time of the full run over that of the averaged run [1]."""
        w = self.wall_time
        if "full" not in w or "averaged" not in w:
            return None
        return w["full"] / w["averaged"]

    def q(self, t: FloatArray) -> FloatArray:
        """Dynamic pressure at attitude time t (from t_start) [Pa]."""
        return np.asarray(self.descent.q_at(self.t_start + np.asarray(t, dtype=float)))


def _small_amplitude_period(capsule: Capsule, fit: MomentFit, q: FloatArray) -> FloatArray:
    """2π/√(−(a + 2b)) at dynamic pressure q: the nutation period about θ = 0 [s]."""
    k = -(fit.c1 + 2.0 * fit.c2) * q * capsule.S * capsule.D / capsule.A
    if np.any(k <= 0.0):
        raise ParameterError(
            "the capsule is not statically stable at α = 0 (c1 + 2c2 ≥ 0): no nutation period"
        )
    return 2.0 * math.pi / np.sqrt(k)


def _layer_crossings(
    descent: Descent, atmosphere: AtmosphereModel, t0: float, t1: float
) -> list[float]:
    """Times in (t0, t1) where the descent crosses an altitude at which dρ/dh jumps [s]."""

    def h(t: float) -> float:
        return float(np.atleast_2d(descent.state(t))[0, 2])

    inside = descent.t[(descent.t > t0) & (descent.t < t1)]
    grid = np.concatenate([[t0], inside, [t1]])
    heights = np.array([h(t) for t in grid])
    out = []
    for hk in atmosphere.kinks:
        d = heights - hk
        for i in np.flatnonzero(d[:-1] * d[1:] < 0.0):
            out.append(float(brentq(lambda t, hk=hk: h(t) - hk, grid[i], grid[i + 1], xtol=1e-12)))
    return sorted(out)


class _PiecewiseSpline:
    """q(t)/q0 as quintic splines between kinks, in τ = (t − t_start)/(t_end − t_start)."""

    def __init__(self, descent: Descent, edges: FloatArray, q0: float) -> None:
        t0, span = float(edges[0]), float(edges[-1] - edges[0])
        self.inner = (edges[1:-1] - t0) / span
        self.pieces = []
        for a, b in itertools.pairwise(edges):
            n = max(8, math.ceil((b - a) / Q_SPACING) + 1)
            nodes = np.linspace(a, b, n)
            spline = make_interp_spline((nodes - t0) / span, descent.q_at(nodes) / q0, k=5)
            self.pieces.append((spline, spline.derivative()))

    def _eval(self, tau: FloatArray, which: int) -> FloatArray:
        t = np.asarray(tau, dtype=float)
        idx = np.searchsorted(self.inner, t, side="right")
        if t.ndim == 0:
            return np.asarray(self.pieces[int(idx)][which](t))
        out = np.empty_like(t)
        for i in np.unique(idx):
            out[idx == i] = self.pieces[i][which](t[idx == i])
        return out

    def value(self, tau: FloatArray) -> FloatArray:
        return self._eval(tau, 0)

    def rate(self, tau: FloatArray) -> FloatArray:
        return self._eval(tau, 1)


def descent_eps(capsule: Capsule, fit: MomentFit, descent: Descent, t: FloatArray) -> FloatArray:
    """T(t)·|q'(t)|/q(t): relative change of q per small-amplitude nutation period [1].

    Parameters
    ----------
    capsule : Capsule
    fit : MomentFit
    descent : Descent
    t : ndarray
        Descent times [s].
    """
    q = np.asarray(descent.q_at(t))
    return _small_amplitude_period(capsule, fit, q) * np.abs(descent.dqdt(t)) / q


def capsule_attitude(
    capsule: Capsule = SOYUZ_CLASS,
    *,
    V0: float = 7600.0,
    gamma0: float = math.radians(-2.0),
    h0: float = 100e3,
    h_end: float = 10e3,
    atmosphere: AtmosphereModel = STANDARD,
    eps_start: float = 0.3,
    t_start: float | None = None,
    theta0: float = math.radians(60.0),
    theta_dot0: float = -0.3,
    spin: float = math.radians(5.0),
    inertia_scale: float = 1.0,
    averaged_init: Literal["exact", "corrected"] = "corrected",
    methods: tuple[str, ...] = ("full", "averaged"),
    samples: int = 2001,
    averaged_samples: int = 201,
    rtol: float = 1e-10,
    averaged_rtol: float = 1e-6,
) -> CapsuleAttitude:
    """Attitude of an uncontrolled capsule during its descent: full vs averaged, §10.

    The attitude run starts when the descent's small parameter T·|q'|/q first falls to
    ``eps_start`` (earlier, q changes too much within a nutation period for any averaging), at
    nutation rate ``theta_dot0``, no precession rate (ψ' = 0) and roll rate ``spin``, and ends
    at altitude ``h_end``.

    Parameters
    ----------
    capsule : Capsule
        Geometry, mass and inertias (default: the illustrative Soyuz-class capsule).
    V0, gamma0, h0 : float
        Entry speed [m/s], flight-path angle [rad] (negative: descending), altitude [m].
    h_end : float
        Altitude where the run ends [m].
    atmosphere : AtmosphereModel
        The atmosphere (default: ICAO 1993 with its isothermal extension; its lapse-rate
        changes make dq/dt jump at a few altitudes, each an abrupt O(ε) change of the forcing
        that the averaged run cannot anticipate).
    eps_start : float
        T·|q'|/q at which the attitude run starts [1], in (0, 1).
    t_start : float, optional
        Descent time at which the attitude run starts [s] (overrides ``eps_start``; to compare
        capsules over the same window).
    theta0 : float
        Initial total angle of attack [rad], in (0, π).
    theta_dot0 : float
        Initial rate of the total angle of attack [rad/s] (the default, mid-swing, is where the
        paper's initialisation is least accurate; 0 starts at a turning point).
    spin : float
        Initial roll rate r [rad/s].
    inertia_scale : float
        Factor applied to A and C (changes the nutation period by √factor, and so the
        descent's ε, without changing the trajectory) [1].
    averaged_init : {"exact", "corrected"}
        Initialisation of the averaged run (§7).
    methods : tuple of str
        ``"full"`` and/or ``"averaged"``.
    samples : int
        Output samples of the full run over the window (its extrema are located on the
        integrator's steps, independently of the samples).
    averaged_samples : int
        Output samples of the averaged run (its envelope is smooth; the discrepancy is
        evaluated on the dense solution at every extremum of the full run).
    rtol : float
        Tolerance of the full integration and of the descent.
    averaged_rtol : float
        Tolerance of the averaged integration (the averaging error, O(ε) or O(ε²), is far
        larger).

    Returns
    -------
    CapsuleAttitude
    """
    check_range("theta0", theta0, low=0.0, high=math.pi)
    check_range("eps_start", eps_start, low=0.0, high=1.0)
    check_range("inertia_scale", inertia_scale, low=0.0)
    if inertia_scale != 1.0:
        from dataclasses import replace

        capsule = replace(capsule, A=capsule.A * inertia_scale, C=capsule.C * inertia_scale)
    fit = fit_moment(capsule)
    descent = descend(capsule, V0, gamma0, h0, h_end=h_end, atmosphere=atmosphere, rtol=rtol)
    t_grid = descent.t
    eps_d = descent_eps(capsule, fit, descent, t_grid)
    if t_start is None:
        t_start = _window_start(capsule, fit, descent, eps_d, eps_start)
    check_range("t_start", t_start, low=0.0, high=float(t_grid[-1]), low_open=False)
    t_end = float(t_grid[-1])
    span = t_end - t_start
    q0 = float(descent.q_at(t_start))
    p = _capsule_params(capsule, fit, descent, atmosphere, t_start, t_end, q0)
    options = AveragingOptions(start=averaged_init)
    R0 = p.mu * spin
    st = nm.State(theta=theta0, theta_dot=theta_dot0, R=R0, G=R0 * math.cos(theta0))
    trajectories = {}
    for m in methods:
        n = samples if m == "full" else averaged_samples
        tol = rtol if m == "full" else averaged_rtol
        t = np.linspace(0.0, span, n)
        trajectories[m] = simulate(nm.MODEL, p, st, t, m, rtol=tol, atol=1e-12, averaging=options)
    rows = nm.extrema(trajectories["full"], p) if "full" in trajectories else []
    env = (
        nm.envelope_discrepancy(rows, trajectories["averaged"])
        if rows and "averaged" in trajectories
        else {}
    )
    window = np.linspace(t_start, t_end, 2001)
    eps_desc = float(np.max(descent_eps(capsule, fit, descent, window)))
    return CapsuleAttitude(
        capsule, fit, descent, t_start, t_end, p, st, trajectories, rows, env, eps_desc
    )


def _window_start(
    capsule: Capsule, fit: MomentFit, descent: Descent, eps_d: FloatArray, eps_start: float
) -> float:
    """The first time the descent's ε = T·|q'|/q falls to ``eps_start`` [s]."""
    t_grid = descent.t
    below = np.flatnonzero(eps_d <= eps_start)
    if below.size == 0:
        raise ParameterError(
            f"eps_start = {eps_start:g}: the descent's T·|q'|/q never falls that low "
            f"(minimum {float(np.min(eps_d)):.3g})"
        )
    i = int(below[0])
    if i == 0:
        return float(t_grid[0])

    def excess(t: float) -> float:
        return float(descent_eps(capsule, fit, descent, np.array([t]))[0]) - eps_start

    return float(brentq(excess, t_grid[i - 1], t_grid[i]))


def _capsule_params(
    capsule: Capsule,
    fit: MomentFit,
    descent: Descent,
    atmosphere: AtmosphereModel,
    t_start: float,
    t_end: float,
    q0: float,
) -> nm.Params:
    """The nonlinear-moment parameters of the capsule over the window [t_start, t_end].

    Q(τ) is a quintic interpolating spline of the descent's q per altitude layer of the
    atmosphere (dρ/dh, hence dq/dt, jumps where the lapse rate changes), and dQ/dτ its
    derivative: one cheap function, smooth between those few kinks, shared by the full and
    the averaged runs; the averaged run is split at each kink (Pressure.breaks). (The
    descent's dense output itself costs ~1 ms per call.)
    """
    span = t_end - t_start
    breaks = _layer_crossings(descent, atmosphere, t_start, t_end)
    profile = _PiecewiseSpline(descent, np.array([t_start, *breaks, t_end]), q0)
    scale = capsule.S * capsule.D / capsule.A
    return nm.Params(
        mu=capsule.C / capsule.A,
        a=q0 * scale * fit.c1,
        b=q0 * scale * fit.c2,
        eps=1.0 / span,
        pressure=nm.Pressure(
            "function",
            function=profile.value,
            derivative=profile.rate,
            tau_end=1.0,
            breaks=tuple((tb - t_start) / span for tb in breaks),
        ),
    )


def capsule_study(
    scales: tuple[float, ...] = (1.0 / 64.0, 1.0 / 16.0, 0.25, 1.0),
    *,
    capsule: Capsule = SOYUZ_CLASS,
    eps_start: float = 0.3,
    theta_dot0: float = -0.3,
    averaged_rtol: float = 1e-6,
    repeat: int = 3,
    **kwargs: Any,
) -> list[dict[str, Any]]:
    """Envelope discrepancy and cost ratio against the descent's ε, §10 (ii)–(iii).

    The window is fixed by the unscaled capsule (its T·|q'|/q falls to ``eps_start``); the
    inertias are then scaled by each factor, which multiplies the nutation period, and so the
    descent's ε, by √factor without changing the trajectory. Both initialisations run.

    Parameters
    ----------
    scales : tuple of float
        Inertia factors [1].
    capsule : Capsule
    eps_start : float
        Start criterion of the window for the unscaled capsule [1].
    theta_dot0 : float
        Initial nutation rate of the unscaled capsule [rad/s].
    averaged_rtol : float
        Tolerance of the averaged runs.
    repeat : int
        The averaged run's wall time is the best of this many runs.
    **kwargs
        Passed to :func:`capsule_attitude` (entry conditions, θ0, spin, tolerances).

    Returns
    -------
    list of dict
        Per scale: ``scale``, ``eps_descent``, ``n_maxima``, and per initialisation
        ``discrepancy_<init>`` (max relative θmax discrepancy) and ``cost_ratio_<init>`` (full
        over averaged wall time), with ``wall_full_s``, ``wall_averaged_<init>_s``.
    """
    base = capsule_attitude(capsule, eps_start=eps_start, methods=(), **kwargs)
    rows = []
    for scale in scales:
        row: dict[str, Any] = {"scale": scale}
        full_traj: Trajectory | None = None
        for init in ("exact", "corrected"):
            methods = ("averaged",) if full_traj is not None else ("full", "averaged")
            run = capsule_attitude(
                capsule,
                t_start=base.t_start,
                theta_dot0=theta_dot0 / math.sqrt(scale),
                inertia_scale=scale,
                averaged_init=init,  # type: ignore[arg-type]
                methods=methods,
                averaged_rtol=averaged_rtol,
                **kwargs,
            )
            if full_traj is None:
                full_traj = run.trajectories["full"]
                rows_ext = run.extrema
                row["eps_descent"] = run.eps_descent
                row["n_maxima"] = sum(1 for r in rows_ext if r[0] == "max")
                row["wall_full_s"] = full_traj.wall_time
            avg = run.trajectories["averaged"]
            env = nm.envelope_discrepancy(rows_ext, avg)
            options = AveragingOptions(start=init)
            wall = _best_averaged_wall(run, avg, options, averaged_rtol, repeat)
            row[f"discrepancy_{init}"] = env["max_relative"]
            row[f"wall_averaged_{init}_s"] = wall
            row[f"cost_ratio_{init}"] = full_traj.wall_time / wall
        rows.append(row)
    return rows


def _best_averaged_wall(
    run: CapsuleAttitude, avg: Trajectory, options: AveragingOptions, rtol: float, repeat: int
) -> float:
    """The best wall time [s] of ``repeat`` averaged runs of ``run`` (``avg`` the first) with
    the averaging ``options`` at tolerance ``rtol``.

    The averaged run takes ~0.1 s: timed as the best of ``repeat`` runs, a busy machine does
    not decide the cost ratio (the full run is timed once).
    """
    again = (
        simulate(nm.MODEL, run.params, run.initial, avg.tau, "averaged", rtol=rtol, atol=1e-12,
                 averaging=options).wall_time
        for _ in range(repeat - 1)
    )  # fmt: skip
    return min(avg.wall_time, *again)
