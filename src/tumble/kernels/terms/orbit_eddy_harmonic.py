"""The eddy-current moment along an orbit (:mod:`tumble.kernels.terms.orbit_eddy`) in a
spherical-harmonic field (the IGRF, :func:`tumble.kernels.space.harmonic_field`)."""

from __future__ import annotations

from tumble._typing import FloatArray
from tumble.kernels.jit import KERNEL, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3
from tumble.kernels.space import HARMONIC, ORBIT, harmonic_field, orbit_at
from tumble.kernels.terms.base import Term
from tumble.kernels.terms.orbit_eddy import eddy_moment

LAYOUT = Layout(
    "orbit_eddy_harmonic",
    (
        Field("orbit", ORBIT.size, doc="the orbit (kernels.space.ORBIT)"),
        Field("tensor", 9, "A·m²/(T/s)", "magnetic tensor M, body axes, by rows"),
    ),
    tail="field",  # a harmonic field (kernels.space.HARMONIC), its length by its degree
)
_AT = LAYOUT.at
_FIELD = LAYOUT.size  # the harmonic field follows the fixed part
_H = HARMONIC.at


@jit(KERNEL)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    r, vel = orbit_at(prog, v + _AT.orbit, t)
    vf = v + _FIELD
    angle = prog[vf + _H.theta0] + prog[vf + _H.earth_rate] * t
    bi, ci = harmonic_field(prog, vf, angle, r, vel)
    return eddy_moment(f, prog, v + _AT.tensor, bi, ci, w1, w2, w3, a)


TERM = Term(
    name="orbit_eddy_harmonic",
    doc="eddy currents along an orbit in a spherical-harmonic field (the IGRF)",
    layout=LAYOUT,
    reads=frozenset({"rate", "attitude", "time", "orbit", "field"}),
    moment=moment,
)

TERMS = (TERM,)
