"""The parameter layouts of the right-hand-side kinds: what each slot of a kind's parameter
array is, declared once (:class:`~tumble.kernels.layout.Layout`); the compiled readers take
their offsets from here, and the Python packers are checked against the same declarations."""

from __future__ import annotations

from tumble.kernels.layout import Field, Layout

__all__ = [
    "FIELD_AVERAGED",
    "MEDIUM_AVERAGED",
    "NONLINEAR_MOMENT",
    "NUTATION_ENGINE",
    "RIGID_BODY",
    "ROTATING_FIELD",
    "SPINNER_AVERAGED",
    "TRIAXIAL_AVERAGED",
]

_INERTIA = Field("inertia", 3, "inertia unit", "principal moments I1, I2, I3", 0.0)
_EPS = Field("eps", 1, "1", "small parameter ε, or the factor of the rates")

RIGID_BODY = Layout("rigid body", (_INERTIA,), tail="program")
"""``KIND_RIGID_BODY`` and ``KIND_ORBITING_BODY``: Euler's equations under a torque program
(:mod:`tumble.kernels.terms`)."""

ROTATING_FIELD = Layout(
    "rotating field",
    (_INERTIA, _EPS, Field("hh", 9, "1", "ĥĥᵀ of the field direction, by rows")),
)
"""``KIND_ROTATING_FIELD``: Martynenko (1979), eq. (1.5)."""

NONLINEAR_MOMENT = Layout(
    "nonlinear moment",
    (
        Field("mu", 1, "1", "μ = C/A"),
        Field("a", 1, "1", "a of M0 = A(a sinθ + b sin2θ) at Q(0)"),
        Field("b", 1, "1", "b at Q(0)"),
        _EPS,
        Field("d", 1, "1", "transverse damping"),
        Field("nu", 1, "1", "axial damping"),
        Field("pressure", 1, "1", "law of Q: 0 constant, 1 exponential, 2 table", 0.0, 2.0),
        Field("q0", 1, "1", "Q(0)"),
        Field("knots", 1, "1", "number n of the table's knots", 0.0),
    ),
    tail="table",  # τ_1..n, then Q_1..n (the averaged kinds append their own slots)
)
"""``KIND_NONLINEAR_MOMENT``, and the head of ``KIND_NUTATION_AVERAGED`` and
``KIND_NUTATION_ENGINE``: Serov (1991), eq. (1.1), with the capsule's damping and pressure."""

NUTATION_ENGINE = Layout(
    "nutation engine",
    (
        Field("u_hint", 1, "1", "cos θ inside the initial well: which well to follow", -1.0, 1.0),
        Field("rtol", 1, "1", "relative tolerance of the quadrature", 0.0),
    ),
    tail="program",
)
"""``KIND_NUTATION_ENGINE``: these slots and the torque program follow the nonlinear moment's
parameters and its pressure table (:data:`NONLINEAR_MOMENT`)."""

MEDIUM_AVERAGED = Layout(
    "medium averaged",
    (
        _EPS,
        Field("a3", 1, "1", "axial constant moment"),
        Field("alpha", 1, "1", "α: linear drag across the axis"),
        Field("beta", 1, "1", "β: linear drag along the axis"),
        Field("gamma", 1, "1", "γ: quadratic drag across the axis"),
        Field("delta", 1, "1", "δ: quadratic drag along the axis"),
        Field("form", 1, "1", "0: (2.2) in [k, ϑ]; 1: (2.3) in [W, V]", 0.0, 1.0),
        Field("kappa", 1, "1", "κ = I3/I1 − 1: the mean proper rotation's rate −κW/(1+κ)"),
        Field("phase_b", 1, "1", "(b21 − b12)/2: the linear drag's mean turn of φ"),
        Field("phase_s", 1, "1", "4(s21 − s12)/(3π): the quadratic drag's, per unit V"),
    ),
)
"""``KIND_MEDIUM_AVERAGED``: Medvedev (1987), eqs. (2.2)–(2.3); a third state component, if
present, is the mean proper rotation φ̄ (the passage of ϑ = π/2 needs its phase)."""

FIELD_AVERAGED = Layout(
    "field averaged",
    (
        _EPS,
        Field("s2", 1, "1", "sin²β", 0.0, 1.0),
        Field("c2", 1, "1", "cos²β", 0.0, 1.0),
        Field("inertia", 3, "inertia unit", "principal moments, ascending", 0.0),
    ),
)
"""``KIND_FIELD_AVERAGED``: the vector form of the averaged equations of Martynenko (1979)."""

SPINNER_AVERAGED = Layout(
    "spinner averaged",
    (
        Field("kappa", 1, "1", "κ = C/A − 1"),
        Field("rtol", 1, "1", "the Python engine's tolerance (unused: the means are exact)", 0.0),
    ),
    tail="program",
)
"""``KIND_SPINNER_AVERAGED`` (:mod:`tumble.kernels.spinner`)."""

TRIAXIAL_AVERAGED = Layout(
    "triaxial averaged",
    (
        _EPS,
        Field("rtol", 1, "1", "relative tolerance of the quadrature", 0.0),
        Field("floor", 1, "momentum unit", "|L| below which the rates are those of rest", 0.0),
        Field("inertia", 3, "inertia unit", "principal moments, ascending", 0.0),
        Field("sorting", 9, "1", "Q: sorted axes ← user axes, by rows"),
        Field("user_inertia", 3, "inertia unit", "principal moments in the user's order", 0.0),
        Field("period", 1, "time", "forcing period (0: none)", 0.0),
        Field("branch", 1, "1", "sense of rotation about the encircled axis (±1)", -1.0, 1.0),
    ),
    tail="program",
)
"""The triaxial engine's kinds (``KIND_TRIAXIAL_*``, :mod:`tumble.kernels.triaxial`): the torque
program follows."""
