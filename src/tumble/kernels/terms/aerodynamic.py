"""The moment of the upper atmosphere on a faceted body in free-molecular flow, along the orbit
and averaged over it.

A facet struck at cos θ = n·s > 0 by air of density ρ met at the relative velocity v (s its
direction in the body) feels f = −ρ v² cos θ [ks s + (kp cos θ + kd) n] with ks = A σt,
kp = A (2 − σn − σt), kd = A σn vw/v (:mod:`tumble.space.aerodynamics`, which states the model
and its sources): the form of sunlight's, so that both read the same facet rows
(:data:`tumble.kernels.terms.solar_radiation.FACET`) and share their compiled code. Two terms:

* ``aerodynamic``: along the orbit: the body's place and velocity at t, the air's velocity
  relative to it (the atmosphere turning with the Earth, v − ω⊕ ξ3 × r), the density of the
  exponential atmosphere at the altitude |r| − R⊕ (a spherical Earth), and every struck facet:
  the full equations;
* ``aerodynamic_mean``: the same averaged over the orbit at a fixed attitude, with the facets'
  illumination max(0, cos θ) expanded to second order in Fourier series as sunlight's expanded
  average does (Benson and Scheeres, *J. Guid. Control Dyn.* 44(4), 2021): the moment is the
  cubic q C(s) of the flow's body direction, q = ρ v² (:func:`tumble.kernels.terms.
  solar_radiation.coefficients` of the air's facets). The orbit average is the trapezoidal
  rule on N eccentric anomalies E_j weighted by 1 − e cos E_j (dM = (1 − e cos E) dE), each
  node the flow's direction ŝ_j and q_j with the node and perigee of t:
  ⟨q C(Aᵀŝ)⟩ = Σ_j w_j q_j C(Aᵀ ŝ_j). Its Euler–Poinsot average is sunlight's closed form
  (:func:`tumble.kernels.terms.solar_radiation.expanded_average`) at each node's direction,
  exact for the cubic: the orbit and the free rotation averaged independently.

**The number of nodes.** Over a circular orbit q ŝ⊗ᵏ is a trigonometric polynomial of degree
≤ 3 in the argument of latitude but for the small turn of the air (ω⊕ r/v ≈ 0.07 in LEO), which
eight nodes hold closely. On an eccentric orbit the density varies as exp(κ cos E) about
the perigee, κ = a e/H with H the scale height at the perigee: its harmonic n is I_n(κ)/I_0(κ),
and :func:`orbit_nodes` takes the fewest N ≥ 8 (a multiple of 4) with I_(N−3)(κ)/I_0(κ) ≤ 1e-8
(N grows like √κ: 8 on a circular orbit, 16 at e = 0.01 in LEO, 140 for a transfer orbit
with its perigee at 250 km); against eight times as many nodes it is within 1e-8 on an orbit
inside one band (tests/kernels/test_aerodynamic.py). The bands of the atmosphere
(:data:`tumble.kernels.astro.ATMOSPHERE_BANDS`, continuous) meet with a kink in the slope of
ln ρ: an eccentric orbit that crosses a band's base converges more slowly there (1e-3 of the
moment from 250 to 2000 km).

The orbiting body's scenario switches it on with ``[torques] aerodynamic = true`` on the facets of
its ``[surface]``, whose accommodation it reads there.
"""

from __future__ import annotations

import math
from typing import Any

from tumble._typing import FloatArray
from tumble.errors import ParameterError
from tumble.kernels.astro import ATMOSPHERE_BANDS, EARTH_RADIUS
from tumble.kernels.frames import to_body
from tumble.kernels.jit import INLINE, KERNEL, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3
from tumble.kernels.lframe import Context, Parts
from tumble.kernels.space import ORBIT, orbit_at, orbit_state
from tumble.kernels.terms.base import ORBIT_FIELD, OrbitContext, OrbitKey, Term
from tumble.kernels.terms.solar_radiation import (
    cubic,
    expanded_average,
    lit_average,
    lit_facets,
)

__all__ = ["LAYOUT", "MEAN_LAYOUT", "TERMS", "air_density", "build", "orbit_nodes"]

