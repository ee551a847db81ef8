"""The compiled Carlson integrals against scipy.special and against a 50-digit evaluation of
the same definitions (Python's decimal): R_F, R_D, R_C and K, E to 1e-14 of scipy; R_J to
4e-15 of the 50-digit values (scipy's own R_J is measured off by up to 1.7e-14 on the
arguments of a complete Π and by 1e-11 where p ≪ x, y, z)."""

from __future__ import annotations

from decimal import Decimal, localcontext

import numpy as np
import pytest
import scipy.special as sp

from tumble.kernels.elliptic import evaluate_carlson

RF, RD, RJ, RC1, K, E, PI = range(7)
RNG = np.random.default_rng(19)
N = 4000


def _relative(ours: np.ndarray, reference: np.ndarray) -> float:
    return float(np.max(np.abs(ours - reference) / np.abs(reference)))


def _wide(n: int) -> np.ndarray:
    """Arguments over 16 decades, one in seven with x = 0 (the complete integrals' case)."""
    X = 10.0 ** RNG.uniform(-8.0, 8.0, (n, 4))
    X[::7, 0] = 0.0
    return X


def test_rf_rd_against_scipy():
    X = _wide(N)
    # Both evaluate the duplication and a series to round-off: a few ulp (measured 8e-16).
    assert _relative(evaluate_carlson(RF, X), sp.elliprf(*X[:, :3].T)) < 1e-14
    assert _relative(evaluate_carlson(RD, X), sp.elliprd(*X[:, :3].T)) < 1e-14


def test_rc_against_scipy_including_e_below_round_off():
    e = np.concatenate(
        [
            10.0 ** RNG.uniform(-20, 3, N),
            -RNG.uniform(0.0, 0.99, N),
            -(10.0 ** RNG.uniform(-20, -1, N)),
        ]
    )
    # scipy takes 1 + e, rounded: where that rounding matters R_C ≈ 1 − e/3 does not feel it.
    assert _relative(evaluate_carlson(RC1, e[:, None]), sp.elliprc(1.0, 1.0 + e)) < 1e-14


def test_rc_near_its_logarithmic_end_against_fifty_digits():
    """e → −1 (p ≪ x, y, z in R_J): R_C grows like log; against 50 digits, not scipy (which
    differs by up to 2e-14 there)."""
    e = -(1.0 - 10.0 ** RNG.uniform(-12, -2, 200))
    with localcontext() as ctx:
        ctx.prec = 50
        exact = np.array([float(_rc_exact(Decimal(float(v)))) for v in e])
    # A logarithm and a square root of exactly given arguments: a few ulp (measured 2e-16).
    assert _relative(evaluate_carlson(RC1, e[:, None]), exact) < 2e-15


def test_k_and_e_against_scipy_up_to_the_separatrix():
    mc = np.concatenate([10.0 ** RNG.uniform(-15, 0, N), RNG.uniform(0.0, 1.0, N)])
    assert _relative(evaluate_carlson(K, mc[:, None]), sp.ellipkm1(mc)) < 1e-14
    # E(m) from scipy at m = 1 − mc carries the rounding of m: ≤ 1 ulp of m, times
    # |dE/dm|·m/E ≤ ~10 at mc ≥ 1e-15.
    assert _relative(evaluate_carlson(E, mc[:, None]), sp.ellipe(1.0 - mc)) < 3e-14


def _rc_exact(e: Decimal) -> Decimal:
    x, y = Decimal(1), 1 + e
    while abs(x - y) > Decimal("1e-45") * y:
        lam = 2 * x.sqrt() * y.sqrt() + y
        x, y = (x + lam) / 4, (y + lam) / 4
    return 1 / ((x + 2 * y) / 3).sqrt()


def _rj_exact(*args: float) -> float:
    """R_J by duplication carried to 50 digits (DLMF 19.36.3 without the series)."""
    with localcontext() as ctx:
        ctx.prec = 50
        x, y, z, p = (Decimal(float(v)) for v in args)
        delta = (p - x) * (p - y) * (p - z)
        total, scale = Decimal(0), Decimal(1)
        while True:
            a = (x + y + z + 2 * p) / 5
            if max(abs(a - x), abs(a - y), abs(a - z), abs(a - p)) < Decimal("1e-40") * a:
                return float(scale / (a * a.sqrt()) + 6 * total)
            sx, sy, sz, sp_ = x.sqrt(), y.sqrt(), z.sqrt(), p.sqrt()
            lam = sx * sy + sx * sz + sy * sz
            d = (sp_ + sx) * (sp_ + sy) * (sp_ + sz)
            total += scale / d * _rc_exact(delta * scale**3 / (d * d))
            x, y, z, p = (x + lam) / 4, (y + lam) / 4, (z + lam) / 4, (p + lam) / 4
            scale /= 4


@pytest.mark.parametrize("domain", ["wide", "complete"])
def test_rj_against_fifty_digits(domain):
    n = 150  # each 50-digit reference costs ~1 ms
    if domain == "wide":
        X = _wide(n)
    else:  # R_J(0, mc, 1, 1 − n): the complete Π of every characteristic n < 1
        X = np.column_stack([np.zeros(n), 10.0 ** RNG.uniform(-12, 0, n), np.ones(n),
                             10.0 ** RNG.uniform(-6, 3, n)])  # fmt: skip
    exact = np.array([_rj_exact(*row) for row in X])
    # ~10 duplications and a series, each step rounding a few times: measured ≤ 1.6e-15.
    assert _relative(evaluate_carlson(RJ, X), exact) < 4e-15


def test_complete_pi_is_rf_plus_rj():
    n_ = np.concatenate([-(10.0 ** RNG.uniform(-3, 3, N)), RNG.uniform(-1.0, 1.0 - 1e-6, N)])
    mc = 10.0 ** RNG.uniform(-12, 0, n_.size)
    ours = evaluate_carlson(PI, np.column_stack([n_, mc]))
    parts = evaluate_carlson(RF, np.column_stack([0 * mc, mc, 1 + 0 * mc])) + n_ / 3 * (
        evaluate_carlson(RJ, np.column_stack([0 * mc, mc, 1 + 0 * mc, 1 - n_]))
    )
    # The definition, evaluated by the same code compiled in another context (fastmath may
    # reassociate differently): a few ulp of the larger term (for n ≪ 0 the two terms cancel).
    scale = np.abs(parts) + np.abs(n_ / 3) * evaluate_carlson(
        RJ, np.column_stack([0 * mc, mc, 1 + 0 * mc, 1 - n_])
    )
    assert np.max(np.abs(ours - parts) / scale) < 1e-15
    # Against scipy's terms: scipy's R_J is off by up to 1.7e-14 here (see the module note).
    reference = sp.elliprf(0.0, mc, 1.0) + n_ / 3 * sp.elliprj(0.0, mc, 1.0, 1.0 - n_)
    assert np.max(np.abs(ours - reference) / scale) < 5e-14
