"""The compiled air terms: the moment along the orbit against the Python model, the
orbit-averaged moment at a fixed attitude against a fine quadrature of the same, its number of
orbit nodes, the closed-form Euler–Poinsot average against the product rule, and the vanishing
of the average on a circular orbit for a body whose facets come in opposite pairs."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import special

from tumble.averaging import triaxial_kernel
from tumble.kernels import KIND_TRIAXIAL_AVERAGED, KIND_TRIAXIAL_CLOSED
from tumble.kernels.astro import ATMOSPHERE_BANDS, EARTH_RADIUS, EXPONENTIAL_ATMOSPHERE
from tumble.kernels.rhs import evaluate
from tumble.kernels.space import orbit_states
from tumble.kernels.terms import compiled_term, flatten
from tumble.kernels.terms.aerodynamic import MEAN_LAYOUT, orbit_nodes
from tumble.kernels.terms.solar_radiation import coefficients, expanded_tensors
from tumble.kernels.torque import moments
from tumble.rotations import quat_to_matrix
from tumble.space import facets as F
from tumble.space.aerodynamics import (
    Accommodation,
    aerodynamic_force_and_moment,
    air_table,
    air_velocity,
    exponential_density,
)
from tumble.space.geomagnetic import EARTH_ROTATION
from tumble.torques import CompiledTorque

MU = 3.986004418e14
INERTIA = np.array([210.0, 85.0, 190.0])  # unsorted: the kernels read them through Q
AIR = Accommodation(0.9, 0.8, 0.05)


def _orbit(perigee_km: float, apogee_km: float) -> np.ndarray:
    """An orbit payload in metres and seconds (T0 = 1 s), tilted, with a node and perigee that
    drift."""
    rp, ra = EARTH_RADIUS + 1e3 * perigee_km, EARTH_RADIUS + 1e3 * apogee_km
    a, e = 0.5 * (rp + ra), (ra - rp) / (ra + rp)
    return np.array([a, e, 0.9, 0.4, 1.1, 0.3, math.sqrt(MU / a**3), -1e-6, 2e-6, MU])


def _box_wing(paired: bool = True) -> F.Facets:
    """A bus and a turned array off the centre of mass; ``paired = False`` drops the array's
    back, leaving a facet with no opposite."""
    optics = F.Optics(0.1, 0.3, 0.8, 0.8)
    wing = F.box_wing([1.0, 1.0, 1.5], optics, 4.0, [0.26, 0.0, 0.97], [0.0, 2.0, 0.0], optics)
    wing = wing.shifted([0.02, -0.2, 0.05])
    if paired:
        return wing
    keep = np.arange(len(wing.area)) != len(wing.area) - 1
    fields = ("area", "normal", "centre", "specular", "diffuse", "emissivity", "back_emissivity")
    return F.Facets(*(getattr(wing, name)[keep] for name in fields))


def _values(orbit: np.ndarray) -> dict:
    return {"orbit": orbit, "earth_rate": EARTH_ROTATION, "inverse_inertia": 1.0}


def _mean(orbit: np.ndarray, exact: bool, facets: F.Facets, nodes: int | None = None):
    table = air_table(facets, AIR)
    values = {**_values(orbit), "coefficients": coefficients(table), "exact": float(exact),
              "count": float(len(table)),
              "nodes": float(nodes or orbit_nodes(orbit[0], orbit[1]))}  # fmt: skip
    return compiled_term("aerodynamic_mean", values, tail=table.ravel())


def test_the_atmosphere_is_vallados_made_continuous():
    for (h0, rho0, scale), (h1, rho1, _), (_, _, printed) in zip(
        ATMOSPHERE_BANDS, ATMOSPHERE_BANDS[1:], EXPONENTIAL_ATMOSPHERE, strict=False
    ):
        # Continuous at each base to round-off, and Vallado's printed scale height is this one
        # rounded (within 0.05 %: 7.249 km for 7.252 at 25 km; 3e-5 elsewhere).
        assert rho0 * math.exp(-(h1 - h0) / scale) == pytest.approx(rho1, rel=1e-13)
        assert scale == pytest.approx(printed, rel=5e-4)
    assert ATMOSPHERE_BANDS[-1] == EXPONENTIAL_ATMOSPHERE[-1]


def test_the_moment_along_the_orbit_is_the_python_model():
    facets, orbit = _box_wing(), _orbit(300.0, 900.0)
    table = air_table(facets, AIR)
    prog = flatten([compiled_term("aerodynamic", {**_values(orbit), "count": float(len(table))},
                                  tail=table.ravel())])  # fmt: skip
    rng = np.random.default_rng(5)
    t = rng.uniform(0.0, 2.0 * 86400.0, 300)
    q = rng.normal(size=(t.size, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    got = moments(prog, t, q, np.zeros((1, 3)))
    states = orbit_states(orbit, t)
    flow = air_velocity(states[:, :3], states[:, 3:])
    density = exponential_density(np.linalg.norm(states[:, :3], axis=1) - EARTH_RADIUS)
    for k in range(t.size):
        body = quat_to_matrix(q[k]).T @ flow[k]
        want = aerodynamic_force_and_moment(facets, AIR, body, float(density[k]))[1]
        size = density[k] * float(body @ body) * float(np.sum(facets.area))
        # The same arithmetic in another order: round-off of the facets' sum.
        assert np.allclose(got[k], want, rtol=0.0, atol=1e-12 * size)


@pytest.mark.parametrize("exact", [True, False])
def test_the_orbit_averaged_moment_at_a_fixed_attitude(exact):
    facets, orbit = _box_wing(paired=False), _orbit(300.0, 900.0)
    prog = flatten([_mean(orbit, exact, facets)])
    rng = np.random.default_rng(3)
    t = rng.uniform(0.0, 30.0 * 86400.0, 12)
    q = rng.normal(size=(t.size, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    got = moments(prog, t, q, np.zeros((1, 3)))
    c0, c1, c2, c3 = expanded_tensors(air_table(facets, AIR))
    # The time average over one orbit, brute force: 4096 equal steps of the mean anomaly
    # (spectrally accurate for the smooth periodic integrand) with the node and perigee of t.
    mean = np.linspace(0.0, 2.0 * math.pi, 4096, endpoint=False)
    for k in range(t.size):
        o = orbit.copy()
        o[3], o[4], o[5] = o[3] + o[7] * t[k], o[4] + o[8] * t[k], 0.0
        states = orbit_states(o, mean / o[6])
        flow = air_velocity(states[:, :3], states[:, 3:])
        density = exponential_density(np.linalg.norm(states[:, :3], axis=1) - EARTH_RADIUS)
        body = flow @ quat_to_matrix(q[k])  # rows Aᵀ u
        if exact:
            each = _exact_moments(facets, body, density)
            # The vectorised moments are the Python model's (one node checked).
            want0 = aerodynamic_force_and_moment(facets, AIR, body[0], float(density[0]))[1]
            np.testing.assert_allclose(each[0], want0, rtol=1e-12, atol=1e-15)
        else:
            s = body / np.linalg.norm(body, axis=1, keepdims=True)
            q2 = density * np.sum(body * body, axis=1)
            each = q2[:, None] * (c0 + s @ c1.T + np.einsum("ijk,nj,nk->ni", c2, s, s)
                                  + np.einsum("ijkl,nj,nk,nl->ni", c3, s, s, s))  # fmt: skip
        want = np.mean(each, axis=0)
        size = float(np.max(np.linalg.norm(each, axis=1)))
        # The kernel's rule (orbit_nodes) neglects harmonics of 1e-8 of the density's, but this
        # orbit (300 × 900 km) crosses seven bases of the atmosphere's bands, where the slope of
        # ln ρ jumps: an O(N⁻²) error, and the exact illumination's kinks (a facet turning into
        # or out of the flow) add theirs. Measured: 2.5e-3 (expanded) and 6.8e-3 (exact) of the
        # largest moment along the orbit.
        tol = 1e-2
        assert np.allclose(got[k], want, rtol=0.0, atol=tol * size), (got[k], want)


def _exact_moments(facets: F.Facets, flow: np.ndarray, density: np.ndarray) -> np.ndarray:
    """The exact air moments [N·m] for the body flows (n, 3) [m/s] and densities (n,)."""
    table = air_table(facets, AIR)
    speed = np.linalg.norm(flow, axis=1)
    s = flow / speed[:, None]
    c = s @ facets.normal.T  # (n, facets)
    struck = np.where(c > 0.0, c, 0.0)
    along_n = table[:, 7] * struck + table[:, 8]
    f = -struck[:, :, None] * (table[:, 6][None, :, None] * s[:, None, :]
                               + along_n[:, :, None] * facets.normal[None, :, :])  # fmt: skip
    q = density * speed**2
    return q[:, None] * np.cross(facets.centre[None, :, :], f).sum(axis=1)


def test_the_number_of_orbit_nodes():
    # Circular and nearly circular: eight; it grows with κ = a e / H like √κ.
    assert orbit_nodes(EARTH_RADIUS + 5e5, 0.0) == 8
    assert orbit_nodes(EARTH_RADIUS + 5e5, 0.001) == 8
    assert orbit_nodes(EARTH_RADIUS + 5e5, 0.01) == 16
    counts = [orbit_nodes(*_orbit(250.0, apogee)[:2]) for apogee in (500.0, 2000.0, 35786.0)]
    assert counts == sorted(counts) and counts[-1] > 100
    for apogee in (500.0, 2000.0, 35786.0):
        a, e = _orbit(250.0, apogee)[:2]
        n = orbit_nodes(a, e)
        kappa = a * e / (1e3 * 45.546)  # H at 250 km
        assert special.ive(n - 3, kappa) <= 1e-8 * special.ive(0, kappa)
        assert special.ive(n - 7, kappa) > 1e-8 * special.ive(0, kappa)  # the fewest


@pytest.mark.parametrize(
    ("perigee", "apogee", "tol"), [(520.0, 590.0, 1e-8), (250.0, 2000.0, 3e-3)]
)
def test_the_rule_of_the_orbit(perigee, apogee, tol):
    facets, orbit = _box_wing(paired=False), _orbit(perigee, apogee)
    rng = np.random.default_rng(9)
    q = rng.normal(size=(6, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    t = np.zeros(6)
    n = orbit_nodes(orbit[0], orbit[1])
    rule = moments(flatten([_mean(orbit, False, facets)]), t, q, np.zeros((1, 3)))
    fine = moments(flatten([_mean(orbit, False, facets, 8 * n)]), t, q, np.zeros((1, 3)))
    # Within one band of the atmosphere (500–600 km) the rule's neglected harmonics are 1e-8
    # of the density's; across bands the kinks of ln ρ at their bases leave an O(N⁻²) error:
    # measured 1e-3 of the largest moment for the 250 × 2000 km orbit (76 nodes).
    assert np.max(np.abs(rule - fine)) <= tol * np.max(np.abs(fine))


@pytest.mark.parametrize("exact", [True, False])
def test_no_mean_moment_on_a_circular_orbit_for_paired_facets(exact):
    # Facets in opposite pairs with one accommodation (any closed box, a two-sided array):
    # M(−s) = −M(s); on a circular orbit the air's velocity is opposite at opposite points
    # (v − ω⊕ × r is linear in the state), so the orbit average is zero at every attitude.
    rng = np.random.default_rng(4)
    q = rng.normal(size=(20, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    t = rng.uniform(0.0, 1e6, 20)
    circular = _orbit(500.0, 500.0)
    for facets, orbit, zero in ((_box_wing(), circular, True),
                                (_box_wing(paired=False), circular, False),
                                (_box_wing(), _orbit(400.0, 600.0), False)):  # fmt: skip
        got = moments(flatten([_mean(orbit, exact, facets)]), t, q, np.zeros((1, 3)))
        table = air_table(facets, AIR)
        size = (
            exponential_density(5e5)
            * orbit[9]
            / orbit[0]
            * float(np.sum(table[:, 6:9].sum(axis=1) * np.linalg.norm(table[:, 3:6], axis=1)))
        )
        largest = float(np.max(np.abs(got)))
        # Round-off of the sum of nodes of size `size` (measured 1e-16 of it) against a
        # moment of 1e-3 of it or more when a pair is broken or the orbit eccentric.
        assert (largest < 1e-13 * size) if zero else (largest > 1e-4 * size), largest / size


def test_the_expanded_closed_form_equals_the_product_rule():
    facets, orbit = _box_wing(paired=False), _orbit(300.0, 900.0)
    torque = CompiledTorque((_mean(orbit, False, facets),), "air")
    kernel = triaxial_kernel(torque, INERTIA, rtol=1e-13)
    assert kernel is not None and kernel.kind == KIND_TRIAXIAL_CLOSED
    i1, i2, i3 = np.sort(INERTIA)
    rng = np.random.default_rng(12)
    for r in [*rng.uniform(1.0 / i3, 1.0 / i1, 8), 1.0002 / i3, 0.9998 / i1]:
        if abs(r * i2 - 1.0) < 1e-3:  # the separatrix band: refused
            continue
        y = np.array([*(2.0 * rng.normal(size=3)), r])
        t = rng.uniform(0.0, 30.0 * 86400.0)
        closed = evaluate(KIND_TRIAXIAL_CLOSED, t, y, kernel.params)
        product = evaluate(KIND_TRIAXIAL_AVERAGED, t, y, kernel.params)
        # Both exact for the cubic at each node; the product rule stops at 1e-13 of the
        # integrand's size (as sunlight's, measured ≤ 3e-15).
        assert np.max(np.abs(closed - product)) <= 1e-11 * np.max(np.abs(product)), (y, closed)


def test_the_mean_layout_reads_the_full_terms_air_fields():
    # _air reads the air's fields at the full layout's offsets in both terms.
    from tumble.kernels.terms.aerodynamic import LAYOUT

    for name in ("orbit", "earth_rate", "inverse_inertia"):
        assert getattr(MEAN_LAYOUT.at, name) == getattr(LAYOUT.at, name)
