"""Axis labels from a quantity's name and units, the way the figures of every command write
them: "name [units]", with no brackets for a dimensionless quantity ("1") or one in the model's
own abstract time unit ("t"), where "[1]" or "[t]" would say nothing."""

from __future__ import annotations

__all__ = ["with_units"]

_SILENT = ("", "1", "t")


def with_units(name: str, units: str) -> str:
    """``name [units]``, or ``name`` alone for a dimensionless or model-time quantity."""
    return str(name) if str(units) in _SILENT else f"{name} [{units}]"
