"""What ``tumble run`` draws for the orbiting-body model (:mod:`tumble.models.display`)."""

from tumble.models.display import FigureSettings

FIGURE = FigureSettings(
    "spin.png", "comparison", ("period", "rate_deg_s", "orbit_angle"), log=("period",)
)
"""The run figure: spin period (logarithmic axis), spin rate and the angle between L and the
orbit normal, every method overlaid."""
