"""A rigid body in Earth orbit under the eddy-current torque of the geomagnetic field and the
gravity gradient, in physical units: the spin evolution of satellites and debris.

The package of the ``orbiting_body`` model: its registry record and equations in
:mod:`tumble.models.orbiting_body.model` (whose names this package gives, loaded on first use),
its parameters, initial state and scenario keys in ``inputs``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tumble.models.package import model_exports

if TYPE_CHECKING:
    from tumble.models.orbiting_body.model import *  # noqa: F403

__getattr__, __dir__ = model_exports(__name__)
