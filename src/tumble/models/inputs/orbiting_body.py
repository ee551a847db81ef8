"""The inputs of the ``orbiting_body`` model under their former path: they are kept in its
package, :mod:`tumble.models.orbiting_body.inputs`, and this module gives the same names."""

from tumble.models.orbiting_body.inputs import *  # noqa: F403
from tumble.models.orbiting_body.inputs import __all__ as __all__
