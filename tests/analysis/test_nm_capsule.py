"""The entry capsule of docs/theory/nonlinear-moment.md §9–§10: envelope discrepancy and
cost."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tumble.analysis.capsule import capsule_attitude, capsule_study
from tumble.entry import ExponentialAtmosphere


@pytest.fixture(scope="module")
def capsule_runs():
    return {
        init: capsule_attitude(averaged_init=init, samples=401) for init in ("exact", "corrected")
    }


def test_pressure_profile_reproduces_the_descent(capsule_runs):
    run = capsule_runs["exact"]
    t = np.linspace(0.0, run.t_end - run.t_start, 2001)
    q = run.q(t) / run.q(np.array(0.0))
    a = run.params.ab(t)[0] / run.params.a
    # Quintic splines with ≤ 0.25 s nodes between the atmosphere's kinks: ~1e-6 relative.
    assert np.max(np.abs(a - q) / q) < 1e-5
    # The window starts where T·|q'|/q = 0.3 and ends at h = 10 km.
    assert run.eps_descent == pytest.approx(0.3, rel=1e-9)


def test_capsule_envelope_meets_the_papers_figure(capsule_runs):
    exact, corrected = capsule_runs["exact"], capsule_runs["corrected"]
    assert exact.envelope["n_max"] > 100  # ~136 nutation periods in the window
    # Theory §10 (iii): ≤ 4 % with the paper's initialisation at a descent ε of 0.3 …
    assert exact.envelope["max_relative"] < 0.04
    # … and the corrected initial state of §7 removes the O(ε) start error (issue: aim 1 %).
    assert corrected.envelope["max_relative"] < 0.01
    assert corrected.envelope["max_relative"] < 0.2 * exact.envelope["max_relative"]


def test_capsule_averaged_run_is_an_order_of_magnitude_cheaper(capsule_runs):
    run = capsule_runs["exact"]
    full, avg = run.trajectories["full"], run.trajectories["averaged"]
    # Theory §10 (ii) in right-hand-side evaluations (wall time is the benchmark's): each of
    # ~136 nutation periods costs the full run hundreds of evaluations.
    assert full.nfev > 10 * avg.nfev


def test_capsule_amplitude_follows_the_dynamic_pressure(capsule_runs):
    run = capsule_runs["exact"]
    maxima = np.array([(r[2], r[3]) for r in run.extrema if r[0] == "max"])
    t_peak = run.descent.t_peak - run.t_start
    before = maxima[maxima[:, 0] < t_peak, 1]
    after = maxima[maxima[:, 0] > t_peak + 20.0, 1]
    # Growing pressure shrinks the nutation, falling pressure lets it grow again.
    assert np.all(np.diff(before) < 0.0)
    assert after[-1] > after[0]
    assert before[0] < math.radians(70.0)


@pytest.mark.slow
def test_capsule_study_scaling():
    """The benchmark's accuracy figures (benchmarks/capsule.py): slopes against the descent's
    ε. Its wall-time ratio is a benchmark target, measured there, not asserted here."""
    for atmosphere, corrected_slope in ((None, None), (ExponentialAtmosphere(), 2.0)):
        kw = {} if atmosphere is None else {"atmosphere": atmosphere}
        rows = capsule_study(**kw)
        eps = np.array([r["eps_descent"] for r in rows])
        exact = np.array([r["discrepancy_exact"] for r in rows])
        corrected = np.array([r["discrepancy_corrected"] for r in rows])
        slope_exact = np.polyfit(np.log(eps), np.log(exact), 1)[0]
        # The paper's start leaves an O(ε) envelope error (§7, §10).
        assert abs(slope_exact - 1.0) < 0.25, exact
        if corrected_slope is not None:
            # Without the standard atmosphere's kinks in dq/dt the corrected start is O(ε²).
            slope = np.polyfit(np.log(eps), np.log(corrected), 1)[0]
            assert abs(slope - corrected_slope) < 0.35, corrected
        assert np.all(corrected < exact)
        base = rows[-1]  # the capsule itself, ε = 0.3
        assert base["discrepancy_exact"] < 0.04
