"""Paper models, one package each, registered by name (docs/architecture.md, "Model packages").

The registry loads on first use (:data:`MODELS`, :func:`get_model`): a scenario is validated
against a model's :class:`~tumble.models.base.Declaration` (:func:`declaration`), which the
shipped models keep apart from their numerics in the ``inputs`` module of their package.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from tumble.catalogue import CATALOGUE
from tumble.errors import ScenarioError, shorten
from tumble.models.base import Declaration, Model

__all__ = [
    "MODELS",
    "AnyModel",
    "declaration",
    "get_model",
    "names",
    "nonlinear_moment",
    "orbiting_body",
    "register",
    "resisting_medium",
    "rotating_field",
    "torqued_body",
]

AnyModel = Model[Any, Any]
"""A registered model of any parameter and state types (the registry's view: each model is
typed with its own Params and State where it is defined)."""

_MODELS: dict[str, AnyModel] = {}
_LOADED = False


def _registry() -> dict[str, AnyModel]:
    """Every registered model by name, the shipped ones first (loaded on the first call)."""
    global _LOADED
    if not _LOADED:
        shipped = {
            name: importlib.import_module(f"tumble.models.{name}").MODEL for name in CATALOGUE
        }
        others = dict(_MODELS)
        _MODELS.clear()
        _MODELS.update(shipped)
        _MODELS.update(others)
        _LOADED = True
    return _MODELS


def register(model: AnyModel) -> AnyModel:
    """Add ``model`` to :data:`MODELS` under its name (a ValueError if the name is taken)."""
    models = _registry()
    if model.name in models and models[model.name] is not model:
        raise ValueError(f"a model called {model.name!r} is already registered")
    models[model.name] = model
    return model


def _unknown(name: object) -> ScenarioError:
    known = sorted(names())
    return ScenarioError(
        f"model = {shorten(repr(name), 60)} is not a known model (allowed: {', '.join(known)})"
    )


def names(*, scenario: bool = False) -> list[str]:
    """The names of every model, shipped first, without loading any; ``scenario``: only those
    a scenario file can name (every shipped one does)."""
    others = [n for n, m in _MODELS.items() if n not in CATALOGUE]
    if scenario:
        others = [n for n in others if _MODELS[n].scenario is not None]
    return [*CATALOGUE, *others]


def get_model(name: str) -> AnyModel:
    """The registered model called ``name``; :class:`ScenarioError` if there is none."""
    if isinstance(name, str) and name in _MODELS:
        return _MODELS[name]
    if not _LOADED and isinstance(name, str) and name in CATALOGUE:
        # Only this model's numerics are loaded: a run of one model does not pay for the others
        # (the full registry, in its order, is built when it is listed).
        model: AnyModel = importlib.import_module(f"tumble.models.{name}").MODEL
        return model
    try:
        return _registry()[name]
    except (KeyError, TypeError):
        raise _unknown(name) from None


def declaration(name: str) -> Declaration[Any, Any]:
    """What a scenario of model ``name`` may ask for, without loading a shipped model's
    numerics; :class:`ScenarioError` if there is no such model."""
    if isinstance(name, str) and name in _MODELS:
        return Declaration.of(_MODELS[name])
    if isinstance(name, str) and name in CATALOGUE:
        module = importlib.import_module(f"tumble.models.{name}.inputs")
        found: Declaration[Any, Any] = module.DECLARED
        return found
    raise _unknown(name)


if TYPE_CHECKING:
    from tumble.models import (
        nonlinear_moment,
        orbiting_body,
        resisting_medium,
        rotating_field,
        torqued_body,
    )

    MODELS: dict[str, AnyModel]
    """Every registered model, by the name a scenario's ``model`` key uses."""


def __getattr__(name: str) -> Any:
    if name == "MODELS":
        return _registry()
    if name in CATALOGUE:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), "MODELS", *CATALOGUE})
