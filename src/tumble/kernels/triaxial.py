"""The general averaging engine's triaxial setting, compiled, for the built-in torques and a
user's numba function.

:func:`tumble.averaging.triaxial_average_vector` averages the rates of the slow variables
``[L_ξ, r = 2T/L²]`` of a triaxial body over the Euler–Poinsot motion (Martynenko (1979),
eq. (3.1)): the polhode phase, the precession angle χ about L and, for a torque with explicit
periodic time dependence, the forcing phase, independently (the non-resonant average). This
module computes the same average in compiled code when the torque is a sum of built-in terms
(:mod:`tumble.kernels.torque`), with two reductions that are exact for them:

* **The forcing phase in closed form.** The explicit time enters the built-in terms only
  through a unit vector turning uniformly on a circle: the orbit radius r̂(u) of the gravity
  gradient, the field direction ĥ(Ωt) of the eddy current. Every channel of the integrand is
  linear in r̂ r̂ᵀ, or in ĥ and ĥ ĥᵀ, so its mean over the phase is its value at the means
  ⟨r̂ r̂ᵀ⟩ = ½(e₁e₁ᵀ + e₂e₂ᵀ) and ⟨ĥ ĥᵀ⟩ = diag(½ sin²β, ½ sin²β, cos²β), ⟨ĥ⟩ = cos β ξ₃
  (each term over its own period, which divides the forcing period). The orbit-averaged terms
  of an orbiting body (:mod:`tumble.space.torques`) vary only with the slowly turning node:
  they are evaluated at the time t; the orbit's own terms never reach the engine (the torqued
  body's parameters refuse them).
* **The precession angle on four nodes.** With the attitude ``A = F Rz(χ) G(τ)`` the channels
  are trigonometric polynomials of degree ≤ 3 in χ (the gravity gradient's ⟨A M⟩ is
  quadratic in A, its power ω·M cubic; the other terms are of lower degree), which the
  trapezoidal rule on χ = 0, π/2, π, 3π/2 integrates exactly; at those angles Rz(χ) only
  permutes rows.

The polhode phase is refined as in the Python engine (:func:`tumble.averaging.triaxial.
_product_mean`): 16 nodes, doubled until the means change by at most ``rtol`` times the mean
size of their integrands (|M| for ⟨A M⟩, |Ω||M| for the power), or by √(rtol/100) once the
changes square from one doubling to the next. Its nodes are uniform in the argument u of the
Jacobi functions over one period 4K; those of the first quarter give the other three by the
shifts u + K, u + 2K, u + 3K, and within the quarter the points beyond K/2 come from K − u
(DLMF 22.4.iii), so that dn is only ever formed where it is at least √k′
(:func:`tumble.kernels.elliptic.jacobi_quarter`).

A program whose every term is polynomial in the attitude (constant moments, linear drag, the
gravity gradient, an orbiting body's orbit-averaged moments) skips the quadrature: its average has a
closed form (:mod:`tumble.kernels.triaxial_closed`). Any other program (a user's numba
function, :mod:`tumble.kernels.user`) is averaged as the Python engine averages it: the
product rule on all three phases, each refined in turn from 16, 4 and 4 nodes with the same
test, the moment at its explicit time.

The three ways are three kinds, so that a run compiles the one it uses:
``KIND_TRIAXIAL_CLOSED`` (:func:`triaxial_closed`), ``KIND_TRIAXIAL_PHASE_MEANS``
(:func:`triaxial_phase_means`) and ``KIND_TRIAXIAL_AVERAGED`` (:func:`triaxial_averaged`, the
product rule). Their parameters: ``[ε, rtol, L_floor, I1, I2, I3 (ascending), Q (sorted ←
user, by rows, 9), I_user (3), forcing period (0: none), branch (±1), torque program]``;
state ``[L_ξ1, L_ξ2, L_ξ3, r]``.

**The sense of rotation.** ``[L_ξ, r]`` does not say in which sense the body turns about the
axis its polhode encircles. The motions of the two senses are images of each other under a
rotation by π about a principal axis across that one: a proper rotation, which carries
motions to motions and keeps L_ξ and T. A torque that is not itself symmetric under it (a
moment fixed in the body, sunlight or air on facets) has different averages on the two.
``branch`` picks one: +1 the body rate's component along the encircled sorted axis positive
(the polhodes of Martynenko (1979), eq. (3.1), as written), −1 the image, its sn and dn
components negated. A run takes it from its initial state and keeps it across a separatrix,
where the sense on the far side is a matter of probability
(:func:`tumble.averaging.separatrix_crossing`).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from tumble._typing import FloatArray
from tumble.kernels.codes import DEGENERATE_RTOL, MC_FLOOR, REACHED_MARGIN, SEPARATRIX_RTOL
from tumble.kernels.elliptic import Table as _Table
from tumble.kernels.elliptic import agm as _agm
from tumble.kernels.elliptic import jacobi_quarter as _quarter
from tumble.kernels.frames import to_body, to_inertial
from tumble.kernels.jit import ENTRY, INLINE, KERNEL, jit
from tumble.kernels.layout import Mat3, Vec3, mat3, vec3
from tumble.kernels.limits import (
    MAX_GRID,
    PHASE_MAX,
    PHASE_START,
    POLHODE_MAX,
    POLHODE_START,
    SQUARING_SAFETY,
)
from tumble.kernels.params import TRIAXIAL_AVERAGED
from tumble.kernels.terms import phase_mean_of
from tumble.kernels.torque import engine_program, program_of
from tumble.kernels.triaxial_closed import closed_mean

__all__ = [
    "PERIOD",
    "PROGRAM_START",
    "jacobi_functions",
    "triaxial_averaged",
    "triaxial_closed",
    "triaxial_phase_means",
]

_AT = TRIAXIAL_AVERAGED.at
PERIOD = _AT.period
"""Index of the forcing period [τ] (0: none, the time frozen at t)."""
PROGRAM_START = TRIAXIAL_AVERAGED.size
"""Index of the torque program in the parameters."""
_Q = _AT.sorting
_NO_FRAME = (0.0,) * 9  # the frame of a refused state (never used)


@jit(ENTRY)
def jacobi_functions(u: FloatArray, mc: float) -> FloatArray:
    """sn, cn, dn (columns) of u ∈ [0, 4K) at the parameter m = 1 − mc (for tests against
    scipy), the way the kernel forms them: the first quarter, then the shifts by K."""
    ratios, n, a = _agm(mc)
    big_k = 0.5 * math.pi / a
    kc = math.sqrt(mc)
    out = np.empty((u.size, 3))
    for i in range(u.size):
        q = min(int(u[i] / big_k), 3)
        s, c, d = _quarter(u[i] - q * big_k, big_k, kc, ratios, n, a)
        out[i, 0], out[i, 1], out[i, 2] = _shifted(q, s, c, d, kc)
    return out


@jit(INLINE)
def _shifted(q: int, s: float, c: float, d: float, kc: float) -> tuple[float, float, float]:
    """sn, cn, dn at u + qK from their values at u (DLMF 22.4.iii)."""
    if q == 0:
        return s, c, d
    if q == 1:
        return c / d, -kc * s / d, kc / d
    if q == 2:
        return -s, -c, d
    return -c / d, kc * s / d, kc / d


# ---------------------------------------------------------------------------------------------
# The torque, averaged over its forcing phase.

_mean_program = program_of(phase_mean_of)
"""Body moment of the program ``prog[start:]``, each term averaged over its forcing phase
(:data:`tumble.kernels.terms.phase_mean_of`): the gravity gradient at ⟨r̂ r̂ᵀ⟩ = ½(e₁e₁ᵀ +
e₂e₂ᵀ), the eddy current of a rotating field at ⟨ĥ ĥᵀ⟩ = diag(½ sin²β, ½ sin²β, cos²β); any
other term as it is at the time t (the orbit-averaged terms of an orbiting body vary only
slowly, with the node)."""


# ---------------------------------------------------------------------------------------------
# The average over the polhode and the precession.


@jit(INLINE)
def _body_frame(p: FloatArray, z1: float, z2: float, z3: float) -> tuple[Vec3, Vec3, Vec3]:
    """The rows of G = Rx(θ) Rz(φ), the rotation taking the body direction of L = I z to the
    third axis (:func:`tumble.averaging.triaxial._polhode_attitudes`)."""
    u1, u2, u3 = vec3(p, _AT.user_inertia)
    j1, j2, j3 = u1 * z1, u2 * z2, u3 * z3
    size = math.sqrt(j1 * j1 + j2 * j2 + j3 * j3)
    l1, l2, l3 = j1 / size, j2 / size, j3 / size
    st = math.sqrt(l1 * l1 + l2 * l2)
    sp, cp = (l1 / st, l2 / st) if st > 0.0 else (0.0, 1.0)
    return (cp, -sp, 0.0), (l3 * sp, l3 * cp, -st), (l1, l2, l3)


_Sums = tuple[float, float, float, float, float, float]
"""The channels of the integrand: ⟨A M⟩ (3), ⟨(Ω − r L_ξ)·M⟩, and the sizes ⟨|M|⟩, ⟨|Ω||M|⟩."""
_NO_SUMS: _Sums = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@jit(INLINE)
def _added(s: _Sums, x: _Sums) -> _Sums:
    """s + x channel by channel: a sum of the integrand over nodes, one node more."""
    return s[0] + x[0], s[1] + x[1], s[2] + x[2], s[3] + x[3], s[4] + x[4], s[5] + x[5]


@jit(INLINE)
def _attitude(F: Mat3, h0: Vec3, h1: Vec3, g2: Vec3) -> Mat3:
    """A = F R with R the rotation of rows h0, h1, g2 (by rows)."""
    return (
        F[0] * h0[0] + F[1] * h1[0] + F[2] * g2[0],
        F[0] * h0[1] + F[1] * h1[1] + F[2] * g2[1],
        F[0] * h0[2] + F[1] * h1[2] + F[2] * g2[2],
        F[3] * h0[0] + F[4] * h1[0] + F[5] * g2[0],
        F[3] * h0[1] + F[4] * h1[1] + F[5] * g2[1],
        F[3] * h0[2] + F[4] * h1[2] + F[5] * g2[2],
        F[6] * h0[0] + F[7] * h1[0] + F[8] * g2[0],
        F[6] * h0[1] + F[7] * h1[1] + F[8] * g2[1],
        F[6] * h0[2] + F[7] * h1[2] + F[8] * g2[2],
    )


@jit(INLINE)
def _channels(
    a: Mat3, z1: float, z2: float, z3: float, m1: float, m2: float, m3: float, rl1: float,
    rl2: float, rl3: float,
) -> _Sums:  # fmt: skip
    """The integrand at one node: A M (3), (Ω − r L_ξ)·A M with Ω = A z, and the sizes |M|
    and |Ω||M| of the engine's convergence test."""
    n1, n2, n3 = to_inertial(a, m1, m2, m3)
    o1, o2, o3 = to_inertial(a, z1, z2, z3)
    mag = math.sqrt(m1 * m1 + m2 * m2 + m3 * m3)
    power = (o1 - rl1) * n1 + (o2 - rl2) * n2 + (o3 - rl3) * n3
    return n1, n2, n3, power, mag, mag * math.sqrt(o1 * o1 + o2 * o2 + o3 * o3)


