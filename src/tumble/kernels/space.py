"""The orbit and the geomagnetic field, compiled: a body's position and velocity on a Keplerian
orbit with the secular drift of its node and perigee, and the field of a tilted dipole or of a
spherical-harmonic model (the IGRF) that turns with the Earth, with its time derivative along
the orbit.

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
  rotation angle at t = 0 (Greenwich sidereal time) and its rate;
* harmonic field, :func:`harmonic_size` (degree N): N, θ0, ω_E, the reference radius a, then
  the coefficients C_nm and S_nm [T] of the unnormalised Legendre functions, n = 1 … N,
  m = 0 … n.
"""

from __future__ import annotations

import cmath
import math

import numpy as np

from tumble._typing import FloatArray
from tumble.kernels.jit import ENTRY, INLINE, KERNEL, jit
from tumble.kernels.layout import Field, Layout

__all__ = [
    "DIPOLE",
    "FIELD_SIZE",
    "HARMONIC",
    "ORBIT",
    "ORBIT_SIZE",
    "dipole_field",
    "field_at",
    "field_samples",
    "fields_along",
    "harmonic_field",
    "harmonic_field_at",
    "harmonic_size",
    "orbit_at",
    "orbit_state",
    "orbit_states",
    "perifocal",
]

ORBIT = Layout(
    "orbit",
    (
        Field("a", 1, "m", "semi-major axis", 0.0),
        Field("e", 1, "1", "eccentricity", 0.0, 1.0),
        Field("i", 1, "rad", "inclination", 0.0, math.pi),
        Field("raan", 1, "rad", "right ascension of the ascending node at t = 0"),
        Field("argp", 1, "rad", "argument of perigee at t = 0"),
        Field("mean", 1, "rad", "mean anomaly at t = 0"),
        Field("mean_rate", 1, "rad/time", "mean motion, with its J2 correction"),
        Field("raan_rate", 1, "rad/time", "secular rate of the node"),
        Field("argp_rate", 1, "rad/time", "secular rate of the perigee"),
        Field("mu", 1, "m³/time²", "gravitational parameter", 0.0),
    ),
)
"""An orbit's payload (module notes)."""
DIPOLE = Layout(
    "dipole field",
    (
        Field("gauss", 3, "T·m³", "R³ (g11, h11, g10), Earth-fixed axes"),
        Field("theta0", 1, "rad", "the Earth's rotation angle at t = 0"),
        Field("earth_rate", 1, "rad/time", "the Earth's rotation rate"),
    ),
)
"""A tilted dipole's payload (module notes)."""
HARMONIC = Layout(
    "harmonic field",
    (
        Field("degree", 1, "1", "degree N", 1.0),
        Field("theta0", 1, "rad", "the Earth's rotation angle at t = 0"),
        Field("earth_rate", 1, "rad/time", "the Earth's rotation rate"),
        Field("radius", 1, "m", "reference radius", 0.0),
    ),
    tail="coefficients",
)
"""A harmonic field's payload: the head, then C_nm and S_nm (module notes)."""
ORBIT_SIZE = ORBIT.size
FIELD_SIZE = DIPOLE.size
_O, _D, _H = ORBIT.at, DIPOLE.at, HARMONIC.at
_HARMONIC_HEAD = HARMONIC.size

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
def perifocal(raan: float, argp: float, inc: float) -> tuple[Vec3, Vec3, Vec3]:
    """The perifocal axes P (to the perigee), Q and W (the orbit normal) in inertial axes, the
    columns of R3(−Ω) R1(−i) R3(−ω), for the node Ω, perigee ω and inclination i [rad]."""
    cO, sO = math.cos(raan), math.sin(raan)
    cw, sw = math.cos(argp), math.sin(argp)
    ci, si = math.cos(inc), math.sin(inc)
    return (
        (cO * cw - sO * sw * ci, sO * cw + cO * sw * ci, sw * si),
        (-cO * sw - sO * cw * ci, -sO * sw + cO * cw * ci, cw * si),
        (sO * si, -cO * si, ci),
    )


@jit(INLINE)
def orbit_state(
    orbit: FloatArray, v: int, mean: float, raan: float, argp: float
) -> tuple[Vec3, Vec3]:
    """Position and velocity (inertial axes) at mean anomaly ``mean`` on the orbit of payload
    ``orbit[v:]`` with node ``raan`` and perigee ``argp`` [rad]. The velocity is the time
    derivative of the drifting ellipse: the motion along it at the rate dM/dt, plus the turn of
    the node about ξ3 (dΩ/dt ξ3 × r) and of the perigee about the normal (dω/dt ĥ × r)."""
    a, e, inc = orbit[v + _O.a], orbit[v + _O.e], orbit[v + _O.i]
    big = _eccentric_anomaly(mean, e)
    ce, se = math.cos(big), math.sin(big)
    eta = math.sqrt(1.0 - e * e)
    x, y = a * (ce - e), a * eta * se
    edot = orbit[v + _O.mean_rate] / (1.0 - e * ce)
    vx, vy = -a * se * edot, a * eta * ce * edot
    (p1, p2, p3), (q1, q2, q3), _ = perifocal(raan, argp, inc)
    r1, r2, r3 = x * p1 + y * q1, x * p2 + y * q2, x * p3 + y * q3
    # dω/dt ĥ × r with ĥ × P = Q, ĥ × Q = −P; dΩ/dt ξ3 × r.
    wd, od = orbit[v + _O.argp_rate], orbit[v + _O.raan_rate]
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
    mean = orbit[v + _O.mean] + orbit[v + _O.mean_rate] * t
    raan = orbit[v + _O.raan] + orbit[v + _O.raan_rate] * t
    argp = orbit[v + _O.argp] + orbit[v + _O.argp_rate] * t
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
    gx, gy, g3 = field[v + _D.gauss], field[v + _D.gauss + 1], field[v + _D.gauss + 2]
    g1 = c * gx - s * gy
    g2 = s * gx + c * gy
    we = field[v + _D.earth_rate]
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
    return dipole_field(field, vf, field[vf + _D.theta0] + field[vf + _D.earth_rate] * t, r, vel)


