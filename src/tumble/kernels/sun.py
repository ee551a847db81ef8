"""The Sun and the Earth's shadow, compiled: what sunlight on an orbiting body needs inside the
integrator's right-hand side, and what :mod:`tumble.space.sun` calls from Python.

* :func:`sun_at`: the unit vector from the Earth to the Sun and its distance at a Julian date,
  by the low-precision solar coordinates of the *Astronomical Almanac* (section C, "Low
  precision formulas for the Sun"; 0.01° from 1950 to 2050), mean equator and equinox of date;
* :func:`cylindrical_shadow` and :func:`conical_shadow`: the fraction of the Sun's disc seen
  from a point near the Earth (Montenbruck and Gill, *Satellite Orbits*, Springer 2000,
  §3.4.2);
* :func:`eclipse_fraction`: the fraction of the time a Keplerian orbit spends in the
  cylindrical shadow, in closed form for a circular orbit and by locating the shadow's arc on
  the orbit otherwise.

Lengths in metres.
"""

from __future__ import annotations

import math

import numpy as np

from tumble._typing import FloatArray
from tumble.kernels.astro import AU, EARTH_RADIUS, J2000, SUN_RADIUS
from tumble.kernels.jit import ENTRY, INLINE, KERNEL, jit

__all__ = [
    "conical_shadow",
    "cylindrical_shadow",
    "eclipse_fraction",
    "eclipse_samples",
    "shadow_samples",
    "sun_at",
    "sun_samples",
]

_DEG = math.pi / 180.0
_CIRCULAR = 1e-9  # an eccentricity below this: the circular orbit's closed form (error e R/a)
_ARC_NODES = 256  # eccentric anomalies searched for the shadow's arc
_BISECTIONS = 52  # to the last bit of the anomaly


@jit(INLINE)
def sun_at(jd: float) -> tuple[float, float, float, float]:
    """(ŝ1, ŝ2, ŝ3, d): the unit vector from the Earth to the Sun and the distance [m] at the
    Julian date ``jd`` (UT or TT: the 69 s between them move the Sun by 0.0008°).

    With n = jd − 2451545.0 days, the mean longitude L = 280.460° + 0.9856474° n and the mean
    anomaly g = 357.528° + 0.9856003° n, the ecliptic longitude is
    λ = L + 1.915° sin g + 0.020° sin 2g, the obliquity ε = 23.439° − 0.0000004° n and the
    distance R = 1.00014 − 0.01671 cos g − 0.00014 cos 2g [AU]; ŝ = (cos λ, cos ε sin λ,
    sin ε sin λ)."""
    n = jd - J2000
    g = (357.528 + 0.9856003 * n) * _DEG
    longitude = (280.460 + 0.9856474 * n + 1.915 * math.sin(g) + 0.020 * math.sin(2.0 * g)) * _DEG
    obliquity = (23.439 - 0.0000004 * n) * _DEG
    sl = math.sin(longitude)
    distance = (1.00014 - 0.01671 * math.cos(g) - 0.00014 * math.cos(2.0 * g)) * AU
    return math.cos(longitude), math.cos(obliquity) * sl, math.sin(obliquity) * sl, distance


@jit(INLINE)
def cylindrical_shadow(r1: float, r2: float, r3: float, s1: float, s2: float, s3: float) -> float:
    """1 in sunlight, 0 inside the cylinder of the Earth's radius behind it along the unit
    vector ŝ towards the Sun, at the point r [m]."""
    along = r1 * s1 + r2 * s2 + r3 * s3
    if along >= 0.0:
        return 1.0
    across2 = r1 * r1 + r2 * r2 + r3 * r3 - along * along
    return 0.0 if across2 < EARTH_RADIUS * EARTH_RADIUS else 1.0


@jit(INLINE)
def conical_shadow(
    r1: float, r2: float, r3: float, s1: float, s2: float, s3: float, distance: float
) -> float:
    """The fraction of the Sun's disc seen from the point r [m], the Sun at ``distance`` [m]
    along ŝ: the overlap of the Sun's and the Earth's apparent discs (radii a and b, centres c
    apart; Montenbruck and Gill §3.4.2): 1 for c ≥ a + b, 0 in the umbra (c ≤ b − a), the
    annulus 1 − b²/a² for c ≤ a − b, and the partial overlap between."""
    d1, d2, d3 = distance * s1 - r1, distance * s2 - r2, distance * s3 - r3  # body → Sun
    to_sun = math.sqrt(d1 * d1 + d2 * d2 + d3 * d3)
    to_earth = math.sqrt(r1 * r1 + r2 * r2 + r3 * r3)
    a = math.asin(min(SUN_RADIUS / to_sun, 1.0))
    b = math.asin(min(EARTH_RADIUS / to_earth, 1.0))
    cos_c = -(r1 * d1 + r2 * d2 + r3 * d3) / (to_earth * to_sun)
    c = math.acos(min(max(cos_c, -1.0), 1.0))
    if c >= a + b:
        return 1.0
    if c <= b - a:
        return 0.0
    if c <= a - b:
        return 1.0 - (b * b) / (a * a)
    x = (c * c + a * a - b * b) / (2.0 * c)
    y = math.sqrt(max(a * a - x * x, 0.0))
    overlap = (
        a * a * math.acos(min(max(x / a, -1.0), 1.0))
        + b * b * math.acos(min(max((c - x) / b, -1.0), 1.0))
        - c * y
    )
    return 1.0 - overlap / (math.pi * a * a)


