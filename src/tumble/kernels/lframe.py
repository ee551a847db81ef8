"""The algebra of the closed-form Euler–Poinsot averages (:mod:`tumble.kernels.triaxial_closed`)
that the torque terms' ``closed`` averages share: the sorted principal axes and the L-frame.

``p`` is the parameter array of the ``KIND_TRIAXIAL_*`` kinds (:data:`~tumble.kernels.params.
TRIAXIAL_AVERAGED`), whose ``sorting`` Q takes the user's body axes to the sorted ones; ``F`` is
a frame (by rows) whose third column is L̂. The context ``ctx`` a term's ``closed`` receives is
``(L, r, inv, sq, pairs, odd, first, a, F, polhode)``: |L|, 2T/L², the inverse sorted
moments, the polhode means ⟨ℓᵢ²⟩, ⟨ℓⱼ²ℓₖ²⟩ and ⟨ℓ_a ℓᵢ²⟩, ⟨ℓ_a⟩, the encircled axis a, F,
and the polhode itself (:data:`Polhode`) for a term that forms other means of it.
"""

from __future__ import annotations

import math

from tumble._typing import FloatArray
from tumble.kernels.frames import dot
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Mat3, Vec3, mat3, mat_vec
from tumble.kernels.params import TRIAXIAL_AVERAGED

__all__ = [
    "Context",
    "Parts",
    "Polhode",
    "column_dot",
    "quadratic",
    "sorted_diagonal",
    "sorted_moments",
    "sorted_vector",
    "turned",
    "weighted",
]

_Q = TRIAXIAL_AVERAGED.at.sorting

Parts = tuple[float, float, float, float]
"""A term's averaged moment in the L-frame (across L: two; along L) and its power ω·M."""
Polhode = tuple[float, float, float, float, float, float, float]
"""(A_c, A_s, A_d, m, ⟨sn²⟩, ⟨sn⁴⟩, ⟨dn⟩): ℓ = (A_c cn u, A_s sn u, A_d dn u) in the sorted axes
(c, s, d) = (1, 2, 3) about the third axis, (3, 2, 1) about the first, at the parameter m, and
the means over u of sn², sn⁴ and dn (:mod:`tumble.kernels.triaxial_closed`)."""
Context = tuple[float, float, Vec3, Vec3, Vec3, Vec3, float, int, Mat3, Polhode]


@jit(INLINE)
def _sorted_row(p: FloatArray, x: FloatArray, v: int, i: int) -> Vec3:
    """Row i of Q X: the user-axes matrix X (by rows at x[v : v + 9])."""
    q = mat3(p, _Q)
    q0, q1, q2 = q[3 * i], q[3 * i + 1], q[3 * i + 2]
    return (
        q0 * x[v] + q1 * x[v + 3] + q2 * x[v + 6],
        q0 * x[v + 1] + q1 * x[v + 4] + q2 * x[v + 7],
        q0 * x[v + 2] + q1 * x[v + 5] + q2 * x[v + 8],
    )


@jit(INLINE)
def sorted_diagonal(p: FloatArray, x: FloatArray, v: int) -> tuple[Vec3, Vec3]:
    """The diagonal of Q X Qᵀ (X in the sorted axes; X by rows at x[v : v + 9]) and its entries
    across each axis, ((QXQᵀ)₂₃, (QXQᵀ)₃₁, (QXQᵀ)₁₂)."""
    r0, r1, r2 = _sorted_row(p, x, v, 0), _sorted_row(p, x, v, 1), _sorted_row(p, x, v, 2)
    q = mat3(p, _Q)
    q0, q1, q2 = (q[0], q[1], q[2]), (q[3], q[4], q[5]), (q[6], q[7], q[8])
    return (
        (dot(r0, q0), dot(r1, q1), dot(r2, q2)),
        (dot(r1, q2), dot(r2, q0), dot(r0, q1)),
    )


@jit(INLINE)
def sorted_vector(p: FloatArray, x1: float, x2: float, x3: float) -> Vec3:
    """Q x: user axes to sorted ones."""
    return mat_vec(p, _Q, x1, x2, x3)


@jit(INLINE)
def sorted_moments(p: FloatArray, i1: float, i2: float, i3: float) -> Vec3:
    """The diagonal of Q diag(I) Qᵀ, Σₖ Qᵢₖ² Iₖ: moments given in the user's order, sorted."""
    q = mat3(p, _Q)
    return (
        q[0] ** 2 * i1 + q[1] ** 2 * i2 + q[2] ** 2 * i3,
        q[3] ** 2 * i1 + q[4] ** 2 * i2 + q[5] ** 2 * i3,
        q[6] ** 2 * i1 + q[7] ** 2 * i2 + q[8] ** 2 * i3,
    )


@jit(INLINE)
def turned(F: Mat3, angle: float) -> Mat3:
    """Rz(angle)ᵀ F (by rows): the L-frame axes (F's columns) in the axes of the inputs at
    t = 0, which have since turned about ξ3 by ``angle`` (the node)."""
    c, s = math.cos(angle), math.sin(angle)
    return (
        c * F[0] + s * F[3], c * F[1] + s * F[4], c * F[2] + s * F[5],
        -s * F[0] + c * F[3], -s * F[1] + c * F[4], -s * F[2] + c * F[5],
        F[6], F[7], F[8],
    )  # fmt: skip


@jit(INLINE)
def column_dot(F: Mat3, j: int, x1: float, x2: float, x3: float) -> float:
    """The L-frame component j of the inertial vector x: (F's column j)·x."""
    return F[j] * x1 + F[3 + j] * x2 + F[6 + j] * x3


@jit(INLINE)
def quadratic(F: Mat3, x: FloatArray, v: int, i: int, j: int) -> float:
    """(F's column i)ᵀ X (F's column j), X by rows at x[v : v + 9]."""
    total = 0.0
    for k in range(3):
        total += F[3 * k + i] * (
            x[v + 3 * k] * F[j] + x[v + 3 * k + 1] * F[3 + j] + x[v + 3 * k + 2] * F[6 + j]
        )
    return total


@jit(INLINE)
def weighted(w: Vec3, x: Vec3, y: Vec3) -> float:
    """Σᵢ wᵢ xᵢ yᵢ."""
    return w[0] * x[0] * y[0] + w[1] * x[1] * y[1] + w[2] * x[2] * y[2]
