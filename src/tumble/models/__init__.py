"""Paper models, one module each, registered by name (STYLE.md section 2)."""

from __future__ import annotations

from typing import Any

from tumble.errors import ScenarioError, shorten
from tumble.models import nonlinear_moment, resisting_medium, rotating_field, torqued_body
from tumble.models.base import Model

__all__ = [
    "MODELS",
    "AnyModel",
    "get_model",
    "nonlinear_moment",
    "register",
    "resisting_medium",
    "rotating_field",
    "torqued_body",
]

AnyModel = Model[Any, Any]
"""A registered model of any parameter and state types (the registry's view: each model is
typed with its own Params and State where it is defined)."""

MODELS: dict[str, AnyModel] = {}
"""Every registered model, by the name a scenario's ``model`` key uses."""


def register(model: AnyModel) -> AnyModel:
    """Add ``model`` to :data:`MODELS` under its name (a ValueError if the name is taken)."""
    if model.name in MODELS and MODELS[model.name] is not model:
        raise ValueError(f"a model called {model.name!r} is already registered")
    MODELS[model.name] = model
    return model


# One line per model.
register(resisting_medium.MODEL)
register(rotating_field.MODEL)
register(nonlinear_moment.MODEL)
register(torqued_body.MODEL)


def get_model(name: str) -> AnyModel:
    """The registered model called ``name``; :class:`ScenarioError` if there is none."""
    try:
        return MODELS[name]
    except (KeyError, TypeError):
        raise ScenarioError(
            f"model = {shorten(repr(name), 60)} is not a known model "
            f"(allowed: {', '.join(sorted(MODELS))})"
        ) from None
