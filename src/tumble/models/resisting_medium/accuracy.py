"""Where averaging the resisting-medium model fails, §10 and §11 of
``docs/theory/resisting-medium.md``: the passage of ϑ = π/2 with a φ-dependent moment,
slow rates no longer small against the fast ones, k through 0, resonances of ψ and φ.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from tumble._typing import FloatArray
from tumble.models.base import SlowPath, ValidityIssue, first_time
from tumble.models.inputs.resisting_medium import Params, State
from tumble.models.resisting_medium.closed_forms import crossing_time

VALIDITY_RATIO = 0.1
"""Averaging is trusted while the slow rates stay below this fraction of the fast rates
(§6: ``ε(|a|/k² + |b|/k + |s|) ≪ |κ cos ϑ|/(1+κ)``); beyond it a run is warned."""


# ---------------------------------------------------------------------------------------------
# Where averaging fails, §10 and §11.


def moment_depends_on_phi(p: Params) -> bool:
    """True if the k, ϑ equations of the full model depend on φ (§10.1 special case).

    They do not (and then (2.2) is exact for k, ϑ, even across ϑ = π/2) when a1 = a2 = 0,
    b11 = b22, b12 = −b21, b13 = b23 = b31 = b32 = 0, and s has no entry but s33.
    """
    a, b, s = p.a.tolist(), p.b.tolist(), p.s.tolist()  # floats: cheaper than numpy here
    return bool(
        a[0] != 0.0
        or a[1] != 0.0
        or b[0][0] != b[1][1]
        or b[0][1] + b[1][0] != 0.0
        or any(b[i][j] != 0.0 for i, j in ((0, 2), (1, 2), (2, 0), (2, 1)))
        or any(s[i][j] != 0.0 for i in range(3) for j in range(3) if (i, j) != (2, 2))
    )


def axial_depends_on_phi(p: Params) -> bool:
    """True if the axial moment m3 of (1.2) depends on φ (b31, b32, s31 or s32 non-zero): then
    W oscillates with φ and its O(ε²) drift moves the phase at the passage by O(1), which the
    first-order run does not know."""
    b, s = p.b.tolist(), p.s.tolist()
    return bool(b[2][0] != 0.0 or b[2][1] != 0.0 or s[2][0] != 0.0 or s[2][1] != 0.0)


def _slow_rate_per_k(p: Params, k: FloatArray) -> FloatArray:
    """Slow rate per unit k, ε(|a|/k² + c|b|/k + c²|s|), §6.

    It bounds |dϑ/dτ|/k and |dk/dτ|/k² since |m| ≤ |a| + |b||w| + |s||w|² with
    |w| ≤ c k, c = 1/min(1, 1+κ); norms are Euclidean (matrix 2-norms).
    """
    c = 1.0 / min(1.0, 1.0 + p.kappa)
    na = float(np.linalg.norm(p.a))
    nb = float(np.linalg.norm(p.b, 2))
    ns = float(np.linalg.norm(p.s, 2))
    with np.errstate(divide="ignore"):
        return p.eps * (na / k**2 + c * nb / k + c * c * ns)


def validity(p: Params, st: State, slow: SlowPath, tau_end: float) -> list[ValidityIssue]:
    """Regions of §10–§11 that an averaged trajectory enters, with the first τ of each.

    Parameters
    ----------
    p : Params
        The body (κ), the moment and the medium (a, b, s), and ε.
    st : State
        The initial state: W0 = k0 cos ϑ0 and ϑ0 decide the passages of ϑ = π/2 (§8.4) and
        of k = 0 (§11).
    slow : callable
        ``slow(tau) -> {"k": ..., "theta": ...}`` along the averaged trajectory.
    tau_end : float
        End of the run [1].

    Returns
    -------
    list of ValidityIssue
        ``theta_crossing`` (ϑ = π/2 passed with a φ-dependent moment: O(√ε) after it, §10.2),
        ``phi_not_fast`` (slow rates not small against |κ cos ϑ|/(1+κ), §6, §10.3),
        ``spin_not_fast`` (k too small: slow rates not small against the precession rate k,
        §10.5), ``through_k_zero`` (ϑ0 ∈ {0, π} and W changes sign: k passes through 0, §11),
        ``resonance`` (the precession rate k = n|Ω_φ|, |cos ϑ| = (1+κ)/(n|κ|), n ≤
        RESONANCE_ORDER, crossed with a φ-dependent moment: ρ, σ may shift, §10.5).
    """
    if p.eps == 0.0 or tau_end <= 0.0:
        return []
    grid = np.linspace(0.0, tau_end, 4001)
    phi_dependent = moment_depends_on_phi(p)

    def cols(t: FloatArray) -> tuple[FloatArray, FloatArray]:
        c = slow(t)
        return c["k"], c["theta"]

    found = [_crossing_issue(p, st, tau_end, phi_dependent)]
    if phi_dependent:
        found += [_resonance_issue(p, cols, grid), _phi_issue(p, cols, grid)]
    found.append(_spin_issue(p, cols, grid))
    return [issue for issue in found if issue is not None]


_KTheta = Callable[[FloatArray], tuple[FloatArray, FloatArray]]  # τ → (k, ϑ) of the trajectory


def _crossing_issue(
    p: Params, st: State, tau_end: float, phi_dependent: bool
) -> ValidityIssue | None:
    """ϑ = π/2 crossed with a φ-dependent moment (§10.2), or k through 0 from ϑ0 ∈ {0, π}
    (§11)."""
    tau1 = crossing_time(st.W, p)
    crosses = tau1 <= tau_end
    if st.W == 0.0 and float(p.a[2]) != 0.0:
        tau1, crosses = 0.0, True  # starts on ϑ = π/2 and leaves it at once
    if crosses and abs(math.sin(st.theta)) < 1e-12:
        return ValidityIssue(
            "through_k_zero",
            tau1,
            f"ϑ0 is 0 or π and W = k cos ϑ changes sign at τ = {tau1:.6g}: the averaged "
            "solution passes through k = 0 and ϑ jumps between 0 and π, outside the "
            "validity of averaging (docs/theory/resisting-medium.md §11)",
        )
    if crosses and phi_dependent:
        from tumble.models.resisting_medium.passage import NEGLIGIBLE, jump_bound

        bound = jump_bound(p, st)  # None where the axial moment depends on φ
        if bound is not None and bound <= NEGLIGIBLE * p.eps:
            return None  # the passage moves V by less than averaging errs anyway
        if axial_depends_on_phi(p):
            why = (
                "; the axial moment depends on φ (b31, b32, s31 or s32 ≠ 0), so the phase of "
                "φ there is not known to first order and the averaged run takes no step"
            )
        else:
            why = (
                "; an averaged run steps across it by stationary phase (O(ε)) unless "
                "run.averaged_only, and this warning is then the closed form's"
            )
        return ValidityIssue(
            "theta_crossing",
            tau1,
            f"the averaged trajectory crosses ϑ = π/2 at τ = {tau1:.6g}: φ stops rotating "
            "there and, with a φ-dependent moment, the averaged equations alone are only "
            f"O(√ε) accurate after the passage{why} (docs/theory/resisting-medium.md §10.2)",
            label="ϑ = π/2",
        )
    return None


def _resonance_issue(p: Params, cols: _KTheta, grid: FloatArray) -> ValidityIssue | None:
    """The first resonance k = n|Ω_φ| crossed (§10.5)."""
    resonance = _first_resonance(p, lambda t: np.abs(np.cos(cols(t)[1])), grid)
    if resonance is None:
        return None
    tau_r, n = resonance
    return ValidityIssue(
        "resonance",
        tau_r,
        f"at τ ≈ {tau_r:.6g} the precession rate k equals {n}× the spin rate "
        f"|Ω_φ| (|cos ϑ| = (1+κ)/({n}|κ|)): the resonant terms, which first-order "
        "averaging drops, can shift ρ and σ; k and ϑ are unaffected "
        "(docs/theory/resisting-medium.md §10.5)",
        label=f"resonance ψ̇ = {n}·|φ̇|",
    )


def _phi_issue(p: Params, cols: _KTheta, grid: FloatArray) -> ValidityIssue | None:
    """The spin φ no longer fast against the slow drift (§6, §10.3)."""

    def phi_slow(t: FloatArray) -> FloatArray:
        k, theta = cols(t)
        fast = np.abs(p.kappa * np.cos(theta)) / (1.0 + p.kappa)
        return _slow_rate_per_k(p, k) - VALIDITY_RATIO * fast

    t_phi = first_time(phi_slow, grid)
    if t_phi is None:
        return None
    return ValidityIssue(
        "phi_not_fast",
        t_phi,
        f"from τ = {t_phi:.6g} the spin φ is no longer fast against the slow drift "
        f"(ε(|a|/k² + |b|/k + |s|) > {VALIDITY_RATIO:g}·|κ cos ϑ|/(1+κ)): averaging "
        "loses accuracy there (docs/theory/resisting-medium.md §6, §10.3)",
    )


def _spin_issue(p: Params, cols: _KTheta, grid: FloatArray) -> ValidityIssue | None:
    """k too small for the body to spin fast against the moment (§10.5)."""

    def spin_slow(t: FloatArray) -> FloatArray:
        k, _ = cols(t)
        return _slow_rate_per_k(p, k) - VALIDITY_RATIO

    t_spin = first_time(spin_slow, grid)
    if t_spin is None:
        return None
    k_at = float(cols(np.array([t_spin]))[0][0])
    return ValidityIssue(
        "spin_not_fast",
        t_spin,
        f"from τ = {t_spin:.6g} (k = {k_at:.3g}) the body no longer spins fast against "
        f"the moment (ε(|a|/k² + |b|/k + |s|) > {VALIDITY_RATIO:g}): the averaged model "
        "is invalid as k → 0 (docs/theory/resisting-medium.md §10.5)",
    )


RESONANCE_ORDER = 4
"""Largest n of the resonances k = n|Ω_φ| reported (§10.5): for a smooth moment the
resonant harmonics fall off with n, and a pass through one of order n costs O(ε^{1/2})
times that harmonic."""


def _first_resonance(
    p: Params, abs_cos: Callable[[FloatArray], FloatArray], grid: FloatArray
) -> tuple[float, int] | None:
    """First τ on ``grid`` where |cos ϑ| crosses (1+κ)/(n|κ|), n ≤ RESONANCE_ORDER, and n."""
    values = abs_cos(grid)
    found: tuple[float, int] | None = None
    for n in range(1, RESONANCE_ORDER + 1):
        level = (1.0 + p.kappa) / (n * abs(p.kappa))
        if level >= 1.0:
            continue
        side = np.sign(values - level)
        flips = np.flatnonzero(side[1:] * side[:-1] < 0.0)
        if not flips.size:
            continue
        s0 = float(side[flips[0]])

        def beyond(t: FloatArray, s0: float = s0, level: float = level) -> FloatArray:
            return -s0 * (abs_cos(t) - level)

        t = first_time(beyond, grid)
        if t is not None and (found is None or t < found[0]):
            found = (t, n)
    return found