@jit(KERNEL)
def _node_sums(
    p: FloatArray, t: float, z1: float, z2: float, z3: float, F: Mat3, rl1: float, rl2: float,
    rl3: float,
) -> _Sums:  # fmt: skip
    """Built-in terms: the channels summed over the four precession nodes at the
    body rate z (user axes), with A = F Rz(χ) G and each term at its phase mean."""
    g0, g1, g2 = _body_frame(p, z1, z2, z3)
    sums = _NO_SUMS
    for k in range(4):
        # Rz(χ) G at χ = kπ/2: its first two rows (cos χ g0 − sin χ g1, sin χ g0 + cos χ g1).
        if k == 0:
            h0, h1 = g0, g1
        elif k == 1:
            h0, h1 = (-g1[0], -g1[1], -g1[2]), g0
        elif k == 2:
            h0, h1 = (-g0[0], -g0[1], -g0[2]), (-g1[0], -g1[1], -g1[2])
        else:
            h0, h1 = g1, (-g0[0], -g0[1], -g0[2])
        a = _attitude(F, h0, h1, g2)
        m1, m2, m3 = _mean_program(p, PROGRAM_START, t, z1, z2, z3, a)
        sums = _added(sums, _channels(a, z1, z2, z3, m1, m2, m3, rl1, rl2, rl3))
    return sums


