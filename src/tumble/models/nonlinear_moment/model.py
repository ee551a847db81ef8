"""The registry record of the ``nonlinear_moment`` model, with the names its package gives (the
package docstring, :mod:`tumble.models.nonlinear_moment`, cites the paper)."""

from __future__ import annotations

from tumble.averaging.nutation import (
    AVERAGE_RTOL,
    Perturbation,
    numeric_averages,
    potential_gradient,
    torque_perturbation,
)
from tumble.models.base import (
    ClosedForm,
    Diagnostics,
    Full,
    Model,
    Unperturbed,
    Validity,
    fixed_columns,
)
from tumble.models.nonlinear_moment.averaged import (
    _averaged_form,
    averaged_initial,
    averaged_rhs,
    barrier_energies,
    nutation_phase,
)
from tumble.models.nonlinear_moment.columns import (
    AVERAGED_COLUMNS,
    DIAGNOSTIC_COLUMNS,
    UNPERTURBED_COLUMNS,
    full_columns,
)
from tumble.models.nonlinear_moment.envelope import (
    EPS_PERIOD_LIMIT,
    NEAR_SEPARATRIX,
    _diagnostics,
    envelope_discrepancy,
    extrema,
    report,
    slow_errors,
    validity,
)
from tumble.models.nonlinear_moment.exact import closed_form, exact_motion, limits
from tumble.models.nonlinear_moment.full import (
    FULL_QUATERNION,
    FULL_REDUCED,
    full_from_slow,
    full_kernel,
    full_rhs,
    invariants,
    reduced_rhs,
    slow_from_full,
)
from tumble.models.nonlinear_moment.inputs import DECLARED, Params, Pressure, State, orbit_of
from tumble.models.nonlinear_moment.perturbation import (
    builtin_perturbation,
    damping_torque,
    engine_perturbation,
)

__all__ = [
    "AVERAGE_RTOL",
    "EPS_PERIOD_LIMIT",
    "FULL_QUATERNION",
    "FULL_REDUCED",
    "MODEL",
    "NEAR_SEPARATRIX",
    "Params",
    "Perturbation",
    "Pressure",
    "State",
    "averaged_initial",
    "averaged_rhs",
    "barrier_energies",
    "builtin_perturbation",
    "closed_form",
    "damping_torque",
    "engine_perturbation",
    "envelope_discrepancy",
    "exact_motion",
    "extrema",
    "full_from_slow",
    "full_kernel",
    "full_rhs",
    "invariants",
    "limits",
    "numeric_averages",
    "nutation_phase",
    "orbit_of",
    "potential_gradient",
    "reduced_rhs",
    "report",
    "slow_errors",
    "slow_from_full",
    "torque_perturbation",
    "validity",
]

# ---------------------------------------------------------------------------------------------
# Registry record.

MODEL: Model[Params, State] = DECLARED.model(
    Full.of(full_columns, FULL_QUATERNION, FULL_REDUCED),
    averaged=DECLARED.averaged(
        _averaged_form,
        fixed_columns(AVERAGED_COLUMNS),
        errors=slow_errors,
        diagnostics=Diagnostics(_diagnostics, DIAGNOSTIC_COLUMNS),
    ),
    closed_form=ClosedForm(evaluate=closed_form, columns=fixed_columns(UNPERTURBED_COLUMNS)),
    unperturbed=Unperturbed(
        "(1.9)-(1.13)", exact_motion, lambda t, y, p: full_rhs(t, y, p.unperturbed())
    ),
    validity=Validity(check=validity, limits=limits),
    report=report,
)