@jit(INLINE)
def _in_shadow(big_e: float, a: float, e: float, sp: float, sq: float, radius2: float) -> bool:
    """Whether the point of eccentric anomaly E lies in the cylindrical shadow, with sp, sq the
    components of ŝ along the perifocal axes P and Q."""
    x, y = a * (math.cos(big_e) - e), a * math.sqrt(1.0 - e * e) * math.sin(big_e)
    along = x * sp + y * sq
    return along < 0.0 and x * x + y * y - along * along < radius2


@jit(KERNEL)
def eclipse_fraction(a: float, e: float, sp: float, sq: float, sw: float) -> float:
    """The fraction of the time spent in the Earth's cylindrical shadow on the orbit of
    semi-major axis ``a`` [m] and eccentricity ``e``, the Sun along ŝ with components sp, sq,
    sw on the perifocal axes P (to the perigee), Q and the orbit normal W.

    Circular: at the angle u from the Sun's projection on the plane the body is a cos β cos u
    along ŝ and a (1 − cos²β cos²u)^½ from the shadow's axis (sin β = sw): the fraction is
    arccos(c*)/π with c* = (1 − R²/a²)^½/cos β, and 0 where c* ≥ 1. Eccentric: the shadow's
    arcs are found among :data:`_ARC_NODES` eccentric anomalies, their ends refined by
    bisection, and measured in mean anomaly M = E − e sin E (an arc shorter than the nodes'
    spacing, at a grazing entry, is missed: its share of the orbit is below 2/256 of the
    grazing geometry's)."""
    radius2 = EARTH_RADIUS * EARTH_RADIUS
    if e < _CIRCULAR:
        cos_beta = math.sqrt(max(1.0 - sw * sw, 0.0))
        inside = 1.0 - radius2 / (a * a)
        if inside <= 0.0:
            return 1.0  # inside the Earth's radius: no orbit, but no light either
        if cos_beta == 0.0:
            return 0.0
        c = math.sqrt(inside) / cos_beta
        return math.acos(c) / math.pi if c < 1.0 else 0.0
    step = 2.0 * math.pi / _ARC_NODES
    previous = _in_shadow(0.0, a, e, sp, sq, radius2)
    start = 0.0  # where the current arc began, in mean anomaly (M = 0 if in shadow there)
    total = 0.0
    for k in range(1, _ARC_NODES + 1):
        now = _in_shadow(k * step, a, e, sp, sq, radius2)
        if now != previous:
            lo, hi = (k - 1) * step, k * step  # the state changes in (lo, hi]
            for _ in range(_BISECTIONS):
                mid = 0.5 * (lo + hi)
                if _in_shadow(mid, a, e, sp, sq, radius2) == previous:
                    lo = mid
                else:
                    hi = mid
            edge = hi - e * math.sin(hi)  # in mean anomaly, increasing with E
            if now:
                start = edge
            else:
                total += edge - start
        previous = now
    if previous:  # an arc still open at E = 2π (it goes on through E = 0)
        total += 2.0 * math.pi - start
    return total / (2.0 * math.pi)


@jit(ENTRY)
def sun_samples(jd: FloatArray) -> FloatArray:
    """:func:`sun_at` at the Julian dates ``jd`` (n,) → (n, 4): ŝ and the distance [m]."""
    out = np.empty((jd.size, 4))
    for k in range(jd.size):
        out[k, 0], out[k, 1], out[k, 2], out[k, 3] = sun_at(jd[k])
    return out


@jit(ENTRY)
def shadow_samples(r: FloatArray, s: FloatArray, distance: FloatArray, conical: bool
                   ) -> FloatArray:  # fmt: skip
    """The visible fraction of the Sun at the points r (n, 3) with the Sun along s (n, 3) at
    ``distance`` (n,): :func:`conical_shadow` or :func:`cylindrical_shadow`."""
    out = np.empty(r.shape[0])
    for k in range(r.shape[0]):
        if conical:
            out[k] = conical_shadow(r[k, 0], r[k, 1], r[k, 2], s[k, 0], s[k, 1], s[k, 2],
                                    distance[k])  # fmt: skip
        else:
            out[k] = cylindrical_shadow(r[k, 0], r[k, 1], r[k, 2], s[k, 0], s[k, 1], s[k, 2])
    return out


@jit(ENTRY)
def eclipse_samples(a: FloatArray, e: FloatArray, s: FloatArray) -> FloatArray:
    """:func:`eclipse_fraction` for each orbit (a, e) (n,) and perifocal Sun s (n, 3)."""
    out = np.empty(a.size)
    for k in range(a.size):
        out[k] = eclipse_fraction(a[k], e[k], s[k, 0], s[k, 1], s[k, 2])
    return out
