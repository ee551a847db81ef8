"""The inputs of the ``resisting_medium`` model under their former path: they are kept in its
package, :mod:`tumble.models.resisting_medium.inputs`, and this module gives the same names."""

from tumble.models.resisting_medium.inputs import *  # noqa: F403
from tumble.models.resisting_medium.inputs import __all__ as __all__