@jit(KERNEL)
def _polhode_sums(
    p: FloatArray, t: float, nodes: int, offset: float, amp: Vec3, x3: bool, big_k: float,
    kc: float, ratios: _Table, n_agm: int, a_agm: float, F: Mat3, rl1: float, rl2: float,
    rl3: float,
) -> _Sums:  # fmt: skip
    """:func:`_node_sums` summed over the polhode nodes u = (j + offset)·4K/nodes, j < nodes:
    one Jacobi evaluation serves the four nodes a quarter period apart."""
    sums = _NO_SUMS
    step = 4.0 * big_k / nodes
    for j in range(nodes // 4):
        sn0, cn0, dn0 = _quarter((j + offset) * step, big_k, kc, ratios, n_agm, a_agm)
        for q in range(4):
            z1, z2, z3 = _user_rates(p, amp, x3, *_shifted(q, sn0, cn0, dn0, kc))
            sums = _added(sums, _node_sums(p, t, z1, z2, z3, F, rl1, rl2, rl3))
    return sums


@jit(KERNEL)
def _exact_mean(
    p: FloatArray, t: float, rtol: float, amp: Vec3, x3: bool, big_k: float, kc: float,
    ratios: _Table, n_agm: int, a_agm: float, F: Mat3, rl1: float, rl2: float, rl3: float,
) -> tuple[bool, float, float, float, float]:  # fmt: skip
    """(converged, ⟨A M⟩ (3), ⟨(Ω − r L_ξ)·M⟩) of built-in terms: the polhode refined
    with the engine's test, the precession and the forcing phase exact (module notes)."""
    nodes = POLHODE_START
    m = _scaled(_polhode_sums(p, t, nodes, 0.0, amp, x3, big_k, kc, ratios, n_agm, a_agm, F, rl1,
                              rl2, rl3), 1.0 / (4 * nodes))  # fmt: skip
    previous = math.inf
    while True:
        if 2 * nodes > POLHODE_MAX:
            return False, math.nan, math.nan, math.nan, math.nan
        fresh = _polhode_sums(
            p, t, nodes, 0.5, amp, x3, big_k, kc, ratios, n_agm, a_agm, F, rl1, rl2, rl3
        )
        m, previous, done = _doubled(m, fresh, 0.5 / (4 * nodes), previous, rtol)
        nodes *= 2
        if done:
            return True, m[0], m[1], m[2], m[3]


@jit(KERNEL)
def _rates_at(
    p: FloatArray, u: float, amp: Vec3, x3: bool, big_k: float, kc: float, ratios: _Table,
    n_agm: int, a_agm: float,
) -> Vec3:  # fmt: skip
    """The body rate (user axes) at the argument u ∈ [0, 4K) of the Jacobi functions."""
    q = min(int(u / big_k), 3)
    sn, cn, dn = _quarter(u - q * big_k, big_k, kc, ratios, n_agm, a_agm)
    return _user_rates(p, amp, x3, *_shifted(q, sn, cn, dn, kc))


@jit(INLINE)
def _user_rates(p: FloatArray, amp: Vec3, x3: bool, sn: float, cn: float, dn: float) -> Vec3:
    """The body rate in user axes, z_user = Qᵀ z_sorted, from the Jacobi functions: sorted
    components (cn, sn, dn) in regime x3 (L² > 2T·I2), (dn, sn, cn) in regime x1, times
    their amplitudes (Martynenko (1979), eq. (3.1))."""
    if x3:
        w1, w2, w3 = amp[0] * cn, amp[1] * sn, amp[2] * dn
    else:
        w1, w2, w3 = amp[2] * dn, amp[1] * sn, amp[0] * cn
    return to_body(mat3(p, _Q), w1, w2, w3)  # Qᵀ w


@jit(KERNEL)
def _grid_sums(
    p: FloatArray, t: float, n0: int, o0: float, n1: int, o1: float, n2: int, o2: float,
    amp: Vec3, x3: bool, big_k: float, kc: float, ratios: _Table, n_agm: int, a_agm: float,
    F: Mat3, rl1: float, rl2: float, rl3: float,
) -> _Sums:  # fmt: skip
    """Any program: the channels of :func:`_node_sums` summed over the product grid
    of n0 polhode phases, n1 precession angles and n2 forcing phases, each axis uniform with
    its offset (in nodes), the moment at its explicit time t + s·P/2π (the Python engine's
    integrand, :func:`tumble.averaging.triaxial._means`)."""
    sums = _NO_SUMS
    period = p[PERIOD]
    for j0 in range(n0):
        z1, z2, z3 = _rates_at(p, (j0 + o0) * 4.0 * big_k / n0, amp, x3, big_k, kc, ratios,
                               n_agm, a_agm)  # fmt: skip
        g0, g1, g2 = _body_frame(p, z1, z2, z3)
        for j1 in range(n1):
            chi = (j1 + o1) * 2.0 * math.pi / n1
            c, s = math.cos(chi), math.sin(chi)
            h0 = (c * g0[0] - s * g1[0], c * g0[1] - s * g1[1], c * g0[2] - s * g1[2])
            h1 = (s * g0[0] + c * g1[0], s * g0[1] + c * g1[1], s * g0[2] + c * g1[2])
            a = _attitude(F, h0, h1, g2)
            for j2 in range(n2):
                tt = t + (j2 + o2) * period / n2 if period > 0.0 else t
                m1, m2, m3 = engine_program(p, PROGRAM_START, tt, z1, z2, z3, a)
                sums = _added(sums, _channels(a, z1, z2, z3, m1, m2, m3, rl1, rl2, rl3))
    return sums


@jit(KERNEL)
def _general_mean(
    p: FloatArray, t: float, rtol: float, amp: Vec3, x3: bool, big_k: float, kc: float,
    ratios: _Table, n_agm: int, a_agm: float, F: Mat3, rl1: float, rl2: float, rl3: float,
) -> tuple[bool, float, float, float, float]:  # fmt: skip
    """(converged, ⟨A M⟩ (3), ⟨(Ω − r L_ξ)·M⟩) of any program: the product rule refined axis
    by axis (polhode, precession, forcing) with the Python engine's test and limits
    (:func:`tumble.averaging.triaxial._product_mean`)."""
    forced = p[PERIOD] > 0.0
    n0, n1, n2 = POLHODE_START, PHASE_START, PHASE_START if forced else 1
    m = _scaled(_grid_sums(p, t, n0, 0.0, n1, 0.0, n2, 0.0, amp, x3, big_k, kc, ratios, n_agm,
                           a_agm, F, rl1, rl2, rl3), 1.0 / (n0 * n1 * n2))  # fmt: skip
    for axis in range(3 if forced else 2):
        previous = math.inf
        while True:
            n = n0 if axis == 0 else (n1 if axis == 1 else n2)
            if 2 * n > (POLHODE_MAX if axis == 0 else PHASE_MAX) or 2 * n0 * n1 * n2 > MAX_GRID:
                return False, math.nan, math.nan, math.nan, math.nan
            fresh = _grid_sums(
                p, t, n0, 0.5 if axis == 0 else 0.0, n1, 0.5 if axis == 1 else 0.0, n2,
                0.5 if axis == 2 else 0.0, amp, x3, big_k, kc, ratios, n_agm, a_agm, F, rl1,
                rl2, rl3,
            )  # fmt: skip
            m, previous, done = _doubled(m, fresh, 0.5 / (n0 * n1 * n2), previous, rtol)
            if axis == 0:
                n0 *= 2
            elif axis == 1:
                n1 *= 2
            else:
                n2 *= 2
            if done:
                break
    return True, m[0], m[1], m[2], m[3]


@jit(INLINE)
def _scaled(s: _Sums, f: float) -> _Sums:
    return f * s[0], f * s[1], f * s[2], f * s[3], f * s[4], f * s[5]


@jit(INLINE)
def _doubled(m: _Sums, fresh: _Sums, scale: float, previous: float, rtol: float
             ) -> tuple[_Sums, float, bool]:  # fmt: skip
    """A doubling of one axis: the means (the old ones halved, plus the new nodes' sums times
    ``scale``), their change relative to the integrands' sizes, and whether the engine's test
    accepts them (:func:`tumble.averaging.triaxial._product_mean`: the change at most
    ``rtol``, or at most √(rtol/100) once the changes square from one doubling to the next)."""
    new = (
        0.5 * m[0] + scale * fresh[0], 0.5 * m[1] + scale * fresh[1],
        0.5 * m[2] + scale * fresh[2], 0.5 * m[3] + scale * fresh[3],
        0.5 * m[4] + scale * fresh[4], 0.5 * m[5] + scale * fresh[5],
    )  # fmt: skip
    change = 0.0
    if new[4] > 0.0:
        change = max(abs(new[0] - m[0]), abs(new[1] - m[1]), abs(new[2] - m[2])) / new[4]
    if new[5] > 0.0:
        change = max(change, abs(new[3] - m[3]) / new[5])
    squaring = previous < math.inf and change <= SQUARING_SAFETY * previous * previous
    done = change <= rtol or (change <= math.sqrt(rtol / SQUARING_SAFETY) and squaring)
    return new, change, done


@jit(KERNEL)
def _frame(l1: float, l2: float, l3: float) -> Mat3:
    """A rotation (by rows) whose third column is the unit vector l
    (:func:`tumble.averaging.triaxial._frame_with_third_column`)."""
    b1, b2, b3 = abs(l1), abs(l2), abs(l3)
    if b1 <= b2 and b1 <= b3:  # e1 = a × l with a the axis of the smallest component
        e1, e2, e3 = 0.0, -l3, l2
    elif b2 <= b3:
        e1, e2, e3 = l3, 0.0, -l1
    else:
        e1, e2, e3 = -l2, l1, 0.0
    size = math.sqrt(e1 * e1 + e2 * e2 + e3 * e3)
    e1, e2, e3 = e1 / size, e2 / size, e3 / size
    f1, f2, f3 = l2 * e3 - l3 * e2, l3 * e1 - l1 * e3, l1 * e2 - l2 * e1
    return (e1, f1, l1, e2, f2, l2, e3, f3, l3)


@jit(INLINE)
def _nan(out: FloatArray) -> None:
    for j in range(4):
        out[j] = math.nan


@jit(INLINE)
def _polhode(y: FloatArray, p: FloatArray) -> tuple[bool, float, float, bool, float, Vec3, Mat3]:
    """(valid, |L|, r, regime x3, the complementary parameter mc, the amplitudes of cn, sn,
    dn, the frame F of L) of the state y = [L_ξ, r]; not valid where the Python engine
    refuses the state: r beyond a pure rotation by more than the margin, L at or below the
    floor, mc below its floor. In the separatrix band, which the Python engine refuses, the
    polhode at the band's edge on the state's side.

    A body with two equal moments (within ``DEGENERATE_RTOL·I3``) has no separatrix: its
    polhodes are circles about the third axis, at m = 0 (mc = 1), where sn and cn are the sine
    and cosine of a phase uniform in time (the k → 0 limit of eq. (3.1)), in regime x3 when
    I1 = I2, x1 when I2 = I3, whatever r; the amplitudes stay finite (their differences of
    moments are the unequal ones). The flat spin about the equal axes is a circle of pure
    rotations, not a separatrix: it is averaged over that circle, as any polhode. For the
    sphere, ω = L/I along the third sorted axis (dn = 1, the other amplitudes 0), as the Python
    engine puts it: every body direction of L is the same to an isotropic body."""
    i1, i2, i3 = vec3(p, _AT.inertia)
    lo, hi = 1.0 / i3, 1.0 / i1
    r = y[3]
    if not lo - REACHED_MARGIN * hi <= r <= hi + REACHED_MARGIN * hi:
        return False, 0.0, r, True, 0.0, (0.0, 0.0, 0.0), _NO_FRAME
    r = min(max(r, lo), hi)
    L = math.sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2])
    d1, d2, d3 = max(1.0 - r * i1, 0.0), 1.0 - r * i2, max(r * i3 - 1.0, 0.0)
    tol = DEGENERATE_RTOL * i3
    low, high = i2 - i1 <= tol, i3 - i2 <= tol  # I1 = I2, I2 = I3
    if not L > p[_AT.floor]:
        return False, L, r, True, 0.0, (0.0, 0.0, 0.0), _NO_FRAME
    if abs(d2) <= SEPARATRIX_RTOL and not (low or high):
        # Inside the band the regime is not known from the state: the polhode at the band's
        # edge on d2's side (its one-sided limit; the rates tend to finite limits there as
        # 1/ln(1/d2)). A run creeping onto the separatrix (its rates' derivatives grow like
        # 1/(d2 ln² d2), so the steps shrink with d2) then steps across it, where the
        # separatrix event restarts it beyond, instead of stalling on refused stages.
        d2 = SEPARATRIX_RTOL if d2 >= 0.0 else -SEPARATRIX_RTOL
    frame = _frame(y[0] / L, y[1] / L, y[2] / L)
    if low and high:  # a sphere
        return True, L, r, True, 1.0, (0.0, 0.0, L / i3), frame
    x3 = low or (d2 > 0.0 and not high)
    if low or high:
        mc = 1.0
    elif x3:
        mc = (i3 - i1) * d2 / ((i3 - i2) * d1)
    else:
        mc = -(i3 - i1) * d2 / ((i2 - i1) * d3)
    if x3:
        amp = (
            L * math.sqrt(d3 / (i1 * (i3 - i1))),  # cn
            L * math.sqrt(d3 / (i2 * (i3 - i2))),  # sn
            L * math.sqrt(d1 / (i3 * (i3 - i1))),  # dn
        )
    else:
        amp = (
            L * math.sqrt(d1 / (i3 * (i3 - i1))),
            L * math.sqrt(d1 / (i2 * (i2 - i1))),
            L * math.sqrt(d3 / (i1 * (i3 - i1))),
        )
    if not mc >= MC_FLOOR:
        return False, L, r, x3, mc, amp, _NO_FRAME
    # The other sense of rotation about the encircled axis: the polhode turned by π about
    # the third sorted axis (x1) or the first (x3), which flips the sn and dn components; a
    # proper rotation, so it is again a motion, the same [L_ξ, r] (module notes).
    branch = p[_AT.branch]
    amp = (amp[0], branch * amp[1], branch * amp[2])
    return True, L, r, x3, min(mc, 1.0), amp, frame