_AIR = (
    ORBIT_FIELD,
    Field("earth_rate", 1, "rad/time", "the atmosphere's rotation rate ω⊕"),
    Field("inverse_inertia", 1, "1/(kg·m²)", "1/I0: the moment in the model's units", 0.0),
)
LAYOUT = Layout(
    "aerodynamic",
    (*_AIR, Field("count", 1, "1", "number of facets", 0.0)),
    tail="facets",  # FACET rows with the air's areas
)
MEAN_LAYOUT = Layout(
    "aerodynamic_mean",
    (
        *_AIR,
        Field("nodes", 1, "1", "eccentric anomalies of the orbit average", 4.0),
        Field("coefficients", 60, "m³", "the cubic M(s)/q by axis, on monomials()"),
        Field("exact", 1, "1", "0: the expanded illumination; 1: the exact one", 0.0, 1.0),
        Field("count", 1, "1", "number of facets", 0.0),
    ),
    tail="facets",  # FACET rows with the air's areas, as the full term's
)
_AT, _MEAN, _O = LAYOUT.at, MEAN_LAYOUT.at, ORBIT.at
_FACETS, _MEAN_FACETS = LAYOUT.size, MEAN_LAYOUT.size
_TABLE = ATMOSPHERE_BANDS
_BANDS = len(ATMOSPHERE_BANDS)
_MIN_NODES, _MAX_NODES = 8, 512
_HARMONIC_TOLERANCE = 1e-8  # I_(N−3)(κ)/I_0(κ): the orbit rule's neglected harmonic (notes)


@jit(INLINE)
def air_density(altitude: float) -> float:
    """The exponential atmosphere's density [kg/m³] at ``altitude`` [m]
    (:data:`tumble.kernels.astro.ATMOSPHERE_BANDS`; the last band goes on above 1000 km; below
    0, the sea level's band)."""
    h = altitude / 1e3
    band = 0
    for j in range(1, _BANDS):
        if h >= _TABLE[j][0]:
            band = j
    h0, rho0, scale = _TABLE[band]
    return rho0 * math.exp(-(h - h0) / scale)


@jit(INLINE)
def _air(prog: FloatArray, v: int, r: Vec3, vel: Vec3) -> tuple[float, float, float, float]:
    """(ŝ inertial, q): the direction of the body's velocity relative to the turning air and
    q = ρ v² / I0 in the model's units (the fields of ``_AIR``, first in both layouts)."""
    we = prog[v + _AT.earth_rate]
    u1, u2, u3 = vel[0] + we * r[1], vel[1] - we * r[0], vel[2]
    speed2 = u1 * u1 + u2 * u2 + u3 * u3
    if speed2 == 0.0:
        return 1.0, 0.0, 0.0, 0.0
    speed = math.sqrt(speed2)
    altitude = math.sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) - EARTH_RADIUS
    q = air_density(altitude) * speed2 * prog[v + _AT.inverse_inertia]
    return u1 / speed, u2 / speed, u3 / speed, q


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """f Σ r × f_facet at the body's place on the orbit (module notes)."""
    r, vel = orbit_at(prog, v + _AT.orbit, t)
    s1, s2, s3, q = _air(prog, v, r, vel)
    b1, b2, b3 = to_body(a, s1, s2, s3)
    return lit_facets(prog, v + _FACETS, int(prog[v + _AT.count]), f * q, b1, b2, b3)


@jit(INLINE)
def _node(prog: FloatArray, v: int, t: float, j: int) -> tuple[float, float, float, float]:
    """The flow's direction and w_j q_j at node j of the orbit average (module notes), the
    elements drifted to t."""
    o = v + _AT.orbit
    nodes = prog[v + _MEAN.nodes]
    e = prog[o + _O.e]
    big = 2.0 * math.pi * j / nodes
    raan = prog[o + _O.raan] + prog[o + _O.raan_rate] * t
    argp = prog[o + _O.argp] + prog[o + _O.argp_rate] * t
    r, vel = orbit_state(prog, o, big - e * math.sin(big), raan, argp)
    s1, s2, s3, q = _air(prog, v, r, vel)
    return s1, s2, s3, q * (1.0 - e * math.cos(big)) / nodes


@jit(INLINE)
def mean_moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """f ⟨q M(Aᵀ ŝ)⟩ over the orbit's nodes at the attitude a, with the expanded (the cubic) or
    the exact illumination (module notes)."""
    m1 = m2 = m3 = 0.0
    exact = prog[v + _MEAN.exact] == 1.0
    count = int(prog[v + _MEAN.count])
    for j in range(int(prog[v + _MEAN.nodes])):
        s1, s2, s3, wq = _node(prog, v, t, j)
        b1, b2, b3 = to_body(a, s1, s2, s3)
        if exact:
            x1, x2, x3 = lit_facets(prog, v + _MEAN_FACETS, count, 1.0, b1, b2, b3)
        else:
            x1, x2, x3 = cubic(prog, v + _MEAN.coefficients, b1, b2, b3)
        g = f * wq
        m1, m2, m3 = m1 + g * x1, m2 + g * x2, m3 + g * x3
    return m1, m2, m3


