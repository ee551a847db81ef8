"""Integration drivers: adaptive ODE solving and running a model's methods.

Names load their module on first use, so that a scenario's ``[run]`` table is checked
(:mod:`tumble.integrate.limits`) without loading the integrators.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tumble._lazy import lazy_exports

# Public name → the module that defines it.
_EXPORTS: dict[str, str] = {
    "DEFAULT_ATOL": "tumble.integrate.ode",
    "DEFAULT_RTOL": "tumble.integrate.ode",
    "DenseSolution": "tumble.integrate.ode",
    "integrate": "tumble.integrate.ode",
    "MAX_STEPS": "tumble.integrate.limits",
    "check_times": "tumble.integrate.limits",
    "Method": "tumble.integrate.simulate",
    "Trajectory": "tumble.integrate.trajectory",
    "simulate": "tumble.integrate.simulate",
    "simulate_batch": "tumble.integrate.simulate",
}

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

if TYPE_CHECKING:
    from tumble.integrate.limits import MAX_STEPS, check_times
    from tumble.integrate.ode import DEFAULT_ATOL, DEFAULT_RTOL, DenseSolution, integrate
    from tumble.integrate.simulate import Method, simulate, simulate_batch
    from tumble.integrate.trajectory import Trajectory

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
