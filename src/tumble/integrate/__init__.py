"""Integration drivers: adaptive ODE solving and running a model's methods."""

from tumble.integrate.ode import DEFAULT_ATOL, DEFAULT_RTOL, DenseSolution, check_times, integrate
from tumble.integrate.simulate import MAX_STEPS, Method, Trajectory, simulate, simulate_batch

__all__ = [
    "DEFAULT_ATOL",
    "DEFAULT_RTOL",
    "MAX_STEPS",
    "DenseSolution",
    "Method",
    "Trajectory",
    "check_times",
    "integrate",
    "simulate",
    "simulate_batch",
]