@jit(KERNEL)
def closed(p: FloatArray, v: int, t: float, ctx: Context) -> Parts:
    """The Euler–Poinsot average of :func:`mean_moment`, L-frame, and its power: sunlight's
    at each node's flow direction (the closed form of the cubic, or the lit arcs), weighted
    by its w_j q_j."""
    total = (0.0, 0.0, 0.0, 0.0)
    exact = p[v + _MEAN.exact] == 1.0
    count = int(p[v + _MEAN.count])
    for j in range(int(p[v + _MEAN.nodes])):
        s1, s2, s3, wq = _node(p, v, t, j)
        if wq == 0.0:
            continue
        if exact:
            parts = lit_average(p, v + _MEAN_FACETS, count, s1, s2, s3, ctx)
        else:
            parts = expanded_average(p, v + _MEAN.coefficients, s1, s2, s3, ctx)
        total = (
            total[0] + wq * parts[0],
            total[1] + wq * parts[1],
            total[2] + wq * parts[2],
            total[3] + wq * parts[3],
        )
    return total


def _scale_height(altitude: float) -> float:
    """The table's scale height [m] at ``altitude`` [m]."""
    band = 0
    for j in range(1, _BANDS):
        if altitude / 1e3 >= _TABLE[j][0]:
            band = j
    return 1e3 * _TABLE[band][2]


def orbit_nodes(a: float, e: float) -> int:
    """The orbit average's number of eccentric anomalies for the semi-major axis ``a`` [m] and
    eccentricity ``e`` (module notes: I_(N−3)(κ)/I_0(κ) ≤ 1e-8, κ = a e/H at the perigee)."""
    from scipy.special import ive

    kappa = a * e / _scale_height(a * (1.0 - e) - EARTH_RADIUS)
    n = _MIN_NODES
    while n < _MAX_NODES and ive(n - 3, kappa) > _HARMONIC_TOLERANCE * ive(0, kappa):
        n += 4
    return n


def build(value: Any, context: OrbitContext) -> tuple[str, list[Any], list[Any]] | None:
    """The terms of ``[torques] aerodynamic = true`` on the ``[surface]`` facets with its
    accommodation, in the model's units (speeds in m per unit of model time, 1/I0)."""
    from tumble.kernels.terms import compiled_term  # the registry, loaded by now
    from tumble.kernels.terms.solar_radiation import coefficients, exact_illumination, principal

    if not value:
        return None
    if context.air is None:
        raise ParameterError("torques.aerodynamic needs the body's surface: give [surface]")
    table = principal(context.air, context.axes)
    air = {
        "orbit": context.orbit,
        "earth_rate": context.earth_rate,
        "inverse_inertia": 1.0 / context.I0,
    }
    full = compiled_term("aerodynamic", {**air, "count": float(table.shape[0])},
                         tail=table.ravel())  # fmt: skip
    nodes = orbit_nodes(context.orbit[_O.a], context.orbit[_O.e])
    mean = compiled_term(
        "aerodynamic_mean",
        {
            **air,
            "nodes": float(nodes),
            "coefficients": coefficients(table),
            "exact": exact_illumination(context),
            "count": float(table.shape[0]),
        },
        tail=table.ravel(),
    )
    return "air drag", [full], [mean]


TERMS = (
    Term(
        name="aerodynamic",
        doc="free-molecular flow on facets along an orbit, the exponential atmosphere",
        layout=LAYOUT,
        reads=frozenset({"attitude", "time", "orbit"}),
        moment=moment,
    ),
    Term(
        name="aerodynamic_mean",
        doc="free-molecular flow on facets averaged over the orbit, the illumination expanded",
        layout=MEAN_LAYOUT,
        reads=frozenset({"attitude", "time"}),
        moment=mean_moment,
        closed=closed,
        precession_degree=4,  # A C(Aᵀ ŝ), C cubic
    ),
)

ORBIT_KEYS = (
    OrbitKey(
        name="aerodynamic",
        kind="boolean",
        meaning="true or false (needs [surface])",
        unit="",
        default=False,
        doc="the upper atmosphere on the [surface] facets (free-molecular flow, the exponential "
        "atmosphere turning with the Earth; the averaged equations expand the facets' exposure "
        "to second order)",
        build=build,
    ),
)
