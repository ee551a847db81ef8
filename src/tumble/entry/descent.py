"""Planar ballistic (zero-lift) descent of a capsule over a spherical, non-rotating Earth.

Point mass, drag only, constant drag coefficient CD; state (V, γ, h, x) with V the speed
[m/s], γ the flight-path angle [rad] (negative below the local horizontal), h the altitude [m]
and x the downrange distance along the Earth's surface [m]:

    dV/dt = -ρ(h) V² S CD / (2m) - g sin γ,
    dγ/dt = (V/(R_E + h) - g/V) cos γ,
    dh/dt = V sin γ,
    dx/dt = R_E V cos γ / (R_E + h),

with g = μ/(R_E + h)², R_E = 6371 km, μ = 3.986004418e14 m³/s² (the planar equations of
e.g. Vinh, Busemann & Culp, *Hypersonic and Planetary Entry Flight Mechanics* (1980), with
zero lift, no Earth rotation). The dynamic pressure q = ρV²/2 is what scales the capsule's
restoring moment: a = q S D c1 / A, b = q S D c2 / A (docs/theory/nonlinear-moment.md §9, Q(τ) ∝ q).

The standard atmosphere's density has a slope discontinuity at each ICAO layer boundary; the
integration stops exactly on each one (event, then the last step redone to land on it) and
restarts there, so no step straddles a kink.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from tumble._typing import ArrayLike, FloatArray
from tumble.entry.aerodynamics import Capsule, coefficients
from tumble.entry.atmosphere import H_MIN, STANDARD, AtmosphereModel
from tumble.errors import IntegrationError, ParameterError, check_range

__all__ = ["MU_EARTH", "R_EARTH", "Descent", "descend"]

R_EARTH = 6_371_000.0
"""Mean Earth radius [m]."""
MU_EARTH = 3.986004418e14
"""Earth's gravitational parameter GM [m³/s²] (WGS 84 / IERS value)."""


@dataclass(frozen=True)
class Descent:
    """A ballistic descent with dense output.

    Attributes
    ----------
    t : ndarray
        Solver step times [s], from 0.
    V, gamma, h, downrange : ndarray
        Speed [m/s], flight-path angle [rad], altitude [m], downrange [m] at ``t``.
    q : ndarray
        Dynamic pressure ρV²/2 [Pa] at ``t``.
    mach : ndarray
        Mach number V/a(h) [1] at ``t``.
    t_peak, q_peak : float
        Time [s] and value [Pa] of the largest dynamic pressure (dq/dt = 0 refined by Brent's
        method between solver steps; an end point if q is monotonic).
    reached_h_end : bool
        True if the run stopped at the terminal altitude, False if at the time limit.
    cd : float
        Drag coefficient used [1].

    Methods ``state(t)``, ``q_at(t)`` and ``dqdt(t)`` evaluate the dense output at any
    t ∈ [0, t[-1]] [s]. (The array of q at the steps is ``q``, hence the name ``q_at``.)
    The samples carry the solver's global error (≈ rtol: 2e-10 in q_peak at rtol = 1e-10);
    DOP853's interpolant between steps is coarser (≈ 4e-9 in V at rtol = 1e-10, measured).

    References
    ----------
    See :func:`descend`.
    """

    t: FloatArray
    V: FloatArray
    gamma: FloatArray
    h: FloatArray
    downrange: FloatArray
    q: FloatArray
    mach: FloatArray
    t_peak: float
    q_peak: float
    reached_h_end: bool
    cd: float
    _sol: Any = field(repr=False)
    _rhs: Any = field(repr=False)
    _atm: AtmosphereModel = field(repr=False)

    def state(self, t: ArrayLike) -> FloatArray:
        """Dense-output state (V, γ, h, x) at times t [s] in [0, t[-1]], shape (..., 4)."""
        return _state(self._sol, _times(t, float(self.t[-1])))

    def q_at(self, t: ArrayLike) -> FloatArray:
        """Dynamic pressure ρ(h)V²/2 [Pa] at times t [s] (dense output), shaped like t."""
        y = self.state(t)
        return 0.5 * self._atm.density(y[..., 2]) * y[..., 0] ** 2

    def dqdt(self, t: ArrayLike) -> FloatArray:
        """Rate dq/dt [Pa/s] at times t [s], from the equations of motion (no differencing).

        dq/dt = ½ (dρ/dh) (dh/dt) V² + ρ V dV/dt, with dh/dt and dV/dt the right-hand side at
        the dense-output state.
        """
        return _dqdt(self.state(t), self._rhs, self._atm)


