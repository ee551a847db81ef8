"""A rigid body in Earth orbit under the eddy-current torque of the geomagnetic field and the
gravity gradient, in physical units: the spin evolution of satellites and debris.

The equations are those of the torqued body (:mod:`tumble.models.torqued_body`): Euler's
equations with quaternion kinematics in principal axes, I dω/dt = −ω × Iω + M(t, q, ω), with
the torques of :mod:`tumble.space.torques` evaluated along the orbit inside the compiled
right-hand side. The averaged equations average the same torques over the orbit and the
Earth's rotation in closed form (the field moments ⟨B Bᵀ⟩, ⟨Ḃ Bᵀ⟩ and ⟨r̂ r̂ᵀ/r³⟩ of
:mod:`tumble.space.moments`), then over the Euler–Poinsot motion with the general engine
(Martynenko (1979), §3, for any torque): one evaluation of their right-hand side is one
quadrature over the free rotation, whatever the orbit, and a year of evolution takes a few
hundred steps.

Time is the model's t = τ in units of T0 = 1/|ω(0)| (``t`` column); the SI columns give it in
seconds and days. Besides the torqued body's columns (L_ξ, |L|, ρ, σ, T, k²) every run writes the
rate 2T/L (the spin rate of a body in pure spin), the spin period 2π L/(2T), and the angle
between L and the orbit normal; a full run also writes the attitude and body rates in the body
axes the scenario gave, and the spin axis ω/|ω| in them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any, cast

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging import rotation_sense
from tumble.models import torqued_body as tb
from tumble.models.base import (
    AveragedForm,
    AveragingOptions,
    Column,
    Full,
    FullForm,
    Model,
    Report,
    Sampled,
    Unperturbed,
    Validity,
    attitude_columns,
    attitude_values,
    fixed_columns,
)
from tumble.models.inputs.orbiting_body import DAY, DECLARED, Params, State
from tumble.models.orbiting_body.capture import capture_band
from tumble.rotations import matrix_to_quat, quat_normalize, quat_to_matrix

__all__ = ["FLOOR_FACTOR", "MODEL", "Decay", "Params", "State", "efolding_time", "spin_decay"]

_THEORY = "docs/theory/orbiting-body.md"


def _orbit_columns(
    p: Params, t: FloatArray, cols: Mapping[str, FloatArray]
) -> dict[str, FloatArray]:
    """The rate 2T/L, the spin period and the angle between L and the orbit normal."""
    L, T = cols["L"], cols["T"]
    rate = 2.0 * T / L
    L_xi = np.stack([cols["L1"], cols["L2"], cols["L3"]], axis=1)
    assert p.orbit is not None  # built with one
    normals = p.orbit.normal(np.asarray(t, dtype=float) * p.T0)
    cosine = np.einsum("ni,ni->n", L_xi, normals) / L
    return {
        "rate": rate,
        "rate_deg_s": np.degrees(rate / p.T0),
        "period": 2.0 * math.pi / rate,
        "orbit_angle": np.arccos(np.clip(cosine, -1.0, 1.0)),
    }


def _full_columns(p: Params, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    cols = tb.FULL.to_columns(p, t, Y)
    # Attitude and rates in the scenario's body axes: A_user = A_principal Rᵀ, ω_user = R ω.
    A = quat_to_matrix(quat_normalize(Y[:, 3:])) @ p.axes.T
    q = matrix_to_quat(A)
    w = Y[:, :3] @ p.axes.T
    size = np.linalg.norm(w, axis=1, keepdims=True)
    axis = w / np.where(size > 0.0, size, 1.0)
    spin = {f"spin_axis{i + 1}": axis[:, i] for i in range(3)}
    return {**cols, **attitude_values(q, w), **_orbit_columns(p, t, cols), **spin}


def _averaged_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    assert tb.MODEL.averaged is not None  # the torqued body has averaged equations
    # The torqued body's form without its own bands: the orbiting body's hybrid run crosses
    # the gravity gradient's capture instead.
    plain = replace(options, hybrid=False)
    form = cast("AveragedForm[Any, State]", tb.MODEL.averaged.form(p, st, plain))
    inner = form.to_columns

    def to_columns(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
        cols = inner(p, st, t, Y)
        return {**cols, **_orbit_columns(p, t, cols)}

    return replace(
        form,
        equation=f"Euler–Poinsot averaging of the orbit-averaged torques ({p.label})",
        to_columns=to_columns,
        crossing=capture_band(p, rotation_sense(p.inertia, st.omega)) if options.hybrid else None,
    )


FLOOR_FACTOR = 10.0
"""The rate is at its floor where its local e-folding time exceeds this many first e-folding
times (:func:`spin_decay`)."""


@dataclass(frozen=True, slots=True)
class Decay:
    """How a rate decays along a run (:func:`spin_decay`); times in the units of its ``t``,
    the rate in its own.

    Attributes
    ----------
    efolding : float
        The e-folding time τ1 of the first e-fold (inf when the rate does not decay).
    fit_end : float
        The end of the window τ1 is fitted over: the first time the rate is down by a factor
        e, or the end of the run when it never is.
    floor_time : float or None
        When the rate has reached its floor; None when it does not within the run.
    floor_rate : float or None
        The rate's median from ``floor_time`` to the end of the run; None without a floor.
    """

    efolding: float
    fit_end: float
    floor_time: float | None = None
    floor_rate: float | None = None


def _slope(t: FloatArray, y: FloatArray) -> float:
    """The slope of the least-squares line through (t, y)."""
    return float(np.polyfit(t - t[0], y, 1)[0])


def _window_slopes(t: FloatArray, y: FloatArray, width: float) -> FloatArray:
    """The least-squares slope of y over each window [t_i, t_i + width] that ends within the
    samples, from cumulative sums (one pass, whatever the number of windows)."""
    x = (t - t[0]) / width  # in widths: the sums stay of order n, not n t²
    ends = np.searchsorted(x, x + 1.0 + 1e-12, side="right")  # 1e-12: a sample on the edge
    starts = np.flatnonzero(x + 1.0 <= x[-1] + 1e-12)
    sums = [np.concatenate(([0.0], np.cumsum(v))) for v in (np.ones_like(x), x, y, x * y, x * x)]
    n, sx, sy, sxy, sxx = (c[ends[starts]] - c[starts] for c in sums)
    spread = n * sxx - sx * sx  # 0 for a window of one sample: no slope (NaN)
    slopes = np.full(spread.shape, math.nan)
    np.divide(n * sxy - sx * sy, spread * width, out=slopes, where=spread > 0.0)
    return slopes


def spin_decay(t: FloatArray, rate: FloatArray, factor: float = FLOOR_FACTOR) -> Decay:
    """The e-folding time of a decaying rate where its decay is exponential, and its floor.

    τ1 is −1/slope of the least-squares line through ln(rate) against t over the first e-fold:
    from the start to the first sample where the rate is down by a factor e (over the whole
    run where it never is). It is exact for a rate exp(−t/τ) until then, whatever follows.
    The local e-folding time at t_i is −1/slope of the same line over the window
    [t_i, t_i + τ1]. The rate has reached its floor at the first t_i from which every window
    (to the last that ends within the run) has a local e-folding time above ``factor`` × τ1,
    or a rate that does not decay; the floor rate is the rate's median from there on (the
    level it keeps, whatever the oscillation about it).

    Parameters
    ----------
    t : array
        Sample times, ascending [any unit of time].
    rate : array
        The rate at those times, > 0 [any unit].
    factor : float
        How many first e-folding times the local one must exceed at the floor.

    Returns
    -------
    Decay
        In the units of ``t`` and ``rate``.
    """
    t = np.asarray(t, dtype=float)
    rate = np.asarray(rate, dtype=float)
    y = np.log(rate)
    down = np.flatnonzero(y <= y[0] - 1.0)
    last = max(int(down[0]), 1) if down.size else t.size - 1
    slope = _slope(t[: last + 1], y[: last + 1])
    if slope >= 0.0:
        return Decay(math.inf, float(t[last]))
    tau = -1.0 / slope
    if t[-1] - t[0] < tau:  # no window of one e-folding time fits: no floor to tell
        return Decay(tau, float(t[last]))
    flat = _window_slopes(t, y, tau) > -1.0 / (factor * tau)
    if not flat[-1]:
        return Decay(tau, float(t[last]))
    first = int(flat.size - np.argmin(flat[::-1])) if not flat.all() else 0
    return Decay(tau, float(t[last]), float(t[first]), float(np.median(rate[first:])))


def efolding_time(t: FloatArray, rate: FloatArray) -> float:
    """The e-folding time of the rate [units of t] over its first e-fold (:func:`spin_decay`);
    inf when the rate does not decay."""
    return spin_decay(t, rate).efolding


def _report(p: Params, st: State, trajectories: Mapping[str, Sampled]) -> Report:
    summary: dict[str, object] = {"torque": p.label, "epoch": p.epoch, "T0_s": p.T0}
    assert p.orbit is not None
    summary["orbit_period_s"] = p.orbit.period
    for method, run in trajectories.items():
        cols = run.columns
        if "rate" not in cols or run.tau.size < 2:
            continue
        decay = spin_decay(run.tau * p.T0 / DAY, cols["rate"] / p.T0)  # days, rad/s
        floor = decay.floor_rate
        summary[f"{method}_efolding_days"] = decay.efolding
        summary[f"{method}_efolding_fit_end_days"] = decay.fit_end
        # The line the summary prints: the e-folding time of a decaying rate, or how the rate
        # of one that does not decay has changed from the start to the end.
        decays = math.isfinite(decay.efolding)
        summary[f"{method}_decays"] = True if decays else None
        ratio = float(cols["rate"][-1] / cols["rate"][0])
        summary[f"{method}_rate_ratio"] = None if decays else ratio
        summary[f"{method}_floor_days"] = decay.floor_time
        summary[f"{method}_floor_rate_deg_s"] = None if floor is None else math.degrees(floor)
        summary[f"{method}_final_period_s"] = float(cols["period"][-1] * p.T0)
    return Report(summary=summary)  # type: ignore[arg-type]


_ORBIT_COLUMNS = (
    Column("rate", "rotation rate 2T/L", "rad/t", f"{_THEORY} §6"),
    Column("rate_deg_s", "rotation rate 2T/L in degrees per second", "deg/s", f"{_THEORY} §6"),
    Column("period", "spin period 2πL/(2T)", "t", f"{_THEORY} §6"),
    Column("orbit_angle", "angle between L and the orbit normal", "rad", f"{_THEORY} §6"),
)
_SPIN_AXIS = tuple(
    Column(f"spin_axis{i}", f"spin axis ω/|ω|, body axis x{i} component", "", f"{_THEORY} §6")
    for i in (1, 2, 3)
)

FULL: FullForm[Params, State] = replace(
    cast("FullForm[Any, State]", tb.FULL), to_columns=_full_columns
)

MODEL: Model[Params, State] = DECLARED.model(
    Full.of(
        fixed_columns((*tb._COLUMNS_SLOW, *_ORBIT_COLUMNS, *attitude_columns("t"), *_SPIN_AXIS)),
        FULL,
    ),
    averaged=DECLARED.averaged(
        _averaged_form,
        fixed_columns((*tb._COLUMNS_SLOW, *_ORBIT_COLUMNS)),
        compare=("L1", "L2", "L3", "T"),
    ),
    unperturbed=Unperturbed(
        "the free body (3.1)",
        tb.MODEL.unperturbed.motion,  # type: ignore[union-attr]
        tb.MODEL.unperturbed.rhs,  # type: ignore[union-attr]
    ),
    validity=Validity(check=tb.validity),
    report=_report,
)
