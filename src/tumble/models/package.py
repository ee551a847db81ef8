"""A model is a package, ``tumble.models.<name>``, whose ``__init__`` stays light: the
package's public names live in its ``model`` module (the registry record and the numerics it
gathers), loaded on first use, so that importing the package — or its ``inputs`` module, to
validate a scenario — loads no numba or scipy.

A package holds

* ``__init__.py``: the paper and the variables (docstring), and :func:`model_exports`;
* ``inputs.py``: parameters, initial state, physical units, scenario keys and ``DECLARED``
  (numpy and tumble's validation only);
* ``model.py``: the registry record ``MODEL``, built from ``DECLARED`` and the equations;
* ``columns.py`` and the equations (``full.py``, ``averaged.py``, …), as the model needs;
* ``display.py``: the run figure and the summary lines (:mod:`tumble.models.display`);
* ``template.toml``: the commented scenario ``tumble init`` prints.

docs/architecture.md ("Model packages") draws it and walks through adding one.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from collections.abc import Callable
from typing import Any

__all__ = ["model_exports"]


def model_exports(package: str) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of the model package ``package``.

    Parameters
    ----------
    package : str
        The package's dotted name, e.g. ``"tumble.models.torqued_body"``.

    Returns
    -------
    tuple of callable
        ``__getattr__(name)``: a name the package does not hold itself, looked up on
        ``<package>.model`` (imported on the first such lookup); ``__dir__()``: the package's
        names and the model module's public ones.
    """
    namespace = vars(sys.modules[package])
    # Whether a name is a submodule, found once: the search walks the file system, and the
    # models' numerics read names of their packages (``tb.FULL``) on every call.
    submodules: dict[str, bool] = {}

    def _model() -> Any:
        return importlib.import_module(f"{package}.model")

    def __getattr__(name: str) -> Any:
        if name.startswith("__"):  # dunder probes (pickle, doctest, …) do not load the numerics
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        if name not in submodules:
            submodules[name] = importlib.util.find_spec(f"{package}.{name}") is not None
        if submodules[name]:
            # A submodule: ``from <package> import inputs`` asks for it as an attribute
            # first, which must not load the numerics (validation stays light).
            return importlib.import_module(f"{package}.{name}")
        try:
            return getattr(_model(), name)
        except AttributeError:
            raise AttributeError(f"module {package!r} has no attribute {name!r}") from None

    def __dir__() -> list[str]:
        return sorted({*namespace, *getattr(_model(), "__all__", ())})

    return __getattr__, __dir__
