"""What each model's run figure shows: the figure's file, its kind and the slow variables
drawn. Settings of the figures, kept out of the models (which hold physics only)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

__all__ = ["FIGURES", "FigureSettings", "figure_settings"]


@dataclass(frozen=True, slots=True)
class FigureSettings:
    """The run figure of a model.

    Attributes
    ----------
    file : str
        File name in the output directory.
    kind : {"comparison", "envelope"}
        One panel per variable with every method overlaid (:func:`plot_comparison`), or θ(t)
        with its extrema and the averaged envelope (:func:`plot_envelope`).
    variables : tuple of str
        The columns drawn, one panel each (also the final values ``tumble run`` prints); empty:
        the averaged method's columns.
    log : tuple of str
        The variables drawn on a logarithmic axis.
    """

    file: str = "comparison.png"
    kind: Literal["comparison", "envelope"] = "comparison"
    variables: tuple[str, ...] = ()
    log: tuple[str, ...] = ()


FIGURES: dict[str, FigureSettings] = {
    "resisting_medium": FigureSettings("comparison.png", "comparison", ("k", "theta")),
    "rotating_field": FigureSettings("evolution.png", "comparison", ("L", "rho", "T", "k2")),
    "nonlinear_moment": FigureSettings(
        "envelope.png", "envelope", ("theta", "theta_max", "theta_min", "R", "G")
    ),
    "torqued_body": FigureSettings("evolution.png", "comparison", ("L", "rho", "sigma", "T")),
    "orbiting_body": FigureSettings(
        "spin.png", "comparison", ("period", "rate_deg_s", "orbit_angle"), log=("period",)
    ),
}
"""The registered models' figures, by model name."""


def figure_settings(model: str) -> FigureSettings:
    """The figure of ``model``; a comparison of the averaged columns if it has no entry."""
    return FIGURES.get(model, FigureSettings())
