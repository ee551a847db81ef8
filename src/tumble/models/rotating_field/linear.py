"""The stationary co-rotation of the rotating-field model and its linearization
(2.1)–(2.6): the matrix of (2.4), the characteristic polynomial (2.5) and its
first-order roots (2.6).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.models.base import StationaryMotion
from tumble.models.inputs.rotating_field import Params
from tumble.models.rotating_field.accuracy import VALIDITY_RATIO
from tumble.models.rotating_field.full import _XI3, full_rhs
from tumble.rotations import rot_z


def _hat(v: Any) -> Any:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]], dtype=v.dtype)


# ---------------------------------------------------------------------------------------------
# Stationary rotation and its linearization (2.1)–(2.6).


def linear_matrix(p: Params) -> FloatArray:
    """The 5×5 matrix of the linearized system (2.4) in (x1, x2, x3, γ1, γ2).

    Parameters
    ----------
    p : Params

    Returns
    -------
    ndarray, shape (5, 5)
        J with (x, γ)′ = J (x, γ) [1].
    """
    I1, I2, I3 = p.inertia.tolist()
    e, c2, s2 = p.eps, p.c2, p.s2
    sc = 0.5 * e * math.sin(2.0 * p.beta)
    return np.array(
        [
            [-e * c2 / I1, -(I3 - I2) / I1, sc / I1, 0.0, -e * c2 / I1],
            [(I3 - I1) / I2, -e / I2, 0.0, e / I2, 0.0],
            [sc / I3, 0.0, -e * s2 / I3, 0.0, sc / I3],
            [1.0, 0.0, 0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0, -1.0, 0.0],
        ]
    )


def characteristic_coefficients(p: Params) -> FloatArray:
    """Coefficients a0 … a5 of the characteristic polynomial (2.5), highest power first.

    Exact for every ε (§6); ``a0 = I1 I2 I3``.

    Parameters
    ----------
    p : Params

    Returns
    -------
    ndarray, shape (6,)
    """
    I1, I2, I3 = p.inertia.tolist()
    e, c2, s2 = p.eps, p.c2, p.s2
    d2, d1 = I3 - I2, I3 - I1
    return np.array(
        [
            I1 * I2 * I3,
            e * (I1 * I3 + I1 * I2 * s2 + I2 * I3 * c2),
            I1 * I2 * I3 + d2 * d1 * I3 + e * e * (I1 * s2 + I3 * c2),
            e * I3 * d2 + e * (d2 * d1 + I1 * I2) * s2 + e * I3 * d1 * c2,
            d2 * d1 * I3 + e * e * d2 * s2,
            e * d2 * d1 * s2,
        ]
    )


def approximate_roots(p: Params) -> np.ndarray:
    """First-order roots (2.6), error O(ε²) where the unperturbed roots are simple.

    ``λ1 = −ε s²/I3``, ``λ2,3 = ±iω0 − (ε/2)[(I3 − I2)/(I2 I3) + (I3 − I1)/(I1 I3) c²]``,
    ``λ4,5 = ±i − ε (1 + c²)/(2 I3)``, ``ω0² = (I3 − I2)(I3 − I1)/(I1 I2)``; for ω0² < 0 (middle
    axis) ±iω0 is the real pair ∓|ω0|.

    Parameters
    ----------
    p : Params

    Returns
    -------
    ndarray of complex, shape (5,)
    """
    I1, I2, I3 = p.inertia.tolist()
    e, c2, s2 = p.eps, p.c2, p.s2
    w02 = (I3 - I2) * (I3 - I1) / (I1 * I2)
    iw0 = 1j * math.sqrt(w02) if w02 >= 0.0 else complex(math.sqrt(-w02))
    d23 = -0.5 * e * ((I3 - I2) / (I2 * I3) + (I3 - I1) / (I1 * I3) * c2)
    d45 = -e * (1.0 + c2) / (2.0 * I3)
    return np.array([-e * s2 / I3, iw0 + d23, -iw0 + d23, 1j + d45, -1j + d45])


def _approx_note(p: Params) -> str:
    I1, I2, I3 = p.inertia.tolist()
    w02 = (I3 - I2) * (I3 - I1) / (I1 * I2)
    small = p.eps / min(I1, I2, I3)
    if w02 == 0.0:
        return "(2.6) is invalid: I3 equals another moment, ω0 = 0 is a double root (§6)"
    if abs(math.sqrt(abs(w02)) - 1.0) <= small and w02 > 0.0:  # (2.6) needs ε/I ≪ |1 − ω0|
        return (
            "(2.6) is invalid: near a thin plate I3 ≈ I1 + I2 the roots ±iω0 and ±i (nearly) "
            "coincide, so the first-order corrections can be wrong at O(ε) (§6)"
        )
    if small > VALIDITY_RATIO:
        return f"(2.6) is a small-ε approximation; ε/min I = {small:.3g} is not small (§6)"
    return ""


def stationary(p: Params, phase: float = 0.0) -> StationaryMotion[Params]:
    """The stationary co-rotation (2.1) about body x3 and its linearization chart (2.2).

    The co-rotations form a family Γ = R3(φ), z = ξ3 (§5): the body's phase φ relative to
    the field is free. The paper linearizes at φ = 0 (Γ = E), where (2.5) and (2.6) hold; at
    other phases the field lies in another plane of the body and the decay rates differ (the
    family is reported by :attr:`StationaryMotion.family`).

    Parameters
    ----------
    p : Params
    phase : float
        φ of Γ = R3(φ) [rad]; 0 is the paper's (2.1).

    Returns
    -------
    StationaryMotion
        Local coordinates (x1, x2, x3, γ1, γ2, γ3) with z = ξ3 + x, Γ = R3(φ)(E + γ̂); γ3 (the
        free phase) decouples, so stability is decided on the first five (§5).
    """
    R = rot_z(phase)

    def embed(x: Any) -> Any:
        # Exact to first order in x, which is all the Jacobian at the stationary point needs.
        return np.concatenate([_XI3 + x[:3], (R @ (np.eye(3) + _hat(x[3:6]))).ravel()])

    def tangent(y: Any, dy: Any) -> Any:
        # γ̂′ = the skew part of R3(φ)ᵀ Γ′ (first order at Γ = R3(φ)).
        W = R.T @ dy[3:].reshape(3, 3)
        W = 0.5 * (W - W.T)
        return np.concatenate([dy[:3], [W[2, 1], W[0, 2], W[1, 0]]])

    paper = phase == 0.0
    coeffs = characteristic_coefficients(p) if paper else None
    return StationaryMotion(
        name="co-rotation about body x3 (2.1)" + ("" if paper else f", phase {phase:.6g} rad"),
        equation="(1.5) linearized as (2.3)/(2.4)",
        state=np.concatenate([_XI3, R.ravel()]),
        rhs=full_rhs,
        embed=embed,
        tangent=tangent,
        coordinates=("x1", "x2", "x3", "gamma1", "gamma2", "gamma3"),
        keep=(0, 1, 2, 3, 4),
        leading=float(np.prod(p.inertia)),
        coefficients=coeffs,
        approx_roots=approximate_roots(p) if paper else None,
        approx_note=_approx_note(p) if paper else "",
        structural_zero=bool(characteristic_coefficients(p)[5] == 0.0),
        family=(lambda phi: stationary(p, phi)) if paper else None,
    )
