"""A triaxial rigid body under any small torque, averaged by the general engine.

The package of the ``torqued_body`` model: its registry record and equations in
:mod:`tumble.models.torqued_body.model` (whose names this package gives, loaded on first use),
its parameters, initial state and scenario keys in ``inputs``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tumble.models.package import model_exports

if TYPE_CHECKING:
    from tumble.models.torqued_body.model import *  # noqa: F403

__getattr__, __dir__ = model_exports(__name__)
