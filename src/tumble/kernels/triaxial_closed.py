"""The Euler–Poinsot average of the torques that are polynomial in the attitude, in closed form.

The general engine's triaxial setting (:mod:`tumble.kernels.triaxial`) averages the rates of
``[L_ξ, r = 2T/L²]`` over the polhode phase and the precession angle χ about L on a grid of
nodes (at least 32 × 4 evaluations of the torque). For the terms below the average has a
closed form, exact to round-off, at the cost of one arithmetic-geometric mean: the kind
``KIND_TRIAXIAL_CLOSED`` (:func:`tumble.kernels.triaxial.triaxial_closed`;
:func:`tumble.averaging.triaxial_kernel` chooses it when every term is one of them).

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
from tumble.kernels.jit import ENTRY, KERNEL, jit
from tumble.kernels.layout import Mat3, Vec3, vec3
from tumble.kernels.lframe import Polhode
from tumble.kernels.params import TRIAXIAL_AVERAGED
from tumble.kernels.terms import HEAD_SIZE, HEADER, closed_of, next_term

__all__ = ["closed_mean", "polhode_moments", "sn_means"]

_HEAD = HEADER.at
_INERTIA = TRIAXIAL_AVERAGED.at.inertia
_Moments = tuple[Vec3, Vec3, Vec3, float, int, Polhode]


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
    i), ⟨ℓ_a ℓᵢ²⟩, ⟨ℓ_a⟩, the encircled axis a (0 or 2) and the polhode
    (:data:`~tumble.kernels.lframe.Polhode`). ``amp`` are the body rate's
    amplitudes of cn, sn, dn as :func:`tumble.kernels.triaxial._polhode` forms them
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
    polhode = (ac, as_, ad, m, x1, x2, dn1)
    if x3:
        return ((sq_c, sq_s, sq_d), (sd, cd, cs), (odd_c, odd_s, odd_d), ad * dn1, a, polhode)
    return ((sq_d, sq_s, sq_c), (cs, cd, sd), (odd_d, odd_s, odd_c), ad * dn1, a, polhode)


@jit(ENTRY)
def polhode_moments(
    i1: float, i2: float, i3: float, L: float, x3: bool, mc: float, a0: float, a1: float,
    a2: float,
) -> tuple[float, float, float, float, float, float, float, float, float, float, int]:  # fmt: skip
    """:func:`_moments` flattened, for tests against quadrature over the polhode."""
    sq, pairs, odd, first, a, _ = _moments(i1, i2, i3, L, x3, mc, (a0, a1, a2))
    return (*sq, *pairs, *odd, first, a)


@jit(KERNEL)
def closed_mean(
    p: FloatArray, start: int, t: float, L: float, r: float, x3: bool, mc: float, amp: Vec3,
    F: Mat3,
) -> tuple[float, float, float, float]:  # fmt: skip
    """(⟨A M⟩ (3, inertial), ⟨(Ω − r L_ξ)·A M⟩) of the program ``p[start:]``, every term with
    a ``closed`` average (:mod:`tumble.kernels.terms`; NaN for any other), averaged over the
    Euler–Poinsot motion at |L_ξ| = L, 2T/L² = r (module notes); F a frame (by rows) whose
    third column is L̂."""
    i1, i2, i3 = vec3(p, _INERTIA)
    inv = (1.0 / i1, 1.0 / i2, 1.0 / i3)
    sq, pairs, odd, first, a, polhode = _moments(i1, i2, i3, L, x3, mc, amp)
    ctx = (L, r, inv, sq, pairs, odd, first, a, F, polhode)
    tx = ty = tz = power = 0.0
    i = start + 1
    for _ in range(int(p[start])):
        f = p[i + _HEAD.factor]
        parts = closed_of(int(p[i + _HEAD.code]), p, i + HEAD_SIZE, t, ctx)
        tx += f * parts[0]
        ty += f * parts[1]
        tz += f * parts[2]
        power += f * parts[3]
        i = next_term(p, i)
    T1 = F[0] * tx + F[1] * ty + F[2] * tz
    T2 = F[3] * tx + F[4] * ty + F[5] * tz
    T3 = F[6] * tx + F[7] * ty + F[8] * tz
    return T1, T2, T3, power - r * L * tz