@jit(INLINE)
def harmonic_field_at(orbit: FloatArray, vo: int, field: FloatArray, vf: int, t: float
                      ) -> tuple[Vec3, Vec3]:  # fmt: skip
    """B and dB/dt (inertial axes) of the harmonic field at field[vf:] (:data:`HARMONIC`) at
    the body's place at time t on the orbit at orbit[vo:] (:data:`ORBIT`): :func:`field_at`
    for a harmonic field."""
    r, vel = orbit_at(orbit, vo, t)
    return harmonic_field(field, vf, field[vf + _H.theta0] + field[vf + _H.earth_rate] * t, r, vel)


@jit(ENTRY)
def orbit_states(orbit: FloatArray, t: FloatArray) -> FloatArray:
    """Positions and velocities at the times t (n,) → (n, 6)."""
    out = np.empty((t.size, 6))
    for k in range(t.size):
        r, vel = orbit_at(orbit, 0, t[k])
        out[k, 0], out[k, 1], out[k, 2] = r
        out[k, 3], out[k, 4], out[k, 5] = vel
    return out


@jit(INLINE)
def _any_field(field: FloatArray, angle: float, r: Vec3, vel: Vec3) -> tuple[Vec3, Vec3]:
    """B and dB/dt of the dipole payload (:data:`FIELD_SIZE` long) or of a harmonic one."""
    if field.size == FIELD_SIZE:
        return dipole_field(field, 0, angle, r, vel)
    return harmonic_field(field, 0, angle, r, vel)


@jit(INLINE)
def _earth_angle(field: FloatArray, t: float) -> float:
    """The Earth's rotation angle at time t of either payload."""
    if field.size == FIELD_SIZE:
        return field[_D.theta0] + field[_D.earth_rate] * t
    return field[_H.theta0] + field[_H.earth_rate] * t


@jit(ENTRY)
def fields_along(orbit: FloatArray, field: FloatArray, t: FloatArray) -> FloatArray:
    """B and dB/dt at the body's place at the times t (n,) → (n, 6), for a dipole or a
    harmonic field."""
    out = np.empty((t.size, 6))
    for k in range(t.size):
        r, vel = orbit_at(orbit, 0, t[k])
        b, bdot = _any_field(field, _earth_angle(field, t[k]), r, vel)
        out[k, 0], out[k, 1], out[k, 2] = b
        out[k, 3], out[k, 4], out[k, 5] = bdot
    return out


@jit(ENTRY)
def field_samples(
    orbit: FloatArray, field: FloatArray, means: FloatArray, angles: FloatArray, t: float
) -> FloatArray:
    """B and dB/dt at every mean anomaly ``means`` (n,) for every Earth angle ``angles``
    (m,), with node and perigee drifted to time t: shape (n, m, 6), for a dipole or a harmonic
    field."""
    out = np.empty((means.size, angles.size, 6))
    raan = orbit[_O.raan] + orbit[_O.raan_rate] * t
    argp = orbit[_O.argp] + orbit[_O.argp_rate] * t
    for i in range(means.size):
        r, vel = orbit_state(orbit, 0, means[i], raan, argp)
        for j in range(angles.size):
            b, bdot = _any_field(field, angles[j], r, vel)
            out[i, j, 0], out[i, j, 1], out[i, j, 2] = b
            out[i, j, 3], out[i, j, 4], out[i, j, 5] = bdot
    return out


# ---------------------------------------------------------------------------------------------
# The field of a spherical-harmonic model (the IGRF) to any degree.


