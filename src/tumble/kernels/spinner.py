"""The general averaging engine's spinner setting, compiled, for a moment of the body rate only.

:func:`tumble.averaging.spinner_average` averages the slow rates of the standard form (1.3) of
Medvedev (1987) over the fast phases ψ and φ of the unperturbed motion (2.1). A moment of the
body rate only (the built-in constant body moment, linear and quadratic drag, in any sum: the
law (1.2)) does not depend on ψ, so only φ is averaged, on the body rates
w = (a sin φ, a cos φ, c), a = k sin ϑ, c = k cos ϑ/(1 + κ). For these terms the φ-means are
elementary, and this module evaluates them in closed form instead of by quadrature:

    μ3 = sin ϑ X + cos ϑ M3,   μ2 = cos ϑ X − sin ϑ M3,   X = sin φ M1 + cos φ M2,

so only ⟨X⟩ and ⟨M3⟩ are needed, and per term (factor f, ⟨sin²φ⟩ = ½, ⟨|sin φ|³⟩ = 4/(3π),
every odd harmonic and every product odd in sin φ or cos φ averaging to 0):

* constant body moment m: ⟨X⟩ = 0, ⟨M3⟩ = f m3;
* linear drag −B w: ⟨X⟩ = −f a (B11 + B22)/2, ⟨M3⟩ = −f B33 c;
* quadratic drag −S (w ∘ |w|): ⟨X⟩ = −f a|a| (4/(3π)) (S11 + S22), ⟨M3⟩ = −f S33 c|c|.

These are the averages behind (2.2) (there for diagonal B and S); the off-diagonal entries
drop out of the mean. The Python engine computes the same means by Romberg quadrature (its
kinks at φ = 0, π/2, … are nodes); a test holds the two together to its tolerance.

Parameters of ``KIND_SPINNER_AVERAGED``: ``[κ, rtol, torque program]`` (rtol is the Python
engine's and unused here: the means are exact); state ``[k, ρ, σ, ϑ]``.
"""

from __future__ import annotations

import math

from tumble._typing import FloatArray
from tumble.kernels.jit import INLINE, KERNEL, jit
from tumble.kernels.params import SPINNER_AVERAGED
from tumble.kernels.terms import HEAD_SIZE, HEADER, next_term, spinner_of
from tumble.rotations import SINGULAR_SIN

__all__ = ["spinner_averaged"]

_PROGRAM = SPINNER_AVERAGED.size  # index of the torque program in the parameters
_KAPPA = SPINNER_AVERAGED.at.kappa
_HEAD = HEADER.at


@jit(KERNEL)
def _phi_means(p: FloatArray, a: float, c: float) -> tuple[bool, float, float]:
    """(known, ⟨X⟩, ⟨M3⟩) of the program at w = (a sin φ, a cos φ, c) over φ (module notes),
    each term's means from its declaration (:data:`tumble.kernels.terms.spinner_of`); known is
    False for a term without them (not a moment of the body rate)."""
    x, m3 = 0.0, 0.0
    i = _PROGRAM + 1
    for _ in range(int(p[_PROGRAM])):
        f = p[i + _HEAD.factor]
        dx, dm = spinner_of(int(p[i + _HEAD.code]), p, i + HEAD_SIZE, a, c)
        if math.isnan(dx):
            return False, math.nan, math.nan
        x += f * dx
        m3 += f * dm
        i = next_term(p, i)
    return True, x, m3


@jit(INLINE)
def spinner_averaged(t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """The averaged rates (dk/dτ, dρ/dτ, dσ/dτ, dϑ/dτ) = (⟨μ3⟩, 0, 0, ⟨μ2⟩/k) of (1.3) for
    y = [k, ρ, σ, ϑ] under a moment of the body rate only (the factor ε in the program);
    NaN outside the engine's domain (k ≤ 0, sin ρ or sin ϑ below SINGULAR_SIN), so that the
    step is rejected."""
    kappa = p[_KAPPA]
    k, rho, theta = y[0], y[1], y[3]
    st = math.sin(theta)
    ok = k > 0.0 and abs(math.sin(rho)) >= SINGULAR_SIN and abs(st) >= SINGULAR_SIN
    if ok:
        ct = math.cos(theta)
        ok, x, m3 = _phi_means(p, k * st, k * ct / (1.0 + kappa))
    if not ok:
        for j in range(4):
            out[j] = math.nan
        return
    out[0] = st * x + ct * m3
    out[1] = 0.0
    out[2] = 0.0
    out[3] = (ct * x - st * m3) / k
