"""The output columns of the rotating-field model: each variable's symbol, unit, long name and
equation, declared once."""

from __future__ import annotations

from tumble.models.base import Column, attitude_columns, mean_columns

__all__ = ["AVERAGED_COLUMNS", "DIAGNOSTIC_COLUMNS", "FULL_COLUMNS", "SLOW_COLUMNS"]

_T = Column("T", "kinetic energy T", "1", "(3.6)")
SLOW_COLUMNS = (
    Column("L", "angular momentum |L|", "1", "(3.5)"),
    Column("rho", "polar angle ρ of L from ξ3", "rad", "(3.5)"),
    Column("sigma", "inertial azimuth σ of L", "rad", "(3.5)", angle=True, unwrap=True),
    _T,
    Column("k2", "Euler–Poinsot modulus k² of the current regime", "1", "(3.7)"),
)
_COLUMNS_MEAN = mean_columns(
    (*(Column(f"L{i}", f"inertial angular momentum L_ξ{i}", "1", "(3.5)") for i in (1, 2, 3)), _T)
)
AVERAGED_COLUMNS = (*SLOW_COLUMNS, *_COLUMNS_MEAN)
"""The averaged runs' columns: L, ρ, σ, T, k², and the mean L_ξ, T of order 2."""
FULL_COLUMNS = (
    *SLOW_COLUMNS,
    Column("z1", "body angular velocity z1 = Ω1/ω", "1", "(1.5)"),
    Column("z2", "body angular velocity z2 = Ω2/ω", "1", "(1.5)"),
    Column("z3", "body angular velocity z3 = Ω3/ω", "1", "(1.5)"),
    *attitude_columns("τ"),  # ω1, ω2, ω3 = z1, z2, z3, as in every model
)
DIAGNOSTIC_COLUMNS = (
    Column("nu1", "polhode frequency ν1 = 2πν/4K", "1", "docs/theory/rotating-field.md §8"),
    Column("nu2", "mean precession rate ν2 about L", "1", "docs/theory/rotating-field.md §8"),
)
