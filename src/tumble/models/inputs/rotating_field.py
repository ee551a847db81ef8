"""The inputs of the ``rotating_field`` model under their former path: they are kept in its
package, :mod:`tumble.models.rotating_field.inputs`, and this module gives the same names."""

from tumble.models.rotating_field.inputs import *  # noqa: F403
from tumble.models.rotating_field.inputs import __all__ as __all__
