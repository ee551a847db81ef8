"""The limits of the averaged resisting-medium motion as τ → ∞: the paper's conclusions,
§9 of ``docs/theory/resisting-medium.md``, by the phase line of each scalar equation of
(2.3).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from tumble.models.inputs.resisting_medium import Params, State

# ---------------------------------------------------------------------------------------------
# Asymptotic conclusions, §9.


def _scalar_limit(x0: float, f: Callable[[float], float], roots: list[float]) -> float:
    """Limit of a monotone scalar flow dx/ds = f(x) from x0: the nearest root ahead, or ±inf."""
    f0 = f(x0)
    if f0 == 0.0:
        return x0
    direction = math.copysign(1.0, f0)
    ahead = [r for r in roots if (r - x0) * direction > 0.0]
    return min(ahead, key=lambda r: abs(r - x0)) if ahead else direction * math.inf


def _riccati_roots(a3: float, beta: float, d: float) -> list[float]:
    if d == 0.0:
        return [a3 / beta] if beta != 0.0 else []
    disc = beta * beta + 4.0 * d * a3
    if disc < 0.0:
        return []
    sq = math.sqrt(disc)
    return [(-beta + sq) / (2 * d), (-beta - sq) / (2 * d)]


def _W_limit(W0: float, a3: float, beta: float, delta: float) -> float:
    if W0 == 0.0 and a3 == 0.0:
        return 0.0
    side = math.copysign(1.0, W0) if W0 != 0.0 else math.copysign(1.0, a3)
    start = W0
    for _ in range(2):
        d = side * delta

        def rate(w: float, d: float = d) -> float:
            return a3 - beta * w - d * w * w

        target = _scalar_limit(start, rate, _riccati_roots(a3, beta, d))
        if side * target >= 0.0:
            return target
        side, start = -side, 0.0  # W reaches 0 first and continues in the other hemisphere
    raise AssertionError("W crosses 0 at most once")  # pragma: no cover (a3 fixes the direction)


def predicted_limits(p: Params, st: State) -> dict[str, Any]:
    """Limits of ϑ and k of the averaged system as τ → ∞, §9 (the paper's conclusions).

    Handles every sign of a3, the a3 = 0 split by β ≷ α, β = α, the quadratic-only medium,
    degenerate and negative coefficients (by the phase line of each scalar equation of (2.3)).

    Parameters
    ----------
    p : Params
        The moment and the medium (a3, α, β, γ, δ, ε).
    st : State
        The initial state, through W0 = k0 cos ϑ0 and V0 = k0 sin ϑ0 [1].

    Returns
    -------
    dict
        ``theta`` [rad] (None where undefined), ``k``, ``W``, ``V`` [1] (may be ±inf), and
        ``statement``: which conclusion of §9 applies.
    """
    a3, al, be, ga, de = float(p.a[2]), p.alpha, p.beta, p.gamma, p.delta
    W0, V0 = st.W, st.V
    if p.eps == 0.0:
        return {"theta": st.theta, "k": st.k, "W": W0, "V": V0, "statement": "ε = 0: no evolution"}
    W_inf = _W_limit(W0, a3, be, de)
    V_inf = _scalar_limit(V0, lambda v: -(al * v + ga * v * v), [0.0] + ([-al / ga] if ga else []))
    theta: float | None
    if W_inf != 0.0 or V_inf != 0.0:
        if math.isinf(W_inf) and math.isinf(V_inf):
            theta, statement = None, "both W and V diverge: ϑ has no limit from (2.3) alone"
        else:
            theta = math.atan2(V_inf, W_inf)
            statement = {1.0: "a3 > 0: ϑ → 0", -1.0: "a3 < 0: ϑ → π"}.get(
                math.copysign(1.0, a3) if a3 else 0.0, "a3 = 0"
            )
            if V_inf != 0.0:
                statement = "V does not decay (α = γ = 0 or self-excitation): ϑ → atan2(V∞, W∞)"
    elif V0 == 0.0:
        theta = 0.0 if math.copysign(1.0, W0) > 0 else math.pi
        statement = "V0 = 0: the axis stays along ±K"
    elif W0 == 0.0:
        theta, statement = math.pi / 2, "W ≡ 0: ϑ stays π/2"
    else:
        # Both components decay (a3 = 0): the slower one wins. Asymptotic amplitudes follow from
        # (2.4) and the a3 = 0 Riccati solution: V ~ αV0/(α+γV0) e^{−αs}, W ~ βW0/(β+δ|W0|) e^{−βs};
        # a zero linear coefficient leaves an algebraic 1/(γs) or 1/(δs) decay.
        if al > 0 and be > 0:
            # β = α to round-off (e.g. b33/(1+κ) computed from b33 = α(1+κ)) is the β = α case:
            # a difference of 1e-16 would only act after ετ ~ 1e16.
            if math.isclose(al, be, rel_tol=1e-12):
                theta = math.atan2(al * V0 / (al + ga * V0), be * W0 / (be + de * abs(W0)))
                statement = "a3 = 0, β = α: tan ϑ∞ = tan ϑ0 (β + δ|W0|)/(α + γV0)"
            elif be > al:
                theta, statement = math.pi / 2, "a3 = 0, β > α: ϑ → π/2"
            else:
                theta = 0.0 if W0 > 0 else math.pi
                statement = "a3 = 0, β < α: ϑ → 0 or π by hemisphere"
        elif be > 0:
            theta, statement = math.pi / 2, "a3 = 0, β > 0 = α: ϑ → π/2"
        elif al > 0:
            theta = 0.0 if W0 > 0 else math.pi
            statement = "a3 = 0, α > 0 = β: ϑ → 0 or π by hemisphere"
        else:
            theta = math.atan2(de, math.copysign(ga, W0))
            statement = "quadratic-only medium: tan ϑ → ±δ/γ (§8.7, correction E8)"
    return {
        "theta": theta,
        "k": math.hypot(W_inf, V_inf),
        "W": W_inf,
        "V": V_inf,
        "statement": statement,
    }
