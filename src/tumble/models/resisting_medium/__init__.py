"""Fast-spinning symmetric gyroscope under a constant body-fixed moment in a resisting medium.

A. V. Medvedev, *Motion of a fast-spinning gyroscope under a constant moment in a resisting
medium* (1987). Equation numbers are the paper's; section numbers (§) are those of
``docs/theory/resisting-medium.md``, which states where tumble departs from the printed paper
and why (corrections E1–E10).

Everything here is in the paper's normalized variables (1.3): time τ, angular momentum
``k = |K|/K0``, inertia ``I1 = 1``, ``I3 = 1 + κ``, moment ``ε m`` with
``m = a − b w − s (w ∘ |w|)``, body angular velocity ``w = (p, q, r)``. Angles follow §2:
ρ, σ locate K in the inertial frame; ψ, ϑ, φ are the 3-1-3 Euler angles of the body in the
K-frame. The averaged system and its closed forms are written in the slow time ``s = ε τ``
internally and take τ at the interface.
"""

from __future__ import annotations

from tumble.models.base import ClosedForm, Full, Model, Unperturbed, Validity, fixed_columns
from tumble.models.inputs.resisting_medium import (
    DECLARED,
    Params,
    PhysicalParams,
    Scaling,
    State,
    normalize_physical,
)
from tumble.models.resisting_medium.accuracy import (
    RESONANCE_ORDER,
    VALIDITY_RATIO,
    moment_depends_on_phi,
    validity,
)
from tumble.models.resisting_medium.averaged import (
    _averaged_form,
    averaged_rhs,
    averaged_rhs_numeric,
    averaged_rhs_wv,
    mean_system,
    spinner_kernel,
)
from tumble.models.resisting_medium.closed_forms import (
    axial_lower_double_root,
    axial_lower_exp,
    axial_lower_tan,
    axial_momentum,
    axial_upper_double_root,
    axial_upper_exp,
    axial_upper_tan,
    closed_form,
    crossing_time,
    equatorial_momentum,
    tan_theta_a3_zero_lower,
    tan_theta_a3_zero_upper,
    tan_theta_quadratic,
)
from tumble.models.resisting_medium.columns import AVERAGED_COLUMNS, FULL_COLUMNS, SLOW_COLUMNS
from tumble.models.resisting_medium.full import (
    FULL_EULER,
    FULL_OSCULATING,
    full_from_slow,
    full_kernel,
    full_rhs,
    invariants,
    osculating_from_slow,
    osculating_rhs,
    slow_from_full,
    state_from_full,
)
from tumble.models.resisting_medium.limits import predicted_limits
from tumble.unperturbed.euler_poinsot import EulerPoinsot

__all__ = [
    "FULL_EULER",
    "FULL_OSCULATING",
    "MODEL",
    "RESONANCE_ORDER",
    "VALIDITY_RATIO",
    "Params",
    "PhysicalParams",
    "Scaling",
    "State",
    "averaged_rhs",
    "averaged_rhs_numeric",
    "averaged_rhs_wv",
    "axial_lower_double_root",
    "axial_lower_exp",
    "axial_lower_tan",
    "axial_momentum",
    "axial_upper_double_root",
    "axial_upper_exp",
    "axial_upper_tan",
    "closed_form",
    "crossing_time",
    "equatorial_momentum",
    "full_from_slow",
    "full_kernel",
    "full_rhs",
    "invariants",
    "mean_system",
    "moment_depends_on_phi",
    "normalize_physical",
    "osculating_from_slow",
    "osculating_rhs",
    "predicted_limits",
    "slow_from_full",
    "spinner_kernel",
    "state_from_full",
    "tan_theta_a3_zero_lower",
    "tan_theta_a3_zero_upper",
    "tan_theta_quadratic",
    "validity",
]

# ---------------------------------------------------------------------------------------------
# Registry record.

MODEL: Model[Params, State] = DECLARED.model(
    Full.of(fixed_columns(FULL_COLUMNS), FULL_EULER, FULL_OSCULATING),
    averaged=DECLARED.averaged(
        _averaged_form,
        fixed_columns(AVERAGED_COLUMNS),
        compare=("k", "rho", "sigma", "theta"),
    ),
    closed_form=ClosedForm(evaluate=closed_form, columns=fixed_columns(SLOW_COLUMNS)),
    unperturbed=Unperturbed(
        "the free symmetric body",
        lambda p, st: EulerPoinsot.from_rigid_body_state(p.inertia, full_from_slow(p, st)).states,
        lambda t, y, p: full_rhs(t, y, p.with_eps(0.0)),
    ),
    validity=Validity(check=validity, limits=predicted_limits),
)
