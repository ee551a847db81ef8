"""The spin decay of the orbiting body's summary: the e-folding time over the first e-fold and
the floor of the rate, on a rate that decays exponentially and then stays flat, whose answer
is known exactly."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.optimize import brentq

from tumble.models.orbiting_body import FLOOR_FACTOR, spin_decay

# For ln r = −min(t, t_f)/τ, the least-squares slope over a window [s, s + τ] whose first
# fraction f decays is −(3f² − 2f³)/τ (the continuous fit): the window is flat (local
# e-folding time above N τ) once 3f² − 2f³ < 1/N, so the floor starts f* τ before t_f.
F_STAR = brentq(lambda f: 3 * f**2 - 2 * f**3 - 1.0 / FLOOR_FACTOR, 0.0, 1.0)


@given(
    tau=st.floats(0.5, 30.0),
    knee=st.floats(1.5, 5.0),  # t_f in e-folding times
    flat=st.floats(3.0, 8.0),  # the flat part in e-folding times
    r0=st.floats(1e-3, 1e3),
)
def test_a_decay_then_a_floor(tau, knee, flat, r0):
    t_f = knee * tau
    t = np.linspace(0.0, t_f + flat * tau, 4001)
    h = t[1]
    rate = r0 * np.exp(-np.minimum(t, t_f) / tau)
    decay = spin_decay(t, rate)
    # ln r is exactly linear over the first e-fold (t_f > τ): the fit returns τ to the
    # round-off of a least-squares line through ~1000 points (1e-9 leaves 1e3 of margin).
    assert decay.efolding == pytest.approx(tau, rel=1e-9)
    # The first sample down by e: within one step past τ. A sample on τ itself is i·h
    # rounded (a few ulps of t_end; 1e-12 of it is the slack), and its rate may round to
    # either side of r0/e.
    slack = 1e-12 * t[-1]
    assert tau - slack <= decay.fit_end <= tau + h + slack
    # The floor starts on a sample, at most one spacing after the continuous answer; the
    # discrete fit over τ/h ≥ 500 samples moves the threshold by a fraction of a spacing.
    assert decay.floor_time == pytest.approx(t_f - F_STAR * tau, abs=2 * h)
    # Most samples from there on are the floor itself: their median is it, to round-off.
    assert decay.floor_rate == pytest.approx(r0 * math.exp(-t_f / tau), rel=1e-12)


def test_a_pure_exponential_has_no_floor_and_a_flat_rate_no_efolding():
    t = np.linspace(0.0, 40.0, 401)
    decay = spin_decay(t, 3.0 * np.exp(-t / 4.0))
    assert decay.efolding == pytest.approx(4.0, rel=1e-12)  # exactly linear: round-off
    assert decay.floor_time is None and decay.floor_rate is None
    flat = spin_decay(t, np.ones_like(t))
    assert flat.efolding == math.inf and flat.floor_time is None


def test_the_efolding_time_does_not_depend_on_the_span():
    # The whole-run fit gave 7.2, 8.8, 14 and 23 for the same decay over longer runs once the
    # rate had levelled off; over the first e-fold it is τ whatever follows.
    tau, t_f = 7.0, 20.0
    for span in (30.0, 60.0, 90.0, 120.0):
        t = np.linspace(0.0, span, int(span * 10) + 1)
        decay = spin_decay(t, np.exp(-np.minimum(t, t_f) / tau))
        assert decay.efolding == pytest.approx(tau, rel=1e-9)  # round-off, as above
