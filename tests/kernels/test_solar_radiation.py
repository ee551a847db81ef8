"""The compiled sunlight terms: the moment along the orbit against its Python transcription, the
orbit-averaged moment at a fixed attitude against the same, and the closed-form Euler–Poinsot
averages against quadrature: the expanded illumination against the product rule (both exact
for it), the exact illumination against a fine brute-force grid."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import special

from tumble.averaging import triaxial_kernel
from tumble.bodies import proper_sorting
from tumble.kernels import KIND_TRIAXIAL_AVERAGED, KIND_TRIAXIAL_CLOSED
from tumble.kernels.astro import AU, SOLAR_FLUX, SPEED_OF_LIGHT
from tumble.kernels.rhs import evaluate
from tumble.kernels.space import orbit_states
from tumble.kernels.sun import sun_samples
from tumble.kernels.terms import compiled_term, flatten
from tumble.kernels.terms.solar_radiation import coefficients
from tumble.kernels.torque import moments
from tumble.rotations import quat_to_matrix
from tumble.space import facets as F
from tumble.space.radiation import (
    expanded_coefficients,
    expanded_moment,
    radiation_force_and_moment,
)
from tumble.space.sun import eclipse_fraction, shadow
from tumble.torques import CompiledTorque, ConstantBodyTorque, QuadraticDrag

JD0 = 2460736.5  # 2025-03-01
DAY = 86400.0
# A GEO orbit with a tilt and a node, in metres and seconds (T0 = 1 s, I0 = 1 kg m²).
ORBIT = np.array([4.2164e7, 0.0, 0.3, 0.4, 0.0, 1.0, 7.2921e-5, -1e-9, 0.0, 3.986004418e14])
PRESSURE = SOLAR_FLUX / SPEED_OF_LIGHT  # at 1 AU [N/m²]
INERTIA = np.array([1750.0, 720.0, 1680.0])  # unsorted: the kernels read them through Q


def _box_wing() -> F.Facets:
    """A bus and a turned solar array off the centre of mass: no symmetry left."""
    bus = F.Optics(0.1, 0.3, 0.8, 0.0)
    cells = F.Optics(0.05, 0.05, 0.8, 0.6)
    wing = F.box_wing([2.0, 2.0, 2.3], bus, 12.0, [0.26, 0.0, 0.97], [0.0, 4.5, 0.0], cells)
    return wing.shifted([0.05, -0.24, 0.1])


def _sun(exact: bool, shadow_code: float = 1.0) -> dict:
    table = _box_wing().table()
    return {
        "orbit": ORBIT,
        "jd0": JD0,
        "days": 1.0 / DAY,
        "pressure": PRESSURE,
        "shadow": shadow_code,
        "coefficients": coefficients(table),
        "exact": float(exact),
        "count": float(len(table)),
    }


def _mean_torque(exact: bool) -> CompiledTorque:
    table = _box_wing().table()
    term = compiled_term("solar_radiation_mean", _sun(exact), tail=table.ravel())
    return CompiledTorque((term,), "sunlight")


@pytest.mark.parametrize("model", ["cylindrical", "conical", "none"])
def test_the_moment_along_the_orbit_is_its_python_transcription(model):
    facets = _box_wing()
    code = {"none": 0.0, "cylindrical": 1.0, "conical": 2.0}[model]
    values = {"orbit": ORBIT, "jd0": JD0, "days": 1.0 / DAY, "pressure": PRESSURE,
              "shadow": code, "count": float(len(facets))}  # fmt: skip
    prog = flatten([compiled_term("solar_radiation", values, tail=facets.table().ravel())])
    rng = np.random.default_rng(7)
    # Times through an eclipse season's shadow (the equinox) and random attitudes.
    t = np.concatenate([rng.uniform(0.0, 2.0 * DAY, 300), rng.uniform(0.0, 400.0 * DAY, 100)])
    q = rng.normal(size=(t.size, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    got = moments(prog, t, q, np.zeros((1, 3)))
    size = PRESSURE * float(np.sum(facets.area * np.linalg.norm(facets.centre, axis=1)))
    r = orbit_states(ORBIT, t)[:, :3]
    sun = sun_samples(JD0 + t * (1.0 / DAY))  # the Julian date formed as the term forms it
    s, d = sun[:, :3], sun[:, 3]
    to_sun = d[:, None] * s - r
    dist = np.linalg.norm(to_sun, axis=1)
    light = np.ones(t.size) if model == "none" else shadow(r, s, d, model)
    if model != "none":
        assert 0 < np.sum(light < 1.0) < t.size  # some samples in the shadow, most not
    for k in range(t.size):
        body = quat_to_matrix(q[k]).T @ (to_sun[k] / dist[k])
        want = radiation_force_and_moment(facets, body, PRESSURE * (AU / dist[k]) ** 2)[1]
        # The same arithmetic, but the compiler may fuse jd0 + days·t: one ulp of the Julian
        # date (~2.46e6 d), 5e-10 d, turns the Sun by 8e-12 rad, which the facets' moments,
        # 70 times their sum here, carry to 1e-10 of it (measured); and moves a penumbra's
        # edge by 4e-5 s of its ~2 min (the visible fraction by 3e-7). Scale: Σ P A |r|.
        tol = 1e-9 if light[k] in (0.0, 1.0) else 1e-6
        assert np.allclose(got[k], light[k] * want, rtol=0.0, atol=tol * size)


@pytest.mark.parametrize("exact", [True, False])
def test_the_orbit_averaged_moment_at_a_fixed_attitude(exact):
    facets = _box_wing()
    prog = flatten([compiled_term("solar_radiation_mean", _sun(exact),
                                  tail=facets.table().ravel())])  # fmt: skip
    rng = np.random.default_rng(3)
    t = rng.uniform(0.0, 365.0 * DAY, 60)
    q = rng.normal(size=(t.size, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    got = moments(prog, t, q, np.zeros((1, 3)))
    sun = sun_samples(JD0 + t * (1.0 / DAY))
    tensors = expanded_coefficients(facets)
    for k in range(t.size):
        # The eclipse fraction of the circular orbit: the Sun's elevation above its plane, the
        # node drifted to t.
        raan = ORBIT[3] + ORBIT[7] * t[k]
        normal = np.array([math.sin(ORBIT[2]) * math.sin(raan),
                           -math.sin(ORBIT[2]) * math.cos(raan), math.cos(ORBIT[2])])  # fmt: skip
        beta = math.asin(float(sun[k, :3] @ normal))
        scale = PRESSURE * (AU / sun[k, 3]) ** 2 * (1.0 - float(eclipse_fraction(ORBIT[0], beta)))
        body = quat_to_matrix(q[k]).T @ sun[k, :3]
        if exact:
            want = radiation_force_and_moment(facets, body, scale)[1]
        else:
            want = expanded_moment(tensors, body, scale)
        # Round-off of the moment (the cubic's 60 terms summed in another order), and of the
        # Julian date as above (1e-11 rad of the Sun).
        assert np.allclose(got[k], want, rtol=1e-10, atol=1e-10 * np.max(np.abs(want)))


def _states(rng: np.random.Generator, r_values) -> list[tuple[float, np.ndarray]]:
    out = []
    for r in r_values:
        L = rng.normal(size=3)
        out.append((rng.uniform(0.0, 365.0 * DAY), np.array([*(2.0 * L), r])))
    return out


@pytest.mark.parametrize("branch", [1.0, -1.0])
def test_the_expanded_closed_form_equals_the_product_rule(branch):
    # Both exact for the cubic: the closed form by its polhode cubature and five precession
    # angles, the product rule refined on every phase to rtol 1e-13; in both senses of
    # rotation, which a box-wing's sunlight tells apart.
    kernel = triaxial_kernel(_mean_torque(exact=False), INERTIA, rtol=1e-13, branch=branch)
    assert kernel is not None and kernel.kind == KIND_TRIAXIAL_CLOSED
    i1, i2, i3 = np.sort(INERTIA)
    rng = np.random.default_rng(11)
    r_values = [*rng.uniform(1.0 / i3, 1.0 / i1, 12), 1.0002 / i3, 0.9998 / i1]
    for t, y in _states(rng, r_values):
        if abs(y[3] * i2 - 1.0) < 1e-3:  # the separatrix band: refused
            continue
        closed = evaluate(KIND_TRIAXIAL_CLOSED, t, y, kernel.params)
        product = evaluate(KIND_TRIAXIAL_AVERAGED, t, y, kernel.params)
        # The product rule stops at 1e-13 of the integrand's size; measured ≤ 3e-15.
        assert np.max(np.abs(closed - product)) <= 1e-11 * np.max(np.abs(product)), (y, closed)


def test_without_its_closed_form_the_sunlight_average_refines_the_precession():
    # A term of degree 4 in the precession angle must not be averaged on its four nodes: with
    # a term that has no closed form the kernel takes the product rule.
    torque = _mean_torque(exact=False) + QuadraticDrag(np.diag([1e-3, 2e-3, 3e-3]))
    kernel = triaxial_kernel(torque, INERTIA)
    assert kernel is not None and kernel.kind == KIND_TRIAXIAL_AVERAGED
    kernel = triaxial_kernel(_mean_torque(exact=False) + ConstantBodyTorque([0.0, 1e-6, 0.0]),
                             INERTIA)  # fmt: skip
    assert kernel is not None and kernel.kind == KIND_TRIAXIAL_CLOSED


def _brute_force(
    y: np.ndarray, t: float, polhode: int, angles: int, branch: float = 1.0
) -> tuple[np.ndarray, float]:
    """(⟨A M⟩ inertial, ⟨ω·M⟩ − r L ⟨ℓ·M⟩) of the exact illumination without its shadow, on a
    grid: the polhode uniform in u (scipy's Jacobi functions), the precession angle uniform;
    ``branch`` −1: the other sense of rotation, the sn and dn components negated."""
    facets = _box_wing()
    L, r = float(np.linalg.norm(y[:3])), float(y[3])
    Q, (i1, i2, i3) = proper_sorting(INERTIA), np.sort(INERTIA)
    d1, d2, d3 = 1.0 - r * i1, 1.0 - r * i2, r * i3 - 1.0
    if d2 > 0.0:
        m = (i2 - i1) * d3 / ((i3 - i2) * d1)
        amp = (d3 / (i1 * (i3 - i1)), d3 / (i2 * (i3 - i2)), d1 / (i3 * (i3 - i1)))
        cols = (0, 1, 2)
    else:
        m = (i3 - i2) * d1 / ((i2 - i1) * d3)
        amp = (d1 / (i3 * (i3 - i1)), d1 / (i2 * (i2 - i1)), d3 / (i1 * (i3 - i1)))
        cols = (2, 1, 0)
    u = np.linspace(0.0, 4.0 * special.ellipk(m), polhode, endpoint=False)
    sn, cn, dn, _ = special.ellipj(u, m)
    w = np.zeros((polhode, 3))
    for row, (col, a) in enumerate(zip(cols, amp, strict=True)):
        w[:, col] = L * math.sqrt(a) * (cn, sn, dn)[row] * (branch if row else 1.0)
    ell = (w * np.sort(INERTIA) / L) @ Q  # the user's axes
    omega = w @ Q
    sun = sun_samples(np.array([JD0 + t / DAY]))[0]
    lhat = y[:3] / L
    along = float(sun[:3] @ lhat)
    f1 = sun[:3] - along * lhat
    across = float(np.linalg.norm(f1))
    F = np.column_stack([f1 / across, np.cross(lhat, f1 / across), lhat])  # s_L = (s⊥, 0, s∥)
    beta = 2.0 * math.pi * (np.arange(angles) + 0.5) / angles  # χ = −β
    total, power = np.zeros(3), 0.0
    for k in range(polhode):
        x = np.array([1.0, 0.0, 0.0]) if abs(ell[k, 0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e1 = np.cross(x, ell[k])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(ell[k], e1)
        sb = across * (np.cos(beta)[:, None] * e1 + np.sin(beta)[:, None] * e2) + along * ell[k]
        M = _moments(facets, sb)
        g1, g2, g3 = M @ e1, M @ e2, M @ ell[k]
        c, s_ = np.cos(-beta), np.sin(-beta)  # Rz(χ) of the L-frame
        total += F @ np.array([np.mean(c * g1 - s_ * g2), np.mean(s_ * g1 + c * g2), np.mean(g3)])
        power += float(np.mean(M @ omega[k]))
    scale = PRESSURE * (AU / sun[3]) ** 2 / polhode
    return scale * total, scale * (power - r * L * float(total @ lhat))


def _moments(facets: F.Facets, sb: np.ndarray) -> np.ndarray:
    """The exact moment [per N/m²] for each body direction of the Sun in sb (n, 3)."""
    table = facets.table()
    c = sb @ facets.normal.T  # (n, facets)
    lit = np.where(c > 0.0, c, 0.0)
    along_n = table[:, 7] * lit + table[:, 8]
    f = -lit[:, :, None] * (table[:, 6][None, :, None] * sb[:, None, :]
                            + along_n[:, :, None] * facets.normal[None, :, :])  # fmt: skip
    return np.cross(facets.centre[None, :, :], f).sum(axis=1)


@pytest.mark.parametrize("branch", [1.0, pytest.param(-1.0, marks=pytest.mark.slow)])
@pytest.mark.parametrize(
    "r",
    [
        0.5716,
        pytest.param(0.5780, marks=pytest.mark.slow),
        pytest.param(0.5850, marks=pytest.mark.slow),
        0.65,
        pytest.param(0.8, marks=pytest.mark.slow),
        pytest.param(1.0, marks=pytest.mark.slow),
        1.2,
        pytest.param(1.388, marks=pytest.mark.slow),
    ],
)  # the default suite: next to the major axis, and the worst two states (2.4 s each)
def test_the_exact_closed_form_against_a_fine_grid(r, branch):
    # r = 2T/L² [1/(1000 kg m²)] across both regimes: 1/I3 = 0.5714 (the major axis), the
    # separatrix 1/I2 = 0.5952, 1/I1 = 1.3889 (the minor axis).
    r = r * 1e-3
    table = _box_wing().table()
    values = {**_sun(True), "shadow": 0.0}
    torque = CompiledTorque((compiled_term("solar_radiation_mean", values, tail=table.ravel()),),
                            "sunlight")  # fmt: skip
    kernel = triaxial_kernel(torque, INERTIA, branch=branch)
    assert kernel is not None and kernel.kind == KIND_TRIAXIAL_CLOSED
    rng = np.random.default_rng(int(r * 1e7))
    for t, y in _states(rng, [r, r]):
        got = evaluate(KIND_TRIAXIAL_CLOSED, t, y, kernel.params)
        want, m4 = _brute_force(y, t, 1024, 1440, branch)
        size = float(np.linalg.norm(want))
        # The closed form is exact over the precession and takes the trapezoidal rule on 8
        # intervals of the quarter polhode, whose error comes from the kinks where a facet's lit
        # arc opens or closes (O(h^2.5)): measured from 4e-9 to 3.3e-3 of |⟨A M⟩| at these
        # states (the grid's own error, O(h²) in both phases, ~2e-5). The power term ω·M −
        # r L ℓ·M, of size |⟨A M⟩| L r, likewise (measured ≤ 6e-5 of that).
        assert np.linalg.norm(got[:3] - want) <= 5e-3 * size, (y, got, want)
        L = float(np.linalg.norm(y[:3]))
        assert abs(got[3] * L * L / 2.0 - m4) <= 5e-3 * size * L * r
