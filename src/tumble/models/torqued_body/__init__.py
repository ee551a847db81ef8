"""A triaxial rigid body under any small torque, averaged by the general engine.

A model package (:mod:`tumble.models.package`): its names load from ``model`` on first use.
"""

from typing import TYPE_CHECKING

from tumble.models.package import model_exports

if TYPE_CHECKING:
    from tumble.models.torqued_body.model import *  # noqa: F403

__getattr__, __dir__ = model_exports(__name__)
