"""The orbit and the geomagnetic dipole: the field's rate against its numerical derivative,
the orbit average ⟨B Bᵀ⟩ of an axial dipole on a circular orbit against its closed form, the
averaged torques against time averages of the instantaneous ones, and the eddy torque of a
sphere against −M B² ω⊥."""

from __future__ import annotations

import math
from datetime import UTC, datetime

import numpy as np
import pytest

from tumble.errors import ParameterError
from tumble.rotations import quat_to_matrix
from tumble.space import (
    EARTH_RADIUS,
    REFERENCE_RADIUS,
    Dipole,
    Orbit,
    OrbitEddyTorque,
    OrbitGravityTorque,
    field_moments,
    greenwich_sidereal_angle,
    sun_synchronous_inclination,
)

ECCENTRIC = Orbit(EARTH_RADIUS + 7e5, 0.05, 1.1, 0.3, 0.7, 0.2)  # with J2 drift
TILTED = Dipole(-29000.0, -1500.0, 4600.0, 0.4)  # turning with the Earth
Q = np.array([0.8, 0.1, -0.3, 0.5]) / np.linalg.norm([0.8, 0.1, -0.3, 0.5])
W = np.array([0.1, -0.2, 0.05])


def test_the_field_rate_is_the_derivative_of_the_field():
    # Central differences with h = 1e-3 s: truncation ~h²(2n)² ≈ 5e-12 relative and round-off
    # ~1e-16|B|/h ≈ 1e-13|B|, both far below the 1e-7 bound. The
    # rate holds the body's motion on the drifting ellipse and the Earth's turn of the dipole.
    t = np.linspace(0.0, 6000.0, 7)
    h = 1e-3
    _, Bdot = TILTED.along(ECCENTRIC, t)
    Bp, _ = TILTED.along(ECCENTRIC, t + h)
    Bm, _ = TILTED.along(ECCENTRIC, t - h)
    assert np.max(np.abs((Bp - Bm) / (2 * h) - Bdot)) <= 1e-7 * np.max(np.abs(Bdot))


def test_the_dipole_field_at_the_poles_and_equator():
    # B = a³[3(g·r)r − r²g]/r⁵: 2 g10 along ξ3 over the north pole (pointing down for
    # g10 < 0), −g10 ξ3 on the equator (northwards): the dipole's textbook values.
    d = Dipole(-30000.0, rotation=0.0)
    a = REFERENCE_RADIUS
    # Over the pole: a polar circular orbit at argument of latitude 90°.
    orbit = Orbit(EARTH_RADIUS + 1e5, 0.0, math.pi / 2, 0.0, 0.0, math.pi / 2, j2=False)
    B, _ = d.along(orbit, [0.0])
    scale = (a / orbit.a) ** 3 * 1e-9
    assert np.allclose(B[0], [0.0, 0.0, 2 * -30000.0 * scale], atol=1e-18)
    equatorial = Orbit(EARTH_RADIUS + 1e5, j2=False)
    B, _ = d.along(equatorial, [0.0])
    assert np.allclose(B[0], [0.0, 0.0, 30000.0 * scale], atol=1e-18)


def test_the_mean_of_b_bt_of_an_axial_dipole_on_a_circular_orbit():
    # B = k[3 z r̂ − ξ3] with z = sin i sin u and k = a³g10/r³; over u,
    # ⟨B Bᵀ⟩ = k²[(9/8) sin²i (e1e1ᵀ + 3 e2e2ᵀ) − (3/2) sin i (e2ξ3ᵀ + ξ3e2ᵀ) + ξ3ξ3ᵀ],
    # e1 the node, e2 = ĥ × e1 (its trace k²(1 + (3/2) sin²i)). A trigonometric polynomial
    # of degree 4 in u: the uniform grid integrates it to round-off (1e-13 relative).
    orbit = Orbit.circular(700.0, 0.9, 0.5, j2=False)
    S, D = field_moments(orbit, Dipole(-30000.0))
    k = 1e-9 * REFERENCE_RADIUS**3 * -30000.0 / orbit.a**3
    i, node = orbit.i, orbit.raan
    e1 = np.array([math.cos(node), math.sin(node), 0.0])
    e2 = np.array([-math.cos(i) * math.sin(node), math.cos(i) * math.cos(node), math.sin(i)])
    z = np.array([0.0, 0.0, 1.0])
    closed = (
        k
        * k
        * (
            9 / 8 * math.sin(i) ** 2 * (np.outer(e1, e1) + 3 * np.outer(e2, e2))
            - 1.5 * math.sin(i) * (np.outer(e2, z) + np.outer(z, e2))
            + np.outer(z, z)
        )
    )
    assert np.max(np.abs(S - closed)) <= 1e-13 * np.max(np.abs(closed))
    # ⟨Ḃ Bᵀ⟩ is antisymmetric: its symmetric part is ½⟨d(B Bᵀ)/dt⟩ = 0 over a period.
    assert np.max(np.abs(D + D.T)) <= 1e-12 * np.max(np.abs(D))


