"""Each model's presentation is declared in its package and found by name."""

from __future__ import annotations

from tumble.catalogue import CATALOGUE
from tumble.models.display import FigureSettings, summary_lines
from tumble.plot.settings import FIGURES, figure_settings


def test_every_shipped_model_declares_its_figure() -> None:
    assert set(FIGURES) == set(CATALOGUE)
    envelope = figure_settings("nonlinear_moment")
    assert (envelope.kind, envelope.extrema, envelope.relative) == (
        "envelope",
        "full_extrema",
        ("a", "Q(εt)/Q(0) = a(t)/a(0)"),
    )
    assert figure_settings("not_shipped") == FigureSettings()


def test_summary_lines_render_the_report_figures() -> None:
    summary = {
        "max_envelope_discrepancy": 0.01234,
        "root_case": 2,
        "k2": 0.25,
        "theta_min": 0.5,
        "theta_max": 1.5,
        "period": 7.0,
    }
    lines = [line.render(summary) for line in summary_lines("nonlinear_moment")]
    assert lines == [
        "max envelope discrepancy (θmax, relative): 1.234%",
        "root case 2, k² = 0.25, θ ∈ [0.5, 1.5] rad, period 7",
    ]
    # An unperturbed run has no discrepancy; a run of another model prints no such line.
    assert summary_lines("nonlinear_moment")[0].render({"max_envelope_discrepancy": None}) is None
    assert summary_lines("rotating_field") == ()
