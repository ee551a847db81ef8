"""Pieces shared by the claim modules: tolerances, the measured record and small numerics.

The thresholds of the claims follow three rules (see each module): "to integration accuracy"
is 1e3 × rtol of the reference integration (:data:`INTEGRATION_FLOOR`), "first order" is a
fitted order of the averaging error ≥ :data:`FIRST_ORDER`, and limits of the full model are
judged within O(ε) of the averaged limit.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any, TypedDict

import numpy as np

from tumble._typing import FloatArray
from tumble.analysis.claims.base import plain
from tumble.errors import TumbleWarning

__all__ = [
    "FIRST_ORDER",
    "INTEGRATION_FLOOR",
    "TIGHT",
    "Tolerances",
    "max_abs",
    "measured",
    "quiet",
    "wrap",
]


class Tolerances(TypedDict):
    """Keyword arguments ``rtol``, ``atol`` of :func:`tumble.integrate.simulate`."""

    rtol: float
    atol: float


TIGHT: Tolerances = {"rtol": 1e-12, "atol": 1e-14}
"""Tolerances of the reference integrations. DOP853 at a local tolerance of 1e-12 keeps the
global error of the O(10³)-step runs below ~1e-9 relative; every threshold "at integration
accuracy" below is 1e3 × rtol, far above that and far below any error a wrong formula leaves
(O(ε) ≥ 1e-3, or O(1))."""

INTEGRATION_FLOOR = 1e3 * TIGHT["rtol"]

FIRST_ORDER = 0.75
"""A fitted order of the averaging error at or above this is first order: the ±0.25 band that
tumble's own error studies use (three to five values of ε; the O(ε²) remainder and the phase of
the O(ε) oscillation at the sampled maxima scatter the slope by up to ±0.2)."""


def measured(
    value: float,
    units: str,
    what: str,
    threshold: float | str,
    criterion: str,
    qualification: str = "",
    **details: Any,
) -> dict[str, Any]:
    """The ``measured`` record of a :class:`Claim`, as plain JSON values.

    Parameters
    ----------
    value : float
        The one measured figure, in ``units``.
    units : str
        Its unit ("1" for a ratio or a fitted order, "rad", "1/τ" …).
    what : str
        What was measured, with the parameters of the run.
    threshold : float or str
        The figure it is judged against (same units).
    criterion : str
        The rule that turns value and threshold into the verdict.
    qualification : str, optional
        The spec's qualification of the paper's statement ("" if none).
    **details
        Further measurements (per case, per variable …), stored under ``details``.

    Returns
    -------
    dict
        ``value``, ``units``, ``what``, ``threshold``, ``criterion`` and, where given,
        ``qualification`` and ``details``; numpy values converted by :func:`plain`.
    """
    out: dict[str, Any] = {
        "value": value,
        "units": units,
        "what": what,
        "threshold": threshold,
        "criterion": criterion,
    }
    if qualification:
        out["qualification"] = qualification
    if details:
        out["details"] = details
    result: dict[str, Any] = plain(out)
    return result


def quiet(fn: Callable[..., Any], *args: Any, **kwargs: Any) -> Any:
    """Call ``fn`` with tumble's validity warnings silenced: the claims record the conditions
    they need explicitly (e.g. ``rm.validity``), and the runner's output stays readable."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TumbleWarning)
        return fn(*args, **kwargs)


def max_abs(x: Any) -> float:
    """max |x| over every element of an array-like, as a float."""
    return float(np.max(np.abs(np.asarray(x, dtype=float))))


def wrap(x: Any) -> FloatArray:
    """Angle difference wrapped to (−π, π] [rad] (angles compared modulo 2π, medvedev.md §14)."""
    return np.asarray(np.angle(np.exp(1j * np.asarray(x, dtype=float))), dtype=float)
