"""The Euler–Poinsot average of the torques that are polynomial in the attitude, in closed form.

The general engine's triaxial setting (:mod:`tumble.kernels.triaxial`) averages the rates of
``[L_ξ, r = 2T/L²]`` over the polhode phase and the precession angle χ about L on a grid of
nodes (at least 32 × 4 evaluations of the torque). For the terms below the average has a
closed form, exact to round-off, at the cost of one arithmetic-geometric mean: mode 2 of that
kernel (:func:`tumble.averaging.triaxial_kernel` chooses it when every term is one of them).

**The precession angle.** Write the attitude A = F Rz(χ) G with F a frame whose third axis is
L̂ and G the body → L-frame rotation, whose third row is the body direction ℓ = L_body/L. The
inputs from inertial space — a symmetric tensor X (the orbit-averaged ⟨B Bᵀ⟩, the gravity
gradient's ĥ ĥᵀ), a vector δ — split in the L-frame into parts that turn as e^{imχ}. Averaged
over χ, a torque linear in them keeps only

* along L̂: the m = 0 parts, X → σ⊥(1 − ℓℓᵀ) + σ₃ ℓℓᵀ in body axes
  (σ⊥ = (X₁₁ + X₂₂)/2, σ₃ = X₃₃ in the L-frame) and δ → δ₃ ℓ; the moment is ℓ·T;
* across L̂: the m = 1 parts u = (X₁₃, X₂₃) or (δ₁, δ₂), which enter the body as J(ℓ) u_body
  for a matrix J; the mean of G ᵀ-conjugated J about the L-axis is a u + b ẑ × u with
  a = (tr J − ℓᵀJℓ)/2 and b = ℓ·k, k the axial vector of J's antisymmetric part;
* in the power ω·T: the m = 0 parts alone.

For the eddy-current moment T = ε:(M C), C = [ω]× S − [δ]× (M, S symmetric), with ω = L I⁻¹ℓ
and g = M(ω × ℓ), this gives T(1) = Mω − tr M ω, ℓ·T(ℓℓᵀ) = 0, ω·T(ℓℓᵀ) = −(ω×ℓ)ᵀM(ω×ℓ),
J_S = [g]× − [ℓ]× M [ω]× (a = ½((ω·ℓ) tr M − ωᵀMℓ), b = (3/2) ℓᵀM(ω × ℓ)) and
J_δ = tr M − M (a = ½(tr M + ℓᵀMℓ), b = 0). For the gravity gradient −c ĥ × (I ĥ),
J = −c([ℓ]× I − [Iℓ]×): a = 0, b = (c/2)(3ℓᵀIℓ − tr I), and nothing along L̂ or in the power.
A body-fixed moment m gives ℓ·m along L̂ and ω·m; an inertial one, itself; a linear drag −Bω,
−ℓᵀBω and −ωᵀBω.

**The polhode.** What remains are means over the polhode of polynomials of degree ≤ 4 in ℓ.
With ℓ = (A_c cn u, A_s sn u, A_d dn u) in the sorted principal axes (axis order of the
regime: dn along the axis the polhode encircles), the odd powers of sn and cn average to zero,
and the rest are, with x = sn², ⟨x⟩ = (K − E)/(mK), ⟨x²⟩ = (2(1 + m)⟨x⟩ − 1)/(3m) (the
recurrence of ∫sn^{2n}), both from one arithmetic-geometric mean without cancellation
(:func:`_sn_means`), ⟨dn⟩ = π/(2K) and ⟨dn sn²⟩ = π/(4K) (dn du = dφ with φ = am u).
The diagonal moments ⟨ℓᵢ²⟩, the products ⟨ℓᵢ²ℓⱼ²⟩, ⟨ℓ_a⟩ and ⟨ℓ_a ℓᵢ²⟩ (a the encircled
axis) are all the terms need.
"""

from __future__ import annotations

import math

from tumble._typing import FloatArray
from tumble.kernels.codes import (
    TERM_BODY_CONSTANT,
    TERM_FIELD_MOMENTS,
    TERM_GRAVITY_GRADIENT,
    TERM_GRAVITY_MOMENTS,
    TERM_INERTIAL_CONSTANT,
    TERM_LINEAR_DRAG,
)
from tumble.kernels.jit import ENTRY, INLINE, KERNEL, jit
from tumble.kernels.torque import Mat3, Vec3, _dot, next_term

__all__ = ["CLOSED_FORM_TERMS", "closed_mean", "polhode_moments", "sn_means"]

