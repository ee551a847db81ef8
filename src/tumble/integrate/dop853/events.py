"""Zeros of an event function located on the interpolant of each accepted step, compiled."""

from __future__ import annotations

from typing import Any

from tumble._typing import FloatArray
from tumble.integrate.dop853.dense import interpolate
from tumble.kernels.jit import INNER, jit

__all__ = ["event_root"]

_EPS = 2.220446049250313e-16  # machine epsilon of float64


@jit(INNER)
def event_root(
    event_fn: Any, p: FloatArray, t: float, h: float, y: FloatArray, F: FloatArray,
    xa: float, ga: float, xb: float, gb: float, out: FloatArray,
) -> float:  # fmt: skip
    """Fraction x in [xa, xb] of the step where the event function ``event_fn(t, y, p)``
    changes sign (the Illinois variant of regula falsi on the interpolant, to a few ulps of
    t)."""
    side = 0
    x = xb
    for _ in range(200):
        x = (xa * gb - xb * ga) / (gb - ga)
        if not xa < x < xb:
            x = 0.5 * (xa + xb)
        interpolate(F, y, x, out)
        g = event_fn(t + x * h, out, p)
        if g == 0.0:
            return x
        if (g > 0.0) == (gb > 0.0):
            xb, gb = x, g
            if side == 1:
                ga *= 0.5
            side = 1
        else:
            xa, ga = x, g
            if side == -1:
                gb *= 0.5
            side = -1
        if (xb - xa) * abs(h) <= 4.0 * _EPS * max(1.0, abs(t)):
            break
    return x
