"""Legendre elliptic integrals of the third kind for any real amplitude, via Carlson's forms.

Convention (Abramowitz & Stegun 17.2.14, DLMF 19.2.7 with n = α², parameter m = k²)::

    F(φ | m)     = ∫0^φ dθ / sqrt(1 − m sin²θ)
    Π(n; φ | m)  = ∫0^φ dθ / ((1 − n sin²θ) sqrt(1 − m sin²θ))
    Π(n | m)     = Π(n; π/2 | m)                      (complete)

so n > 0 makes the integrand larger (n is the *characteristic* with the sign of
Mathematica's ``EllipticPi[n, φ, m]``; some texts write ``1 + n sin²θ`` instead). For
|φ| ≤ π/2 (DLMF 19.25.14, multiplied through by sin³φ with the homogeneity of R_F, R_J)::

    Π(n; φ | m) = s R_F(c², Δ², 1) + (n/3) s³ R_J(c², Δ², 1, 1 − n s²),
    s = sin φ, c = cos φ, Δ² = 1 − m s² = c² + (1 − m) s².

Larger amplitudes use oddness and quasi-periodicity: the integrand is even and π-periodic,
so Π(n; φ + jπ | m) = 2j Π(n | m) + Π(n; φ | m). The complementary parameter 1 − m enters
only through Δ², never through a difference 1 − m·s², so the functions stay accurate near
m = 1; the internal ``*_mc`` helpers take it directly, for callers that know 1 − m to more
digits than m itself (the Euler–Poinsot motion near its separatrix).

Domain: n ≤ 1, 0 ≤ m ≤ 1, any finite φ; where n = 1 or m = 1 the integral diverges at
φ = ±π/2, so there |φ| ≤ π/2 (the floating-point π/2, which lies just below the true one).
n > 1 (a principal value) is not supported. Outside the domain the functions raise
:class:`~tumble.errors.ParameterError`; they never return NaN.

The Jacobi elliptic functions sn, cn, dn of the closed-form motions (the Euler–Poinsot body
and the symmetric body) are here too: :func:`_jacobi` reduces the argument to a quarter
period and polishes scipy's values there, so that they keep their digits up to m = 1.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy import special

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError

__all__ = ["ellippi", "ellippi_inc"]

_HALF_PI = 0.5 * math.pi


def _floats(*args: ArrayLike) -> list[FloatArray]:
    return [np.asarray(a, dtype=float) for a in np.broadcast_arrays(*args)]


def _reject(field: str, values: FloatArray, ok: NDArray[np.bool_], allowed: str) -> None:
    """Raise for the first element of ``values`` where ``ok`` is False."""
    if not np.all(ok):
        bad = float(values[~ok].flat[0])
        if not math.isfinite(bad):
            raise ParameterError(f"{field} = {bad!r} must be a finite number")
        raise ParameterError(f"{field} = {bad:g} is outside the allowed range {allowed}")


def _check_n_m(n: FloatArray, m: FloatArray) -> None:
    _reject("n", n, np.isfinite(n) & (n <= 1.0), "(-inf, 1]")
    _reject("m", m, np.isfinite(m) & (m >= 0.0) & (m <= 1.0), "[0, 1]")


def _ellippi_mc(n: FloatArray, mc: FloatArray) -> FloatArray:
    """Complete Π(n | m) from mc = 1 − m > 0 and n < 1 (unchecked)."""
    return special.elliprf(0.0, mc, 1.0) + n / 3.0 * special.elliprj(0.0, mc, 1.0, 1.0 - n)


def _ellippi_sc(n: ArrayLike, s: ArrayLike, c: ArrayLike, mc: ArrayLike) -> FloatArray:
    """Π(n; φ | m) for |φ| ≤ π/2 from s = sin φ, c = cos φ ≥ 0 (unchecked).

    Taking (s, c) rather than φ keeps the digits of a small c (φ near ±π/2, where the
    integrand is large when m ≈ 1 or n ≈ 1), which φ itself cannot hold.
    """
    s, c = np.asarray(s, dtype=float), np.asarray(c, dtype=float)
    c2, s2 = c * c, s * s
    d2 = c2 + mc * s2  # Δ² without the cancellation of 1 − m s² near m = 1
    rf = special.elliprf(c2, d2, 1.0)
    rj = special.elliprj(c2, d2, 1.0, c2 + (1.0 - n) * s2)  # 1 − n s², also for n → 1
    return np.asarray(s * rf + n / 3.0 * (s * s2) * rj, dtype=float)


def _ellipf_sc(s: ArrayLike, c: ArrayLike, mc: ArrayLike) -> FloatArray:
    """F(φ | m) for |φ| ≤ π/2 from s = sin φ, c = cos φ ≥ 0 (unchecked)."""
    s, c = np.asarray(s, dtype=float), np.asarray(c, dtype=float)
    return np.asarray(s * special.elliprf(c * c, c * c + mc * s * s, 1.0), dtype=float)


def _pi_principal(n: FloatArray, phi: FloatArray, mc: FloatArray) -> FloatArray:
    """Π(n; φ | m) for |φ| ≤ π/2 by Carlson's forms (unchecked)."""
    return _ellippi_sc(n, np.sin(phi), np.cos(phi), mc)