CLOSED_FORM_TERMS = frozenset(
    {
        TERM_BODY_CONSTANT,
        TERM_INERTIAL_CONSTANT,
        TERM_LINEAR_DRAG,
        TERM_GRAVITY_GRADIENT,
        TERM_FIELD_MOMENTS,
        TERM_GRAVITY_MOMENTS,
    }
)
"""The terms whose Euler–Poinsot average :func:`closed_mean` gives (the magnetic tensor and
⟨B Bᵀ⟩ of a field-moments term symmetric, as the caller checks)."""

_Moments = tuple[Vec3, Vec3, Vec3, float, int]


@jit(KERNEL)
def _sn_means(mc: float) -> tuple[float, float, float]:
    """(K, ⟨sn²⟩, ⟨sn⁴⟩) over a period at the parameter m = 1 − mc, from one arithmetic-
    geometric mean (module notes): with c₀² = m, c_{n+1} = c_n²/(4a_{n+1}),
    K = π/(2a_∞) and K − E = K Σ 2^{n−1} c_n² (DLMF 19.8.5–6), so ⟨sn²⟩ = (K − E)/(mK) =
    ½ + m s and ⟨sn⁴⟩ = (2s + 2⟨sn²⟩)/3 with s = Σ_{n≥1} 2^{n−1} (c_n/m)²; the c_n/m are
    formed without a difference, so that neither mean loses digits as m → 0 (a symmetric
    body) nor m → 1."""
    m = 1.0 - mc
    a, b = 1.0, math.sqrt(mc)
    d = 0.5 / (1.0 + b)  # c₁/m: (1 − √mc)/2 = m/(2(1 + √mc))
    a, b = 0.5 * (a + b), math.sqrt(a * b)
    s, weight = d * d, 1.0
    while m * d > 1e-17 * a:
        d = m * d * d / (2.0 * (a + b))  # c_{n+1}/m = m (c_n/m)²/(4 a_{n+1})
        a, b = 0.5 * (a + b), math.sqrt(a * b)
        weight *= 2.0
        s += weight * d * d
    x1 = 0.5 + m * s
    return 0.5 * math.pi / a, x1, (2.0 * s + 2.0 * x1) / 3.0


@jit(ENTRY)
def sn_means(mc: float) -> tuple[float, float, float]:
    """:func:`_sn_means` from Python, for tests against scipy."""
    return _sn_means(mc)


@jit(KERNEL)
def _moments(i1: float, i2: float, i3: float, L: float, x3: bool, mc: float, amp: Vec3) -> _Moments:
    """The polhode means (sorted axes) of ℓ = L_body/L: ⟨ℓᵢ²⟩, ⟨ℓⱼ²ℓₖ²⟩ (i, j, k cyclic, by
    i), ⟨ℓ_a ℓᵢ²⟩, ⟨ℓ_a⟩ and the encircled axis a (0 or 2). ``amp`` are the body rate's
    amplitudes of cn, sn, dn as :func:`tumble.kernels.triaxial.triaxial_averaged` forms them
    (Martynenko (1979), eq. (3.1))."""
    big_k, x1, x2 = _sn_means(mc)
    m = 1.0 - mc
    if x3:  # rates (cn, sn, dn) about axes (1, 2, 3): the polhode encircles axis 3
        a = 2
        ad, ac = i3 * amp[2] / L, i1 * amp[0] / L
    else:  # (dn, sn, cn): it encircles axis 1
        a = 0
        ad, ac = i1 * amp[2] / L, i3 * amp[0] / L
    as_ = i2 * amp[1] / L
    ad2, ac2, as2 = ad * ad, ac * ac, as_ * as_
    # ⟨cn²⟩ = 1 − ⟨x⟩, ⟨dn²⟩ = 1 − m⟨x⟩; products of two: ⟨(1 − x)(1 − mx)⟩ and so on.
    sq_d, sq_c, sq_s = ad2 * (1.0 - m * x1), ac2 * (1.0 - x1), as2 * x1
    cs = ac2 * as2 * (x1 - x2)
    cd = ac2 * ad2 * (1.0 - (1.0 + m) * x1 + m * x2)
    sd = as2 * ad2 * (x1 - m * x2)
    dn1 = 0.5 * math.pi / big_k  # ⟨dn⟩; ⟨dn sn²⟩ = ⟨dn cn²⟩ = ⟨dn⟩/2
    odd_d = ad * ad2 * dn1 * (1.0 - 0.5 * m)
    odd_c, odd_s = ad * ac2 * 0.5 * dn1, ad * as2 * 0.5 * dn1
    if x3:
        return ((sq_c, sq_s, sq_d), (sd, cd, cs), (odd_c, odd_s, odd_d), ad * dn1, a)
    return ((sq_d, sq_s, sq_c), (cs, cd, sd), (odd_d, odd_s, odd_c), ad * dn1, a)


