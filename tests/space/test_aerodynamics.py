"""The free-molecular force and moment on facets against their closed forms (a flat plate, a
meshed plate, a sphere in both limits of accommodation), the exponential atmosphere against its
table, and the air's velocity relative to the turning Earth."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tumble.errors import ParameterError
from tumble.space import facets as F
from tumble.space.aerodynamics import (
    EXPONENTIAL_ATMOSPHERE,
    Accommodation,
    aerodynamic_force_and_moment,
    air_table,
    air_velocity,
    exponential_density,
)
from tumble.space.geomagnetic import EARTH_ROTATION

RHO, SPEED = 3.7e-12, 7.7e3  # 400 km, a circular orbit's speed [kg/m³, m/s]


def _plate_force(a: Accommodation, area: float, n: np.ndarray, s: np.ndarray) -> np.ndarray:
    """The closed form of one facet (module notes of tumble.space.aerodynamics)."""
    c = max(float(n @ s), 0.0)
    return (
        -RHO
        * SPEED**2
        * area
        * c
        * (
            a.tangential * s
            + (a.normal * a.wall_speed_ratio + (2.0 - a.normal - a.tangential) * c) * n
        )
    )


def test_a_plate_face_on_in_both_limits():
    n = np.array([0.0, 0.0, 1.0])
    plate = F.Facets.of([2.0], n, [0.0, 0.0, 0.0], F.Optics())
    q = RHO * SPEED**2
    # Diffuse, a cold wall: the molecules' momentum absorbed, q A.
    force, _ = aerodynamic_force_and_moment(plate, Accommodation(1.0, 1.0, 0.0), SPEED * n, RHO)
    assert force == pytest.approx(-q * 2.0 * n, rel=1e-15)
    # Specular: reflected, 2 q A.
    force, _ = aerodynamic_force_and_moment(plate, Accommodation(0.0, 0.0, 0.0), SPEED * n, RHO)
    assert force == pytest.approx(-2.0 * q * 2.0 * n, rel=1e-15)
    # Diffuse from a warm wall: the re-emitted molecules add q A vw/v.
    force, _ = aerodynamic_force_and_moment(plate, Accommodation(1.0, 1.0, 0.05), SPEED * n, RHO)
    assert force == pytest.approx(-q * 2.0 * 1.05 * n, rel=1e-15)
    # Seen edge-on or from behind: nothing.
    for v in ([SPEED, 0.0, 0.0], [0.0, 0.0, -SPEED]):
        force, moment = aerodynamic_force_and_moment(plate, Accommodation(), v, RHO)
        assert not np.any(force) and not np.any(moment)


@settings(max_examples=60, deadline=None)
@given(
    theta=st.floats(0.0, 1.5),
    phi=st.floats(0.0, 2.0 * math.pi),
    sn=st.floats(0.0, 1.0),
    stg=st.floats(0.0, 1.0),
    vw=st.floats(0.0, 0.2),
    dx=st.floats(-2.0, 2.0),
)
def test_a_meshed_plate_is_its_closed_form_at_its_centroid(theta, phi, sn, stg, vw, dx):
    # A 1 m × 2 m plate in 256 triangles, offset by dx along x: the force is the closed form of
    # one facet, the moment that force at the centroid (every triangle is struck alike).
    trimesh = pytest.importorskip("trimesh")
    grid = trimesh.creation.box(extents=[1.0, 2.0, 1e-9]).subdivide().subdivide().subdivide()
    up = grid.face_normals[:, 2] > 0.5
    top = F.Facets.of(grid.area_faces[up], grid.face_normals[up],
                      grid.triangles_center[up] + [dx, 0.0, 0.0], F.Optics())  # fmt: skip
    a = Accommodation(sn, stg, vw)
    s = np.array([math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi),
                  math.cos(theta)])  # fmt: skip
    force, moment = aerodynamic_force_and_moment(top, a, SPEED * s, RHO)
    want = _plate_force(a, float(top.area.sum()), np.array([0.0, 0.0, 1.0]), s)
    scale = RHO * SPEED**2 * 2.0 * 3.0  # q A (2 − σn − σt + σt + …) at most, with |r| ≤ 3
    # Sums of 128 terms: round-off, 1e-13 of the scale.
    assert np.allclose(force, want, rtol=0.0, atol=1e-13 * scale)
    centroid = top.area @ top.centre / top.area.sum()  # (dx, 0, 5e-10): the top face
    assert np.allclose(moment, np.cross(centroid, want), rtol=0.0, atol=1e-13 * scale)


@pytest.mark.parametrize(("sn", "stg", "vw"), [(1.0, 1.0, 0.0), (0.0, 0.0, 0.0), (0.9, 0.8, 0.05)])
def test_a_sphere_drags_as_its_closed_form_and_turns_nothing(sn, stg, vw):
    # F = q πR² [1 + (σt − σn)/2 + ⅔ σn vw/v] (the hemisphere's ∫c dA, ∫c² n dA, ∫c³ n dA):
    # Cd = 2 for both a diffuse cold sphere and a specular one. The icosphere's facets make
    # it 3e-4 off at 5 subdivisions (as the sphere in sunlight).
    trimesh = pytest.importorskip("trimesh")
    sphere = F.from_mesh(trimesh.creation.icosphere(subdivisions=5, radius=1.0), F.Optics())
    a = Accommodation(sn, stg, vw)
    s = np.array([0.3, -0.4, 0.866])
    s /= np.linalg.norm(s)
    force, moment = aerodynamic_force_and_moment(sphere, a, SPEED * s, RHO)
    want = -RHO * SPEED**2 * math.pi * (1.0 + (stg - sn) / 2.0 + 2.0 / 3.0 * sn * vw) * s
    assert np.allclose(force, want, rtol=0.0, atol=5e-4 * np.linalg.norm(want))
    assert np.linalg.norm(moment) <= 1e-5 * np.linalg.norm(want)


def test_the_air_table_is_the_surface_in_the_form_of_sunlights():
    body = F.box([1.0, 2.0, 3.0], F.Optics(0.2, 0.3))
    a = Accommodation(0.9, 0.7, 0.04)
    got, light = air_table(body, a), body.table()
    np.testing.assert_array_equal(got[:, :6], light[:, :6])  # normals, centres
    np.testing.assert_array_equal(got[:, 9:], light[:, 9:])  # arms
    np.testing.assert_allclose(got[:, 6:9], np.outer(body.area, [0.7, 0.4, 0.9 * 0.04]),
                               rtol=1e-15)  # fmt: skip


def test_the_exponential_atmosphere_is_its_table():
    h0, rho0, scale = EXPONENTIAL_ATMOSPHERE.T
    # At each band's base: its nominal density, to the rounding.
    np.testing.assert_allclose(exponential_density(h0 * 1e3), rho0, rtol=1e-15)
    # One scale height up (within the band where it fits): e times less.
    inside = scale < np.diff(np.append(h0, 2000.0))
    np.testing.assert_allclose(exponential_density((h0 + scale)[inside] * 1e3),
                               rho0[inside] / math.e, rtol=1e-14)  # fmt: skip
    # From band to band continuous (each scale height reaches the next base's density; the
    # exponential of a difference of logarithms: a few ulps), and falling everywhere.
    top = rho0[:-1] * np.exp(-np.diff(h0) / scale[:-1])
    assert np.max(np.abs(top / rho0[1:] - 1.0)) < 1e-13
    h = np.linspace(0.0, 1.2e6, 5000)
    assert np.all(np.diff(exponential_density(h)) < 0.0)
    with pytest.raises(ParameterError, match="altitude"):
        exponential_density(-1.0)


def test_the_air_turns_with_the_earth():
    # A prograde circular equatorial orbit at 400 km: the air comes at v − ω r.
    r = 6378137.0 + 4e5
    v = math.sqrt(3.986004418e14 / r)
    rel = air_velocity([r, 0.0, 0.0], [0.0, v, 0.0])
    assert rel == pytest.approx([0.0, v - EARTH_ROTATION * r, 0.0], rel=1e-15)
    # Over a pole, the air moves across the track at ω r cos(latitude) = 0 there.
    rel = air_velocity([0.0, 0.0, r], [v, 0.0, 0.0])
    assert rel == pytest.approx([v, 0.0, 0.0], rel=1e-15)


def test_bad_accommodation_is_refused_in_one_line():
    for bad in ({"normal": 1.2}, {"tangential": -0.1}, {"wall_speed_ratio": 1.0}):
        with pytest.raises(ParameterError) as err:
            Accommodation(**bad)
        assert "\n" not in str(err.value)
