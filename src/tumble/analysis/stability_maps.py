"""Stability maps of the co-rotation of a conducting body in a rotating magnetic field.

Yu. G. Martynenko (1979); docs/theory/rotating-field.md §§5–7 and §16. The stationary rotation
(2.1) about body axis x3 is classified from the roots of (2.5) over a 2-D grid of parameters
with :func:`tumble.analysis.stability.stability_grid`:

* ``over="inertia"``: I1/I3 and I2/I3 (with I3 = 1) at fixed β and ε. Points breaking the
  triangle inequality are not bodies (code −1). The map shows the paper's three regions — x3
  the largest axis (asymptotically stable), the middle one (unstable, real root ≈ |ω0|) and
  the smallest one (unstable, O(ε) oscillatory growth) — separated by the critical lines
  I1 = I3, I2 = I3, and at β = π/2 the thin plate I1 + I2 = I3 on the edge of the domain.
* ``over="beta-eps"``: the field cone angle β and ε (log-spaced) at a fixed body.

One point of the maps, with its characteristic polynomial and roots, is
:func:`co_rotation_stability` (``tumble stability``).

Each point is the paper's member φ = 0 of the family of co-rotations (Γ = E, the field in the
body's (x1, x3) plane), where (2.5) holds.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any, Literal

import numpy as np
import xarray as xr

from tumble._typing import FloatArray
from tumble.analysis.stability import StabilityReport, analyze, stability_grid
from tumble.errors import ParameterError, check_range
from tumble.models import rotating_field

__all__ = [
    "DEFAULT_BETA",
    "DEFAULT_EPS",
    "DEFAULT_INERTIA",
    "DEFAULT_N",
    "co_rotation_stability",
    "field_map",
    "inertia_map",
    "rotating_field_map",
]

DEFAULT_INERTIA = (1.0, 1.5, 2.0)
"""Body of the (β, ε) map: x3 is the largest axis [inertia unit]."""
DEFAULT_BETA = math.pi / 4
"""Field cone angle of the inertia map [rad]: a generic cone (β = π/2 adds the thin plate)."""
DEFAULT_EPS = 0.05
"""ε of the inertia map [inertia unit, with I3 = 1]."""
DEFAULT_N = 41
"""Grid points per axis: 41 × 41 classifications take a few seconds."""

RATIO_RANGE = (0.05, 2.0)
"""Default range of I1/I3 and I2/I3 [1]."""
BETA_RANGE = (0.0, math.pi / 2)
"""Default range of β [rad]; β ∈ (π/2, π] mirrors it (only sin²β, cos²β enter (2.5))."""
EPS_RANGE = (1e-3, 1.0)
"""Default range of ε, log-spaced [inertia unit]."""

MAX_N = 1001

Progress = Callable[[int, int], None]


def co_rotation_stability(
    inertia: Sequence[float], beta: float, eps: float
) -> tuple[rotating_field.Params, StabilityReport, dict[str, Any]]:
    """The stability of the co-rotation (2.1) about body x3 of one body, from (2.5)/(2.6).

    Parameters
    ----------
    inertia : (I1, I2, I3)
        Principal moments [inertia unit]; the rotation is about x3.
    beta : float
        Field cone angle β [rad], in [0, π].
    eps : float
        ε = M0/ω > 0 [inertia unit].

    Returns
    -------
    params : rotating_field.Params
        The validated parameters.
    report : StabilityReport
        Coefficients, exact and first-order roots, classification
        (:func:`tumble.analysis.stability.analyze`).
    document : dict
        The model, the parameters and the report as one JSON-ready mapping.
    """
    p = rotating_field.Params(np.array(inertia), beta, eps)
    rep = analyze(rotating_field.MODEL, p)
    doc = {
        "model": rotating_field.MODEL.name,
        "parameters": {"inertia": p.inertia.tolist(), "beta": p.beta, "eps": p.eps},
        **rep.to_dict(),
    }
    return p, rep, doc


def _check_n(n: int) -> int:
    check_range("map.n", n, low=2, high=MAX_N, low_open=False, high_open=False)
    if int(n) != n:
        raise ParameterError(f"map.n = {n!r} must be a whole number of grid points")
    return int(n)


def _check_interval(
    field: str, lo_hi: Sequence[float], *, low: float, high: float, low_open: bool = True
) -> None:
    if len(lo_hi) != 2:
        raise ParameterError(f"{field} must be two numbers (low, high), got {list(lo_hi)!r}")
    lo, hi = (float(v) for v in lo_hi)
    for i, v in enumerate((lo, hi)):
        check_range(f"{field}[{i}]", v, low=low, high=high, low_open=low_open, high_open=False)
    if not lo < hi:
        raise ParameterError(f"{field} = ({lo:g}, {hi:g}) must be ascending")


def _fmt(x: float) -> str:
    return f"{x:.6g}"


def inertia_map(
    beta: float = DEFAULT_BETA,
    eps: float = DEFAULT_EPS,
    *,
    ratio1: Sequence[float] = RATIO_RANGE,
    ratio2: Sequence[float] = RATIO_RANGE,
    n: int = DEFAULT_N,
    progress: Progress | None = None,
) -> xr.Dataset:
    """Classification of the co-rotation (2.1) over (I1/I3, I2/I3), from (2.5).

    Parameters
    ----------
    beta : float
        Field cone angle β [rad], in [0, π].
    eps : float
        ε = M0/ω > 0 [inertia unit, with I3 = 1].
    ratio1, ratio2 : (float, float)
        Ranges of I1/I3 (x axis) and I2/I3 (y axis) [1], positive, ascending.
    n : int
        Grid points per axis, 2 … 1001.
    progress : callable, optional
        ``progress(done, total)`` after each grid point.

    Returns
    -------
    xarray.Dataset
        ``classification`` (index in :data:`~tumble.analysis.stability.CLASSES`, −1: not a
        body) and ``max_real`` [1/τ] on dims (``I2_over_I3``, ``I1_over_I3``).
    """
    rotating_field.Params(np.ones(3), beta, eps)  # β and ε themselves must be valid
    n = _check_n(n)
    _check_interval("map.ratio1", ratio1, low=0.0, high=math.inf)
    _check_interval("map.ratio2", ratio2, low=0.0, high=math.inf)
    x = np.linspace(float(ratio1[0]), float(ratio1[1]), n)
    y = np.linspace(float(ratio2[0]), float(ratio2[1]), n)

    def make(r1: float, r2: float) -> rotating_field.Params:
        return rotating_field.Params(np.array([r1, r2, 1.0]), beta, eps)

    return _map(
        make,
        ("I1_over_I3", x, {"long_name": "I1/I3", "units": "1", "equation": "(2.5)"}),
        ("I2_over_I3", y, {"long_name": "I2/I3", "units": "1", "equation": "(2.5)"}),
        {
            "beta": float(beta),
            "eps": float(eps),
            "fixed_parameters": f"β = {_fmt(beta)} rad, ε = {_fmt(eps)}, I3 = 1",
            "outside_domain_label": "not a body (triangle inequality)",
        },
        progress,
    )


def field_map(
    inertia: Sequence[float] = DEFAULT_INERTIA,
    *,
    beta: Sequence[float] = BETA_RANGE,
    eps: Sequence[float] = EPS_RANGE,
    n: int = DEFAULT_N,
    progress: Progress | None = None,
) -> xr.Dataset:
    """Classification of the co-rotation (2.1) over (β, ε) for one body, from (2.5).

    Parameters
    ----------
    inertia : (I1, I2, I3)
        Principal moments [inertia unit]; the rotation is about x3.
    beta : (float, float)
        Range of the field cone angle β [rad], within [0, π] (x axis, linear).
    eps : (float, float)
        Range of ε = M0/ω [inertia unit], positive (y axis, log-spaced).
    n : int
        Grid points per axis (in β and in ε), 2 … 1001.
    progress : callable, optional
        ``progress(done, total)`` after each of the n² points.

    Returns
    -------
    xarray.Dataset
        ``classification`` and ``max_real`` [1/τ] on dims (``eps``, ``beta``).
    """
    n = _check_n(n)
    _check_interval("map.beta", beta, low=0.0, high=math.pi, low_open=False)
    _check_interval("map.eps", eps, low=0.0, high=math.inf)
    body = rotating_field.Params(np.asarray(inertia, dtype=float), float(beta[0]), float(eps[0]))
    x = np.linspace(float(beta[0]), float(beta[1]), n)
    y = np.geomspace(float(eps[0]), float(eps[1]), n)
    moments = ", ".join(_fmt(v) for v in body.inertia.tolist())

    def make(b: float, e: float) -> rotating_field.Params:
        return rotating_field.Params(body.inertia, b, e)

    return _map(
        make,
        ("beta", x, {"long_name": "field cone angle β", "units": "rad", "equation": "(1.1)"}),
        (
            "eps",
            y,
            {"long_name": "ε = M0/ω", "units": "inertia unit", "equation": "(1.5)", "scale": "log"},
        ),
        {
            "inertia": body.inertia.tolist(),
            "fixed_parameters": f"I = ({moments})",
            "outside_domain_label": "outside the domain",
        },
        progress,
    )


def _map(
    make: Callable[[float, float], rotating_field.Params],
    x: tuple[str, FloatArray, dict[str, str]],
    y: tuple[str, FloatArray, dict[str, str]],
    attrs: dict[str, Any],
    progress: Progress | None,
) -> xr.Dataset:
    """The co-rotation classified at the parameters ``make(x, y)`` of every point of the grid
    of axes ``x`` and ``y`` (name, values, attributes), with the map's ``attrs``, the motion,
    the equation and the reference (:func:`tumble.analysis.stability.stability_grid`)."""
    ds = stability_grid(rotating_field.MODEL, make, x, y, attrs=attrs, progress=progress)
    ds.attrs.update(
        motion="co-rotation about body x3 (2.1), phase φ = 0",
        equation="(2.5)",
        reference="Yu. G. Martynenko (1979); docs/theory/rotating-field.md §§5–7, §16",
    )
    return ds


def rotating_field_map(
    over: Literal["inertia", "beta-eps"],
    *,
    inertia: Sequence[float] | None = None,
    beta: float | Sequence[float] | None = None,
    eps: float | Sequence[float] | None = None,
    n: int = DEFAULT_N,
    progress: Progress | None = None,
) -> xr.Dataset:
    """One of the two stability maps, by name (for the CLI and notebooks).

    Parameters
    ----------
    over : {"inertia", "beta-eps"}
        ``"inertia"``: :func:`inertia_map` at the fixed ``beta`` [rad] and ``eps`` (defaults
        :data:`DEFAULT_BETA`, :data:`DEFAULT_EPS`); ``inertia`` must be None.
        ``"beta-eps"``: :func:`field_map` of the body ``inertia`` (default
        :data:`DEFAULT_INERTIA`); ``beta`` and ``eps`` may give the (low, high) ranges.
    inertia, beta, eps
        See ``over``.
    n : int
        Grid points per axis.
    progress : callable, optional
        ``progress(done, total)`` after each grid point.

    Returns
    -------
    xarray.Dataset
        The map of :func:`inertia_map` or of :func:`field_map`.
    """
    if over == "inertia":
        if inertia is not None:
            raise ParameterError(
                "map.inertia does not apply to the inertia map (I1/I3 and I2/I3 are its axes); "
                'use over = "beta-eps" for a fixed body'
            )
        b = DEFAULT_BETA if beta is None else beta
        e = DEFAULT_EPS if eps is None else eps
        if not isinstance(b, int | float) or not isinstance(e, int | float):
            raise ParameterError("map.beta and map.eps of the inertia map must be single numbers")
        return inertia_map(float(b), float(e), n=n, progress=progress)
    if over == "beta-eps":
        if isinstance(beta, int | float) or isinstance(eps, int | float):
            raise ParameterError(
                "map.beta and map.eps are the axes of the beta-eps map: give (low, high) ranges "
                "or leave them out"
            )
        return field_map(
            DEFAULT_INERTIA if inertia is None else inertia,
            beta=BETA_RANGE if beta is None else beta,
            eps=EPS_RANGE if eps is None else eps,
            n=n,
            progress=progress,
        )
    raise ParameterError(f'map.over = {over!r} must be "inertia" or "beta-eps"')
