"""The closed-form Euler–Poinsot average (``KIND_TRIAXIAL_CLOSED`` of the compiled triaxial
engine) against the same average by quadrature (``KIND_TRIAXIAL_PHASE_MEANS``), and its polhode
means against direct quadrature."""

from __future__ import annotations

import math

import numpy as np
import pytest
from closed_forms import closed_and_quadrature
from scipy import special

from tumble.averaging import triaxial_kernel
from tumble.kernels import KIND_TRIAXIAL_PHASE_MEANS
from tumble.kernels.triaxial_closed import polhode_moments, sn_means
from tumble.space.torques import FieldMomentsTorque, GravityMomentsTorque
from tumble.torques import (
    ConstantBodyTorque,
    ConstantInertialTorque,
    GravityGradientTorque,
    InternalDissipation,
    LinearDrag,
    QuadraticDrag,
)

INERTIA = np.array([2.0, 3.1, 1.2])  # unsorted on purpose: the kernel reads them through Q


def _spd(rng: np.random.Generator) -> np.ndarray:
    a = rng.normal(size=(3, 3))
    return a @ a.T


def _amplitudes(inertia: np.ndarray, L: float, r: float) -> tuple[bool, float, tuple[float, ...]]:
    """The regime, mc and the body rate's amplitudes as the compiled engine forms them."""
    i1, i2, i3 = inertia
    d1, d2, d3 = 1.0 - r * i1, 1.0 - r * i2, r * i3 - 1.0
    if d2 > 0.0:
        mc = (i3 - i1) * d2 / ((i3 - i2) * d1)
        amp = (L * math.sqrt(d3 / (i1 * (i3 - i1))), L * math.sqrt(d3 / (i2 * (i3 - i2))),
               L * math.sqrt(d1 / (i3 * (i3 - i1))))  # fmt: skip
        return True, mc, amp
    mc = -(i3 - i1) * d2 / ((i2 - i1) * d3)
    amp = (L * math.sqrt(d1 / (i3 * (i3 - i1))), L * math.sqrt(d1 / (i2 * (i2 - i1))),
           L * math.sqrt(d3 / (i1 * (i3 - i1))))  # fmt: skip
    return False, mc, amp


@pytest.mark.parametrize("mc", [1.0, 1.0 - 1e-12, 1.0 - 1e-6, 0.75, 0.5, 1e-3, 1e-9])
def test_sn_means_equal_scipys_integrals(mc):
    m = 1.0 - mc
    K = float(special.elliprf(0.0, mc, 1.0))
    # ⟨sn²⟩ = (K − E)/(mK) = R_D(0, mc, 1)/(3K) (DLMF 19.25.1), which holds at m → 0 too;
    # ⟨sn⁴⟩ from the recurrence where it does not cancel, else from the series
    # (∫₀ᴷ sn⁴ du)/K = (3/8 + 5m/32 + …)/(1 + m/4 + …) = 3/8 + m/16 + O(m²).
    x1 = float(special.elliprd(0.0, mc, 1.0)) / (3.0 * K)
    x2 = (2.0 * (1.0 + m) * x1 - 1.0) / (3.0 * m) if m > 0.1 else 3.0 / 8.0 + m / 16.0
    got = sn_means(mc)
    assert abs(got[0] - K) <= 1e-14 * K
    assert abs(got[1] - x1) <= 1e-14
    # Below m = 0.1 the reference is the series to first order: its remainder is O(m²).
    assert abs(got[2] - x2) <= (1e-14 if m > 0.1 else m * m + 1e-15)


# r across both regimes: near the pure rotations (m → 0, the series of ⟨sn⁴⟩), mid-way (the
# recurrence) and near the separatrix (m → 1).
@pytest.mark.parametrize("r", [0.3230, 0.3300, 0.3600, 0.4500, 0.4900, 0.5200, 0.6000, 0.8300])
def test_polhode_means_equal_quadrature(r):
    sorted_inertia = np.sort(INERTIA)
    L = 1.7
    x3, mc, amp = _amplitudes(sorted_inertia, L, r)
    got = polhode_moments(*sorted_inertia, L, x3, mc, *amp)
    m = 1.0 - mc
    K = float(special.ellipk(m))
    # The trapezoidal rule over a period is spectrally accurate for these smooth periodic
    # integrands: 4096 nodes give round-off even at m = 0.97 (nome 0.35).
    u = np.linspace(0.0, 4.0 * K, 4096, endpoint=False)
    sn, cn, dn, _ = special.ellipj(u, m)
    w = (amp[0] * cn, amp[1] * sn, amp[2] * dn) if x3 else (amp[2] * dn, amp[1] * sn, amp[0] * cn)
    ell = np.array(w) * sorted_inertia[:, None] / L
    a = got[-1]
    want = (
        *(np.mean(ell**2, axis=1)),
        *(np.mean(ell[(i + 1) % 3] ** 2 * ell[(i + 2) % 3] ** 2) for i in range(3)),
        *(np.mean(ell[a] * ell[i] ** 2) for i in range(3)),
        np.mean(ell[a]),
    )
    # The moments are O(1); both sides are accurate to a few ulps of them.
    assert np.max(np.abs(np.array(got[:-1]) - np.array(want))) < 1e-13


def _torques(rng: np.random.Generator) -> dict[str, object]:
    normal = rng.normal(size=3)
    return {
        "field moments": FieldMomentsTorque(_spd(rng), _spd(rng), rng.normal(size=(3, 3)), 0.3),
        "gravity moments": GravityMomentsTorque(INERTIA, 0.7, normal, -0.2),
        "gravity gradient": GravityGradientTorque(INERTIA, 0.4, normal, 0.3),
        "constant moments": ConstantBodyTorque(rng.normal(size=3))
        + ConstantInertialTorque(rng.normal(size=3)),
        "linear drag": LinearDrag(rng.normal(size=(3, 3))),
        "internal dissipation": InternalDissipation(INERTIA, 0.8),
    }


@pytest.mark.parametrize("name", ["field moments", "gravity moments", "gravity gradient",
                                  "constant moments", "linear drag", "internal dissipation",
                                  "all"])  # fmt: skip
def test_closed_form_equals_the_quadrature(name):
    rng = np.random.default_rng(5)
    torques = _torques(rng)
    torque = sum(torques.values(), start=ZERO) if name == "all" else torques[name]
    period = 2.0 * math.pi / 0.4 if name in ("gravity gradient", "all") else None
    for y, got, ref in closed_and_quadrature(torque, INERTIA, period, rng):
        # The quadrature stops refining the polhode when two levels agree to 1e-13 of the
        # integrand's size and is exact in the precession; the closed form is exact: they
        # agree to round-off of the largest rate (measured 2e-14).
        assert np.max(np.abs(got - ref)) <= 1e-11 * np.max(np.abs(ref)), (y, got, ref)


def test_terms_without_a_closed_form_keep_the_quadrature():
    rng = np.random.default_rng(2)
    skew = rng.normal(size=(3, 3))  # a magnetic tensor that is not symmetric
    for torque in (
        FieldMomentsTorque(skew, _spd(rng), np.zeros((3, 3))),
        QuadraticDrag(np.diag([0.1, 0.2, 0.3])) + ConstantBodyTorque([0.0, 0.1, 0.0]),
    ):
        kernel = triaxial_kernel(torque, INERTIA)
        assert kernel is not None and kernel.kind == KIND_TRIAXIAL_PHASE_MEANS


ZERO = ConstantBodyTorque(np.zeros(3))
