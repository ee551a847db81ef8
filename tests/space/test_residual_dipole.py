"""The residual magnetic dipole, M = m × B: the compiled moment against the field evaluated
directly, the orbit-averaged field against its closed form for an axial dipole, the closed-form
Euler–Poinsot average against the quadrature, the orbiting body's averaged run against the full
one, and its scenario key."""

from __future__ import annotations

import dataclasses
import math
import tomllib
from datetime import UTC, datetime

import numpy as np
import pytest
from closed_forms import closed_and_quadrature
from files import EXAMPLES, write
from scipy.spatial.transform import Rotation
from typer.testing import CliRunner

from tumble.cli import app
from tumble.integrate import simulate
from tumble.io import parse_scenario
from tumble.kernels import terms
from tumble.kernels.space import DIPOLE
from tumble.kernels.terms import residual_dipole as rd
from tumble.space import Orbit
from tumble.space.geomagnetic import Dipole, Igrf
from tumble.torques import CompiledTorque

ENVISAT = EXAMPLES / "ob_envisat_like.toml"
M_USER = np.array([10.0, -3.0, 5.0])  # A m²


def _context(orbit: Orbit, field: Dipole | Igrf) -> terms.OrbitContext:
    return terms.OrbitContext(orbit.payload(), field.payload(), np.eye(3), 1.0, 1.0)


@pytest.mark.parametrize("harmonic", [False, True])
def test_the_moment_is_m_cross_the_field_at_the_bodys_place(harmonic):
    orbit = Orbit.circular(700.0, i=1.2, raan=0.4, u0=0.3)
    field = (
        Igrf.at(datetime(2020, 1, 1, tzinfo=UTC), degree=4)
        if harmonic
        else Dipole(-29000.0, -1500.0, 4500.0, 0.7)
    )
    label, full, _ = rd.build(M_USER, _context(orbit, field))
    assert label == "residual dipole"
    rng = np.random.default_rng(1)
    t = rng.uniform(0.0, 6000.0, 20)
    q = rng.normal(size=(20, 4))
    q /= np.linalg.norm(q, axis=1)[:, None]
    got = CompiledTorque(tuple(full))(t, q, rng.normal(size=(20, 3)))
    B, _ = field.along(orbit, t)  # inertial [T]
    A = Rotation.from_quat(q[:, [1, 2, 3, 0]]).as_matrix()  # body → inertial
    want = np.cross(M_USER, np.einsum("kji,kj->ki", A, B))
    # One formula evaluated twice in double precision: round-off of |m||B| (measured 9e-16).
    assert np.max(np.abs(got - want)) <= 1e-13 * np.max(np.abs(want))


def test_the_mean_field_of_an_axial_dipole_on_a_circular_orbit():
    # ⟨B⟩ = (1/r³)(3⟨r̂r̂ᵀ⟩ − 1) g with ⟨r̂r̂ᵀ⟩ = (1 − ĥĥᵀ)/2: for g = G ξ3,
    # ⟨B⟩ = (G/r³)(ξ3/2 − (3/2) cos i ĥ), whatever the Earth's turn.
    i, raan = 0.9, 0.4
    orbit = Orbit.circular(800.0, i=i, raan=raan, j2=False)
    field = Dipole(-29000.0, 0.0, 0.0, 0.3)
    payload = field.payload()
    G = payload[DIPOLE.at.gauss + 2]
    h = np.array([math.sin(raan) * math.sin(i), -math.cos(raan) * math.sin(i), math.cos(i)])
    want = G / orbit.a**3 * (np.array([0.0, 0.0, 0.5]) - 1.5 * math.cos(i) * h)
    got = rd.mean_field(orbit.payload(), payload)
    # The trapezoidal rule on a smooth periodic integrand: exact to round-off.
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * np.linalg.norm(want))


