"""What ``tumble run`` draws and prints for a model, declared in the model's package: the run
figure (:class:`FigureSettings`) and the lines of the model's own summary figures
(:class:`SummaryLine`). Settings of the presentation, kept out of the equations; the plots
(:mod:`tumble.plot`) and the run summary (:mod:`tumble.app.summary`) render whatever a model
declares here and know no model by name.

A shipped model declares them in ``tumble.models.<name>.display`` as ``FIGURE`` and
``SUMMARY``; a model without that module gets the defaults.
"""

from __future__ import annotations

import importlib
import string
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

from tumble.catalogue import CATALOGUE

__all__ = ["FigureSettings", "SummaryLine", "figure_settings", "summary_lines"]


@dataclass(frozen=True, slots=True)
class FigureSettings:
    """The run figure of a model.

    Attributes
    ----------
    file : str
        File name in the output directory.
    kind : {"comparison", "envelope"}
        One panel per variable with every method overlaid (:func:`plot_comparison`), or θ(t)
        with its extrema and the averaged envelope (:func:`plot_envelope`).
    variables : tuple of str
        The columns drawn, one panel each (also the final values ``tumble run`` prints); empty:
        the averaged method's columns.
    log : tuple of str
        The variables drawn on a logarithmic axis.
    extrema : str
        An envelope figure's table of the full motion's extrema in the run's report (its
        name in ``Report.tables``); empty: none.
    relative : (str, str), optional
        A column drawn on a second axis relative to its initial value, with its label, where
        it varies along a run (an envelope figure's); None: none.
    """

    file: str = "comparison.png"
    kind: Literal["comparison", "envelope"] = "comparison"
    variables: tuple[str, ...] = ()
    log: tuple[str, ...] = ()
    extrema: str = ""
    relative: tuple[str, str] | None = None


@dataclass(frozen=True, slots=True)
class SummaryLine:
    """One line ``tumble run`` prints from the summary of a run's report (``Report.summary``).

    Attributes
    ----------
    text : str
        A :meth:`str.format` template over the summary's keys, with each figure's format and
        unit written in it, e.g. ``"max envelope discrepancy (θmax, relative): {x:.3%}"``.
    when : str
        The key whose value, present and not None, makes the line printed; empty: the first
        key the template names.
    """

    text: str
    when: str = ""
    keys: tuple[str, ...] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        named = tuple(f for _, f, _, _ in string.Formatter().parse(self.text) if f)
        object.__setattr__(self, "keys", named)
        if not self.when:
            object.__setattr__(self, "when", named[0])

    def render(self, summary: Mapping[str, Any]) -> str | None:
        """The line for ``summary``, or None where it lacks the figure :attr:`when` names."""
        if summary.get(self.when) is None:
            return None
        return self.text.format(**{k: summary[k] for k in self.keys})


def _declared(model: str, name: str, default: Any) -> Any:
    """The attribute ``name`` of ``tumble.models.<model>.display``; ``default`` for a model
    that declares none (one registered from outside the shipped packages)."""
    if model not in CATALOGUE:
        return default
    return getattr(importlib.import_module(f"tumble.models.{model}.display"), name, default)


def figure_settings(model: str) -> FigureSettings:
    """The figure of ``model``; a comparison of the averaged columns if it declares none."""
    found: FigureSettings = _declared(model, "FIGURE", FigureSettings())
    return found


def summary_lines(model: str) -> tuple[SummaryLine, ...]:
    """The lines of ``model``'s own summary figures that ``tumble run`` prints (none if it
    declares none)."""
    found: tuple[SummaryLine, ...] = _declared(model, "SUMMARY", ())
    return found
