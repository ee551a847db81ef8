"""The IGRF to any degree: its compiled synthesis against the maintained package ppigrf, its
rate by the complex step against differences, and its degree 1 against the dipole."""

from __future__ import annotations

import math
from datetime import UTC, datetime

import numpy as np
import pytest
from ppigrf import igrf_gc

from tumble.errors import ParameterError
from tumble.kernels.space import orbit_states
from tumble.space import EARTH_RADIUS, Dipole, Igrf, Orbit, field_moments

EPOCH = datetime(2024, 3, 1, tzinfo=UTC)
ECCENTRIC = Orbit(EARTH_RADIUS + 7e5, 0.05, 1.7, 0.3, 0.7, 0.2)  # near-polar, with J2 drift


def _ppigrf_inertial(field: Igrf, orbit: Orbit, t: np.ndarray) -> np.ndarray:
    """ppigrf's field (geocentric spherical components at the Earth-fixed place) turned into
    inertial axes at the body's place at times t."""
    out = []
    for k, r in enumerate(orbit_states(orbit.payload(), t)[:, :3]):
        angle = field.theta0 + field.rotation * t[k]
        c, s = math.cos(angle), math.sin(angle)
        x, y, z = c * r[0] + s * r[1], -s * r[0] + c * r[1], r[2]
        rr, th, ph = math.hypot(x, y, z), math.acos(z / math.hypot(x, y, z)), math.atan2(y, x)
        br, bt, bp = (float(np.ravel(v)[0]) for v in igrf_gc(
            rr / 1e3, math.degrees(th), math.degrees(ph), EPOCH.replace(tzinfo=None),
            max_degree=field.degree))  # fmt: skip
        e_r = np.array([x, y, z]) / rr
        e_t = np.array([math.cos(th) * math.cos(ph), math.cos(th) * math.sin(ph), -math.sin(th)])
        e_p = np.array([-math.sin(ph), math.cos(ph), 0.0])
        b = 1e-9 * (br * e_r + bt * e_t + bp * e_p)
        out.append([c * b[0] - s * b[1], s * b[0] + c * b[1], b[2]])
    return np.array(out)


@pytest.mark.parametrize("degree", [1, 4, 13])
def test_the_synthesis_equals_ppigrf(degree):
    field = Igrf.at(EPOCH, degree)
    t = np.linspace(0.0, 20000.0, 9)  # three orbits: the poles' neighbourhood included
    B, _ = field.along(ECCENTRIC, t)
    want = _ppigrf_inertial(field, ECCENTRIC, t)
    # Both sum the same series in double precision by different recursions: round-off.
    assert np.max(np.abs(B - want)) <= 1e-13 * np.max(np.abs(want))


def test_the_rate_is_the_derivative_of_the_field():
    # Central differences with h = 1e-2 s: truncation ~h²(14 n)²/6 ≈ 3e-11 relative (the
    # degree-13 field turns 14 times an orbit), round-off ~1e-16/h·|B|/|Ḃ| ≈ 1e-11: within 1e-9.
    field = Igrf.at(EPOCH, 13)
    t, h = np.linspace(0.0, 6000.0, 7), 1e-2
    _, rate = field.along(ECCENTRIC, t)
    plus, _ = field.along(ECCENTRIC, t + h)
    minus, _ = field.along(ECCENTRIC, t - h)
    assert np.max(np.abs((plus - minus) / (2 * h) - rate)) <= 1e-9 * np.max(np.abs(rate))


def test_degree_one_is_the_dipole():
    field = Igrf.at(EPOCH, 1)
    dipole = Dipole(field.g[0], field.g[1], field.h[1], field.theta0)
    t = np.linspace(0.0, 9000.0, 5)
    for got, want in zip(field.along(ECCENTRIC, t), dipole.along(ECCENTRIC, t), strict=True):
        # Two formulas of one field (recursion, closed form): round-off.
        assert np.max(np.abs(got - want)) <= 1e-14 * np.max(np.abs(want))
    circular = Orbit(EARTH_RADIUS + 7e5, 0.0, 1.7)
    for got, want in zip(field_moments(circular, field), field_moments(circular, dipole),
                         strict=True):  # fmt: skip
        # The same quadrature on the same field, to its 1e-12 test.
        assert np.max(np.abs(got - want)) <= 1e-11 * np.max(np.abs(want))


def test_the_full_fields_moments_differ_from_the_dipoles_by_its_higher_degrees():
    # At 700 km the degrees 2–13 carry a few per cent of B²: ⟨B²⟩ differs from the dipole's
    # by about that, and S stays symmetric positive definite.
    circular = Orbit(EARTH_RADIUS + 7e5, 0.0, 1.7)
    S13, _ = field_moments(circular, Igrf.at(EPOCH, 13))
    S1, _ = field_moments(circular, Igrf.at(EPOCH, 1))
    assert np.allclose(S13, S13.T, rtol=0.0, atol=1e-12 * np.trace(S13))
    assert np.all(np.linalg.eigvalsh(S13) > 0.0)
    assert 0.005 < abs(np.trace(S13) / np.trace(S1) - 1.0) < 0.1


def test_bad_igrf_input_is_refused():
    with pytest.raises(ParameterError, match=r"orbit\.epoch must be within 1900–2030"):
        Igrf.at(datetime(1890, 1, 1, tzinfo=UTC))
    with pytest.raises(ParameterError, match=r"field\.degree"):
        Igrf(14, (), ())
