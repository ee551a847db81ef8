"""Sunlight on a faceted body: the facet model against its closed forms, the tessellated
sphere's moment vanishing as its mesh is refined, the solar ephemeris against the seasons and
the Earth's shadow across its edge."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from hypothesis import given
from hypothesis import strategies as st

from tumble.errors import ParameterError
from tumble.space.facets import Facets, Optics, box, box_wing, cylinder, from_mesh, plate
from tumble.space.orbit import EARTH_RADIUS
from tumble.space.radiation import pressure, radiation_force_and_moment
from tumble.space.sun import AU, eclipse_fraction, shadow, sun_direction

P = float(pressure(AU))
unit = st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3).filter(
    lambda v: np.linalg.norm(v) > 0.1
)
optics = st.tuples(st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.05, 1.0)).filter(
    lambda o: o[0] + o[1] <= 1.0
)


def test_the_pressure_at_one_astronomical_unit():
    # Φ/c with Φ = 1361 W/m² (IAU 2015 B3): 4.54e-6 N/m², the value every SRP model uses.
    assert P == pytest.approx(4.5398e-6, rel=1e-4)


def test_a_black_plate_and_a_mirror_facing_the_sun():
    # The two textbook limits: absorbed, the momentum P A; reflected back, twice that. A black
    # facet of a closed body also re-emits its heat from its face, ⅔ P A more (Lambertian).
    s = np.array([0.0, 0.0, 1.0])
    black = Facets.of(2.0, s, [0.0, 0.0, 0.0], Optics(0.0, 0.0, 1.0, 1.0))  # κ = 0
    mirror = Facets.of(2.0, s, [0.0, 0.0, 0.0], Optics(1.0, 0.0))
    hot = Facets.of(2.0, s, [0.0, 0.0, 0.0], Optics(0.0, 0.0))  # κ = 1
    for facets, factor in ((black, 1.0), (mirror, 2.0), (hot, 1.0 + 2.0 / 3.0)):
        force, _ = radiation_force_and_moment(facets, s, P)
        np.testing.assert_allclose(force, -factor * P * 2.0 * s, rtol=1e-14)


@given(unit, unit, optics, st.floats(0.1, 5.0), st.lists(st.floats(-3, 3), min_size=3, max_size=3))
def test_a_tessellated_plate_is_its_closed_form_at_its_centre_of_pressure(
    normal, sun, o, side, offset
):
    # A square plate cut into 200 triangles (a mesh, as a user's would be) against the closed
    # form of one flat facet: the same force, and its moment about the centre of mass that of
    # the force at the plate's centroid, its centre of pressure under uniform light.
    n = np.asarray(normal) / np.linalg.norm(normal)
    s = np.asarray(sun) / np.linalg.norm(sun)
    mesh = trimesh.creation.box(extents=[side, side, 1e-9])
    grid = trimesh.remesh.subdivide_to_size(mesh.vertices, mesh.faces, side / 9.0)
    top = trimesh.Trimesh(*grid)
    top = top.submesh([np.flatnonzero(top.face_normals[:, 2] > 0.5)], append=True)
    turn = trimesh.geometry.align_vectors([0.0, 0.0, 1.0], n)
    top.apply_transform(turn)
    top.apply_translation(offset)
    n = top.face_normals.mean(axis=0)  # the plate as meshed (trimesh snaps tiny turns)
    n /= np.linalg.norm(n)
    optic = Optics(o[0], o[1], o[2])
    facets = from_mesh(top, optic)
    assert len(facets) >= 100
    force, moment = radiation_force_and_moment(facets, s, P)
    cos = max(float(n @ s), 0.0)
    alpha = 1.0 - o[0] - o[1]
    along_n = 2 * o[0] * cos + 2 / 3 * o[1] + 2 / 3 * alpha
    closed = -P * side**2 * cos * ((1 - o[0]) * s + along_n * n)
    scale = P * side**2
    # Sums of a few hundred terms of one size: a few ulps each (1e-12 relative, with margin).
    np.testing.assert_allclose(force, closed, atol=1e-12 * scale)
    centroid = (top.area_faces[:, None] * top.triangles_center).sum(axis=0) / top.area
    np.testing.assert_allclose(moment, np.cross(centroid, closed), atol=1e-11 * scale * (1 + side))


def test_a_thin_panel_with_like_faces_has_no_thermal_push():
    # Both faces at one temperature and of one emissivity re-emit alike: κ = 0, so a black panel
    # feels the momentum of the light alone.
    s = np.array([0.6, 0.0, 0.8])
    panel = plate(3.0, [0.0, 0.0, 1.0], [0.0, 0.0, 0.0], Optics(0.0, 0.0, 0.8))
    force, _ = radiation_force_and_moment(panel, s, P)
    np.testing.assert_allclose(force, -P * 3.0 * 0.8 * s, rtol=1e-14)
    assert np.allclose(panel.thermal, 0.0)


def _sphere(subdivisions: int, o: Optics) -> Facets:
    return from_mesh(trimesh.creation.icosphere(subdivisions=subdivisions, radius=1.0), o)


def test_a_tessellated_sphere_feels_no_moment_in_the_limit():
    # A uniform sphere's light passes through its centre: the moment of the tessellated sphere
    # about it must vanish as the mesh is refined. Measured: the moment falls as the square of
    # the facet size (slope 2.0 against the edge length); the force tends to the sphere's
    # closed form P πR² [1 + 4/9 (ρd + α)] (the specular part adds nothing on a sphere).
    o = Optics(0.3, 0.2, 0.9)
    s = np.array([0.37, -0.52, 0.77])
    s /= np.linalg.norm(s)
    levels = (2, 3, 4, 5)
    moments, forces, edges = [], [], []
    for k in levels:
        facets = _sphere(k, o)
        force, moment = radiation_force_and_moment(facets, s, P)
        moments.append(np.linalg.norm(moment) / (P * math.pi))
        forces.append(force)
        edges.append(2.0**-k)
    slope = np.polyfit(np.log(edges), np.log(moments), 1)[0]
    assert slope > 1.5, (moments, slope)  # measured 2.0: second order in the facet size
    assert moments[-1] < 1e-4
    closed = -P * math.pi * (1.0 + 4.0 / 9.0 * (o.diffuse + (1.0 - o.specular - o.diffuse))) * s
    # The inscribed polyhedron's area and the terminator's cut: second order too (measured
    # 3.0e-4 relative at 5 subdivisions, 7.5e-5 at 6).
    np.testing.assert_allclose(forces[-1], closed, rtol=2e-3)


def test_a_box_wing_satellite():
    # Six bus faces and the two faces of its array; the array's sunlit face pushes the whole
    # body, and its moment is the array's offset crossed with its force.
    bus = Optics(0.1, 0.3, 0.8)
    cells = Optics(0.05, 0.05, 0.85)
    back = Optics(0.1, 0.1, 0.9)
    body = box_wing([2.0, 2.0, 3.0], bus, 20.0, [1.0, 0.0, 0.0], [0.0, 8.0, 0.0], cells, back)
    assert len(body) == 8
    assert body.area.sum() == pytest.approx(2 * (4 + 6 + 6) + 40.0)
    s = np.array([1.0, 0.0, 0.0])
    array_only = plate(20.0, [1.0, 0.0, 0.0], [0.0, 8.0, 0.0], cells, back)
    f_array, m_array = radiation_force_and_moment(array_only, s, P)
    _, m_all = radiation_force_and_moment(body, s, P)
    # The bus is centred on the origin: its lit face pushes through it, no moment of its own.
    np.testing.assert_allclose(m_all, m_array, atol=1e-20)
    np.testing.assert_allclose(m_array, np.cross([0.0, 8.0, 0.0], f_array), atol=1e-20)


def test_a_rocket_body_is_a_closed_cylinder():
    facets = cylinder(1.2, 6.5, Optics(0.2, 0.3), sides=64)
    # Area of the 64-sided prism and its caps; its normals sum to zero (a closed surface).
    side = 64 * 6.5 * 2 * 1.2 * math.sin(math.pi / 64)
    caps = 2 * 0.5 * 64 * 1.2**2 * math.sin(2 * math.pi / 64)
    assert facets.area.sum() == pytest.approx(side + caps, rel=1e-12)
    assert np.allclose((facets.area[:, None] * facets.normal).sum(axis=0), 0.0, atol=1e-12)
    # Its long axis is body axis 1: the caps face ±x.
    caps_normals = facets.normal[np.abs(facets.normal[:, 0]) > 0.99]
    assert len(caps_normals) > 0


def test_bad_optics_and_facets_are_refused_in_one_line():
    with pytest.raises(ParameterError, match="specular \\+ diffuse"):
        Optics(0.7, 0.5)
    with pytest.raises(ParameterError, match="emissivity"):
        Optics(0.1, 0.1, 0.0)
    with pytest.raises(ParameterError, match="unit vector"):
        Facets.of(1.0, [0.0, 0.0, 2.0], [0.0, 0.0, 0.0], Optics())
    with pytest.raises(ParameterError, match="positive"):
        box([1.0, -1.0, 1.0], Optics())


@pytest.mark.parametrize(
    ("when", "declination_deg"),
    [
        (2451623.816, 0.0),  # March equinox 2000, 07:35 UT
        (2451716.575, 23.437),  # June solstice 2000, 01:48 UT
        (2451900.067, -23.437),  # December solstice 2000, 13:37 UT
    ],
)
def test_the_sun_at_the_equinox_and_the_solstices(when, declination_deg):
    # The Almanac's formula is good to 0.01°; the epochs are rounded to the minute (the Sun
    # moves 0.0007° in declination a minute at the equinox).
    direction, distance = sun_direction(when)
    assert np.linalg.norm(direction) == pytest.approx(1.0, abs=1e-15)
    assert math.degrees(math.asin(direction[2])) == pytest.approx(declination_deg, abs=0.02)
    assert 0.983 * AU < distance < 1.017 * AU


def test_the_sun_is_nearest_in_early_january():
    days = 2451545.0 + np.arange(0.0, 366.0)
    _, distance = sun_direction(days)
    assert abs(int(np.argmin(distance)) - 2) <= 2  # perihelion 2000 January 3
    assert distance.min() == pytest.approx(0.98333 * AU, rel=2e-4)


def test_the_shadow_across_its_edge():
    s = np.array([1.0, 0.0, 0.0])
    d = AU
    far = 7.0e6  # m from the Earth's centre, behind it
    across = np.linspace(EARTH_RADIUS - 1.0e5, EARTH_RADIUS + 1.0e5, 2001)
    points = np.stack([-far * np.ones_like(across), across, np.zeros_like(across)], axis=-1)
    cyl = shadow(points, s, d, "cylindrical")
    cone = shadow(points, s, d, "conical")
    assert np.all(np.diff(cone) >= -1e-12)  # light grows across the penumbra, never falls
    assert cone[0] == 0.0 and cone[-1] == 1.0 and cyl[0] == 0.0 and cyl[-1] == 1.0
    # The penumbra is as wide as the Sun's disc seen from the body (0.53°, ~65 km at 7000 km),
    # about the cylinder's edge.
    partial = across[(cone > 0.0) & (cone < 1.0)]
    width = partial.max() - partial.min()
    assert 50e3 < width < 80e3
    assert partial.min() < EARTH_RADIUS < partial.max() + 30e3
    # The sunlit side sees the whole Sun.
    assert shadow(np.array([far, 0.0, 0.0]), s, d) == 1.0
    with pytest.raises(ParameterError, match="shadow"):
        shadow(points, s, d, "umbral")


@pytest.mark.parametrize("beta_deg", [0.0, 20.0, 50.0, 66.0, 75.0])
def test_the_eclipse_fraction_of_a_circular_orbit(beta_deg):
    # The closed form against the cylindrical shadow sampled along the orbit (100 000 points:
    # the fraction to 1e-5), and the conical shadow's mean, which differs by the penumbra's
    # share (measured ≤ 2e-3 at 7000 km).
    a, beta = 7.0e6, math.radians(beta_deg)
    s = np.array([math.cos(beta), 0.0, math.sin(beta)])  # the plane is x-y
    u = 2.0 * math.pi * (np.arange(100_000) + 0.5) / 100_000
    points = a * np.stack([np.cos(u), np.sin(u), np.zeros_like(u)], axis=-1)
    sampled = 1.0 - shadow(points, s, AU, "cylindrical").mean()
    closed = float(eclipse_fraction(a, beta))
    assert closed == pytest.approx(sampled, abs=2e-5)
    cone = 1.0 - shadow(points, s, AU, "conical").mean()
    assert abs(cone - closed) < 3e-3
    if beta_deg == 0.0:  # the whole diameter: arcsin(R/a)/π
        assert closed == pytest.approx(math.asin(EARTH_RADIUS / a) / math.pi, rel=1e-12)
    if beta_deg >= 66.0:  # beyond the critical elevation, asin(R/a) = 65.7°: no eclipse
        assert closed == 0.0


@pytest.mark.parametrize(
    ("e", "beta_deg", "sun_perigee_deg"),
    [(0.7, 0.0, 0.0), (0.7, 10.0, 180.0), (0.7, 5.0, 120.0), (0.3, 30.0, 250.0), (0.05, 0.0, 90.0),
     (0.7, 80.0, 0.0)],
)  # fmt: skip
def test_the_eclipse_fraction_of_an_eccentric_orbit(e, beta_deg, sun_perigee_deg):
    # A transfer orbit (perigee 7000 km): the located arc against the cylindrical shadow
    # sampled at 200 000 mean anomalies (the fraction to 1e-5; the arc's ends are exact to
    # the bisection's last bit).
    rp = 7.0e6
    a = rp / (1.0 - e)
    beta, w = math.radians(beta_deg), math.radians(sun_perigee_deg)
    s = np.array([math.cos(beta) * math.cos(w), math.cos(beta) * math.sin(w), math.sin(beta)])
    mean = 2.0 * math.pi * (np.arange(200_000) + 0.5) / 200_000
    big = mean.copy()
    for _ in range(50):  # Kepler's equation by Newton's method
        big -= (big - e * np.sin(big) - mean) / (1.0 - e * np.cos(big))
    points = np.stack([a * (np.cos(big) - e), a * math.sqrt(1 - e * e) * np.sin(big),
                       np.zeros_like(big)], axis=-1)  # fmt: skip
    sampled = 1.0 - shadow(points, s, AU, "cylindrical").mean()
    located = float(eclipse_fraction(a, beta, e, w))
    assert located == pytest.approx(sampled, abs=2e-5)
    # Towards a circle, the closed form (the eccentric path at e = 1e-6: its error ~ e).
    assert float(eclipse_fraction(rp, beta, 1e-6, w)) == pytest.approx(
        float(eclipse_fraction(rp, beta)), abs=1e-5
    )


def test_a_mesh_file_is_read_as_its_triangles(tmp_path):
    # A cube written as STL and read back: twelve triangles of the six faces, a closed surface
    # (its normals weighted by area sum to zero), and centred on the origin: no moment.
    cube = trimesh.creation.box(extents=[1.0, 2.0, 3.0])
    path = tmp_path / "cube.stl"
    cube.export(path)
    facets = from_mesh(path, Optics(0.2, 0.3))
    assert len(facets) == 12
    assert facets.area.sum() == pytest.approx(2 * (2 + 3 + 6), rel=1e-6)  # STL's float32
    assert np.allclose((facets.area[:, None] * facets.normal).sum(axis=0), 0.0, atol=1e-5)
    _, moment = radiation_force_and_moment(facets, [0.3, -0.4, 0.866], P)
    assert np.linalg.norm(moment) < 1e-6 * P
    with pytest.raises(ParameterError, match="no mesh file"):
        from_mesh(tmp_path / "missing.stl", Optics())
    bad = tmp_path / "bad.stl"
    bad.write_text("this is not a mesh")
    with pytest.raises(ParameterError, match="facets"):
        from_mesh(bad, Optics())
