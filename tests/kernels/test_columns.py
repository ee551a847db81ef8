"""The compiled columns of the vector form [L_ξ, r] against numpy: L, ρ, σ, T and k² as
tumble.unperturbed.modulus_squared_of_ratio gives it, in every regime, on the separatrix band,
for symmetric bodies and on the ξ3 axis."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from tumble.kernels.codes import SEPARATRIX_RTOL
from tumble.kernels.columns import VECTOR_COLUMNS, vector_columns
from tumble.unperturbed import modulus_squared_of_ratio

# Round-off of a few operations on numbers of order one (the compiled code may contract a
# product and a sum into one fused operation where numpy rounds twice).
CLOSE = 1e-13


def _numpy_columns(Y, inertia, sigma0):
    L = np.sqrt(np.sum(Y[:, :3] ** 2, axis=1))
    perp = np.hypot(Y[:, 0], Y[:, 1])
    raw = np.where(perp > 0.0, np.arctan2(Y[:, 1], Y[:, 0]), sigma0)
    return {
        "L": L,
        "rho": np.arctan2(perp, Y[:, 2]),
        "sigma": sigma0 + (np.mod(raw - sigma0 + math.pi, 2.0 * math.pi) - math.pi),
        "T": 0.5 * Y[:, 3] * L * L,
        "k2": modulus_squared_of_ratio(*inertia, Y[:, 3]),
    }


def _compiled(Y, inertia, symmetric, sigma0):
    table = vector_columns(np.ascontiguousarray(Y), *inertia, symmetric, sigma0)
    return dict(zip(VECTOR_COLUMNS, table.T, strict=True))


@settings(max_examples=60, deadline=None)
@given(
    gaps=st.tuples(st.floats(0.05, 2.0), st.floats(0.05, 2.0)),
    sigma0=st.floats(-4.0, 4.0),
    seed=st.integers(0, 2**31),
)
def test_vector_columns_are_numpys(gaps, sigma0, seed):
    inertia = (1.0, 1.0 + gaps[0], 1.0 + gaps[0] + gaps[1])
    rng = np.random.default_rng(seed)
    n = 64
    Y = np.empty((n, 4))
    Y[:, :3] = rng.normal(size=(n, 3))
    Y[:8, :2] = 0.0  # on the ξ3 axis: no azimuth, the initial one
    # r over [1/I3, 1/I1] with the ends, the separatrix and its band's edges among them
    i1, i2, i3 = inertia
    r = rng.uniform(1.0 / i3, 1.0 / i1, n)
    r[:6] = ((1.0 - SEPARATRIX_RTOL) / i2, (1.0 + SEPARATRIX_RTOL) / i2, 1.0 / i3, 1.0 / i1,
             1.0 / i2, (1.0 - 1e-9) / i2)  # fmt: skip
    Y[:, 3] = r
    got, expected = _compiled(Y, inertia, False, sigma0), _numpy_columns(Y, inertia, sigma0)
    for name in VECTOR_COLUMNS:
        assert np.allclose(got[name][4:], expected[name][4:], rtol=CLOSE, atol=CLOSE), name
    # At the separatrix band's edges the rounding of 1 − r·I2 decides whether a state is on
    # the separatrix (k² = 1) or beside it (k² = 1 − O(the band's width)): the two may differ
    # there by that much, and agree elsewhere to round-off.
    assert np.allclose(got["k2"][:4], expected["k2"][:4], rtol=0.0, atol=1e-10)
    assert np.all(np.abs(got["sigma"] - sigma0) <= math.pi + CLOSE)
    assert np.all(got["sigma"][:8] == sigma0)


def test_a_symmetric_body_has_no_modulus():
    Y = np.array([[0.3, 0.4, 1.0, 0.8], [0.0, 0.0, -1.0, 0.5]])
    got = _compiled(Y, (1.0, 1.0, 2.0), True, 0.7)
    assert np.array_equal(got["k2"], [0.0, 0.0])
    assert np.array_equal(modulus_squared_of_ratio(1.0, 1.0, 2.0, Y[:, 3]), [0.0, 0.0])
    assert got["sigma"][1] == 0.7 and abs(got["sigma"][0] - math.atan2(0.4, 0.3)) < CLOSE
    assert vector_columns(np.empty((0, 4)), 1.0, 1.5, 2.0, False, 0.0).shape == (0, 5)
