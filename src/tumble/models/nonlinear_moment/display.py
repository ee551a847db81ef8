"""What ``tumble run`` draws and prints for the nonlinear-moment model
(:mod:`tumble.models.display`)."""

from tumble.models.display import FigureSettings, SummaryLine

FIGURE = FigureSettings(
    "envelope.png",
    "envelope",
    ("theta", "theta_max", "theta_min", "R", "G"),
    extrema="full_extrema",
    relative=("a", "Q(εt)/Q(0) = a(t)/a(0)"),
)
"""The run figure: θ(t) with its extrema and the averaged envelope, and where the pressure
varies, Q(εt)/Q(0) = a(t)/a(0)."""

SUMMARY = (
    SummaryLine("max envelope discrepancy (θmax, relative): {max_envelope_discrepancy:.3%}"),
    SummaryLine(
        "root case {root_case}, k² = {k2:.6g}, θ ∈ [{theta_min:.6g}, {theta_max:.6g}] rad, "
        "period {period:.6g}"
    ),
)
"""The report's own figures: the largest envelope discrepancy of a perturbed run, and the root
case, modulus, θ range and period of the unperturbed motion."""
