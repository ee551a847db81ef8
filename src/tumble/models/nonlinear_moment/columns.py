"""The output columns of the nonlinear-moment model: each variable's symbol, unit, long name
and equation, declared once."""

from __future__ import annotations

from tumble.models.base import Column, attitude_columns, mean_columns
from tumble.models.inputs.nonlinear_moment import Params

__all__ = ["AVERAGED_COLUMNS", "DIAGNOSTIC_COLUMNS", "UNPERTURBED_COLUMNS", "full_columns"]

_THETA = Column("theta", "nutation angle θ", "rad", "(1.9)")
_PSI = Column("psi", "precession angle ψ", "rad", "(1.13)", angle=True, unwrap=True)
_PHI = Column("phi", "proper rotation angle φ", "rad", "(1.13)", angle=True, unwrap=True)
_THETA_DOT = Column("theta_dot", "nutation rate θ'", "rad/t", "(1.2)")
_R = Column("R", "reduced axial momentum R = Cr/A", "1/t", "docs/theory/nonlinear-moment.md §1")
_G = Column(
    "G", "reduced momentum about e_z, G = K·e_z/A", "1/t", "docs/theory/nonlinear-moment.md §1"
)
_A = Column(
    "a", "sinθ coefficient a(τ) of M0/A", "1/t^2", "(1.5), docs/theory/nonlinear-moment.md §9"
)
_B = Column(
    "b", "sin2θ coefficient b(τ) of M0/A", "1/t^2", "(1.5), docs/theory/nonlinear-moment.md §9"
)
UNPERTURBED_COLUMNS = (_THETA, _PSI, _PHI, _THETA_DOT)
_PERTURBED_FULL = (_THETA, _PSI, _PHI, _R, _G, _A, _B)
_AVERAGED = (
    Column("theta_max", "envelope θmax (averaged)", "rad", "(2.2)"),
    Column("theta_min", "envelope θmin (averaged)", "rad", "(2.2)"),
    _R,
    _G,
    _A,
    _B,
)
_AVERAGED_MEAN = (
    Column("H_mean", "mean energy H̄ (averaging of order 2)", "1/t^2", "(1.6)"),
    *mean_columns((_R, _G, _A, _B)),
    Column("w_mean", "mean nutation phase w̄ from θmax (averaging of order 2)", "rad",
           "docs/theory/nonlinear-moment.md §4"),
)  # fmt: skip
AVERAGED_COLUMNS = (*_AVERAGED, *_AVERAGED_MEAN)
"""The averaged runs' columns: the envelope θmax, θmin, z = (R, G, a, b), and the mean
variables of order 2."""
DIAGNOSTIC_COLUMNS = (
    Column("k2", "modulus squared k² of the nutation", "1", "docs/theory/nonlinear-moment.md §4"),
    Column("period", "nutation period T", "t", "docs/theory/nonlinear-moment.md §4"),
    Column(
        "root_case",
        "root case (1: four real roots, 2: a complex pair)",
        "1",
        "docs/theory/nonlinear-moment.md §3",
    ),
    Column(
        "E",
        "energy H of (1.6) along the averaged solution",
        "1/t^2",
        "(1.6), docs/theory/nonlinear-moment.md §7",
    ),
)


def full_columns(p: Params) -> tuple[Column, ...]:
    """The full runs' columns for parameters ``p``: a perturbed run also writes the moment
    coefficients; every full run its attitude."""
    return (*(_PERTURBED_FULL if p.perturbed else UNPERTURBED_COLUMNS), *attitude_columns("t"))
