"""The eddy-current moment along an orbit (:mod:`tumble.kernels.terms.orbit_eddy`) in a
spherical-harmonic field (the IGRF, :func:`tumble.kernels.space.harmonic_field`)."""

from __future__ import annotations

from tumble._typing import FloatArray
from tumble.kernels.jit import KERNEL, jit
from tumble.kernels.layout import Layout, Mat3, Vec3
from tumble.kernels.space import harmonic_field_at
from tumble.kernels.terms.base import MAGNETIC_TENSOR, ORBIT_FIELD, Term
from tumble.kernels.terms.orbit_eddy import eddy_moment

LAYOUT = Layout(
    "orbit_eddy_harmonic",
    (
        ORBIT_FIELD,
        MAGNETIC_TENSOR,
    ),
    tail="field",  # a harmonic field (kernels.space.HARMONIC), its length by its degree
)
_AT = LAYOUT.at
_FIELD = LAYOUT.size  # the harmonic field follows the fixed part


@jit(KERNEL)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    bi, ci = harmonic_field_at(prog, v + _AT.orbit, prog, v + _FIELD, t)
    return eddy_moment(f, prog, v + _AT.tensor, bi, ci, w1, w2, w3, a)


TERM = Term(
    name="orbit_eddy_harmonic",
    doc="eddy currents along an orbit in a spherical-harmonic field (the IGRF)",
    layout=LAYOUT,
    reads=frozenset({"rate", "attitude", "time", "orbit", "field"}),
    moment=moment,
)

TERMS = (TERM,)
