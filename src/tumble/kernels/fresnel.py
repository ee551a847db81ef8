"""The inner solution of a passage through a stopped phase, compiled: the sum over the
harmonics of Fresnel integrals near the passage and of their expansion away from it
(:mod:`tumble.models.resisting_medium.passage`), per sample.

The Fresnel integrals C(x) = ∫₀ˣ cos(πt²/2) dt and S(x) = ∫₀ˣ sin(πt²/2) dt are scipy's
(``scipy.special.fresnel``) on a table of x ∈ [0, :data:`TABLE_END`], interpolated by cubic
Hermite polynomials with their exact derivatives cos(πx²/2) and sin(πx²/2): the error is
below (Δx)⁴/384 · max|d⁴C/dx⁴|, about (πx)³(Δx)⁴/384, 7e-11 at x = 4 for Δx = 1/512 (a test
holds it to scipy within 1e-9).
Compiled code cannot call scipy and still be cached (see :mod:`tumble.kernels.elliptic`), so
the table is computed once, in Python, and handed in.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from tumble._typing import ComplexArray, FloatArray
from tumble.kernels.jit import ENTRY, KERNEL, jit

__all__ = ["BLEND", "TABLE_END", "fresnel_table", "interpolated_fresnel", "passage_sum"]

TABLE_END = 4.0
"""The largest x the table covers: the inner formula is used below it (the caller's switch
must not exceed it)."""
_PER_UNIT = 512


@functools.cache
def fresnel_table() -> tuple[FloatArray, FloatArray]:
    """S and C of scipy on x = 0, 1/512, …, :data:`TABLE_END`."""
    from scipy.special import fresnel

    x = np.linspace(0.0, TABLE_END, int(TABLE_END * _PER_UNIT) + 1)
    s, c = fresnel(x)
    return np.ascontiguousarray(s), np.ascontiguousarray(c)


@jit(KERNEL)
def _fresnel(x: float, s_tab: FloatArray, c_tab: FloatArray) -> tuple[float, float]:
    """(S(x), C(x)) for |x| ≤ TABLE_END by cubic Hermite interpolation of the tables."""
    a = abs(x)
    h = 1.0 / _PER_UNIT
    i = min(int(a * _PER_UNIT), s_tab.size - 2)
    t = (a - i * h) / h
    x0, x1 = i * h, (i + 1) * h
    d0c, d1c = math.cos(0.5 * math.pi * x0 * x0), math.cos(0.5 * math.pi * x1 * x1)
    d0s, d1s = math.sin(0.5 * math.pi * x0 * x0), math.sin(0.5 * math.pi * x1 * x1)
    t2, t3 = t * t, t * t * t
    h00, h10 = 2.0 * t3 - 3.0 * t2 + 1.0, t3 - 2.0 * t2 + t
    h01, h11 = -2.0 * t3 + 3.0 * t2, t3 - t2
    s = h00 * s_tab[i] + h10 * h * d0s + h01 * s_tab[i + 1] + h11 * h * d1s
    c = h00 * c_tab[i] + h10 * h * d0c + h01 * c_tab[i + 1] + h11 * h * d1c
    if x < 0.0:
        return -s, -c
    return s, c


@jit(ENTRY)
def interpolated_fresnel(
    x: FloatArray, s_tab: FloatArray, c_tab: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """(S, C) at each of ``x`` (|x| ≤ TABLE_END) from the tables: for tests."""
    s, c = np.empty(x.size), np.empty(x.size)
    for j in range(x.size):
        s[j], c[j] = _fresnel(x[j], s_tab, c_tab)
    return s, c


BLEND = 0.5
"""Within this many Fresnel units of the first harmonic u is the time from the passage, not
the phase's: there ½φ̈u² is of the size of the phase's own error (the integration's, ~1e-10
of a phase of 1e4 rad), which the square root and 1/u would magnify (the two agree to
(φ⃛/6φ̈)·u relative, below 1e-3 there). And the tail term (1/Ω − 1/(φ̈u)), finite at u = 0
but the difference of two rates that vanish there, is left out: it tends to
−φ⃛/(3φ̈²) = −β(1+κ)/(3κ a3) for the law (1.2), O(1), so leaving it out errs by that times
|h_n|/n, O(ε) with a small constant, where keeping it would magnify any offset δτ between the
run's stationary point and the step's as δτ/(φ̈u²)."""


@jit(ENTRY)
def passage_sum(
    s: FloatArray,
    rel: FloatArray,
    omega: FloatArray,
    orders: FloatArray,
    weights: ComplexArray,
    accel: float,
    switch: float,
    s_tab: FloatArray,
    c_tab: FloatArray,
) -> ComplexArray:
    """η = Σ_k weights_k · G_{n_k} at each sample, n_k = ``orders[k]``, with ``s`` the time
    from the passage, ``rel`` the mean phase less its value there and ``omega`` its rate
    (Medvedev (1987), (1.3) averaged); u with ½φ̈u² = rel, signed as s (or s itself within
    :data:`BLEND` units); and, for a = nφ̈, σ = sgn a, x = |u| √(|a|/π):

    * for x < ``switch``: G = √(π/|a|) [(½ + C(x')) + iσ(½ + S(x')) − H(u)(1 + iσ)]
      + (1/Ω − 1/(φ̈u)) e^{in·rel}/(in), x' = u √(|a|/π) signed, the last term beyond
      :data:`BLEND` units only;
    * beyond: G = e^{in·rel} [1/(inΩ) − 1/(n²φ̈²u³)], the expansion of the same."""
    out = np.zeros(s.size, dtype=np.complex128)
    root = math.sqrt(abs(accel) / math.pi)
    K = orders.size
    power = np.empty(K, dtype=np.int64)  # |n|
    xn_per_u = np.empty(K)  # x = |u| √(|a|/π) per unit |u|
    for k in range(K):
        power[k] = int(abs(orders[k]))
        xn_per_u[k] = root * math.sqrt(abs(orders[k]))
    for j in range(s.size):
        om = omega[j]
        uj = math.copysign(math.sqrt(max(2.0 * rel[j] / accel, 0.0)), s[j])
        near = abs(s[j]) * root < BLEND
        if near:
            uj = s[j]
        # e^{in·rel} as a power of e^{i·rel}: one cosine and sine per sample, not per term.
        c1, s1 = math.cos(rel[j]), math.sin(rel[j])
        total = 0.0 + 0.0j
        for k in range(K):
            n = orders[k]
            turn = _power(c1, s1, power[k])
            if n < 0.0:
                turn = turn.conjugate()
            xn = abs(uj) * xn_per_u[k]
            if xn < switch:
                sigma = 1.0 if n * accel > 0.0 else -1.0
                scale = 1.0 / xn_per_u[k]  # √(π/|nφ̈|)
                sv, cv = _fresnel(uj * xn_per_u[k], s_tab, c_tab)
                g = complex(0.5 + cv, sigma * (0.5 + sv))
                if uj >= 0.0:
                    g -= complex(1.0, sigma)
                g *= scale
                if not near:  # + (1/Ω − 1/(φ̈u)) e^{in·rel}/(in)
                    g += turn * complex(0.0, -(1.0 / om - 1.0 / (accel * uj)) / n)
            else:  # e^{in·rel} [1/(inΩ) − 1/(n²φ̈²u³)]
                g = turn * complex(-1.0 / (n * n * accel * accel * uj**3), -1.0 / (n * om))
            total += weights[k] * g
        out[j] = total
    return out


@jit(KERNEL)
def _power(c: float, s: float, n: int) -> complex:
    """(c + is)ⁿ for n ≥ 0 by repeated squaring. For c + is = e^{ix} rounded, its error is
    about (n + log₂ n) ε_machine; cos(n·x) and sin(n·x) would err by |n·x| ε_machine (the
    rounding of n·x), more for a phase x of many turns."""
    re, im = 1.0, 0.0
    br, bi = c, s
    while n > 0:
        if n & 1:
            re, im = re * br - im * bi, re * bi + im * br
        n >>= 1
        if n:
            br, bi = br * br - bi * bi, 2.0 * br * bi
    return complex(re, im)
