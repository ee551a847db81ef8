"""The inputs of the ``nonlinear_moment`` model under their former path: they are kept in its
package, :mod:`tumble.models.nonlinear_moment.inputs`, and this module gives the same names."""

from tumble.models.nonlinear_moment.inputs import *  # noqa: F403
from tumble.models.nonlinear_moment.inputs import __all__ as __all__