@jit(ENTRY)
def polhode_moments(
    i1: float, i2: float, i3: float, L: float, x3: bool, mc: float, a0: float, a1: float,
    a2: float,
) -> tuple[float, float, float, float, float, float, float, float, float, float, int]:  # fmt: skip
    """:func:`_moments` flattened, for tests against quadrature over the polhode."""
    sq, pairs, odd, first, a = _moments(i1, i2, i3, L, x3, mc, (a0, a1, a2))
    return (*sq, *pairs, *odd, first, a)


@jit(INLINE)
def _sorted_row(p: FloatArray, x: FloatArray, v: int, i: int) -> Vec3:
    """Row i of Q X: the user-axes matrix X (by rows at x[v : v + 9]), Q by rows at p[6:15]."""
    q0, q1, q2 = p[6 + 3 * i], p[7 + 3 * i], p[8 + 3 * i]
    return (
        q0 * x[v] + q1 * x[v + 3] + q2 * x[v + 6],
        q0 * x[v + 1] + q1 * x[v + 4] + q2 * x[v + 7],
        q0 * x[v + 2] + q1 * x[v + 5] + q2 * x[v + 8],
    )


@jit(INLINE)
def _sorted(p: FloatArray, x: FloatArray, v: int) -> tuple[Vec3, Vec3]:
    """The diagonal of Q X Qᵀ (X in the sorted axes) and its entries across each axis,
    ((QXQᵀ)₂₃, (QXQᵀ)₃₁, (QXQᵀ)₁₂)."""
    r0, r1, r2 = _sorted_row(p, x, v, 0), _sorted_row(p, x, v, 1), _sorted_row(p, x, v, 2)
    q0, q1, q2 = (p[6], p[7], p[8]), (p[9], p[10], p[11]), (p[12], p[13], p[14])
    return (
        (_dot(r0, q0), _dot(r1, q1), _dot(r2, q2)),
        (_dot(r1, q2), _dot(r2, q0), _dot(r0, q1)),
    )


@jit(INLINE)
def _sorted_vector(p: FloatArray, x1: float, x2: float, x3: float) -> Vec3:
    """Q x: user axes to sorted ones."""
    return (
        p[6] * x1 + p[7] * x2 + p[8] * x3,
        p[9] * x1 + p[10] * x2 + p[11] * x3,
        p[12] * x1 + p[13] * x2 + p[14] * x3,
    )


@jit(INLINE)
def _turned(F: Mat3, angle: float) -> Mat3:
    """Rz(angle)ᵀ F (by rows): the L-frame axes (F's columns) in the axes of the inputs at
    t = 0, which have since turned about ξ3 by ``angle`` (the node)."""
    c, s = math.cos(angle), math.sin(angle)
    return (
        c * F[0] + s * F[3], c * F[1] + s * F[4], c * F[2] + s * F[5],
        -s * F[0] + c * F[3], -s * F[1] + c * F[4], -s * F[2] + c * F[5],
        F[6], F[7], F[8],
    )  # fmt: skip


@jit(INLINE)
def _column_dot(F: Mat3, j: int, x1: float, x2: float, x3: float) -> float:
    """The L-frame component j of the inertial vector x: (F's column j)·x."""
    return F[j] * x1 + F[3 + j] * x2 + F[6 + j] * x3


@jit(INLINE)
def _quadratic(F: Mat3, x: FloatArray, v: int, i: int, j: int) -> float:
    """(F's column i)ᵀ X (F's column j), X by rows at x[v : v + 9]."""
    total = 0.0
    for k in range(3):
        total += F[3 * k + i] * (
            x[v + 3 * k] * F[j] + x[v + 3 * k + 1] * F[3 + j] + x[v + 3 * k + 2] * F[6 + j]
        )
    return total


_Parts = tuple[float, float, float, float]
"""A term's averaged moment in the L-frame (across L: two; along L) and its power ω·M."""