@jit(INLINE)
def triaxial_closed(t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """``KIND_TRIAXIAL_CLOSED``: ε⟨A M⟩ and ε·2⟨(Ω − r L_ξ)·M⟩/L² for y = [L_ξ, r] of a
    program whose every term has a closed-form average (:mod:`tumble.kernels.
    triaxial_closed`); NaN where :func:`_polhode` refuses the state, so
    that the step is rejected."""
    valid, L, r, x3, mc, amp, F = _polhode(y, p)
    if not valid:
        _nan(out)
        return
    m1, m2, m3, m4 = closed_mean(p, PROGRAM_START, t, L, r, x3, mc, amp, F)
    _rates(out, p[_AT.eps], L, m1, m2, m3, m4)


@jit(INLINE)
def _quadrature(
    mean: Callable[..., tuple[bool, float, float, float, float]], t: float, y: FloatArray,
    p: FloatArray, out: FloatArray,
) -> None:  # fmt: skip
    """The rates with the means of ``mean`` (:func:`_exact_mean` or :func:`_general_mean`,
    a compile-time constant), NaN where the state is refused or the quadrature does not
    converge."""
    valid, L, r, x3, mc, amp, F = _polhode(y, p)
    if not valid:
        _nan(out)
        return
    ratios, n_agm, a_agm = _agm(mc)
    big_k = 0.5 * math.pi / a_agm
    ok, m1, m2, m3, m4 = mean(p, t, p[_AT.rtol], amp, x3, big_k, math.sqrt(mc), ratios, n_agm,
                              a_agm, F, r * y[0], r * y[1], r * y[2])  # fmt: skip
    if not ok:
        _nan(out)
        return
    _rates(out, p[_AT.eps], L, m1, m2, m3, m4)


@jit(INLINE)
def triaxial_phase_means(t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """``KIND_TRIAXIAL_PHASE_MEANS``: the rates of :func:`triaxial_closed` for built-in terms
    without a closed form, the polhode refined, the precession and the forcing phase exact
    (module notes)."""
    _quadrature(_exact_mean, t, y, p, out)


@jit(INLINE)
def triaxial_averaged(t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """``KIND_TRIAXIAL_AVERAGED``: the rates of :func:`triaxial_closed` for any program (a
    user's numba function among its terms), by the product rule on all three phases."""
    _quadrature(_general_mean, t, y, p, out)


@jit(INLINE)
def _rates(out: FloatArray, eps: float, L: float, m1: float, m2: float, m3: float, m4: float
           ) -> None:  # fmt: skip
    """The rates from the means ⟨A M⟩ (m1, m2, m3) and ⟨(Ω − r L_ξ)·A M⟩ (m4)."""
    out[0] = eps * m1
    out[1] = eps * m2
    out[2] = eps * m3
    out[3] = eps * 2.0 * m4 / (L * L)
