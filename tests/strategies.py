"""Hypothesis strategies: valid inertias, media, angles."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import strategies as st

finite = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)
angle = st.floats(-math.pi, math.pi, allow_nan=False)
theta_regular = st.floats(0.05, math.pi - 0.05)
rho_regular = st.floats(0.1, math.pi - 0.1)
kappa = st.one_of(st.floats(-0.8, -0.05), st.floats(0.05, 1.0))


@st.composite
def inertias(draw: st.DrawFn) -> tuple[float, float, float]:
    """Principal moments obeying the triangle inequality."""
    i1 = draw(st.floats(0.1, 10.0))
    i2 = draw(st.floats(0.1, 10.0))
    i3 = draw(st.floats(abs(i1 - i2) + 1e-3, i1 + i2 - 1e-3).filter(lambda x: x > 0.05))
    return i1, i2, i3


@st.composite
def vectors(draw: st.DrawFn, scale: float = 1.0) -> np.ndarray:
    return np.array([draw(finite) for _ in range(3)]) * scale


@st.composite
def matrices(draw: st.DrawFn, scale: float = 1.0) -> np.ndarray:
    return np.array([[draw(finite) for _ in range(3)] for _ in range(3)]) * scale


# Parameters of the built-in torques: body moment a, drags B and S, inertial moment M, the
# gravity gradient's mean motion n and orbit normal, the field's cone angle β, a time t.
TORQUE_PARAMETERS = {
    "a": vectors(),
    "B": matrices(),
    "S": matrices(),
    "M": vectors(),
    "n": st.floats(0.1, 3.0),
    "normal": vectors().filter(lambda v: np.linalg.norm(v) > 0.1),
    "beta": st.floats(0.0, math.pi),
    "t": st.floats(0.0, 50.0),
}
