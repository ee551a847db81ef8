"""The eddy-current moment (M x) × B averaged over the orbit and the Earth's rotation
(:mod:`tumble.space.moments`): with S = ⟨B Bᵀ⟩ and ⟨Ḃ Bᵀ⟩ = [δ]× (its mean is antisymmetric)
in body axes, C = [ω]× S − [δ]× and N = M C, the moment is (N23 − N32, N31 − N13, N12 − N21).
S and δ turn about ξ3 with the node, Ω̇ t."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.kernels.frames import dot
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3, mat3, mat_vec, vec3
from tumble.kernels.lframe import (
    Context,
    Parts,
    column_dot,
    quadratic,
    sorted_diagonal,
    turned,
    weighted,
)
from tumble.kernels.terms.base import MAGNETIC_TENSOR, NODE_RATE, Term

LAYOUT = Layout(
    "field_moments",
    (
        MAGNETIC_TENSOR,
        Field("S", 9, "T²", "⟨B Bᵀ⟩, inertial axes at t = 0, by rows"),
        Field("delta", 3, "T²/time", "δ of ⟨Ḃ Bᵀ⟩ = [δ]×, inertial axes at t = 0"),
        NODE_RATE,
    ),
)
_AT = LAYOUT.at


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    angle = prog[v + _AT.node_rate] * t
    c, s = math.cos(angle), math.sin(angle)
    # The columns of A' = Rz(Ω̇t)ᵀ A, so that Aᵀ Rz S Rzᵀ A = A'ᵀ S A'.
    u0 = (c * a[0] + s * a[3], -s * a[0] + c * a[3], a[6])
    u1 = (c * a[1] + s * a[4], -s * a[1] + c * a[4], a[7])
    u2 = (c * a[2] + s * a[5], -s * a[2] + c * a[5], a[8])
    vs = v + _AT.S
    p0, p1, p2 = mat_vec(prog, vs, *u0), mat_vec(prog, vs, *u1), mat_vec(prog, vs, *u2)
    s00, s11, s22 = dot(u0, p0), dot(u1, p1), dot(u2, p2)
    s01, s02, s12 = dot(u0, p1), dot(u0, p2), dot(u1, p2)
    e = vec3(prog, v + _AT.delta)
    d0, d1, d2 = dot(u0, e), dot(u1, e), dot(u2, e)
    # C = [ω]× S − [δ]×, by rows.
    c00, c01, c02 = w2 * s02 - w3 * s01, w2 * s12 - w3 * s11 + d2, w2 * s22 - w3 * s12 - d1
    c10, c11, c12 = w3 * s00 - w1 * s02 - d2, w3 * s01 - w1 * s12, w3 * s02 - w1 * s22 + d0
    c20, c21, c22 = w1 * s01 - w2 * s00 + d1, w1 * s11 - w2 * s01 - d0, w1 * s12 - w2 * s02
    m = mat3(prog, v + _AT.tensor)
    n01 = m[0] * c01 + m[1] * c11 + m[2] * c21
    n02 = m[0] * c02 + m[1] * c12 + m[2] * c22
    n10 = m[3] * c00 + m[4] * c10 + m[5] * c20
    n12 = m[3] * c02 + m[4] * c12 + m[5] * c22
    n20 = m[6] * c00 + m[7] * c10 + m[8] * c20
    n21 = m[6] * c01 + m[7] * c11 + m[8] * c21
    return f * (n12 - n21), f * (n20 - n02), f * (n01 - n10)


@jit(INLINE)
def closed(p: FloatArray, v: int, t: float, ctx: Context) -> Parts:
    """ε:(M C), C = [ω]× S − [δ]× (:mod:`tumble.kernels.triaxial_closed`), with S and δ
    turned with the node."""
    L, r, inv, sq, pairs, odd, a, F = ctx[0], ctx[1], ctx[2], ctx[3], ctx[4], ctx[5], ctx[7], ctx[8]
    d, o = sorted_diagonal(p, p, v + _AT.tensor)
    trace = d[0] + d[1] + d[2]
    ones = (1.0, 1.0, 1.0)
    inv2 = (inv[0] * inv[0], inv[1] * inv[1], inv[2] * inv[2])
    # γᵢ = 1/I_{i+1} − 1/I_{i+2}: (I⁻¹ℓ × ℓ)ᵢ = γᵢ ℓ_{i+1} ℓ_{i+2}.
    gam = (inv[1] - inv[2], inv[2] - inv[0], inv[0] - inv[1])
    mq = weighted(d, sq, ones)  # ⟨ℓᵀMℓ⟩
    a_s = 0.5 * L * (trace * r - weighted(d, sq, inv))  # ⟨ℓᵀMω⟩, ⟨ω·ℓ⟩ = L r
    # b = (3/2)⟨ℓᵀM(ω × ℓ)⟩: only M's entry across the encircled axis survives.
    pa, qa = (a + 1) % 3, (a + 2) % 3
    b_s = 1.5 * L * o[a] * (gam[qa] * odd[pa] + gam[pa] * odd[qa])
    cross = weighted(d, (gam[0] ** 2, gam[1] ** 2, gam[2] ** 2), pairs)  # ⟨(ω×ℓ)ᵀM(ω×ℓ)⟩/L²
    G = turned(F, p[v + _AT.node_rate] * t)
    vs = v + _AT.S
    s_perp = 0.5 * (quadratic(G, p, vs, 0, 0) + quadratic(G, p, vs, 1, 1))
    s3 = quadratic(G, p, vs, 2, 2)
    s13, s23 = quadratic(G, p, vs, 0, 2), quadratic(G, p, vs, 1, 2)
    x1, x2, x3 = vec3(p, v + _AT.delta)
    e1, e2, e3 = (
        column_dot(G, 0, x1, x2, x3),
        column_dot(G, 1, x1, x2, x3),
        column_dot(G, 2, x1, x2, x3),
    )
    a_d = 0.5 * (trace + mq)
    ww, w2 = weighted(d, sq, inv2), weighted(ones, sq, inv2)
    return (
        a_s * s13 - b_s * s23 + a_d * e1,
        a_s * s23 + b_s * s13 + a_d * e2,
        -2.0 * s_perp * a_s + e3 * (trace - mq),
        L * L * (s_perp * (ww - trace * w2 + cross) - s3 * cross) + 2.0 * e3 * a_s,
    )


def _symmetric(values: dict[str, Any]) -> bool:
    """The closed form needs M and ⟨B Bᵀ⟩ symmetric (to round-off)."""
    return all(
        np.abs(X - X.T).max() <= 1e-14 * np.abs(X).max() for X in (values["tensor"], values["S"])
    )


TERM = Term(
    name="field_moments",
    doc="eddy currents averaged over the orbit and the Earth's turn, from ⟨B Bᵀ⟩ and ⟨Ḃ Bᵀ⟩",
    layout=LAYOUT,
    reads=frozenset({"rate", "attitude", "time"}),
    moment=moment,
    closed=closed,
    closed_if=_symmetric,
)

TERMS = (TERM,)
