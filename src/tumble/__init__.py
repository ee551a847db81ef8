"""tumble: slow evolution of rigid-body rotation under small torques.

Full equations of motion, averaged (evolution) equations, exact unperturbed motions and
closed forms from the papers in ``shared/spec``, with their accuracy measured.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("tumble")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"

__all__ = ["__version__"]
