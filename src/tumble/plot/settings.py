"""What each model's run figure shows: the figure's file, its kind and the slow variables
drawn. Each model declares its figure in its package (:mod:`tumble.models.display`); this
module gives them to the plots."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from tumble.catalogue import CATALOGUE
from tumble.models.display import FigureSettings, figure_settings

__all__ = ["FIGURES", "FigureSettings", "figure_settings"]

if TYPE_CHECKING:
    FIGURES: dict[str, FigureSettings]
    """The shipped models' figures, by model name."""


def __getattr__(name: str) -> Any:
    if name == "FIGURES":  # built on use: each model's display module is read
        return {model: figure_settings(model) for model in CATALOGUE}
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
