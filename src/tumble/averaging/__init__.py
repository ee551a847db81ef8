"""Averaging any torque over the unperturbed motion (issue 5): plain numerics below the models.

* :mod:`~tumble.averaging.quadrature`: adaptive periodic trapezoidal means over fast phases.
"""

from tumble.averaging.quadrature import AVERAGE_RTOL, AveragingError, torus_mean

__all__ = ["AVERAGE_RTOL", "AveragingError", "torus_mean"]
