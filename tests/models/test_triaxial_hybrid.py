"""Hybrid runs of the triaxial setting (rotating field, torqued body): the maps between the
mean state and the full one at the hand-overs, the torus a run returns onto, and runs that
cross resonance bands and the polhode separatrix on the full equations."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from tumble.averaging.triaxial_second import TriaxialSystem
from tumble.rotations import quat_normalize, quat_to_matrix
from tumble.torques import ConstantBodyTorque


def _no_torque(t, q, w):
    return np.zeros_like(w)


@pytest.mark.parametrize("period", [None, 2.0 * math.pi])
def test_the_state_at_the_phases_of_a_state_is_that_state(period):
    # state_at is the forward map at one point, phases_of its inverse: 20 random states of
    # both regimes, any axis order. phases_of's search finds the polhode time to about
    # √(1e-16) of the period (4.6e-9 in the states), its Gauss–Newton steps to round-off:
    # measured 3.0e-15; the bound leaves a thousand times that.
    rng = np.random.default_rng(1)
    worst = 0.0
    for _ in range(20):
        inertia = np.array([1.0, 2.0, 3.0])[rng.permutation(3)]
        omega = rng.normal(size=3)
        A = quat_to_matrix(quat_normalize(rng.normal(size=4)))
        system, x, w = TriaxialSystem.through(inertia, _no_torque, 0.01, omega, A, period)
        omega2, A2 = system.state_at(x, w)
        worst = max(worst, float(np.abs(omega2 - omega).max()), float(np.abs(A2 - A).max()))
    assert worst < 1e-12


def test_a_return_onto_the_other_torus_leaves_the_earlier_terms_on_theirs():
    # A body in regime x1 on the torus of positive ω1; from t = 5 on, the mirror one. The
    # terms at t = 1 are those of the first torus (the same numbers as before the return),
    # those at t = 6 the mirror's, and both tori give the same frequencies.
    inertia = np.array([1.0, 2.0, 3.0])
    torque = ConstantBodyTorque([0.1, -0.2, 0.15])
    omega = np.array([1.0, 0.3, 0.2])
    system, x, _ = TriaxialSystem.through(inertia, torque, 1e-2, omega, np.eye(3))
    before = system.terms(1.0, x)
    system.reorient(5.0, x, -omega)
    assert system.sign == -1.0
    again, mirror = system.terms(1.0, x), system.terms(6.0, x)
    assert np.array_equal(again.first, before.first)
    assert not np.allclose(mirror.first, before.first)
    assert mirror.frequencies == pytest.approx(before.frequencies, rel=1e-14)


def test_a_full_states_bands_are_read_on_its_own_torus():
    # A full leg may cross the separatrix onto either torus: the band of a full state is read
    # on the torus of its own body rate, the same table as after a return onto that torus.
    inertia = np.array([1.0, 2.0, 3.0])
    torque = ConstantBodyTorque([0.1, -0.2, 0.15])
    omega = np.array([1.0, 0.3, 0.2])
    system, x, _ = TriaxialSystem.through(inertia, torque, 1e-2, omega, np.eye(3))
    mirror = system.resonances(0.0, x, -omega)
    assert system.resonances(0.0, x, omega) != mirror  # the torque tells the two apart
    system.reorient(1.0, x, -omega)
    assert system.resonances(2.0, x) == mirror
    assert system.resonances(0.5, x) == system.resonances(0.0, x, omega)


def _rf_request(eps: float):
    import tomllib

    from files import EXAMPLES

    from tumble.io import parse_scenario

    data = tomllib.loads((EXAMPLES / "rf_transient_x1.toml").read_text())
    data["parameters"]["eps"] = eps
    return parse_scenario(data, "rf_transient_x1.toml").request


def test_the_hand_over_maps_are_inverse():
    # The rotating field's example at ε = 1e-3, at t = 40 (2.3 widths out of the nearest
    # band): mean → full → mean gives the mean state back to the fixed point's tolerance,
    # and the full state is that of (1.5), Γ by rows a rotation.
    req = _rf_request(1e-3)
    options = replace(req.averaging, order=2, hybrid=True)
    form = req.model.averaged.form(req.params, req.initial, options)
    crossing = form.crossing
    z = form.initial_state(req.params, req.initial)
    z[4:] += [0.4, 1.1, 40.0]  # phases of t = 40 (the forcing's is the time)
    y = crossing.to_full(40.0, z)
    G = y[3:].reshape(3, 3)
    assert G @ G.T == pytest.approx(np.eye(3), abs=1e-13)
    back = crossing.to_mean(40.0, y, z)
    # the slow part and the phases (mod 2π) to the map's fixed point (MAP_TOL 1e-13 of the
    # scale; the generator's phase part from differences between neighbouring motions, ~1e-11
    # in the phases): measured 5.3e-14 and 1.2e-12; bounds 20× and 100× those
    assert back[:4] == pytest.approx(z[:4], abs=1e-12)
    turn = np.angle(np.exp(1j * (back[4:] - z[4:])))
    assert np.abs(turn).max() < 1e-10
    assert crossing.band_full(y) == pytest.approx(crossing.band(z), abs=0.05)


@pytest.mark.slow
@pytest.mark.parametrize(("order", "bound"), [(1, 0.5), (2, 0.2)])
def test_a_hybrid_run_carries_the_direction_of_l_through_the_separatrix(order, bound):
    # The damper-and-drag example at ε = 1e-3 (a spin about x1 taken through the separatrix
    # to x3): the plain averaged run errs by 4.8ε in L, the kick of the passage of
    # ν2 = 2ν1 at τ ≈ 1648 (tests/averaging/test_crossing.py), which a first-order run
    # without mean phases cannot follow. The hybrid run in mean variables hands the band to
    # the full equations (τ ≈ 1507 … 2151: the passage and the separatrix) and returns
    # through the map: measured 0.12ε (order 1) and 0.03ε
    # (order 2) in L, T within 2e-6. Bounds: 4× and 7× the measured, far below the plain
    # run's 4.8ε.
    from tumble.analysis.verify import slow_errors
    from tumble.app.bench_crossings import request_at
    from tumble.integrate import simulate

    eps = 1e-3
    req = request_at("tb_damper_crossing", eps)
    options = replace(req.averaging, order=order, hybrid=True)
    run = simulate(req.model, req.params, req.initial, req.tau, "averaged", rtol=1e-9,
                   atol=1e-12, averaging=options)  # fmt: skip
    assert [kind for kind, _, _ in run.legs] == ["averaged", "full", "averaged"]
    ref = simulate(req.model, req.params, req.initial, req.tau, "full", rtol=1e-11, atol=1e-13)
    errors = slow_errors(req.model, req.params, ref, run)
    worst_L = max(float(errors[f"L{i}"][1].max()) for i in (1, 2, 3))
    assert worst_L < bound * eps
    assert float(errors["T"][1].max()) < 1e-5


@pytest.mark.parametrize(
    ("run", "hybrid"),
    [
        ({}, False),
        ({"averaging_order": 2}, True),  # auto: order 2 would stop at the first band
        ({"averaging_order": 2, "averaged_method": "plain"}, False),
        ({"averaged_method": "hybrid"}, True),
    ],
)
def test_a_run_of_order_2_is_hybrid_unless_asked_plain(run, hybrid):
    import tomllib

    from files import EXAMPLES

    from tumble.io import parse_scenario

    data = tomllib.loads((EXAMPLES / "rf_transient_x1.toml").read_text())
    data["run"].update(run)
    assert parse_scenario(data, "rf_transient_x1.toml").request.averaging.hybrid is hybrid
