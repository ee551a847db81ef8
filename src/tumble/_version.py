"""The installed version of tumble (kept apart so that any layer can report it)."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("tumble")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"
