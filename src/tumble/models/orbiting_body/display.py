"""What ``tumble run`` draws for the orbiting-body model (:mod:`tumble.models.display`)."""

from tumble.models.display import FigureSettings, SummaryLine

FIGURE = FigureSettings(
    "spin.png", "comparison", ("period", "rate_deg_s", "orbit_angle"), log=("period",)
)
"""The run figure: spin period (logarithmic axis), spin rate and the angle between L and the
orbit normal, every method overlaid."""

SUMMARY = tuple(
    line
    for m in ("full", "averaged")
    for line in (
        SummaryLine(
            f"{m}: e-folding time of the rate {{{m}_efolding_days:.4g}} d (fitted over its first "
            f"e-fold, 0–{{{m}_efolding_fit_end_days:.4g}} d)",
            when=f"{m}_decays",
        ),
        SummaryLine(
            f"{m}: no e-folding time (the trend of ln rate over 0–"
            f"{{{m}_efolding_fit_end_days:.4g}} d does not fall); the rate's end over its start "
            f"{{{m}_rate_ratio:.4g}}",
            when=f"{m}_rate_ratio",
        ),
        SummaryLine(
            f"{m}: floor of the rate {{{m}_floor_rate_deg_s:.4g}} deg/s, reached at "
            f"{{{m}_floor_days:.4g}} d",
            when=f"{m}_floor_days",
        ),
    )
)
"""The lines of the spin decay (:func:`tumble.models.orbiting_body.spin_decay`): per method,
the e-folding time of the rate over its first e-fold (or, for a rate that does not decay, its
end over its start), and its floor where it has one."""
