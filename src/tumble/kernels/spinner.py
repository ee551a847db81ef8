"""The general averaging engine's spinner setting, compiled, for a moment of the body rate only.

:func:`tumble.averaging.spinner_average` averages the slow rates of the standard form (1.3) of
Medvedev (1987) over the fast phases ψ and φ of the unperturbed motion (2.1). A moment of the
body rate only (the built-in constant body moment, linear and quadratic drag, in any sum: the
law (1.2)) does not depend on ψ, so only φ is averaged, on the body rates
w = (k sin ϑ sin φ, k sin ϑ cos φ, k cos ϑ/(1 + κ)). This module computes that φ-mean in
compiled code with the same rule and acceptance test as the Python engine
(:func:`tumble.averaging.quadrature.torus_mean` with Romberg extrapolation: the trapezoidal
means on 16, 32, … up to 16384 nodes), so the two agree to the quadrature's tolerance; a test
holds them to it. The Python engine evaluates the first 512 nodes in one call (one call costs
about as much as a few there); compiled, each doubling is computed only when the last level
has not passed, the tolerance relative to the largest moment met so far (at most the
Python engine's: never a looser test).

Parameters of ``KIND_SPINNER_AVERAGED``: ``[κ, rtol, torque program]``; state ``[k, ρ, σ, ϑ]``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import cast

from numba.cpython.unsafe.tuple import tuple_setitem as _tuple_setitem

from tumble._typing import FloatArray
from tumble.kernels.jit import INLINE, KERNEL, jit
from tumble.kernels.romberg import romberg_weights
from tumble.kernels.torque import _program
from tumble.rotations import SINGULAR_SIN

__all__ = ["spinner_averaged"]

_N_START = 16  # first φ grid (a multiple of 4: the kinks of (1.2) at multiples of π/2 are nodes)
_LEVELS = 11  # 16 … 16384 nodes, the Python engine's limit
_ROMBERG_PREVIOUS = 1e3  # the Romberg test's bound on the previous change, × tol


_W = romberg_weights(_LEVELS)  # a constant of the compiled code

_Table = tuple[float, ...]  # T_j of μ3 at 2j, of μ2 at 2j + 1 (fixed size, no allocation)
_EMPTY = (0.0,) * (2 * _LEVELS)
# numba's tuple "assignment" (a new tuple with one entry replaced): a fixed-size table without
# an allocation, which the right-hand sides may not make.
tuple_setitem = cast(Callable[[_Table, int, float], _Table], _tuple_setitem)


@jit(INLINE)
def _node(
    prog: FloatArray, t: float, kst: float, r: float, ct: float, st: float, cf: float,
    sf: float,
) -> tuple[float, float, float]:  # fmt: skip
    """μ = Rx(ϑ) Rz(φ) m at the node with cos φ = cf, sin φ = sf: the moment turned back by
    ψ (Medvedev (1987), (1.3))."""
    m1, m2, m3 = _program(prog, 2, t, kst * sf, kst * cf, r,
                          (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0))  # fmt: skip
    across = sf * m1 + cf * m2
    return cf * m1 - sf * m2, ct * across - st * m3, st * across + ct * m3


@jit(KERNEL)
def _sums(
    prog: FloatArray, t: float, kst: float, r: float, ct: float, st: float, n: int,
    offset: float,
) -> tuple[float, float, float]:  # fmt: skip
    """Σ μ3, Σ μ2 over φ = (j + offset) 2π/n, j < n (n a multiple of 4), and the largest
    |μ_i| there. The nodes j, j + n/4, j + n/2, j + 3n/4 are a quarter turn apart: one
    cosine and sine serve all four."""
    s3, s2, big = 0.0, 0.0, 0.0
    step = 2.0 * math.pi / n
    for j in range(n // 4):
        phi = (j + offset) * step
        c, s = math.cos(phi), math.sin(phi)
        for cf, sf in ((c, s), (-s, c), (-c, -s), (s, -c)):
            mu1, mu2, mu3 = _node(prog, t, kst, r, ct, st, cf, sf)
            s3 += mu3
            s2 += mu2
            big = max(big, abs(mu1), abs(mu2), abs(mu3))
    return s3, s2, big


@jit(INLINE)
def _romberg(T: _Table, j: int, c: int) -> float:
    """D_j = R(j, j) of component c (0: μ3, 1: μ2)."""
    out = 0.0
    for i in range(j + 1):
        out += _W[j, i] * T[2 * i + c]
    return out


@jit(KERNEL)
def _accepted(
    T: _Table, j: int, levels: int, rtol: float, atol: float
) -> tuple[bool, float, float]:
    """Whether level j passes the test of the Python engine (``_first_accepted``), and the
    accepted means of μ3 and μ2 (the plain one first, else the extrapolated one)."""
    t3, t2 = T[2 * j], T[2 * j + 1]
    tol = atol + rtol * max(abs(t3), abs(t2))
    plain = max(abs(t3 - T[2 * j - 2]), abs(t2 - T[2 * j - 1])) <= tol
    if plain:
        return True, t3, t2
    if levels > 2 and j >= 2:
        d3, d2 = _romberg(T, j, 0), _romberg(T, j, 1)
        p3, p2 = _romberg(T, j - 1, 0), _romberg(T, j - 1, 1)
        q3, q2 = _romberg(T, j - 2, 0), _romberg(T, j - 2, 1)
        change = max(abs(d3 - p3), abs(d2 - p2))
        before = max(abs(p3 - q3), abs(p2 - q2))
        if change <= tol and before <= _ROMBERG_PREVIOUS * tol:
            return True, d3, d2
    return False, t3, t2


@jit(KERNEL)
def _phi_mean(
    prog: FloatArray, t: float, kst: float, r: float, ct: float, st: float, rtol: float
) -> tuple[bool, float, float]:
    """(converged, ⟨μ3⟩, ⟨μ2⟩) over φ (module notes): one doubling at a time, each level
    tested as it comes, with the tolerance relative to the largest |μ| met so far."""
    T: _Table = _EMPTY
    s3, s2, big = _sums(prog, t, kst, r, ct, st, _N_START, 0.0)
    T = tuple_setitem(T, 0, s3 / _N_START)
    T = tuple_setitem(T, 1, s2 / _N_START)
    n = _N_START
    for level in range(1, _LEVELS):
        a3, a2, b = _sums(prog, t, kst, r, ct, st, n, 0.5)
        big = max(big, b)
        T = tuple_setitem(T, 2 * level, 0.5 * (T[2 * level - 2] + a3 / n))
        T = tuple_setitem(T, 2 * level + 1, 0.5 * (T[2 * level - 1] + a2 / n))
        n *= 2
        ok, m3, m2 = _accepted(T, level, level + 1, rtol, rtol * big)
        if ok:
            return True, m3, m2
    return False, math.nan, math.nan


@jit(INLINE)
def spinner_averaged(t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """The averaged rates (dk/dτ, dρ/dτ, dσ/dτ, dϑ/dτ) = (⟨μ3⟩, 0, 0, ⟨μ2⟩/k) of (1.3) for
    y = [k, ρ, σ, ϑ] under a moment of the body rate only (the factor ε in the program);
    NaN outside the engine's domain (k ≤ 0, sin ρ or sin ϑ below SINGULAR_SIN) or where the
    quadrature does not converge, so that the step is rejected."""
    kappa, rtol = p[0], p[1]
    k, rho, theta = y[0], y[1], y[3]
    st = math.sin(theta)
    ok = k > 0.0 and abs(math.sin(rho)) >= SINGULAR_SIN and abs(st) >= SINGULAR_SIN
    if ok:
        ct = math.cos(theta)
        ok, m3, m2 = _phi_mean(p, t, k * st, k * ct / (1.0 + kappa), ct, st, rtol)
    if not ok:
        for j in range(4):
            out[j] = math.nan
        return
    out[0] = m3
    out[1] = 0.0
    out[2] = 0.0
    out[3] = m2 / k
