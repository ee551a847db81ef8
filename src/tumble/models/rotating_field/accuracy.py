"""Where averaging the rotating-field model loses accuracy (§12): ε/min I not small, the
separatrix, a small angular momentum, resonances of the field with the fast
frequencies, and the final co-rotation; the fast frequencies along an averaged run.
"""

from __future__ import annotations

import math

import numpy as np

from tumble._typing import BoolArray, FloatArray
from tumble.models.base import SlowPath, ValidityIssue, first_time, separatrix_issue
from tumble.models.inputs.rotating_field import Params, State
from tumble.unperturbed import fast_frequencies_of_states

VALIDITY_RATIO = 0.1
"""``ε/I ≪ 1`` and ``fast ≫ slow`` are taken to hold while the ratio stays below this value."""

RESONANCE_ORDERS = (2, 2)
"""Largest |n1|, |n2| of the resonances m = n1 ν1 + n2 ν2 (m = 1, 2) that are watched, §12."""


# ---------------------------------------------------------------------------------------------
# Validity and the fast frequencies, §12.


def _frequencies(p: Params, cols: dict[str, FloatArray]) -> dict[str, FloatArray]:
    nu1, nu2 = fast_frequencies_of_states(*p.sorted_inertia, cols["L"], cols["T"])
    return {"nu1": nu1, "nu2": nu2}


def diagnostics(p: Params, st: State, cols: dict[str, FloatArray]) -> dict[str, FloatArray]:
    """Fast frequencies along an averaged solution, §8 and §15.

    Parameters
    ----------
    p : Params
    st : State
    cols : dict
        Averaged columns (``L``, ``T``).

    Returns
    -------
    dict
        ``nu1`` (polhode frequency 2πν/4K) and ``nu2`` (mean precession rate about L), in units
        of the field rate [1].
    """
    return _frequencies(p, cols)


def _resonances() -> list[tuple[int, int, int]]:
    n1max, n2max = RESONANCE_ORDERS
    out = []
    for m in (1, 2):
        for n2 in range(-n2max, n2max + 1):
            for n1 in range(-n1max, n1max + 1):
                if (n1, n2) != (0, 0) and (m, n1, n2) != (1, -1, 1):
                    out.append((m, n1, n2))
    return out


def validity(p: Params, st: State, slow: SlowPath, tau_end: float) -> list[ValidityIssue]:
    """Regions of §12 that an averaged trajectory enters, with the first τ of each.

    Parameters
    ----------
    p : Params
        The body and the field (ε/min I is the small parameter).
    st : State
        The initial state (not read: the checks follow the averaged trajectory).
    slow : callable
        ``slow(tau) -> columns`` (``L``, ``T``) along the averaged trajectory.
    tau_end : float
        End of the run [1].

    Returns
    -------
    list of ValidityIssue
        ``eps_not_small`` (ε/min I > 0.1), ``separatrix`` (L² = 2T I2 crossed: ν1 → 0),
        ``momentum_small`` (L so small that the fast frequencies are not fast), ``resonance``
        (m = n1 ν1 + n2 ν2 for m = 1, 2, |n1|, |n2| ≤ 2, crossed or approached within
        √(ε/min I)), ``co_rotation`` (the final stage, |ν2 − ν1 − 1| ≤ ε/min I, where the
        body's phase relative to the field is slow and (3.7) over-predicts the nutation decay of
        a triaxial body; (2.6) gives the true rate).
    """
    small = p.small_parameter
    issues: list[ValidityIssue] = []
    if small > VALIDITY_RATIO:
        issues.append(
            ValidityIssue(
                "eps_not_small",
                0.0,
                f"ε/min I = {small:.3g} is not small (> {VALIDITY_RATIO:g}): the averaged "
                "equations do not apply; only the full model and the linear stability results "
                "are exact (docs/theory/rotating-field.md §12)",
            )
        )
    if tau_end <= 0.0:
        return issues
    grid = np.linspace(0.0, tau_end, 2001)
    cols = slow(grid)
    # Fast frequencies ~ L/I3 against the slow rates ~ ε/I1.
    I1, I2, I3 = p.sorted_inertia
    L_small = I3 * small / VALIDITY_RATIO
    found = (
        separatrix_issue(slow, grid, I2, time="τ", cols=cols) if I1 < I2 < I3 else None,
        _momentum_issue(slow, grid, L_small, cols),
        *_frequency_issues(p, grid, cols, L_small),
    )
    return issues + [issue for issue in found if issue is not None]