@jit(INLINE)
def _weighted(w: Vec3, x: Vec3, y: Vec3) -> float:
    """Σᵢ wᵢ xᵢ yᵢ."""
    return w[0] * x[0] * y[0] + w[1] * x[1] * y[1] + w[2] * x[2] * y[2]


@jit(INLINE)
def _constant_parts(p: FloatArray, v: int, L: float, r: float, inv: Vec3, first: float, a: int,
                    F: Mat3, inertial: bool) -> _Parts:  # fmt: skip
    """A body-fixed moment m: ⟨ℓ·m⟩ = ⟨ℓ_a⟩ m_a along L, ω·m; an inertial one: itself, with
    ⟨Ω⟩ = L r L̂ in the power."""
    if inertial:
        x1 = _column_dot(F, 0, p[v], p[v + 1], p[v + 2])
        x2 = _column_dot(F, 1, p[v], p[v + 1], p[v + 2])
        along = _column_dot(F, 2, p[v], p[v + 1], p[v + 2])
        return x1, x2, along, L * r * along
    b = _sorted_vector(p, p[v], p[v + 1], p[v + 2])
    return 0.0, 0.0, b[a] * first, L * b[a] * first * inv[a]


@jit(INLINE)
def _drag_parts(p: FloatArray, v: int, L: float, inv: Vec3, sq: Vec3) -> _Parts:
    """A linear drag −Bω: −⟨ℓᵀBω⟩ along L, −⟨ωᵀBω⟩ (only B's diagonal survives)."""
    d, _ = _sorted(p, p, v)
    return 0.0, 0.0, -L * _weighted(d, sq, inv), -L * L * _weighted(d, sq, (
        inv[0] * inv[0], inv[1] * inv[1], inv[2] * inv[2]))  # fmt: skip


@jit(INLINE)
def _gravity_parts(p: FloatArray, v: int, code: int, t: float, sq: Vec3, F: Mat3) -> _Parts:
    """The gravity gradient −c ĥ × (I ĥ): b = (c/2)(3⟨ℓᵀIℓ⟩ − tr I) on the m = 1 input
    ĥ₃(ĥ₁, ĥ₂) of ĥĥᵀ, nothing along L nor in the power. The circular orbit's term has
    c = 3n²/2 (⟨r̂r̂ᵀ⟩ = ½(1 − ĥĥᵀ)) and a fixed normal; the orbit-averaged one turns its
    normal with the node."""
    if code == TERM_GRAVITY_GRADIENT:
        c = 1.5 * p[v + 3] ** 2
        h1, h2, h3 = p[v + 11], p[v + 12], p[v + 13]
    else:
        c = p[v + 3]
        cn, sn = math.cos(p[v + 7] * t), math.sin(p[v + 7] * t)
        h1, h2, h3 = cn * p[v + 4] - sn * p[v + 5], sn * p[v + 4] + cn * p[v + 5], p[v + 6]
    # The diagonal of Q diag(I) Qᵀ, Σₖ Qᵢₖ² Iₖ (the payload's moments in user order).
    moments = (
        p[6] ** 2 * p[v] + p[7] ** 2 * p[v + 1] + p[8] ** 2 * p[v + 2],
        p[9] ** 2 * p[v] + p[10] ** 2 * p[v + 1] + p[11] ** 2 * p[v + 2],
        p[12] ** 2 * p[v] + p[13] ** 2 * p[v + 1] + p[14] ** 2 * p[v + 2],
    )
    b = 0.5 * c * (3.0 * _weighted(moments, sq, (1.0, 1.0, 1.0)) - (p[v] + p[v + 1] + p[v + 2]))
    u1, u2, u3 = (_column_dot(F, 0, h1, h2, h3), _column_dot(F, 1, h1, h2, h3),
                  _column_dot(F, 2, h1, h2, h3))  # fmt: skip
    return -b * u3 * u2, b * u3 * u1, 0.0, 0.0  # b L̂ × u₃(u₁, u₂)