def _split_amplitude(phi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """φ = jπ + φr with |φr| ≤ π/2; j = 0 wherever |φ| ≤ π/2 already."""
    j = np.where(np.abs(phi) > _HALF_PI, np.rint(phi / math.pi), 0.0)
    return j, np.clip(phi - j * math.pi, -_HALF_PI, _HALF_PI)


def _ellippi_inc_mc(n: FloatArray, phi: FloatArray, mc: FloatArray) -> FloatArray:
    """Π(n; φ | m) for any real φ from mc = 1 − m (unchecked; see the module docstring)."""
    j, phir = _split_amplitude(phi)
    out = _pi_principal(n, phir, mc)
    wrap = j != 0.0
    if np.any(wrap):
        # Only where |φ| > π/2, so n < 1 and mc > 0 there: the complete integral is finite.
        full = _ellippi_mc(np.where(wrap, n, 0.0), np.where(wrap, mc, 1.0))
        out = out + np.where(wrap, 2.0 * j * full, 0.0)
    return np.asarray(out, dtype=float)


def ellippi_inc(n: ArrayLike, phi: ArrayLike, m: ArrayLike) -> FloatArray:
    """Incomplete elliptic integral of the third kind Π(n; φ | m), for any real φ.

    Used for the precession angle ψ(τ) of the Euler–Poinsot motion, §8 of
    (3.1) of the rotating-field paper; convention in the module docstring.

    Parameters
    ----------
    n : array_like
        Characteristic [1], n ≤ 1 (n = 1 only with |φ| ≤ π/2).
    phi : array_like
        Amplitude [rad], any finite value.
    m : array_like
        Parameter m = k² [1], 0 ≤ m ≤ 1 (m = 1 only with |φ| ≤ π/2).

    Returns
    -------
    ndarray
        Π(n; φ | m) [1], broadcast shape of the inputs (0-d for scalars). Odd in φ.

    Raises
    ------
    ParameterError
        An input outside the domain above, or not finite.
    """
    n_, phi_, m_ = _floats(n, phi, m)
    _check_n_m(n_, m_)
    _reject("phi", phi_, np.isfinite(phi_), "(-inf, inf)")
    singular = (n_ == 1.0) | (m_ == 1.0)
    _reject(
        "phi (with n = 1 or m = 1)", phi_, ~singular | (np.abs(phi_) <= _HALF_PI), "[-π/2, π/2]"
    )
    return _ellippi_inc_mc(n_, phi_, 1.0 - m_)


def ellippi(n: ArrayLike, m: ArrayLike) -> FloatArray:
    """Complete elliptic integral of the third kind Π(n | m) = Π(n; π/2 | m).

    Parameters
    ----------
    n : array_like
        Characteristic [1], n < 1.
    m : array_like
        Parameter m = k² [1], 0 ≤ m < 1.

    Returns
    -------
    ndarray
        Π(n | m) [1], broadcast shape of the inputs (0-d for scalars).

    Raises
    ------
    ParameterError
        n ≥ 1 or m ≥ 1 (the integral diverges), m < 0, or an input not finite.
    """
    n_, m_ = _floats(n, m)
    _reject("n", n_, np.isfinite(n_) & (n_ < 1.0), "(-inf, 1)")
    _reject("m", m_, np.isfinite(m_) & (m_ >= 0.0) & (m_ < 1.0), "[0, 1)")
    return np.asarray(_ellippi_mc(n_, 1.0 - m_), dtype=float)


# --------------------------------------------------------------------------------------
# Jacobi elliptic functions, accurate up to the separatrix m = 1
# --------------------------------------------------------------------------------------


def _sech(u: FloatArray) -> FloatArray:
    e = np.exp(-np.abs(u))  # no overflow for large |u|
    return 2.0 * e / (1.0 + e * e)


def _jacobi_quarter(v: FloatArray, m: float, mc: float) -> tuple[FloatArray, ...]:
    """sn, cn, dn of 0 ≤ v ≤ K/2: scipy's amplitude polished by Newton on F(φ | m) = v.

    On [0, K/2] F'(φ) = 1/dn ≤ (1 − m)^(−1/4), so Newton is well conditioned, and scipy's
    start is good to O(1 − m) even where ellipj uses its expansion in 1 − m (m > 1 − 1e-9).
    Above φ = π/4 the iteration runs on χ = π/2 − φ, which keeps the digits of a small cn
    (χ → 0 as v → K/2 → ∞ for m → 1).
    """
    sn, cn, _, _ = special.ellipj(v, m)
    phi, chi = np.arctan2(sn, cn), np.arctan2(cn, sn)
    upper = phi > 0.25 * math.pi
    for _ in range(3):  # quadratic convergence: ~1e-7 → 1e-11 → round-off
        s = np.where(upper, np.cos(chi), np.sin(phi))
        c = np.where(upper, np.sin(chi), np.cos(phi))
        dn = np.sqrt(c * c + mc * s * s)
        step = (_ellipf_sc(s, c, mc) - v) * dn
        phi, chi = phi - step, chi + step
    s = np.where(upper, np.cos(chi), np.sin(phi))
    c = np.where(upper, np.sin(chi), np.cos(phi))
    return s, c, np.sqrt(c * c + mc * s * s)  # dn without the cancellation of 1 − m sn²


def _jacobi(u: FloatArray, m: float, mc: float, K: float) -> tuple[FloatArray, ...]:
    """Reduced Jacobi functions of u, parameter m (mc = 1 − m): (sn u_r, cn u_r, dn u, j).

    u = 2jK + u_r with |u_r| ≤ K, so sn u = (−1)^j sn u_r, cn u = (−1)^j cn u_r ≥ ... and
    am u = jπ + am u_r with |am u_r| ≤ π/2 (cn u_r ≥ 0). |u_r| > K/2 is reflected to
    v = K − |u_r| ≤ K/2 with sn(K − v) = cd v, cn(K − v) = k' sd v, dn(K − v) = k' nd v
    (k' = sqrt(mc)): the small values of cn and dn near u = K keep their digits for any
    mc > 0, where scipy's ellipj alone loses them (its expansion for mc < 1e-9). On the
    separatrix (mc = 0): sn = tanh u, cn = dn = sech u, j = 0.
    """
    if mc == 0.0:
        return np.tanh(u), _sech(u), _sech(u), np.zeros_like(u)
    j = np.rint(u / (2.0 * K))
    ur = u - 2.0 * K * j
    a = np.minimum(np.abs(ur), K)
    far = a > 0.5 * K
    sv, cv, dv = _jacobi_quarter(np.where(far, K - a, a), m, mc)
    kc = math.sqrt(mc)
    sn = np.where(far, cv / dv, sv) * np.sign(ur)
    cn = np.where(far, kc * sv / dv, cv)
    dn = np.where(far, kc / dv, dv)
    return sn, cn, dn, j
