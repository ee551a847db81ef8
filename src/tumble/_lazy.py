"""Public names that load their module on first use (PEP 562), for package ``__init__``s that
must stay light: ``import tumble`` or ``import tumble.io.fileset`` loads neither numba, scipy
nor xarray until a name that needs them is used."""

from __future__ import annotations

import importlib
import sys
import types
from collections.abc import Callable
from typing import Any

__all__ = ["lazy_exports"]


class _Package(types.ModuleType):
    """A package some of whose public names are also its submodules' names (``run``, the
    function, from ``run``, the module): the import system binds a submodule to its name on
    the package once it is loaded, which would hide the function; such a binding is skipped
    (the submodule stays in ``sys.modules``), as an eager ``from .run import run`` would
    overwrite it."""

    _shadowed: frozenset[str] = frozenset()

    def __setattr__(self, name: str, value: Any) -> None:
        if name in self._shadowed and isinstance(value, types.ModuleType):
            return
        super().__setattr__(name, value)


def lazy_exports(
    package: str, exports: dict[str, str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of ``package`` for ``exports`` (name → module)."""
    module = sys.modules[package]
    shadowed = frozenset(n for n, m in exports.items() if m == f"{package}.{n}")
    if shadowed:
        module.__class__ = type("Package", (_Package,), {"_shadowed": shadowed})
    namespace = vars(module)

    def __getattr__(name: str) -> Any:
        module = exports.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        namespace[name] = value  # later lookups skip this function
        return value

    def __dir__() -> list[str]:
        # The public names (the exports and the loaded submodules) and the dunders, not what
        # the package imported for its own use (TYPE_CHECKING, annotations, this function).
        submodules = {
            n
            for n, v in namespace.items()
            if not n.startswith("_") and getattr(v, "__name__", None) == f"{package}.{n}"
        }
        dunders = {n for n in namespace if n.startswith("__") and n.endswith("__")}
        return sorted({*exports, *namespace.get("__all__", ()), *submodules, *dunders})

    return __getattr__, __dir__
