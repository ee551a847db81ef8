"""A rigid body in Earth orbit under the eddy-current torque of the geomagnetic field and the
gravity gradient, in physical units: the spin evolution of satellites and debris.

A model package (:mod:`tumble.models.package`): its names load from ``model`` on first use.
"""

from typing import TYPE_CHECKING

from tumble.models.package import model_exports

if TYPE_CHECKING:
    from tumble.models.orbiting_body.model import *  # noqa: F403

__getattr__, __dir__ = model_exports(__name__)
