"""The registry record of the ``resisting_medium`` model, with the names its package gives (the
package docstring, :mod:`tumble.models.resisting_medium`, cites the paper)."""

from __future__ import annotations

from tumble.models.base import ClosedForm, Full, Model, Unperturbed, Validity, fixed_columns
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
from tumble.models.resisting_medium.inputs import (
    DECLARED,
    Params,
    PhysicalParams,
    Scaling,
    State,
    normalize_physical,
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
