"""Figures. Plot functions take data and an optional Axes and compute no physics."""

from tumble.plot.claims import claim_figure, claim_png
from tumble.plot.comparison import plot_comparison, plot_methods
from tumble.plot.envelope import plot_envelope
from tumble.plot.settings import FigureSettings, figure_settings
from tumble.plot.stability import (
    plot_classification,
    plot_leading_real_part,
    plot_stability_map,
    stability_map_bytes,
)
from tumble.plot.verify import plot_verify

__all__ = [
    "FigureSettings",
    "claim_figure",
    "claim_png",
    "figure_settings",
    "plot_classification",
    "plot_comparison",
    "plot_envelope",
    "plot_leading_real_part",
    "plot_methods",
    "plot_stability_map",
    "plot_verify",
    "stability_map_bytes",
]
