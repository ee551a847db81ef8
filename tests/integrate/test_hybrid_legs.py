"""A hybrid run's averaged leg finds a band that one of its steps jumps whole."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tumble.integrate.hybrid import _averaged_leg
from tumble.models.base import AveragedForm, Crossing


def _drift(signed: bool) -> tuple[AveragedForm[None, None], Crossing]:
    # z' = −1 from z = 100: DOP853 integrates a constant rate exactly, so its steps grow
    # until one spans the band |z| < 3 about the resonance z = 0.
    def table(z: np.ndarray) -> dict[tuple[int, ...], float]:
        return {(1,): float(z[0])}

    crossing = Crossing(
        band=lambda z: abs(float(z[0])) / 3.0 - 1.0,
        band_full=lambda y: abs(float(y[0])) / 3.0 - 1.0,
        to_full=lambda t, z: z,
        to_mean=lambda t, y, z: y,
        label="a toy resonance",
        chunk=1.0,
        signed=table if signed else None,
    )
    form = AveragedForm(
        name="drift",
        equation="z' = -1",
        slow=("z",),
        rhs=lambda t, y, p: -np.ones_like(y),
        initial_state=lambda p, st: np.array([100.0]),
        to_columns=lambda p, st, t, Y: {"z": Y[:, 0]},
        crossing=crossing,
    )
    return form, crossing


@pytest.mark.parametrize("signed", [True, False])
def test_the_edge_of_a_jumped_band_is_found_inside_the_step(signed):
    form, crossing = _drift(signed)
    leg, _, entry, z = _averaged_leg(form, None, crossing, 0.0, np.array([100.0]), 300.0,
                                     1e-6, 1e-9)  # fmt: skip
    assert leg.steps.size < 20  # steps far longer than the band (6 time units)
    if not signed:  # the band's measure alone is positive at every step's end: jumped
        assert entry is None
        return
    # The edge z = 3 at t = 97, to the root finder's tolerance (1e-9 of a step).
    assert entry == pytest.approx(97.0, abs=1e-6)
    assert z[0] == pytest.approx(3.0, abs=1e-6)
    assert leg.t1 == entry and math.isclose(float(leg.states(np.array([entry]))[0, 0]), 3.0)
