"""Elliptic integrals of the third kind (tumble.unperturbed.elliptic) against quadrature."""

import itertools
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import special
from scipy.integrate import quad

from tumble.errors import ParameterError
from tumble.unperturbed import ellippi, ellippi_inc

HALF_PI = 0.5 * math.pi
# quad is asked for 1e-13 relative on each smooth piece between multiples of π/2; the
# Carlson forms are accurate to a few ulps. 1e-12 leaves a margin of 10 over quad.
RTOL = 1e-12


def pi_quad(n, phi, m):
    """Π(n; φ | m) by adaptive quadrature, split at the multiples of π/2 (peaks for m ≈ 1).

    1 − m sin²θ is written cos²θ + (1 − m) sin²θ: the plain form loses digits near m = 1
    and would make the reference, not the function under test, the inaccurate one.
    """
    mc = 1.0 - m

    def f(t):
        s2 = math.sin(t) ** 2
        return 1.0 / ((1.0 - n * s2) * math.sqrt(math.cos(t) ** 2 + mc * s2))

    edges = [*np.arange(0.0, abs(phi), HALF_PI), abs(phi)]
    total = sum(
        quad(f, a, b, epsabs=0.0, epsrel=1e-13, limit=200)[0] for a, b in itertools.pairwise(edges)
    )
    return math.copysign(total, phi)


N_VALUES = [-40.0, -2.5, -0.3, 0.0, 0.4, 0.95]
M_VALUES = [0.0, 0.3, 0.8, 0.999, 1.0 - 1e-8]
PHI_VALUES = [0.3, -1.1, HALF_PI, 1.9, -3.5, 7.7, 31.0]


@pytest.mark.parametrize("n", N_VALUES)
@pytest.mark.parametrize("m", M_VALUES)
def test_incomplete_pi_matches_quadrature(n, m):
    phi = np.array(PHI_VALUES)
    got = ellippi_inc(n, phi, m)  # vectorized over φ
    ref = np.array([pi_quad(n, p, m) for p in PHI_VALUES])
    assert np.allclose(got, ref, rtol=RTOL, atol=0.0)


@pytest.mark.parametrize("n", N_VALUES)
@pytest.mark.parametrize("m", M_VALUES)
def test_complete_pi_matches_quadrature_and_half_period(n, m):
    assert ellippi(n, m) == pytest.approx(pi_quad(n, HALF_PI, m), rel=RTOL)
    # Quasi-periodicity: Π(n; φ + π | m) − Π(n; φ | m) = 2 Π(n | m). Both sides are sums of
    # O(1) values accurate to a few ulps.
    assert float(ellippi_inc(n, 2.2 + math.pi, m) - ellippi_inc(n, 2.2, m)) == pytest.approx(
        2.0 * float(ellippi(n, m)), rel=1e-13
    )


def test_reduces_to_first_kind_and_elementary_forms():
    phi = np.linspace(-9.0, 9.0, 37)
    # n = 0: Π = F, scipy's ellipkinc (Cephes, any φ) is an independent implementation.
    assert np.allclose(ellippi_inc(0.0, phi, 0.6), special.ellipkinc(phi, 0.6), rtol=1e-13)
    # m = 0, n < 0: Π = atan(sqrt(1 − n) tan φ)/sqrt(1 − n) on the continuous branch.
    n = -3.0
    a = math.sqrt(1.0 - n)
    elementary = (np.arctan(a * np.tan(phi)) + math.pi * np.rint(phi / math.pi)) / a
    assert np.allclose(ellippi_inc(n, phi, 0.0), elementary, rtol=1e-13, atol=1e-15)


def test_singular_edges_inside_the_domain():
    # n = 1 and m = 1 are allowed below π/2: finite, and match quadrature.
    assert float(ellippi_inc(1.0, 1.2, 0.5)) == pytest.approx(pi_quad(1.0, 1.2, 0.5), rel=RTOL)
    assert float(ellippi_inc(-2.0, 1.4, 1.0)) == pytest.approx(pi_quad(-2.0, 1.4, 1.0), rel=RTOL)
    # m = 1 closed form: Π(n; φ | 1) = [artanh(sin φ) + b atan(b sin φ)]/(1 − n), n = −b².
    b = 1.5
    s = math.sin(1.4)
    closed = (math.atanh(s) + b * math.atan(b * s)) / (1.0 + b * b)
    assert float(ellippi_inc(-b * b, 1.4, 1.0)) == pytest.approx(closed, rel=1e-14)


@given(
    st.floats(-50.0, 0.99),
    st.floats(-40.0, 40.0),
    st.floats(0.0, 0.999),
)
def test_odd_in_phi_and_monotone(n, phi, m):
    # The integrand is positive, so Π is odd and increasing in φ. Oddness holds to round-off
    # of the reduction φ − jπ (|φ| ulps), relative to the value.
    v = float(ellippi_inc(n, phi, m))
    assert float(ellippi_inc(n, -phi, m)) == pytest.approx(-v, rel=1e-13, abs=1e-300)
    assert float(ellippi_inc(n, phi + 0.01, m)) > v


@pytest.mark.parametrize(
    "args, match",
    [
        ((1.5, 0.3, 0.5), "n = 1.5"),
        ((0.3, 0.3, -0.1), "m = -0.1"),
        ((0.3, 0.3, 1.2), "m = 1.2"),
        ((1.0, 2.0, 0.5), "phi"),
        ((0.3, 2.0, 1.0), "phi"),
        ((math.nan, 0.3, 0.5), "n = nan"),
        ((0.3, math.inf, 0.5), "phi = inf"),
    ],
)
def test_outside_the_domain_raises(args, match):
    with pytest.raises(ParameterError, match=match):
        ellippi_inc(*args)


def test_complete_outside_the_domain_raises():
    with pytest.raises(ParameterError, match="n = 1"):
        ellippi(1.0, 0.5)
    with pytest.raises(ParameterError, match="m = 1"):
        ellippi(0.5, 1.0)


def test_broadcasting_and_shapes():
    out = ellippi_inc(np.array([[-1.0], [0.5]]), np.array([0.2, 3.0, -7.0]), 0.4)
    assert out.shape == (2, 3)
    assert np.all(np.isfinite(out))
    assert np.asarray(ellippi_inc(0.1, 0.2, 0.3)).shape == ()