def _momentum_issue(
    slow: SlowPath, grid: FloatArray, L_small: float, cols: dict[str, FloatArray]
) -> ValidityIssue | None:
    """The first time L falls below ``L_small``, where the fast frequencies stop being fast
    (``cols``: ``slow(grid)``)."""

    def momentum_small(t: FloatArray) -> FloatArray:
        return L_small - slow(t)["L"]

    tau_l = first_time(momentum_small, grid, L_small - cols["L"])
    if tau_l is None:
        return None
    return ValidityIssue(
        "momentum_small",
        tau_l,
        f"from τ = {tau_l:.6g} L < {L_small:.3g}: the fast frequencies are no longer "
        "fast against the slow drift, averaging is locally invalid; the vector form "
        "carries L through 0, but k² after such a passage is not predicted "
        "(docs/theory/rotating-field.md §12)",
    )


def _frequency_issues(
    p: Params, grid: FloatArray, cols: dict[str, FloatArray], L_small: float
) -> tuple[ValidityIssue | None, ValidityIssue | None]:
    """The first resonance the averaged motion meets, and the start of the co-rotation."""
    small = p.small_parameter
    nu = _frequencies(p, cols)
    moving = cols["L"] > L_small
    det_co = np.abs(nu["nu2"] - nu["nu1"] - 1.0)
    co = np.flatnonzero(moving & (det_co <= small))
    co_rotation = None
    if co.size:
        tau_c = float(grid[co[0]])
        co_rotation = ValidityIssue(
            "co_rotation",
            tau_c,
            f"from τ ≈ {tau_c:.6g} the body nearly co-rotates with the field (|ν2 − ν1 − 1| "
            "≤ ε/min I): the phase relative to the field is slow, independent averaging "
            "fails, and the final nutation decay of a triaxial body depends on the phase at "
            "which it settles, between the rate of (2.6) and 1.8 times it; (3.7) gives its mean "
            "over that phase (docs/theory/rotating-field.md §12)",
        )
    return _resonance_issue(p, grid, nu, moving), co_rotation


def _resonance_issue(
    p: Params, grid: FloatArray, nu: dict[str, FloatArray], moving: BoolArray
) -> ValidityIssue | None:
    """The first resonance m = n1 ν1 + n2 ν2 (m = 1, 2; |n1|, |n2| ≤ 2) crossed or approached
    within √(ε/min I), and how long the motion lingers near it."""
    small = p.small_parameter
    width = math.sqrt(small)
    first: tuple[float, float, tuple[int, int, int]] | None = None
    dtau = grid[1] - grid[0]
    for m, n1, n2 in _resonances():
        det = n1 * nu["nu1"] + n2 * nu["nu2"] - m
        near = moving & (np.abs(det) <= width)
        crossed = moving[1:] & moving[:-1] & (det[1:] * det[:-1] < 0.0)
        candidates = [int(i) for i in np.flatnonzero(near)[:1]]
        candidates += [int(i) + 1 for i in np.flatnonzero(crossed)[:1]]
        if candidates:
            i = min(candidates)
            if first is None or grid[i] < first[0]:
                first = (float(grid[i]), float(np.count_nonzero(near)) * dtau, (m, n1, n2))
    if first is None:
        return None
    tau_r, linger, (m, n1, n2) = first
    # Lingering over a tenth of the slow scale 1/(ε/min I) or more: the resonant terms act
    # as long as the averaged ones, O(1) effect (§12).
    effect = (
        "it lingers there long enough to put averaged k² and T off by O(1)"
        if linger >= VALIDITY_RATIO / small
        else "a passage shifts averaged k² and T by O(√ε) at most"
    )
    sign = "+" if n2 >= 0 else "−"
    return ValidityIssue(
        "resonance",
        tau_r,
        f"at τ ≈ {tau_r:.6g} the averaged motion meets the resonance {m} = {n1}·ν1 "
        f"{sign} {abs(n2)}·ν2 (field harmonic vs polhode ν1 and "
        f"precession ν2) and stays within √(ε/min I) of it for Δτ ≈ {linger:.3g}: "
        f"{effect}; L and ρ stay O(ε)-accurate (docs/theory/rotating-field.md §12)",
        label=f"resonance {m}·ω = {n1}·ν1 {sign} {abs(n2)}·ν2",
    )
