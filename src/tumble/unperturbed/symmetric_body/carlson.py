"""Carlson's integrals in the forms the orbit's closed forms use: F(γ) from its sine and
cosine, complete R_J and its derivative in p, and the incomplete pieces S(γ, w) and Λ(γ) of
the pole integrals (§5 of the theory)."""

from __future__ import annotations

import numpy as np
from scipy import special

from tumble._typing import FloatArray


def _ellipf_scalar(s: float, c: float, mc: float) -> float:
    """F(φ | m) from s = sin φ, c = cos φ ≥ 0: :func:`_ellipf_sc` for plain floats."""
    return s * float(special.elliprf(c * c, c * c + mc * s * s, 1.0))


def _rj_complete(mc: float, p: float) -> float:
    return float(special.elliprj(0.0, mc, 1.0, p))


def _drj_dp(mc: float, p: float) -> float:
    """∂R_J(0, mc, 1, p)/∂p by integration by parts (derived for this module).

    With s(t) = t(t + Y)(t + Z) ({Y, Z} = {mc, 1}) and d/dt[√s/((t + p)(t + Z))] integrated over
    (0, ∞): −I_F + c_b I_D + c_c I_J + c_d J2 = 0, I_F = 2R_F, I_D = (2/3)R_D(0, Y, Z),
    I_J = (2/3)R_J, J2 = −(2/3)∂R_J/∂p, c_b = Z(Y − Z)/(p − Z), c_c = 3p − 2Y + Z − c_b,
    c_d = 2p(Y − p). Removable 0/0 at p = Y and p = Z, i.e. at n = m and n = 0 (§8): callers
    keep away from them.
    """
    Y, Z = (mc, 1.0) if abs(p - mc) >= abs(p - 1.0) else (1.0, mc)
    i_f = 2.0 * float(special.elliprf(0.0, Y, Z))
    i_d = 2.0 / 3.0 * float(special.elliprd(0.0, Y, Z))
    i_j = 2.0 / 3.0 * _rj_complete(mc, p)
    cb = Z * (Y - Z) / (p - Z)
    cc = 3.0 * p - 2.0 * Y + Z - cb
    cd = 2.0 * p * (Y - p)
    return 1.5 * (-i_f + cb * i_d + cc * i_j) / cd


def _s_integral(
    sn: FloatArray, cn: FloatArray, dn: FloatArray, j: FloatArray, p: float, Sc: float
) -> FloatArray:
    """S(γ) = ∫0^γ sin²/((1 + (p − 1) sin²)Δ), γ = jπ + γr, from sn γr, cn γr ≥ 0, Δ (§5)."""
    s2, c2 = sn * sn, cn * cn
    return np.asarray(
        2.0 * j * Sc + sn * s2 * special.elliprj(c2, dn * dn, 1.0, c2 + p * s2) / 3.0, dtype=float
    )


def _lam_integral(sin_g: FloatArray, dn: FloatArray, lam: float) -> FloatArray:
    """Λ(γ) = λ⁻¹ arctan(λ sinγ/Δ) = −L(γ) of (1.13) (corrections S8); sinγ/Δ when λ = 0."""
    y = sin_g / dn
    if lam == 0.0:
        return np.asarray(y, dtype=float)
    return np.asarray(np.arctan(lam * y) / lam, dtype=float)
