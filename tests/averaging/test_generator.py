"""The first-order generator w₁ by FFT against closed forms, and its small divisors."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tumble.averaging.generator import SmallDivisorError, zero_mean_antiderivative
from tumble.errors import ParameterError


def _grid(*sizes):
    return np.meshgrid(*(2 * np.pi * np.arange(n) / n for n in sizes), indexing="ij")


def test_one_phase_against_the_closed_form():
    (phi,) = _grid(32)
    f = 3.0 + np.cos(phi) + 0.5 * np.sin(3 * phi)
    nu = 2.0
    w = zero_mean_antiderivative(f, [nu])
    exact = (np.sin(phi) - 0.5 / 3.0 * np.cos(3 * phi)) / nu
    # A trigonometric polynomial the grid resolves: exact to round-off (a few ulps of 1/ν).
    assert np.max(np.abs(w - exact)) < 1e-14


def test_two_phases_and_components_against_the_closed_form():
    a, b = _grid(16, 8)
    nu = np.array([1.0, 0.3])
    f = np.stack([np.cos(a - 2 * b), np.sin(a) * np.cos(b) + 0.2])
    w = zero_mean_antiderivative(f, nu)
    # sin a cos b = (sin(a + b) + sin(a − b))/2; k·ν = 1 − 0.6, 1 + 0.3, 1 − 0.3.
    exact = np.stack(
        [
            np.sin(a - 2 * b) / 0.4,
            -0.5 * (np.cos(a + b) / 1.3 + np.cos(a - b) / 0.7),
        ]
    )
    assert np.max(np.abs(w - exact)) < 1e-13  # divisors down to 0.4: a few ulps of 2.5


@settings(max_examples=30, deadline=None)
@given(
    nu=st.tuples(st.floats(0.3, 3.0), st.floats(-2.0, 2.0)),
    coef=st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4),
)
def test_the_generator_solves_its_equation(nu, coef):
    # ν·∂w/∂φ = f − ⟨f⟩, with the derivative taken spectrally, for smooth f on 2 phases
    # (non-resonant: |k·ν| ≥ 0.1 for the harmonics below, else the case is skipped).
    a, b = _grid(32, 32)
    f = (coef[0] * np.exp(np.cos(a)) + coef[1] * np.sin(a + b) + coef[2] * np.cos(2 * b)
         + coef[3] * np.sin(a - b))  # fmt: skip
    k = [(1, 0), (2, 0), (3, 0), (1, 1), (0, 2), (1, -1)]
    if min(abs(i * nu[0] + j * nu[1]) for i, j in k) < 0.1:
        return
    w = zero_mean_antiderivative(f, nu)
    kw = np.meshgrid(np.fft.fftfreq(32) * 32, np.fft.fftfreq(32) * 32, indexing="ij")
    dw = np.fft.ifft2(1j * (kw[0] * nu[0] + kw[1] * nu[1]) * np.fft.fft2(w)).real
    # exp(cos a) has harmonics decaying like 1/(k! 2^k): resolved to round-off on 32 nodes;
    # the residual is round-off times the largest 1/|k·ν| (≤ 10).
    assert np.max(np.abs(dw - (f - f.mean()))) < 1e-12
    assert abs(w.mean()) < 1e-14


def test_a_resonant_harmonic_is_reported_not_divided_by():
    a, b = _grid(16, 16)
    f = np.cos(a - 2 * b) + np.cos(a)
    with pytest.raises(SmallDivisorError, match=r"k = \((1, -2|-1, 2)\).*resonance"):
        zero_mean_antiderivative(f, [1.0, 0.5])  # 1·1 − 2·0.5 = 0
    # The same frequencies with that harmonic absent: no divisor to fear.
    w = zero_mean_antiderivative(np.cos(a), [1.0, 0.5])
    assert np.max(np.abs(w - np.sin(a))) < 1e-14


def test_a_resonant_harmonic_below_the_floor_is_dropped_not_reported():
    # 1e-9 of the largest (below RESONANT_FLOOR, which the resonance table gives no band):
    # at its exact resonance its term is dropped, and w is that of the rest to the size of
    # the dropped oscillation.
    a, b = _grid(16, 16)
    w = zero_mean_antiderivative(np.cos(a) + 1e-9 * np.cos(a - 2 * b), [1.0, 0.5])
    assert np.max(np.abs(w - np.sin(a))) < 1e-14
    with pytest.raises(SmallDivisorError):  # at the floor's thousandfold it is reported
        zero_mean_antiderivative(np.cos(a) + 1e-3 * np.cos(a - 2 * b), [1.0, 0.5])


def test_bad_input_is_refused():
    with pytest.raises(ParameterError, match="phases"):
        zero_mean_antiderivative(np.zeros(8), [1.0, 2.0])
    with pytest.raises(ParameterError, match="finite"):
        zero_mean_antiderivative(np.full(8, np.nan), [1.0])


@pytest.mark.parametrize("n", [7, 8, 33])
def test_one_phase_by_the_real_transform_equals_the_torus_path(n):
    # One turning phase takes the real transform's half; the same grid as a torus whose
    # second phase has one node (k₂ = 0 only) takes the general path: equal to round-off,
    # odd and even n (the Nyquist harmonic dropped by both), with leading components.
    rng = np.random.default_rng(n)
    f = rng.normal(size=(3, n))
    one = zero_mean_antiderivative(f, [1.7])
    torus = zero_mean_antiderivative(f[..., None], [1.7, 1.0])[..., 0]
    assert np.max(np.abs(one - torus)) < 1e-15 * n  # measured ≤ 2.2e-16


def test_one_phase_at_rest_is_a_small_divisor():
    # ν = 0: every harmonic present is resonant (the general path judges it, as on a torus).
    (phi,) = _grid(16)
    with pytest.raises(SmallDivisorError, match=r"k = \((1|-1),\)"):
        zero_mean_antiderivative(np.cos(phi), [0.0])
