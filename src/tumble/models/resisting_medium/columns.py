"""The output columns of the resisting-medium model: each variable's symbol, unit, long name
and equation, declared once."""

from __future__ import annotations

from tumble.models.base import Column, attitude_columns, mean_columns

__all__ = ["AVERAGED_COLUMNS", "FULL_COLUMNS", "SLOW_COLUMNS"]

_ANGLE = "rad"
SLOW_COLUMNS = (
    Column("k", "angular momentum |K|/K0", "1", "(1.3)"),
    Column("theta", "nutation angle ϑ between x3 and K", _ANGLE, "(1.3)", angle=False),
    Column("rho", "polar angle ρ of K from X3", _ANGLE, "(1.3)"),
    Column("sigma", "azimuth σ of K about X3", _ANGLE, "(1.3)", angle=True, unwrap=True),
)
_PSI = Column("psi", "precession angle ψ of x3 about K", _ANGLE, "(1.3)", angle=True)
_PHI = Column("phi", "proper rotation angle φ", _ANGLE, "(1.3)", angle=True)
_COLUMNS_MEAN = mean_columns((*SLOW_COLUMNS, _PSI, _PHI))
AVERAGED_COLUMNS = (*SLOW_COLUMNS, *_COLUMNS_MEAN)
"""The averaged runs' columns: k, ϑ, ρ, σ, and the mean variables of order 2."""
FULL_COLUMNS = (
    *SLOW_COLUMNS,
    Column(_PSI.name, _PSI.long_name, _ANGLE, "(1.3)", angle=True, unwrap=True),
    Column(_PHI.name, _PHI.long_name, _ANGLE, "(1.3)", angle=True, unwrap=True),
    *attitude_columns("τ"),
)
