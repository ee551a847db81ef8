"""tumble: slow evolution of rigid-body rotation under small torques.

Full equations of motion, averaged (evolution) equations, exact unperturbed motions and the
closed forms of three papers (Medvedev 1987, Martynenko 1979, Serov 1991), with their
accuracy measured.

The entry points, one verb per action::

    import tumble
    sc = tumble.load_scenario("examples/a3_positive.toml")   # validate a scenario file
    result = tumble.run(sc, "out/a3")                         # run it (files when given a dir)
    check = tumble.verify(sc)                                 # averaged against full: the order
    tumble.sweep("examples/sweeps/rm_a3_line.toml", "out/sw") # a grid or Monte Carlo on Dask
    tumble.reproduce(["all"], "out/reproduce")                # every claim of the papers
    traj = tumble.simulate(tumble.get_model("resisting_medium"), p, initial, tau, "full")

The models are :mod:`tumble.models` (``tumble.models.resisting_medium`` and the others) and
the composable torques are exported here (``tumble.LinearDrag(...) + tumble.ConstantBodyTorque
(...)``). Submodules load on first use, so ``import tumble`` stays fast.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tumble._lazy import lazy_exports

# Public name → the module that defines it.
_EXPORTS: dict[str, str] = {
    "__version__": "tumble._version",
    "load_scenario": "tumble.io.scenario",
    "Scenario": "tumble.io.scenario",
    "run": "tumble.app.runner",
    "verify": "tumble.app.runner",
    "sweep": "tumble.app.sweep",
    "reproduce": "tumble.app.reproduce",
    "simulate": "tumble.integrate.simulate",
    "get_model": "tumble.models",
    "MODELS": "tumble.models",
    "Torque": "tumble.torques",
    "ConstantBodyTorque": "tumble.torques",
    "ConstantInertialTorque": "tumble.torques",
    "EddyCurrentTorque": "tumble.torques",
    "GravityGradientTorque": "tumble.torques",
    "InternalDissipation": "tumble.torques",
    "LinearDrag": "tumble.torques",
    "QuadraticDrag": "tumble.torques",
    "UserTorque": "tumble.torques",
    "TumbleError": "tumble.errors",
    "TumbleWarning": "tumble.errors",
}

__all__ = [
    "MODELS",
    "ConstantBodyTorque",
    "ConstantInertialTorque",
    "EddyCurrentTorque",
    "GravityGradientTorque",
    "InternalDissipation",
    "LinearDrag",
    "QuadraticDrag",
    "Scenario",
    "Torque",
    "TumbleError",
    "TumbleWarning",
    "UserTorque",
    "__version__",
    "get_model",
    "load_scenario",
    "reproduce",
    "run",
    "simulate",
    "sweep",
    "verify",
]

if TYPE_CHECKING:
    from tumble._version import __version__
    from tumble.app.reproduce import reproduce
    from tumble.app.runner import run, verify
    from tumble.app.sweep import sweep
    from tumble.errors import TumbleError, TumbleWarning
    from tumble.integrate.simulate import simulate
    from tumble.io.scenario import Scenario, load_scenario
    from tumble.models import MODELS, get_model
    from tumble.torques import (
        ConstantBodyTorque,
        ConstantInertialTorque,
        EddyCurrentTorque,
        GravityGradientTorque,
        InternalDissipation,
        LinearDrag,
        QuadraticDrag,
        Torque,
        UserTorque,
    )


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