def _times(t: ArrayLike, t_last: float) -> FloatArray:
    """Validate query times against [0, t_last] [s]; clip end-point rounding."""
    ts = np.asarray(t, dtype=float)
    # Dense output is a polynomial: allow rounding at the ends, refuse extrapolation.
    slack = 1e-9 * max(t_last, 1.0)
    bad = ~np.isfinite(ts) | (ts < -slack) | (ts > t_last + slack)
    if np.any(bad):
        i = int(np.flatnonzero(bad.ravel())[0])
        raise ParameterError(
            f"t = {ts.ravel()[i]:g} s is outside the allowed range [0, {t_last:g}] s"
        )
    return np.clip(ts, 0.0, t_last)


def _state(sol: Any, ts: FloatArray) -> FloatArray:
    """Dense-output states at validated times, shape (*ts.shape, 4)."""
    return np.asarray(sol(ts.ravel()), dtype=float).T.reshape((*ts.shape, 4))


def _dqdt(y: FloatArray, rhs: Any, atm: AtmosphereModel) -> FloatArray:
    """dq/dt [Pa/s] at states y (..., 4) from the right-hand side."""
    flat = y.reshape(-1, 4)
    dy = np.array([rhs(0.0, row) for row in flat]).reshape(y.shape)
    rho = atm.density(y[..., 2])
    drho = atm.density_gradient(y[..., 2])
    v = y[..., 0]
    return 0.5 * drho * dy[..., 2] * v**2 + rho * v * dy[..., 0]


def descend(
    capsule: Capsule,
    V0: float,
    gamma0: float,
    h0: float,
    *,
    h_end: float = 10_000.0,
    cd: float | None = None,
    atmosphere: AtmosphereModel = STANDARD,
    gravity: bool = True,
    t_max: float = 3600.0,
    rtol: float = 1e-10,
) -> Descent:
    """Integrate the ballistic descent from (V0, γ0, h0) down to ``h_end`` (DOP853).

    Parameters
    ----------
    capsule : Capsule
        Mass m [kg] and reference area S [m²] (and the default CD).
    V0 : float
        Initial speed [m/s], > 0 (typical 7600).
    gamma0 : float
        Initial flight-path angle [rad] in [-π/2, π/2], negative descending (typical
        -1.5° … -3°).
    h0 : float
        Initial altitude [m], > h_end (typical 100 km).
    h_end : float
        Terminal altitude [m], ≥ -5004 m (default 10 km, assumed: about where a capsule's
        parachutes take over and the ballistic phase ends).
    cd : float, optional
        Constant drag coefficient [1], ≥ 0; default: modified-Newtonian CD of the capsule at
        α = 0, M → ∞ (:func:`~tumble.entry.aerodynamics.coefficients`).
    atmosphere : AtmosphereModel
        Density model; default the ICAO 1993 standard atmosphere with its isothermal extension.
    gravity : bool
        False drops the g terms (for the Allen–Eggers closed form); the curvature term
        V cos γ/(R_E + h) stays, so the path is then a straight line in space.
    t_max : float
        Time limit [s], > 0.
    rtol : float
        Relative tolerance of the solver, in [1e-13, 1e-3]; absolute tolerances are rtol times
        (V0, 1 rad, h0, h0).

    Returns
    -------
    Descent
        Samples at the solver steps, dense output, and the dynamic-pressure peak.

    Raises
    ------
    ParameterError
        For an input outside its range.
    IntegrationError
        If the solver fails or the state stops being finite (e.g. V → 0 on a lofted path).

    References
    ----------
    Planar entry equations over a spherical non-rotating Earth, with zero lift: N. X. Vinh,
    A. Busemann, R. D. Culp, *Hypersonic and Planetary Entry Flight Mechanics* (1980).
    """
    cd = _checked(capsule, V0, gamma0, h0, h_end, cd, t_max, rtol)
    k = capsule.S * cd / (2.0 * capsule.m)  # drag per unit ρV² [m²/kg]
    rhs = _entry_rhs(k, MU_EARTH if gravity else 0.0, atmosphere.density_at)
    scale_h = max(abs(h0), 1.0)
    flight = _Flight(rhs, rtol, rtol * np.array([V0, 1.0, scale_h, scale_h]), scale_h)
    y0 = np.array([V0, gamma0, h0, 0.0])
    sol, ts, ys, reached = flight.fly(y0, h_end, t_max, atmosphere.kinks)
    t = np.concatenate(ts)
    v, gam, h, x = np.concatenate(ys, axis=1)
    q = 0.5 * atmosphere.density(h) * v**2
    t_peak = _peak_time(t, q, lambda s: float(_dqdt(_state(sol, np.array(s)), rhs, atmosphere)))
    v_peak, _, h_peak, _ = sol(np.array([t_peak]))[:, 0]
    q_peak = float(0.5 * atmosphere.density(h_peak) * v_peak**2)
    mach = v / atmosphere.speed_of_sound(h)
    return Descent(t, v, gam, h, x, q, mach, t_peak, q_peak, reached, cd, sol, rhs, atmosphere)


