"""The registry record of the ``rotating_field`` model, with the names its package gives (the
package docstring, :mod:`tumble.models.rotating_field`, cites the paper)."""

from __future__ import annotations

from tumble.models.base import Diagnostics, Full, Model, Unperturbed, Validity, fixed_columns
from tumble.models.rotating_field.accuracy import (
    RESONANCE_ORDERS,
    VALIDITY_RATIO,
    diagnostics,
    validity,
)
from tumble.models.rotating_field.averaged import (
    SEPARATRIX_STEP,
    _averaged_form,
    averaged_kernel,
    averaged_rhs,
    averaged_rhs_k2,
    averaged_rhs_numeric,
    averaged_rhs_vector,
    field_average,
    modulus_rate,
    numeric_kernel,
)
from tumble.models.rotating_field.columns import AVERAGED_COLUMNS, DIAGNOSTIC_COLUMNS, FULL_COLUMNS
from tumble.models.rotating_field.full import (
    FULL_INERTIAL,
    FULL_ROTATING,
    _free_rhs,
    free_motion,
    full_from_slow,
    full_kernel,
    full_rhs,
    inertial_kernel,
    inertial_rhs,
    invariants,
    slow_elements,
    slow_from_full,
)
from tumble.models.rotating_field.inputs import (
    DECLARED,
    GAMMA_TOL,
    Params,
    PhysicalParams,
    Scaling,
    State,
    normalize_physical,
    state_from_elements,
)
from tumble.models.rotating_field.limits import final_nutation_decay_rate, predicted_limits
from tumble.models.rotating_field.linear import (
    approximate_roots,
    characteristic_coefficients,
    linear_matrix,
    stationary,
)

__all__ = [
    "FULL_INERTIAL",
    "FULL_ROTATING",
    "GAMMA_TOL",
    "MODEL",
    "RESONANCE_ORDERS",
    "SEPARATRIX_STEP",
    "VALIDITY_RATIO",
    "Params",
    "PhysicalParams",
    "Scaling",
    "State",
    "approximate_roots",
    "averaged_kernel",
    "averaged_rhs",
    "averaged_rhs_k2",
    "averaged_rhs_numeric",
    "averaged_rhs_vector",
    "characteristic_coefficients",
    "diagnostics",
    "field_average",
    "final_nutation_decay_rate",
    "free_motion",
    "full_from_slow",
    "full_kernel",
    "full_rhs",
    "inertial_kernel",
    "inertial_rhs",
    "invariants",
    "linear_matrix",
    "modulus_rate",
    "normalize_physical",
    "numeric_kernel",
    "predicted_limits",
    "slow_elements",
    "slow_from_full",
    "state_from_elements",
    "stationary",
    "validity",
]

# ---------------------------------------------------------------------------------------------
# Registry record.

MODEL: Model[Params, State] = DECLARED.model(
    Full.of(fixed_columns(FULL_COLUMNS), FULL_ROTATING, FULL_INERTIAL),
    averaged=DECLARED.averaged(
        _averaged_form,
        fixed_columns(AVERAGED_COLUMNS),
        # σ is left out: it is the azimuth of L about ξ3, undefined as the transient aligns L
        # with ξ3 (ρ → 0), where its error says nothing about the motion.
        compare=("L", "rho", "T"),
        diagnostics=Diagnostics(diagnostics, DIAGNOSTIC_COLUMNS),
    ),
    unperturbed=Unperturbed("the free body (3.1)", free_motion, _free_rhs),
    validity=Validity(check=validity, limits=predicted_limits),
    stationary=stationary,
)