@jit(INLINE)
def _field_parts(
    p: FloatArray, v: int, t: float, L: float, r: float, inv: Vec3, sq: Vec3, pairs: Vec3,
    odd: Vec3, a: int, F: Mat3,
) -> _Parts:  # fmt: skip
    """The orbit-averaged eddy moment ε:(M C), C = [ω]× S − [δ]× (module notes), with S and δ
    turned with the node."""
    d, o = _sorted(p, p, v)
    trace = d[0] + d[1] + d[2]
    ones = (1.0, 1.0, 1.0)
    inv2 = (inv[0] * inv[0], inv[1] * inv[1], inv[2] * inv[2])
    # γᵢ = 1/I_{i+1} − 1/I_{i+2}: (I⁻¹ℓ × ℓ)ᵢ = γᵢ ℓ_{i+1} ℓ_{i+2}.
    gam = (inv[1] - inv[2], inv[2] - inv[0], inv[0] - inv[1])
    mq = _weighted(d, sq, ones)  # ⟨ℓᵀMℓ⟩
    a_s = 0.5 * L * (trace * r - _weighted(d, sq, inv))  # ⟨ℓᵀMω⟩, ⟨ω·ℓ⟩ = L r
    # b = (3/2)⟨ℓᵀM(ω × ℓ)⟩: only M's entry across the encircled axis survives.
    pa, qa = (a + 1) % 3, (a + 2) % 3
    b_s = 1.5 * L * o[a] * (gam[qa] * odd[pa] + gam[pa] * odd[qa])
    cross = _weighted(d, (gam[0] ** 2, gam[1] ** 2, gam[2] ** 2), pairs)  # ⟨(ω×ℓ)ᵀM(ω×ℓ)⟩/L²
    G = _turned(F, p[v + 21] * t)
    s_perp = 0.5 * (_quadratic(G, p, v + 9, 0, 0) + _quadratic(G, p, v + 9, 1, 1))
    s3 = _quadratic(G, p, v + 9, 2, 2)
    s13, s23 = _quadratic(G, p, v + 9, 0, 2), _quadratic(G, p, v + 9, 1, 2)
    e1 = _column_dot(G, 0, p[v + 18], p[v + 19], p[v + 20])
    e2 = _column_dot(G, 1, p[v + 18], p[v + 19], p[v + 20])
    e3 = _column_dot(G, 2, p[v + 18], p[v + 19], p[v + 20])
    a_d = 0.5 * (trace + mq)
    ww, w2 = _weighted(d, sq, inv2), _weighted(ones, sq, inv2)
    return (
        a_s * s13 - b_s * s23 + a_d * e1,
        a_s * s23 + b_s * s13 + a_d * e2,
        -2.0 * s_perp * a_s + e3 * (trace - mq),
        L * L * (s_perp * (ww - trace * w2 + cross) - s3 * cross) + 2.0 * e3 * a_s,
    )


@jit(KERNEL)
def closed_mean(
    p: FloatArray, start: int, t: float, L: float, r: float, x3: bool, mc: float, amp: Vec3,
    F: Mat3,
) -> tuple[float, float, float, float]:  # fmt: skip
    """(⟨A M⟩ (3, inertial), ⟨(Ω − r L_ξ)·A M⟩) of the program ``p[start:]``, every term in
    :data:`CLOSED_FORM_TERMS`, averaged over the Euler–Poinsot motion at |L_ξ| = L, 2T/L² = r
    (module notes); F a frame (by rows) whose third column is L̂."""
    inv = (1.0 / p[3], 1.0 / p[4], 1.0 / p[5])
    sq, pairs, odd, first, a = _moments(p[3], p[4], p[5], L, x3, mc, amp)
    tx = ty = tz = power = 0.0
    i = start + 1
    for _ in range(int(p[start])):
        code, f, v = int(p[i]), p[i + 1], i + 2
        if code == TERM_BODY_CONSTANT or code == TERM_INERTIAL_CONSTANT:
            parts = _constant_parts(p, v, L, r, inv, first, a, F, code == TERM_INERTIAL_CONSTANT)
        elif code == TERM_LINEAR_DRAG:
            parts = _drag_parts(p, v, L, inv, sq)
        elif code == TERM_GRAVITY_GRADIENT or code == TERM_GRAVITY_MOMENTS:
            parts = _gravity_parts(p, v, code, t, sq, F)
        elif code == TERM_FIELD_MOMENTS:
            parts = _field_parts(p, v, t, L, r, inv, sq, pairs, odd, a, F)
        else:
            return math.nan, math.nan, math.nan, math.nan
        tx += f * parts[0]
        ty += f * parts[1]
        tz += f * parts[2]
        power += f * parts[3]
        i = next_term(p, i)
        if i < 0:
            break
    T1 = F[0] * tx + F[1] * ty + F[2] * tz
    T2 = F[3] * tx + F[4] * ty + F[5] * tz
    T3 = F[6] * tx + F[7] * ty + F[8] * tz
    return T1, T2, T3, power - r * L * tz
