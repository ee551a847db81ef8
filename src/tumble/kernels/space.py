"""The orbit and the geomagnetic field, compiled: a body's position and velocity on a Keplerian
orbit with the secular drift of its node and perigee, and the field of a tilted dipole that turns
with the Earth, with its time derivative along the orbit.

The one definition of this physics: the torque terms of an orbiting body
(:mod:`tumble.kernels.torque`) evaluate it inside the integrator's right-hand side, and
:mod:`tumble.space` calls it through :func:`field_samples` and :func:`orbit_states` (the field
moments of the averaged equations, the outputs). Any consistent units: tumble passes lengths in
metres and times in its model's unit.

Payloads (floats):

* orbit, :data:`ORBIT_SIZE` = 10: a, e, i, Ω0, ω0, M0, Ṁ, Ω̇, ω̇, μ — semi-major axis, eccentricity,
  inclination, right ascension of the ascending node and argument of perigee at t = 0, mean
  anomaly at t = 0 and its rate (the mean motion with its J2 correction), the secular rates of
  Ω and ω, and the gravitational parameter;
* field, :data:`FIELD_SIZE` = 5: R³g1, R³g2, R³g3, θ0, ω_E — the dipole's Gauss vector
  g = (g11, h11, g10) in Earth-fixed axes times the reference radius cubed, the Earth's
  rotation angle at t = 0 (Greenwich sidereal time) and its rate.
"""

from __future__ import annotations

import math

import numpy as np

from tumble._typing import FloatArray
from tumble.kernels.jit import ENTRY, INLINE, jit

__all__ = [
    "FIELD_SIZE",
    "ORBIT_SIZE",
    "dipole_field",
    "field_at",
    "field_samples",
    "fields_along",
    "orbit_at",
    "orbit_state",
    "orbit_states",
]

ORBIT_SIZE = 10
FIELD_SIZE = 5

Vec3 = tuple[float, float, float]

_KEPLER_TOL = 1e-15
_KEPLER_ITERATIONS = 30


@jit(INLINE)
def _eccentric_anomaly(mean: float, e: float) -> float:
    """E of Kepler's equation E − e sin E = M, by Newton's method from E = M + e sin M (a few
    iterations for e < 0.9; at most 30)."""
    m = mean - 2.0 * math.pi * math.floor(mean / (2.0 * math.pi) + 0.5)  # in [−π, π)
    big = m + e * math.sin(m)
    for _ in range(_KEPLER_ITERATIONS):
        step = (big - e * math.sin(big) - m) / (1.0 - e * math.cos(big))
        big -= step
        if abs(step) < _KEPLER_TOL:
            break
    return big


@jit(INLINE)
def orbit_state(
    orbit: FloatArray, v: int, mean: float, raan: float, argp: float
) -> tuple[Vec3, Vec3]:
    """Position and velocity (inertial axes) at mean anomaly ``mean`` on the orbit of payload
    ``orbit[v:]`` with node ``raan`` and perigee ``argp`` [rad]. The velocity is the time
    derivative of the drifting ellipse: the motion along it at the rate dM/dt, plus the turn of
    the node about ξ3 (dΩ/dt ξ3 × r) and of the perigee about the normal (dω/dt ĥ × r)."""
    a, e, inc = orbit[v], orbit[v + 1], orbit[v + 2]
    big = _eccentric_anomaly(mean, e)
    ce, se = math.cos(big), math.sin(big)
    eta = math.sqrt(1.0 - e * e)
    x, y = a * (ce - e), a * eta * se
    edot = orbit[v + 6] / (1.0 - e * ce)
    vx, vy = -a * se * edot, a * eta * ce * edot
    cO, sO = math.cos(raan), math.sin(raan)
    cw, sw = math.cos(argp), math.sin(argp)
    ci, si = math.cos(inc), math.sin(inc)
    # Columns P, Q of the perifocal frame in inertial axes: R3(−Ω) R1(−i) R3(−ω).
    p1, p2, p3 = cO * cw - sO * sw * ci, sO * cw + cO * sw * ci, sw * si
    q1, q2, q3 = -cO * sw - sO * cw * ci, -sO * sw + cO * cw * ci, cw * si
    r1, r2, r3 = x * p1 + y * q1, x * p2 + y * q2, x * p3 + y * q3
    # dω/dt ĥ × r with ĥ × P = Q, ĥ × Q = −P; dΩ/dt ξ3 × r.
    wd, od = orbit[v + 8], orbit[v + 7]
    return (
        (r1, r2, r3),
        (
            vx * p1 + vy * q1 + wd * (x * q1 - y * p1) - od * r2,
            vx * p2 + vy * q2 + wd * (x * q2 - y * p2) + od * r1,
            vx * p3 + vy * q3 + wd * (x * q3 - y * p3),
        ),
    )


