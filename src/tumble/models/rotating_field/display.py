"""What ``tumble run`` draws for the rotating-field model (:mod:`tumble.models.display`)."""

from tumble.models.display import FigureSettings

FIGURE = FigureSettings("evolution.png", "comparison", ("L", "rho", "T", "k2"))
"""The run figure: L, ρ, T and k², every method overlaid."""
