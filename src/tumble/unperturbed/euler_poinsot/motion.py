"""The torque-free motion itself in closed form, (3.1): :class:`EulerPoinsot`, its state in
Jacobi functions and its attitude by 3-1-3 angles relative to the L-frame (§8 of
docs/theory/rotating-field.md). Conventions: :mod:`tumble.unperturbed.euler_poinsot`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from scipy import special

from tumble._docstrings import DocSections
from tumble._typing import ArrayLike, FloatArray
from tumble.bodies import RigidBody, proper_sorting
from tumble.errors import ParameterError, warn
from tumble.kernels.codes import SEPARATRIX_RTOL
from tumble.rotations import (
    matrix_to_quat,
    quat_conjugate,
    quat_multiply,
    quat_normalize,
    quat_to_matrix,
)
from tumble.unperturbed._checks import finite_array, finite_vector, moments
from tumble.unperturbed.elliptic import _ellipf_sc, _ellippi_mc, _ellippi_sc, _jacobi
from tumble.unperturbed.euler_poinsot.regimes import (
    Regime,
    _characteristic,
    _mean_precession,
    _side_modulus,
    _symmetry,
    _u_rate,
)

_ATTITUDE_ATOL = 1e-9  # ‖A Aᵀ − E‖ allowed for attitude0 (a rotation given to ~1e-9)

_DOC = DocSections(
    tau="""
    Parameters
    ----------
    tau : array_like
        Times [τ].
    """
)


def _qz(a: FloatArray) -> FloatArray:
    """Quaternion of Rz(a)."""
    z = np.zeros_like(a)
    return np.stack([np.cos(0.5 * a), z, z, np.sin(0.5 * a)], -1)


def _qx(a: FloatArray) -> FloatArray:
    """Quaternion of Rx(a)."""
    z = np.zeros_like(a)
    return np.stack([np.cos(0.5 * a), np.sin(0.5 * a), z, z], -1)


def _wrap(x: FloatArray) -> FloatArray:
    """x reduced to [−π, π]."""
    return x - 2.0 * math.pi * np.rint(x / (2.0 * math.pi))


def _u_from_sn_cn(sn: float, cn: float, mc: float, K: float) -> float:
    """u in (−2K, 2K] with (sn u, cn u) ∝ (sn, cn): F(am | m) from the pair, not the angle."""
    r = math.hypot(sn, cn)
    s, c = sn / r, cn / r
    f = float(_ellipf_sc(s, abs(c), mc))
    if c >= 0.0:
        return f
    return math.copysign(2.0 * K, s) - f  # F(π − φ) = 2K − F(φ) on the far half


@dataclass(frozen=True)
class _Still:
    """Uniform rotation (or rest) about z0 (∥ L, a principal axis): ψ = |z| τ, θ = φ = 0."""

    rate: float

    def evaluate(self, tau: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        zp = np.zeros((*tau.shape, 3))
        zp[..., 2] = self.rate
        zero = np.zeros_like(tau)
        return zp, self.rate * tau, zero, zero


@dataclass(frozen=True)
class _Precession:
    """Regular precession of a symmetric body in its p-frame (polar axis third).

    φ = φ0 + φ̇ τ with φ̇ = z_c (I_a − I_c)/I_a, θ constant, ψ = L τ/I_a (§8 "Degenerate
    inertia"); z_p = (r sin φ, r cos φ, z_c).
    """

    Ia: float
    Ic: float
    L: float
    r: float
    zc: float
    phi0: float

    def evaluate(self, tau: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        phi = self.phi0 + self.zc * (self.Ia - self.Ic) / self.Ia * tau
        zp = np.stack([self.r * np.sin(phi), self.r * np.cos(phi), np.full_like(phi, self.zc)], -1)
        theta = np.full_like(tau, math.atan2(self.Ia * self.r, self.Ic * self.zc))
        return zp, self.L / self.Ia * tau, theta, phi


@dataclass(frozen=True)
class _Elliptic:
    """Triaxial motion (3.1) in its branch frame (dn component > 0), regime x3, x1 or the
    separatrix (x3 form with m = 1).

    Amplitudes a_cn, a_sn, a_dn multiply cn u, sn u, dn u; in regime x3 they are the
    components (z1, z2, z3), in regime x1 (z3, z2, z1). u = ν τ + u0.
    """

    side: str  # "x3" or "x1"
    moments: tuple[float, float, float]  # sorted I1 ≤ I2 ≤ I3
    L: float
    m: float
    mc: float
    K: float
    nu: float
    u0: float
    a_cn: float
    a_sn: float
    a_dn: float
    n: float  # characteristic of ψ̇
    Pi: float  # complete Π(n | m) (inf on the separatrix, unused there)

    def _psi_integral(self, u: FloatArray) -> tuple[FloatArray, ...]:
        """sn u, cn u, dn u, am u and G(u) = ∫0^u du'/(1 − n sn²u') = Π(n; am u | m).

        G(u) = 2jΠ(n | m) + Π(n; am u_r | m), the latter from (sn u_r, cn u_r) directly;
        on the separatrix G = [u + b atan(b tanh u)]/(1 − n), n = −b².
        """
        sn, cn, dn, j = _jacobi(u, self.m, self.mc, self.K)
        if self.mc == 0.0:
            b = math.sqrt(-self.n)
            G = (u + b * np.arctan(b * np.tanh(u))) / (1.0 - self.n)
            return sn, cn, dn, np.arctan2(sn, cn), G
        G = 2.0 * j * self.Pi + _ellippi_sc(self.n, sn, cn, self.mc)
        am = np.arctan2(sn, cn) + math.pi * j
        sign = 1.0 - 2.0 * np.mod(j, 2.0)
        return sign * sn, sign * cn, dn, am, G

    def evaluate(self, tau: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        I1, I2, I3 = self.moments
        u = self.nu * tau + self.u0
        sn, cn, dn, am, G = self._psi_integral(u)
        zcn, zsn, zdn = self.a_cn * cn, self.a_sn * sn, self.a_dn * dn
        dG = G - self._psi_integral(np.asarray(self.u0))[4]
        coeff = self.L * (I3 - I1) / (I1 * I3 * self.nu)
        if self.side == "x3":
            # p-frame = branch frame: (a, b, c) = (z1 ∝ cn, z2 ∝ sn, z3 ∝ dn)
            zp = np.stack([zcn, zsn, zdn], -1)
            Ia, Ib, Ic = I1, I2, I3
            psi = self.L / I3 * tau + coeff * dG
            phi_ref = 0.5 * math.pi - am  # φ = atan2(I1 a_cn cos am, I2 a_sn sin am) ≈ π/2 − am
        else:
            # p-frame = (x2, x3, x1) of the branch frame: (z2 ∝ sn, z3 ∝ cn, z1 ∝ dn)
            zp = np.stack([zsn, zcn, zdn], -1)
            Ia, Ib, Ic = I2, I3, I1
            psi = self.L / I1 * tau - coeff * dG
            phi_ref = am  # φ = atan2(I2 a_sn sin am, I3 a_cn cos am) ≈ am
        la, lb, lc = Ia * zp[..., 0], Ib * zp[..., 1], Ic * zp[..., 2]
        theta = np.arctan2(np.hypot(la, lb), lc)
        # φ and its reference stay in the same quadrant: unwrap to a continuous angle.
        phi = phi_ref + _wrap(np.arctan2(la, lb) - phi_ref)
        return zp, psi, theta, phi


_Kernel = _Still | _Precession | _Elliptic


def _frame_with_third_row(v: FloatArray) -> FloatArray:
    """A rotation matrix whose third row is v/|v|."""
    unit = v / np.linalg.norm(v)
    e = np.zeros(3)
    e[int(np.argmin(np.abs(unit)))] = 1.0
    r1 = np.cross(e, unit)
    r1 /= np.linalg.norm(r1)
    return np.stack([r1, np.cross(unit, r1), unit])


_CYCLE_TO_X1 = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
"""(x1, x2, x3) → (x2, x3, x1): puts the polar axis x1 of regime x1 third."""


def _check_attitude(A: FloatArray) -> None:
    if A.shape != (3, 3) or not np.all(np.isfinite(A)):
        raise ParameterError("attitude0 must be a finite 3×3 rotation matrix")
    err = float(np.max(np.abs(A @ A.T - np.eye(3))))
    if err > _ATTITUDE_ATOL or np.linalg.det(A) <= 0.0:
        raise ParameterError(
            f"attitude0 is not a proper rotation: max |A Aᵀ − E| = {err:g} (allowed "
            f"{_ATTITUDE_ATOL:g}), det = {np.linalg.det(A):g} (must be > 0)"
        )


_Built = tuple[Regime, float, float, float, float, float, _Kernel, FloatArray]
"""Regime, k2, ν, period, ν1, ν2, kernel and P (sorted axes → p-frame) of a state."""


def _build_kernel(Is: tuple[float, float, float], zs: FloatArray, L: float, T: float) -> _Built:
    """Regime, k2, ν, period, ν1, ν2, kernel and P (sorted axes → p-frame) of a state.

    The state is normalised (largest |z_i| in [½, 1)), so squares neither overflow nor
    underflow except for components negligible against 1.
    """
    I1, I2, I3 = Is
    z1, z2, z3 = (float(x) for x in zs)
    if L == 0.0:
        return "rest", 0.0, 0.0, math.inf, 0.0, 0.0, _Still(0.0), np.eye(3)
    sym = _symmetry(I1, I2, I3)
    if sym == "sphere":
        return _uniform(zs, "sphere", 0.0, 0.0, math.inf, 0.0, L / I2)
    if sym:
        return _symmetric(Is, zs, L, sym)
    # d's from the components: sums of non-negative terms, no cancellation (except d2).
    d1 = I2 * (I2 - I1) * z2 * z2 + I3 * (I3 - I1) * z3 * z3
    d3 = I1 * (I3 - I1) * z1 * z1 + I2 * (I3 - I2) * z2 * z2
    d2 = I3 * (I3 - I2) * z3 * z3 - I1 * (I2 - I1) * z1 * z1
    side: Literal["x3", "x1"] = "x3" if d2 > 0.0 else "x1"
    m, mc = _side_modulus(side, I1, I2, I3, d1, d2, d3)
    if mc == 0.0:  # exactly on the separatrix (up to _MC_FLOOR)
        return _on_separatrix(Is, zs, L, d1, d3)
    # Separatrix band: the attributes take their separatrix values (k2 = 1, period = inf,
    # ν1 = 0, ν2 = L/I2); the motion follows the state itself.
    sep = abs(d2) <= SEPARATRIX_RTOL * L * L
    return _elliptic(Is, zs, L, side, sep, m, mc, d1, d3)


def _uniform(
    zs: FloatArray, reg: Regime, k2: float, nu: float, period: float, nu1: float, nu2: float
) -> _Built:
    """z0 along a principal axis (or a sphere): uniform rotation about z0 (∥ L)."""
    P = _frame_with_third_row(zs)
    return reg, k2, nu, period, nu1, nu2, _Still(float(np.linalg.norm(zs))), P


def _symmetric(Is: tuple[float, float, float], zs: FloatArray, L: float, sym: str) -> _Built:
    """Regular precession about the symmetry axis c, I_a the mean of the equal pair."""
    I1, I2, I3 = Is
    P = np.eye(3) if sym == "x3" else _CYCLE_TO_X1
    za, zb, zc = (float(x) for x in P @ zs)
    Ia, Ic = (0.5 * (I1 + I2), I3) if sym == "x3" else (0.5 * (I2 + I3), I1)
    nu = abs(zc * (Ia - Ic) / Ia)  # |φ̇|: the limit k → 0 of ν, = ν1
    period = 2.0 * math.pi / nu if nu > 1e-300 else math.inf  # > 1e-300: no overflow
    if (za == 0.0 and zb == 0.0) or zc == 0.0:
        return _uniform(zs, "symmetric", 0.0, nu, period, nu, L / Ia)
    kern: _Kernel = _Precession(Ia, Ic, L, math.hypot(za, zb), zc, math.atan2(za, zb))
    return "symmetric", 0.0, nu, period, nu, L / Ia, kern, P


def _amplitudes(
    side: Literal["x3", "x1"], Is: tuple[float, float, float], d1: float, d3: float
) -> tuple[float, float, float]:
    """Amplitudes (a_cn, a_sn, a_dn) of cn u, sn u, dn u in (3.1), regime ``side``.

    Regime x3 (and the separatrix, its m = 1 form): the largest |z1|, |z2|, |z3|; regime x1:
    those of |z3|, |z2|, |z1|, the same formulas with indices 1 and 3 exchanged (correction
    C7).

    Parameters
    ----------
    side : {"x3", "x1"}
        Which set of formulas (polar axis x3 or x1).
    Is : tuple of float
        Principal moments I1 ≤ I2 ≤ I3 [inertia unit].
    d1, d3 : float
        L² − 2T·I1 and 2T·I3 − L², both ≥ 0 [inertia unit² · (rad/τ)²].

    Returns
    -------
    a_cn, a_sn, a_dn : float
        [rad/τ].
    """
    I1, I2, I3 = Is
    if side == "x3":
        return (
            math.sqrt(d3 / (I1 * (I3 - I1))),
            math.sqrt(d3 / (I2 * (I3 - I2))),
            math.sqrt(d1 / (I3 * (I3 - I1))),
        )
    return (
        math.sqrt(d1 / (I3 * (I3 - I1))),
        math.sqrt(d1 / (I2 * (I2 - I1))),
        math.sqrt(d3 / (I1 * (I3 - I1))),
    )


def _on_separatrix(
    Is: tuple[float, float, float], zs: FloatArray, L: float, d1: float, d3: float
) -> _Built:
    """Exactly on the separatrix: the asymptotic motion (3.1) with m = 1, x3 form; half-turns
    make z1 ≥ 0, z3 ≥ 0."""
    I1, I2, I3 = Is
    z1, _, z3 = (float(x) for x in zs)
    nu = _u_rate("x3", I1, I2, I3, d1, d3)
    s1, s3 = math.copysign(1.0, z1), math.copysign(1.0, z3)
    S = np.diag([s1, s1 * s3, s3])
    b1, b2, _ = (float(x) for x in S @ zs)
    a_cn, a_sn, a_dn = _amplitudes("x3", Is, d1, d3)
    s0, c0 = b2 / a_sn, (b1 / a_cn if a_cn > 0.0 else 0.0)
    if c0 == 0.0 or z3 == 0.0:  # on it, z1 = 0 ⇔ z3 = 0: rotation about x2
        return _uniform(zs, "separatrix", 1.0, nu, math.inf, 0.0, L / I2)
    # sn/cn = tanh/sech = sinh u0: u0 = asinh(s/c), as logarithms (c may be tiny).
    u0 = math.copysign(math.log(abs(s0) + math.hypot(s0, c0)) - math.log(c0), s0)
    n = _characteristic("x3", I1, I2, I3)
    kern = _Elliptic("x3", Is, L, 1.0, 0.0, math.inf, nu, u0, a_cn, a_sn, a_dn, n, math.inf)
    return "separatrix", 1.0, nu, math.inf, 0.0, L / I2, kern, S


def _elliptic(
    Is: tuple[float, float, float],
    zs: FloatArray,
    L: float,
    side: Literal["x3", "x1"],
    sep: bool,
    m: float,
    mc: float,
    d1: float,
    d3: float,
) -> _Built:
    """The Jacobi-function motion (3.1) in regime ``side`` (in the separatrix band when
    ``sep``, with the separatrix's attributes)."""
    I1, I2, I3 = Is
    nu = _u_rate(side, I1, I2, I3, d1, d3)
    K = float(special.elliprf(0.0, mc, 1.0))
    if sep:
        reg: Regime = "separatrix"
        k2, period, nu1, nu2 = 1.0, math.inf, 0.0, L / I2
    else:
        reg = side
        k2, period = m, 4.0 * K / nu
        nu1, nu2 = 0.5 * math.pi * nu / K, _mean_precession(side, I1, I2, I3, L, mc)
    if side == "x3":
        S = np.diag([1.0, math.copysign(1.0, zs[2]), math.copysign(1.0, zs[2])])  # z3 > 0
        bcn, bsn, _ = (float(x) for x in S @ zs)  # (z1, z2) ∝ (cn, sn)
        P = S
    else:
        S = np.diag([math.copysign(1.0, zs[0]), math.copysign(1.0, zs[0]), 1.0])  # z1 > 0
        _, bsn, bcn = (float(x) for x in S @ zs)  # (z2, z3) ∝ (sn, cn)
        P = _CYCLE_TO_X1 @ S
    a_cn, a_sn, a_dn = _amplitudes(side, Is, d1, d3)
    if a_cn == 0.0 or a_sn == 0.0:  # k = 0 (to underflow): uniform rotation about the pole
        return _uniform(zs, reg, k2, nu, period, nu1, nu2)
    u0 = _u_from_sn_cn(bsn / a_sn, bcn / a_cn, mc, K)
    n = _characteristic(side, I1, I2, I3)
    Pi = float(_ellippi_mc(np.asarray(n), np.asarray(mc)))
    kern = _Elliptic(side, Is, L, m, mc, K, nu, u0, a_cn, a_sn, a_dn, n, Pi)
    return reg, k2, nu, period, nu1, nu2, kern, P


def _checked_state(
    inertia: ArrayLike, z0: ArrayLike, attitude0: ArrayLike | None
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The inputs of :meth:`EulerPoinsot.from_state` checked: moments, body rate, attitude."""
    I_user = moments(inertia)
    RigidBody(*(float(x) for x in I_user))  # positive moments, triangle inequality
    z_user = finite_vector("z0", z0)
    A0 = np.eye(3) if attitude0 is None else np.asarray(attitude0, dtype=float)
    _check_attitude(A0)
    return I_user, z_user, A0


@dataclass(frozen=True, eq=False)
class EulerPoinsot:
    """Torque-free motion of a rigid body, (3.1), in closed form (docs/theory/rotating-field.md
    §8).

    Build it with :meth:`from_state`. All angles in rad, rates in rad/τ.

    Attributes
    ----------
    inertia : ndarray, shape (3,)
        Principal moments in the user's axis order [inertia unit].
    z0 : ndarray, shape (3,)
        Body angular velocity at τ = 0, user's axes [rad/τ].
    attitude0 : ndarray, shape (3, 3)
        Body → inertial rotation at τ = 0.
    L : float
        Angular momentum |I z| [inertia unit · rad/τ].
    T : float
        Kinetic energy ½ z·Iz [inertia unit · (rad/τ)²].
    regime : {"x3", "x1", "separatrix", "symmetric", "sphere", "rest"}
        See the module docstring.
    k2 : float
        Modulus squared of the current regime [1]; 1 on the separatrix, 0 for symmetric
        bodies, the sphere and rest.
    nu : float
        u-rate ν of (3.1), u = ν(τ − τ0) [rad/τ]; |φ̇| for a symmetric body, 0 for the sphere
        and rest.
    period : float
        Period of z in body axes, 4K/ν [τ]: inf on the separatrix, for the sphere and at rest;
        2π/|φ̇| for a symmetric body (inf if φ̇ = 0). At k2 = 0 it is the limit 2π/ν.
    nu1, nu2 : float
        Fast frequencies of §8: polhode frequency 2πν/(4K) and mean precession rate ⟨ψ̇⟩
        [rad/τ], as :func:`fast_frequencies` (on the separatrix 0 and L/I2, the values of
        its asymptotic motion).
    lframe : ndarray, shape (3, 3)
        Columns: the axes of the L-frame in inertial components (third column L/|L|).
    polar_frame : ndarray, shape (3, 3)
        P: user body components → p-frame components (polar axis third); proper.

    Notes
    -----
    Separatrix band (|L² − 2T·I2| ≤ SEPARATRIX_RTOL·L²): regime "separatrix", one
    TumbleWarning, and k2 = 1, period = inf, nu1 = 0, nu2 = L/I2. ω(τ) and A(τ) still follow
    the state: exactly on the separatrix (L² = 2T·I2 in floating point) they are the
    asymptotic motion, (3.1) with m = 1 (sn = tanh, cn = dn = sech), tending to the rotation
    about x2; otherwise the periodic motion of the state's own modulus, which the band
    cannot distinguish from it for ~K/ν ≳ 14/ν but which stays exact for the given z0.

    Accuracy: ω(τ) to a few ulps of |z| for any k'² = 1 − k² > 0 (Jacobi functions are
    evaluated on a quarter period and reflected, see
    :func:`~tumble.unperturbed.elliptic._jacobi`); ψ(τ) to ~1e-16/k' rad near the middle
    axis when k' is tiny (the amplitude there is resolved to 1e-16).
    """

    inertia: FloatArray
    z0: FloatArray
    attitude0: FloatArray
    L: float
    T: float
    regime: Regime
    k2: float
    nu: float
    period: float
    nu1: float
    nu2: float
    lframe: FloatArray = field(repr=False)
    polar_frame: FloatArray = field(repr=False)
    _kernel: _Kernel = field(repr=False)
    _q_lframe: FloatArray = field(repr=False)
    _q_polar: FloatArray = field(repr=False)
    _scale: float = field(repr=False)

    @classmethod
    def from_state(
        cls, inertia: ArrayLike, z0: ArrayLike, attitude0: ArrayLike | None = None
    ) -> EulerPoinsot:
        """Free motion through the body angular velocity z0 and attitude attitude0 at τ = 0.

        Parameters
        ----------
        inertia : array_like, shape (3,)
            Principal moments (I1, I2, I3) in any order [inertia unit]; positive, triangle
            inequality (:class:`~tumble.bodies.RigidBody`).
        z0 : array_like, shape (3,)
            Body angular velocity at τ = 0 in the same axes [rad/τ]; finite.
        attitude0 : array_like, shape (3, 3), optional
            Body → inertial rotation at τ = 0 (default identity); orthonormal to 1e-9.

        Returns
        -------
        EulerPoinsot

        Warns
        -----
        TumbleWarning
            On the separatrix L² = 2T·I2: the motion is asymptotic (period infinite).
        """
        I_user, z_user, A0 = _checked_state(inertia, z0, attitude0)

        Q = proper_sorting(I_user)
        Is_arr = np.sort(I_user)
        Is = (float(Is_arr[0]), float(Is_arr[1]), float(Is_arr[2]))
        # The motion of s·ẑ is that of ẑ at time s·τ, scaled by s: build it for the largest
        # |component| in [½, 1), so that squares neither overflow nor underflow. s is a power
        # of 2: the scaling is exact (a state exactly on the separatrix stays on it).
        biggest = float(np.max(np.abs(z_user)))
        scale = math.ldexp(1.0, math.frexp(biggest)[1]) if biggest > 0.0 else 0.0
        zs = Q @ z_user / (scale if scale > 0.0 else 1.0)
        Lvec = Is_arr * zs
        L = float(np.linalg.norm(Lvec))
        T = 0.5 * float(zs @ Lvec)
        reg, k2, nu, period, nu1, nu2, kern, P_sorted = _build_kernel(Is, zs, L, T)
        if reg == "separatrix":
            warn(
                f"the motion is on the separatrix L² = 2T·I2 (|L² − 2T·I2| ≤ "
                f"{SEPARATRIX_RTOL:g}·L²): it is asymptotic to the rotation about the middle "
                "axis and its period is infinite (ν1 = 0: averaging is invalid, §12)"
            )
        P = P_sorted @ Q
        q_polar = matrix_to_quat(P)
        q_a0 = matrix_to_quat(A0)
        _, psi0, theta0, phi0 = kern.evaluate(np.zeros(()))
        q_g0 = quat_multiply(
            quat_multiply(_qz(psi0), _qx(theta0)), quat_multiply(_qz(phi0), q_polar)
        )
        q_lframe = quat_multiply(q_a0, quat_conjugate(q_g0))
        return cls(
            inertia=I_user.copy(),
            z0=z_user.copy(),
            attitude0=A0.copy(),
            L=scale * L,
            T=scale * scale * T,
            regime=reg,
            k2=k2,
            nu=scale * nu,
            period=period / scale if scale > 0.0 else math.inf,
            nu1=scale * nu1,
            nu2=scale * nu2,
            lframe=quat_to_matrix(q_lframe),
            polar_frame=P,
            _kernel=kern,
            _q_lframe=q_lframe,
            _q_polar=q_polar,
            _scale=scale,
        )

    @classmethod
    def from_rigid_body_state(cls, inertia: ArrayLike, y: ArrayLike) -> EulerPoinsot:
        """Free motion through the state ``y = [ω, q]`` of Euler's equations with quaternions
        (body angular velocity [rad/τ], attitude quaternion body → inertial) at τ = 0."""
        y = np.asarray(y, dtype=float)
        return cls.from_state(inertia, y[:3], quat_to_matrix(quat_normalize(y[3:7])))

    def _tau(self, tau: ArrayLike) -> FloatArray:
        t = finite_array("tau", tau)
        return np.asarray(self._scale * t, dtype=float)  # the kernel's time (unit largest |z_i|)

    def omega(self, tau: ArrayLike) -> FloatArray:
        """Body angular velocity z(τ) in the user's axes, (3.1).

        Parameters
        ----------
        tau : array_like
            Times [τ], any shape.

        Returns
        -------
        ndarray, shape tau.shape + (3,)
            [rad/τ].
        """
        zp = self._kernel.evaluate(self._tau(tau))[0]
        return np.asarray(self._scale * (zp @ self.polar_frame), dtype=float)  # s Pᵀ z_p

    @_DOC
    def euler_angles(self, tau: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """3-1-3 angles (ψ, θ, φ) of the p-frame relative to the L-frame, §8.

        body → L-frame = Rz(ψ) Rx(θ) Rz(φ) · polar_frame. ψ and φ are continuous
        (unwrapped), ψ(0) = 0, ψ̇ = L(2T − I_c z_c²)/(L² − I_c² z_c²), computed in closed form
        with Π(n; am u | k²). For a uniform rotation (k2 = 0, or a symmetric body spinning
        about a principal axis) θ = φ = 0 and ψ = |z| τ.

        {{tau}}

        Returns
        -------
        psi, theta, phi : ndarray, shape tau.shape
            [rad].
        """
        _, psi, theta, phi = self._kernel.evaluate(self._tau(tau))
        return psi, theta, phi

    @_DOC
    def quaternion(self, tau: ArrayLike) -> FloatArray:
        """Attitude quaternion q(τ) (scalar first, body → inertial), continuous in τ.

        {{tau}}

        Returns
        -------
        ndarray, shape tau.shape + (4,)
            q(0) equals ``matrix_to_quat(attitude0)`` up to round-off.
        """
        _, psi, theta, phi = self._kernel.evaluate(self._tau(tau))
        q = quat_multiply(_qz(psi), _qx(theta))
        q = quat_multiply(q, quat_multiply(_qz(phi), self._q_polar))
        return quat_multiply(self._q_lframe, q)

    @_DOC
    def attitude(self, tau: ArrayLike) -> FloatArray:
        """Attitude matrix A(τ), body (user's axes) → inertial, A(0) = attitude0.

        {{tau}}

        Returns
        -------
        ndarray, shape tau.shape + (3, 3)
        """
        return quat_to_matrix(self.quaternion(tau))

    def states(self, tau: ArrayLike) -> FloatArray:
        """Full states ``[ω, q]`` at times τ, shape (n, 7): the state vector of Euler's
        equations with quaternions (:func:`tumble.dynamics.rigid_body_rhs`).

        Parameters
        ----------
        tau : array_like, shape (n,)
            Times [τ].
        """
        t = np.ravel(np.asarray(tau, dtype=float))
        return np.concatenate([self.omega(t), self.quaternion(t)], axis=1)

    @property
    def angular_momentum(self) -> FloatArray:
        """Inertial components of the (constant) angular momentum [inertia unit · rad/τ]."""
        return np.asarray(self.L * self.lframe[:, 2], dtype=float)