def _checked(
    capsule: Capsule,
    V0: float,
    gamma0: float,
    h0: float,
    h_end: float,
    cd: float | None,
    t_max: float,
    rtol: float,
) -> float:
    """The inputs of :func:`descend` checked (one line naming the first out of its range);
    the drag coefficient to use."""
    check_range("V0", V0, low=0.0)
    check_range(
        "gamma0", gamma0, low=-math.pi / 2, high=math.pi / 2, low_open=False, high_open=False
    )
    check_range("h_end", h_end, low=H_MIN, low_open=False)
    check_range("h0", h0, low=h_end)
    check_range("t_max", t_max, low=0.0)
    check_range("rtol", rtol, low=1e-13, high=1e-3, low_open=False, high_open=False)
    if cd is None:
        cd = float(coefficients(capsule, 0.0).CD)
    check_range("cd", cd, low=0.0, low_open=False)
    return cd


def _entry_rhs(
    k: float, mu: float, density_at: Callable[[float], float]
) -> Callable[[float, FloatArray], FloatArray]:
    """d(V, γ, h, x)/dt of the planar zero-lift entry with drag ρV²k and gravity μ/r²."""

    def rhs(t: float, y: FloatArray) -> FloatArray:
        v, gam, h = float(y[0]), float(y[1]), float(y[2])
        r = R_EARTH + h
        g = mu / (r * r)
        sg, cg = math.sin(gam), math.cos(gam)
        # The trial stages of the step that crosses h_end may probe below the atmosphere's
        # floor H_MIN ≤ h_end; there the floor's density is used (the accepted path ends at
        # h_end, so only the last step's interpolant can feel it, and only if h_end ≈ H_MIN).
        rho = density_at(max(h, H_MIN)) if k > 0.0 else 0.0
        return np.array(
            [
                -rho * v * v * k - g * sg,
                (v / r - g / v) * cg,
                v * sg,
                R_EARTH * v * cg / r,
            ]
        )

    return rhs