@jit(INLINE)
def harmonic_size(degree: int) -> int:
    """The payload length of a harmonic field of ``degree``: N, θ0, ω_E, the reference radius,
    then C_nm and S_nm for 1 ≤ n ≤ N, 0 ≤ m ≤ n."""
    return _HARMONIC_HEAD + 2 * ((degree + 1) * (degree + 2) // 2 - 1)


@jit(KERNEL)
def _earth_fixed_field(field: FloatArray, v: int, x: complex, y: complex, z: complex
                       ) -> tuple[complex, complex, complex]:  # fmt: skip
    """B = −∇V in Earth-fixed axes at the point (x, y, z) in units of the reference radius,
    V = a Σ (a/r)^{n+1} Σ (C_nm cos mλ + S_nm sin mλ) P_nm(cos θ) with the unnormalised
    Legendre functions P_nm (no Condon–Shortley phase): the recursions of the solid harmonics
    V_nm, W_nm and the gradient of each term in them (Montenbruck & Gill, *Satellite Orbits*,
    §3.2.4–3.2.5, with GM/R → a). Rational in x, y, z throughout, so that
    complex arguments give the derivative along their imaginary part exactly (the complex
    step)."""
    degree = int(field[v + _H.degree])
    k = (degree + 1) * (degree + 2) // 2 - 1
    c0, s0 = (
        v + _HARMONIC_HEAD,
        v + _HARMONIC_HEAD + k,
    )  # C_nm at c0 + n(n+1)/2 + m − 1, S_nm likewise
    rho2 = x * x + y * y + z * z
    inv2 = 1.0 / rho2
    xr, yr, zr = x * inv2, y * inv2, z * inv2
    bx = by = bz = 0.0 * x
    vmm, wmm = 1.0 / cmath.sqrt(rho2), 0.0 * x
    for j in range(degree + 2):  # the order of the solid harmonics V_kj, W_kj
        if j > 0:
            vmm, wmm = (2 * j - 1) * (xr * vmm - yr * wmm), (2 * j - 1) * (xr * wmm + yr * vmm)
        v1, w1 = vmm, wmm
        v2 = w2 = 0.0 * x
        for kk in range(j, degree + 2):  # the degree of V_kj
            if kk == j:
                vk, wk = vmm, wmm
            else:
                f1, f2 = (2 * kk - 1) / (kk - j), (kk + j - 1) / (kk - j)
                vk, wk = f1 * zr * v1 - f2 * inv2 * v2, f1 * zr * w1 - f2 * inv2 * w2
                v2, w2, v1, w1 = v1, w1, vk, wk
            n = kk - 1  # the degree of the terms V_kj enters
            if n < 1:
                continue
            if j <= n:  # ∂/∂z of the term (n, j)
                c, s = field[c0 + n * (n + 1) // 2 + j - 1], field[s0 + n * (n + 1) // 2 + j - 1]
                bz += (n - j + 1) * (c * vk + s * wk)
            m = j - 1  # the term (n, j − 1) through V_{n+1, m+1}
            if 0 <= m <= n:
                c, s = field[c0 + n * (n + 1) // 2 + m - 1], field[s0 + n * (n + 1) // 2 + m - 1]
                if m == 0:
                    bx += c * vk
                    by += c * wk
                else:
                    bx += 0.5 * (c * vk + s * wk)
                    by += 0.5 * (c * wk - s * vk)
            m = j + 1  # the term (n, j + 1) through V_{n+1, m−1}
            if m <= n:
                c, s = field[c0 + n * (n + 1) // 2 + m - 1], field[s0 + n * (n + 1) // 2 + m - 1]
                f = 0.5 * (n - m + 2) * (n - m + 1)
                bx -= f * (c * vk + s * wk)
                by -= f * (s * vk - c * wk)
    return bx, by, bz


_STEP = 1e-20  # the complex step [s]: far below any scale of the field along the orbit


@jit(KERNEL)
def harmonic_field(field: FloatArray, v: int, angle: float, r: Vec3, vel: Vec3
                   ) -> tuple[Vec3, Vec3]:  # fmt: skip
    """B and dB/dt (inertial axes) of a harmonic field at position r moving at ``vel``, the
    Earth turned by ``angle`` about ξ3 and turning at ω_E: with r_e = Rz(−angle) r and v_e its
    rate in Earth-fixed axes, dB/dt = Rz(angle) (ω_E ξ3 × B_e + (∇B_e) v_e), the directional
    derivative by the complex step B_e(r_e + i h v_e) (no cancellation: exact to round-off)."""
    c, s = math.cos(angle), math.sin(angle)
    we, radius = field[v + _H.earth_rate], field[v + _H.radius]
    # Earth-fixed position and velocity (relative to the turning Earth), in reference radii.
    x, y, z = (c * r[0] + s * r[1]) / radius, (-s * r[0] + c * r[1]) / radius, r[2] / radius
    u1 = vel[0] + we * r[1]  # v − ω_E ξ3 × r
    u2 = vel[1] - we * r[0]
    ux, uy, uz = (c * u1 + s * u2) / radius, (-s * u1 + c * u2) / radius, vel[2] / radius
    bx, by, bz = _earth_fixed_field(field, v, complex(x, _STEP * ux), complex(y, _STEP * uy),
                                    complex(z, _STEP * uz))  # fmt: skip
    e1, e2, e3 = bx.real, by.real, bz.real
    d1 = bx.imag / _STEP - we * e2  # (∇B_e) v_e + ω_E ξ3 × B_e
    d2 = by.imag / _STEP + we * e1
    d3 = bz.imag / _STEP
    return (
        (c * e1 - s * e2, s * e1 + c * e2, e3),
        (c * d1 - s * d2, s * d1 + c * d2, d3),
    )
