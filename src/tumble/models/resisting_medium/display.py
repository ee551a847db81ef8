"""What ``tumble run`` draws for the resisting-medium model (:mod:`tumble.models.display`)."""

from tumble.models.display import FigureSettings

FIGURE = FigureSettings("comparison.png", "comparison", ("k", "theta"))
"""The run figure: k and θ, every method overlaid."""
