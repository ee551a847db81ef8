"""The inputs of the ``torqued_body`` model under their former path: they are kept in its
package, :mod:`tumble.models.torqued_body.inputs`, and this module gives the same names."""

from tumble.models.torqued_body.inputs import *  # noqa: F403
from tumble.models.torqued_body.inputs import __all__ as __all__
