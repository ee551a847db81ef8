"""A physical scenario's outputs speak one system of units: its warnings give their times in
seconds or days with the unit."""

from __future__ import annotations

import pytest

from tumble.analysis.run import issue_in_si
from tumble.models.torqued_body.inputs import Scaling

SCALING = Scaling(T0=5.7, I0=2.0)  # 1 model time unit = 5.7 s


def _issue(tau: float, message: str) -> dict[str, object]:
    return {"condition": "resonance", "tau": tau, "message": message, "methods": ["averaged"]}


def test_a_warning_gives_its_time_in_days_or_seconds():
    tau = 88065.1
    message = f"at t ≈ {tau:.6g} the averaged motion meets a resonance, for Δτ ≈ {tau:.6g}"
    # A run beyond two days shows days: 88065.1 × 5.7 s = 5.80985 d.
    long = issue_in_si(_issue(tau, message), SCALING, t_end=1e6)
    assert long["message"].startswith("at t ≈ 5.80985 d the averaged motion")
    assert long["message"].endswith(f"Δτ ≈ {tau:.6g}")  # a duration, not the issue's time
    assert long["t_s"] == pytest.approx(tau * 5.7, rel=1e-15)  # one product's round-off
    assert long["tau"] == tau  # the model's time kept, for the figure's marks
    # A run of two days or less shows seconds.
    short = issue_in_si(_issue(tau, f"from τ = {tau:.6g} the spin is slow"), SCALING, 1e3)
    assert short["message"] == "from t = 501971 s the spin is slow"
    # Another number that only begins like the time is left alone.
    other = issue_in_si(_issue(12.5, "from t = 12.55 on"), SCALING, 1e3)
    assert other["message"] == "from t = 12.55 on"
