"""Figures. Plot functions take data and an optional Axes and compute no physics."""

from tumble.plot.comparison import plot_comparison, plot_methods

__all__ = ["plot_comparison", "plot_methods"]