def test_the_closed_form_average_equals_the_quadrature():
    inertia = np.array([2.0, 3.1, 1.2])
    rng = np.random.default_rng(3)
    values = {"dipole": rng.normal(size=3), "field": rng.normal(size=3), "node_rate": -0.2}
    torque = CompiledTorque((terms.compiled_term("residual_dipole_mean", values),))
    for y, got, ref in closed_and_quadrature(torque, inertia, None, rng):
        # The quadrature refines the polhode to 1e-13 of the integrand and is exact in the
        # precession; the closed form is exact: round-off of the largest rate apart. The power
        # (the rate of r) is zero in both: the term does no work on average.
        assert np.max(np.abs(got - ref)) <= 1e-11 * np.max(np.abs(ref)), (y, got, ref)
        assert abs(got[3]) <= 1e-14 * np.max(np.abs(got))


def _envisat(dipole: list[float], days: float, samples: int) -> tuple[dict, object]:
    data = tomllib.loads(ENVISAT.read_text(encoding="utf-8"))
    data["torques"] = {"eddy_current": False, "gravity_gradient": False, "residual_dipole": dipole}
    data["run"] = {"t_end_days": days, "samples": samples, "methods": ["full", "averaged"]}
    return data, parse_scenario(data, str(ENVISAT)).request


def _directions(columns: dict) -> tuple[np.ndarray, np.ndarray]:
    L = np.stack([columns[f"L{i}"] for i in (1, 2, 3)], axis=1)
    size = np.linalg.norm(L, axis=1)
    return L / size[:, None], size


def _angles(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return np.degrees(np.arccos(np.clip(np.sum(u * v, axis=1), -1.0, 1.0)))


def test_averaged_against_full_for_a_dipole_alone():
    # An Envisat-like body with a 1000 A m² dipole along its spin axis and no other torque:
    # m × B does no work on average, so |L| stays put, and L precesses about the mean field
    # (23.5° in 3 days).
    _, request = _envisat([0.0, 0.0, 1000.0], 3.0, 13)
    p = request.params
    assert p.label == "residual dipole"
    runs = {
        "full": simulate(request.model, p, request.initial, request.tau, "full").columns,
        "averaged": simulate(request.model, p, request.initial, request.tau, "averaged").columns,
        # the full motion under the orbit-averaged torque: what the free-rotation average sees
        "orbit-averaged": simulate(
            request.model, dataclasses.replace(p, torque=p.mean_torque), request.initial,
            request.tau, "full",
        ).columns,
    }  # fmt: skip
    u = {m: _directions(c) for m, c in runs.items()}
    # |L| of the full run wobbles at the orbit's period by ~|m||B|/(L n) · (precession/spin)
    # (measured 1.6e-7); the averaged run's is constant to the integrator's tolerance.
    assert np.max(np.abs(u["full"][1] / u["full"][1][0] - 1.0)) <= 1e-6
    assert np.max(np.abs(u["averaged"][1] / u["averaged"][1][0] - 1.0)) <= 1e-9
    turn = _angles(u["full"][0][-1:], u["full"][0][:1])[0]
    assert turn >= 20.0
    # The free-rotation average (its small parameter the precession rate over the spin,
    # 1e-4): measured 2.8e-5 of the turn.
    assert np.max(_angles(u["averaged"][0], u["orbit-averaged"][0])) <= 1e-4 * turn
    # The orbit average: the full L wobbles about the averaged one at the orbit's and the
    # Earth's periods, by about |m||B|/(L n) = 0.3° here, a bounded gap (measured 0.61°, 2.6 %
    # of the turn, not growing from day to day); a wrong mean torque would leave a gap growing
    # with the turn.
    assert np.max(_angles(u["averaged"][0], u["full"][0])) <= 0.05 * turn


@pytest.mark.parametrize(
    ("value", "needle"),
    [
        ("[1e10, 0.0, 0.0]", "torques.residual_dipole"),
        ("[nan, 0.0, 0.0]", "torques.residual_dipole"),
        ('[0.0, 0.0, 1.0]\n\n[field]\nmodel = "none"', "needs a field"),
    ],
)
def test_bad_values_get_one_clear_line(tmp_path, value, needle):
    text = ENVISAT.read_text(encoding="utf-8").replace(
        "[initial]", f"[torques]\nresidual_dipole = {value}\n\n[initial]"
    )
    path = write(tmp_path, text)
    result = CliRunner().invoke(app, ["run", str(path), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    lines = [line for line in result.output.strip().splitlines() if line.strip()]
    assert len(lines) == 1 and needle in lines[0], result.output
