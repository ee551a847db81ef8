"""The end state of the averaged rotating-field motion (§11) and the final nutation decay
rates at co-rotation (§12).
"""

from __future__ import annotations

import math
from typing import Any

from tumble.models.inputs.rotating_field import Params, State
from tumble.models.rotating_field.averaged import _initial_sigma


def final_nutation_decay_rate(p: Params, phase: float = 0.0) -> float:
    """Decay rate of k² (∝ nutation amplitude²) at co-rotation with phase φ, 2 Re λ2,3.

    ``2 Re λ2,3 = −ε [a (cos²φ + c² sin²φ) + b (c² cos²φ + sin²φ)]`` with
    ``a = (I3 − I2)/(I2 I3)``, ``b = (I3 − I1)/(I1 I3)`` (body x3 the largest axis, user
    labels). At φ = 0 this is (2.6); the co-rotations Γ = R3(φ) form a family (§5) and the
    phase a body settles at decides its final rate. The mean over φ is the linearization of
    (3.7) at k → 0, ρ = 0, −ε (1 + c²)(a + b)/2: averaging over the field phase is exact for
    this rate only on average (§12 compares with φ = 0 alone). Derived here by first-order
    perturbation of the linearization at Γ = R3(φ); tests check it against the exact roots.

    Parameters
    ----------
    p : Params
    phase : float
        φ [rad].

    Returns
    -------
    float
        d ln k²/dτ [1/τ], first order in ε.
    """
    I1, I2, I3 = p.inertia.tolist()
    a, b = (I3 - I2) / (I2 * I3), (I3 - I1) / (I1 * I3)
    cp, sp = math.cos(phase) ** 2, math.sin(phase) ** 2
    return -p.eps * (a * (cp + p.c2 * sp) + b * (p.c2 * cp + sp))


def predicted_limits(p: Params, st: State) -> dict[str, Any]:
    """End state of the averaged system, §11, and the final nutation decay rates, §12.

    For β ≠ 0: ρ → 0, k² → 0, L → I_max (co-rotation about the largest axis), T → I_max/2.
    For β = 0: L_ξ3 is conserved, ρ → 0 or π by the initial hemisphere, L → |L_ξ3(0)|.

    Parameters
    ----------
    p : Params
        The body (principal moments [inertia unit]) and the field (β [rad], ε).
    st : State
        The initial state (z [1], Γ), which fixes σ and, for β = 0, L_ξ3.

    Returns
    -------
    dict
        ``L`` [inertia unit], ``rho``, ``sigma`` [rad], ``T`` [1], ``k2`` [1] and the
        ``end_state`` in words; for I3 > I1 also the final nutation decay rates [1/τ] of the
        averaged equations (``nutation_decay_rate_averaged``), at the phase 0 (``_phase0``)
        and their range over the phase (``_range``).
    """
    I1, I2, I3 = p.sorted_inertia
    out: dict[str, Any] = {"sigma": _initial_sigma(p, st), "k2": 0.0}
    if p.s2 > 0.0:
        out.update(L=I3, rho=0.0, T=0.5 * I3, end_state="co-rotation about the largest axis")
    else:
        L3 = float((st.gamma @ (p.inertia * st.z))[2])
        out.update(
            L=abs(L3),
            rho=0.0 if L3 > 0 else (math.pi if L3 < 0 else float("nan")),
            T=0.5 * L3 * L3 / I3,
            end_state="spin about the static field along ξ3 (β = 0)",
        )
    # Nutation decay at the end: linearization of (3.7) vs 2 Re λ2,3 at the final phase, §12.
    if I3 > I1:
        rates = [final_nutation_decay_rate(p, phi) for phi in (0.0, 0.5 * math.pi)]
        out["nutation_decay_rate_averaged"] = (
            -p.eps * (1.0 + p.c2) / 2.0 * ((I3 - I2) / (I2 * I3) + (I3 - I1) / (I1 * I3))
        )
        out["nutation_decay_rate_phase0"] = rates[0]
        out["nutation_decay_rate_range"] = [min(rates), max(rates)]
    return out