@dataclass(frozen=True)
class _Flight:
    """The descent integrated layer by layer of the atmosphere, each leg landing exactly on
    its end altitude."""

    rhs: Callable[[float, FloatArray], FloatArray]
    rtol: float
    atol: FloatArray
    scale_h: float  # altitude scale of the tolerances [m]

    def run(self, t_a: float, y_a: FloatArray, t_b: float, events: list[Any] | None) -> Any:
        """scipy's DOP853 from (t_a, y_a) to t_b; IntegrationError on any failure."""
        with np.errstate(divide="raise", over="raise", invalid="raise"):
            try:
                res = solve_ivp(
                    self.rhs, (t_a, t_b), y_a, method="DOP853", rtol=self.rtol,
                    atol=self.atol, dense_output=True, events=events,
                )  # fmt: skip
            except (FloatingPointError, OverflowError, ZeroDivisionError, ParameterError) as exc:
                raise IntegrationError(f"descent: integration failed ({exc})") from exc
        if res.status < 0 or not np.all(np.isfinite(res.y)):
            raise IntegrationError(f"descent: integration failed ({res.message})")
        return res

    def land(self, t_k: float, y_k: FloatArray, t_hit: float, target: float) -> Any:
        """The last step redone to end on h = target, its end time corrected by Newton's
        method on h: the event's time and state come from the dense interpolant, far less
        accurate than the steps (mm in h at rtol = 1e-10)."""
        for _ in range(8):
            land = self.run(t_k, y_k, t_hit, None)
            miss = float(land.y[2, -1]) - target
            if abs(miss) <= self.rtol * self.scale_h:
                return land
            t_hit -= miss / float(self.rhs(t_hit, land.y[:, -1])[2])
        raise IntegrationError(f"descent: could not land on h = {target:g} m")

    def fly(
        self, y0: FloatArray, h_end: float, t_max: float, kinks: Sequence[float]
    ) -> tuple[_Piecewise, list[FloatArray], list[FloatArray], bool]:
        """From y0 down to h_end (or t_max): dense output, step times and states, and whether
        h_end was reached.

        dρ/dh jumps at the atmosphere's kinks (ICAO layer boundaries): no step may straddle
        one, so each crossing stops the solver and it restarts there (as integrate/ode.py does
        with breakpoints). Without this the error at rtol = 1e-10 is ~50 rtol instead of ~rtol.
        """
        V0 = float(y0[0])

        def floor(t: float, y: FloatArray) -> float:
            return float(y[2]) - h_end

        def stall(t: float, y: FloatArray) -> float:
            return float(y[0]) - 1e-6 * V0  # V → 0: the g/V term is singular

        floor.terminal = True  # type: ignore[attr-defined]
        floor.direction = -1.0  # type: ignore[attr-defined]
        stall.terminal = True  # type: ignore[attr-defined]
        t0, y = 0.0, y0
        starts, sols, ts, ys = [0.0], [], [np.array([0.0])], [y0[:, None]]
        last = math.nan  # the kink the leg starts on
        while True:
            crossings = [_Crossing(hk) for hk in kinks if h_end < hk and hk != last]
            res = self.run(t0, y, t_max, [floor, stall, *crossings])
            if res.t_events[1].size:
                raise IntegrationError(
                    f"descent: the speed fell to ~0 at t = {res.t_events[1][0]:g} s (lofted "
                    "path); a ballistic descent needs V > 0"
                )
            if res.status != 1:  # t_max reached
                sols.append(res.sol)
                ts.append(res.t[1:])
                ys.append(res.y[:, 1:])
                return _Piecewise(starts, sols), ts, ys, False
            fired = next(i for i, ev in enumerate(res.t_events) if ev.size)
            target = h_end if fired == 0 else crossings[fired - 2].altitude
            t_k = float(res.t[-2])
            land = self.land(t_k, res.y[:, -2], float(res.t_events[fired][0]), target)
            sols.extend([res.sol, land.sol])
            starts.append(t_k)
            ts.extend([res.t[1:-1], land.t[1:]])
            ys.extend([res.y[:, 1:-1], land.y[:, 1:]])
            if fired == 0:
                return _Piecewise(starts, sols), ts, ys, True
            t0, y, last = float(land.t[-1]), land.y[:, -1], target
            starts.append(t0)


class _Crossing:
    """Terminal event h = altitude (either direction), for restarts at a kink of ρ(h)."""

    terminal = True

    def __init__(self, altitude: float) -> None:
        self.altitude = altitude

    def __call__(self, t: float, y: FloatArray) -> float:
        return float(y[2]) - self.altitude


class _Piecewise:
    """Dense output of consecutive segments [t_i, t_(i+1)] (restarts at kinks)."""

    def __init__(self, starts: list[float], sols: list[Any]) -> None:
        self.starts = np.asarray(starts[1:], dtype=float)
        self.sols = sols

    def __call__(self, t: FloatArray) -> FloatArray:
        t = np.atleast_1d(np.asarray(t, dtype=float))
        which = np.searchsorted(self.starts, t, side="right")
        out = np.empty((4, t.size))
        for i, sol in enumerate(self.sols):
            mask = which == i
            if np.any(mask):
                out[:, mask] = sol(t[mask])
        return out


def _peak_time(t: FloatArray, q: FloatArray, rate: Callable[[float], float]) -> float:
    """Time [s] of the largest q: the root of dq/dt next to the largest sample."""
    i = int(np.argmax(q))
    if i == 0 or i == t.size - 1:
        return float(t[i])  # q monotonic over the run: the peak is an end point
    r_mid = rate(float(t[i]))
    if r_mid == 0.0:
        return float(t[i])
    # dq/dt < 0 at the largest sample: the peak lies before it, else after it.
    a, b = (t[i - 1], t[i]) if r_mid < 0.0 else (t[i], t[i + 1])
    if not rate(float(a)) > 0.0 > rate(float(b)):
        return float(t[i])
    return float(brentq(rate, a, b, xtol=1e-12 * max(float(t[-1]), 1.0)))
