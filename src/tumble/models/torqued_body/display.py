"""What ``tumble run`` draws for the torqued-body model (:mod:`tumble.models.display`)."""

from tumble.models.display import FigureSettings

FIGURE = FigureSettings("evolution.png", "comparison", ("L", "rho", "sigma", "T"))
"""The run figure: L, ρ, σ and T, every method overlaid."""