def test_the_averaged_torques_are_the_time_averages_along_one_orbit():
    # A dipole fixed in inertial space and no J2: the orbit is periodic and the average over
    # the mean anomaly is the time average over one period; 4000 uniform samples integrate
    # the periodic integrands (harmonics well below 4000 at e = 0.05) to ~1e-12.
    orbit = Orbit(EARTH_RADIUS + 7e5, 0.05, 1.1, 0.3, 0.7, 0.0, j2=False)
    dipole = Dipole(-29000.0, -1500.0, 4600.0, 0.4, rotation=0.0)
    t = np.linspace(0.0, orbit.period, 4001)[:-1]
    tensor = np.array([[1.0, 0.2, 0.0], [0.2, 2.0, 0.1], [0.0, 0.1, 3.0]])
    eddy = OrbitEddyTorque(orbit, dipole, tensor)
    assert np.allclose(eddy.averaged()(0.0, Q, W), np.mean(eddy(t, Q, W), axis=0),
                       rtol=1e-9, atol=0.0)  # fmt: skip
    gravity = OrbitGravityTorque(orbit, [1.0, 2.0, 3.0])
    assert np.allclose(gravity.averaged()(0.0, Q, W), np.mean(gravity(t, Q, W), axis=0),
                       rtol=1e-9, atol=0.0)  # fmt: skip


def test_a_spheres_eddy_torque_is_minus_m_b_squared_omega_perp():
    # M = m·1: (M(ω × B)) × B = −m (B² ω − (ω·B) B) = −m B² ω⊥; the part of the moment that
    # does not depend on ω (the field's own rate along the orbit) is removed by T(ω) − T(0).
    m = 2.0
    torque = OrbitEddyTorque(ECCENTRIC, TILTED, m * np.eye(3))
    B, _ = TILTED.along(ECCENTRIC, [100.0])
    Bb = quat_to_matrix(Q).T @ B[0]
    expected = -m * (Bb @ Bb * W - (W @ Bb) * Bb)
    got = torque(100.0, Q, W) - torque(100.0, Q, np.zeros(3))
    assert np.allclose(got, expected, rtol=1e-12, atol=0.0)


def test_sun_synchronous_inclination_and_the_sidereal_angle():
    # 98.19° at 700 km (the node turns 360° per tropical year under J2); the Greenwich
    # sidereal angle at J2000.0 is 280.46061837°, by definition of the formula.
    orbit = Orbit.circular(700.0, sun_synchronous_inclination(700.0))
    assert math.degrees(orbit.i) == pytest.approx(98.19, abs=0.01)
    assert orbit.secular_rates()[0] * 365.2421897 * 86400 == pytest.approx(2 * math.pi, rel=1e-9)
    j2000 = datetime(2000, 1, 1, 12, tzinfo=UTC)
    assert math.degrees(greenwich_sidereal_angle(j2000)) == pytest.approx(280.46061837, abs=1e-9)


def test_the_igrf_dipole_is_tilted_by_about_nine_and_a_half_degrees():
    # IGRF-13: |g| ≈ 29,700–29,800 nT and a tilt of about 9.2–9.7° over 2020–2030.
    d = Dipole.igrf(datetime(2025, 1, 1, tzinfo=UTC))
    assert 29_500.0 < d.strength < 30_000.0
    assert 9.0 < math.degrees(d.tilt) < 10.0


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"a": EARTH_RADIUS - 1.0}, "perigee"),
        ({"a": 8e6, "e": 1.0}, "orbit.e"),
        ({"a": 8e6, "e": 0.5}, "perigee"),
    ],
)
def test_bad_orbits_are_refused_in_one_line(kwargs, field):
    with pytest.raises(ParameterError, match=field) as info:
        Orbit(**kwargs)
    assert "\n" not in str(info.value)


VANGUARD = (
    "1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753",
    "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667",
)  # Vanguard 1: the test element set of Vallado's SGP4 (Revisiting Spacetrack Report #3)


def test_an_orbit_from_a_two_line_element_set():
    sgp4 = pytest.importorskip("sgp4.api")  # the test extra installs it
    orbit, epoch = Orbit.from_tle(*VANGUARD)
    assert epoch == datetime(2000, 6, 27, 18, 50, 19, 733568, tzinfo=UTC)
    assert math.degrees(orbit.i) == pytest.approx(34.2682, abs=1e-9)
    assert orbit.e == 0.1859667
    assert math.degrees(orbit.raan) == pytest.approx(348.7242, abs=1e-9)
    # Against SGP4 itself at the epoch and a day later: tumble's mean elements with secular J2
    # leave out SGP4's short-period J2 terms, ~J2 (R/a)² a ≈ 5 km, and more at this e = 0.19
    # perigee (measured 8.1 km and 1.9 km): within 20 km of 7,000–8,000 km.
    sat = sgp4.Satrec.twoline2rv(*VANGUARD)
    mine = orbit.states([0.0, 86400.0])[:, :3] / 1e3
    for k, day in enumerate((0.0, 1.0)):
        _, r, _ = sat.sgp4(sat.jdsatepoch, sat.jdsatepochF + day)
        assert np.linalg.norm(mine[k] - np.array(r)) < 20.0


def test_a_malformed_element_set_is_refused_in_one_line():
    pytest.importorskip("sgp4.api")
    with pytest.raises(ParameterError, match=r"orbit\.tle line 1") as info:
        Orbit.from_tle("1 00005U nonsense", VANGUARD[1])
    assert "\n" not in str(info.value)
    # One digit changed (34.2682° → 35.2682°): the checksum catches it.
    with pytest.raises(ParameterError, match=r"orbit\.tle line 2: checksum"):
        Orbit.from_tle(VANGUARD[0], VANGUARD[1].replace(" 34.2682", " 35.2682"))