@jit(INLINE)
def orbit_at(orbit: FloatArray, v: int, t: float) -> tuple[Vec3, Vec3]:
    """Position and velocity at time t: the elements drifted secularly from t = 0."""
    mean = orbit[v + 5] + orbit[v + 6] * t
    raan = orbit[v + 3] + orbit[v + 7] * t
    argp = orbit[v + 4] + orbit[v + 8] * t
    return orbit_state(orbit, v, mean, raan, argp)


@jit(INLINE)
def dipole_field(field: FloatArray, v: int, angle: float, r: Vec3, vel: Vec3) -> tuple[Vec3, Vec3]:
    """The dipole's field B at position r and its rate dB/dt along the velocity ``vel``, with
    the Earth turned by ``angle`` about the inertial ξ3 axis and turning at ω_E.

    B = R³ [3 (g·r) r − r² g] / r⁵ (the degree-1 term of the geomagnetic potential) with
    g = (g11, h11, g10) turned into inertial axes; dB/dt adds the motion of the body along r
    and the Earth's rotation of g (dg/dt = ω_E ξ3 × g).
    """
    c, s = math.cos(angle), math.sin(angle)
    g1 = c * field[v] - s * field[v + 1]
    g2 = s * field[v] + c * field[v + 1]
    g3 = field[v + 2]
    we = field[v + 4]
    d1, d2 = -we * g2, we * g1  # dg/dt
    x, y, z = r
    u, w, h = vel
    r2 = x * x + y * y + z * z
    inv3 = 1.0 / (r2 * math.sqrt(r2))
    inv5 = inv3 / r2
    gr = g1 * x + g2 * y + g3 * z
    rv = x * u + y * w + z * h
    b = (
        3.0 * gr * x * inv5 - g1 * inv3,
        3.0 * gr * y * inv5 - g2 * inv3,
        3.0 * gr * z * inv5 - g3 * inv3,
    )
    # d/dt of 3(g·r) r/r⁵ − g/r³ with r and g both moving.
    grdot = g1 * u + g2 * w + g3 * h + d1 * x + d2 * y
    k = 3.0 * grdot * inv5 - 15.0 * gr * rv * inv5 / r2
    j = 3.0 * rv * inv5
    bdot = (
        k * x + 3.0 * gr * u * inv5 + j * g1 - d1 * inv3,
        k * y + 3.0 * gr * w * inv5 + j * g2 - d2 * inv3,
        k * z + 3.0 * gr * h * inv5 + j * g3,
    )
    return b, bdot


@jit(INLINE)
def field_at(orbit: FloatArray, vo: int, field: FloatArray, vf: int, t: float) -> tuple[Vec3, Vec3]:
    """B and dB/dt (inertial axes) at the body's place at time t."""
    r, vel = orbit_at(orbit, vo, t)
    return dipole_field(field, vf, field[vf + 3] + field[vf + 4] * t, r, vel)


@jit(ENTRY)
def orbit_states(orbit: FloatArray, t: FloatArray) -> FloatArray:
    """Positions and velocities at the times t (n,) → (n, 6)."""
    out = np.empty((t.size, 6))
    for k in range(t.size):
        r, vel = orbit_at(orbit, 0, t[k])
        out[k, 0], out[k, 1], out[k, 2] = r
        out[k, 3], out[k, 4], out[k, 5] = vel
    return out


@jit(ENTRY)
def fields_along(orbit: FloatArray, field: FloatArray, t: FloatArray) -> FloatArray:
    """B and dB/dt at the body's place at the times t (n,) → (n, 6)."""
    out = np.empty((t.size, 6))
    for k in range(t.size):
        b, bdot = field_at(orbit, 0, field, 0, t[k])
        out[k, 0], out[k, 1], out[k, 2] = b
        out[k, 3], out[k, 4], out[k, 5] = bdot
    return out


@jit(ENTRY)
def field_samples(
    orbit: FloatArray, field: FloatArray, means: FloatArray, angles: FloatArray, t: float
) -> FloatArray:
    """B and dB/dt at every mean anomaly ``means`` (n,) for every Earth angle ``angles``
    (m,), with node and perigee drifted to time t: shape (n, m, 6)."""
    out = np.empty((means.size, angles.size, 6))
    raan = orbit[3] + orbit[7] * t
    argp = orbit[4] + orbit[8] * t
    for i in range(means.size):
        r, vel = orbit_state(orbit, 0, means[i], raan, argp)
        for j in range(angles.size):
            b, bdot = dipole_field(field, 0, angles[j], r, vel)
            out[i, j, 0], out[i, j, 1], out[i, j, 2] = b
            out[i, j, 3], out[i, j, 4], out[i, j, 5] = bdot
    return out
