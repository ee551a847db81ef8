"""Symmetric body under the nonlinear moment M0(θ) = A(a·sinθ + b·sin2θ): full motion, the
exact unperturbed motion, and Volosov's averaged equations for the nutation envelope.

V. M. Serov, *Rotational motion of a dynamically symmetric rigid body under the action of a
nonlinear moment* (1991). Equation numbers are the paper's; section numbers (§) are those of
``docs/theory/nonlinear-moment.md``, which states where tumble departs from the printed paper and
why (corrections S1–S16 of its §12: A is the equatorial moment; β, τ0, γ0, χ±, λ±, L± and the
coefficient of L±).

Variables (§1): time t in the unit of the coefficients (a, b [1/t²], R, G [1/t]),
μ = C/A, classical z–x–z Euler angles ψ, θ, φ of the body relative to the fixed axis e_z (for
an entry vehicle the velocity direction, θ the total angle of attack), R = μr and G = K·e_z/A
the reduced angular momenta. The perturbation of §9 (the entry capsule) has slow time τ = εt:
a = a0·Q(τ), b = b0·Q(τ) with the dynamic-pressure profile Q, pitch damping εd and roll
damping εν.

The averaged method integrates (2.2)–(2.3) for the slow variables: the energy H (form
``"energy"``, the better-conditioned one of §7) or the turning point θext (form
``"theta_max"``/``"theta_min"``, the paper's (2.2)), together with z = (R, G, a, b). The
averages come from the closed forms of §8 (⟨u⟩, ⟨u²⟩ by K, E, Π) for the built-in
perturbation, and from adaptive quadrature over the nutation period for any perturbation
given as Φθ(θ, θ', z), Φz(θ, z) (:class:`Perturbation`).
"""

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
from tumble.models.inputs.nonlinear_moment import DECLARED, Params, Pressure, State, orbit_of
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
