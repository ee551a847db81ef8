"""The resisting medium's cases shared by its claims: the media and states of theory §13 and
the branch cases of the closed forms (A. V. Medvedev 1987; docs/theory/resisting-medium.md)."""

from __future__ import annotations

import math

import numpy as np

from tumble.models import resisting_medium as rm

RM = "resisting_medium"
RM_KAPPA = 0.5
"""κ of the closed-form cases (an oblate body, as in §13 checks and tumble's tests)."""

RM_GENERAL = rm.Params(
    eps=0.01,
    kappa=0.5,
    a=np.array([0.1, -0.05, 0.3]),
    b=np.array([[0.2, 0.01, 0.02], [0.0, 0.25, 0.0], [0.03, 0.0, 0.1]]),
    s=np.array([[0.1, 0.0, 0.01], [0.0, 0.12, 0.0], [0.0, 0.02, 0.05]]),
)
"""Theory §13.2/§13.6: full (non-diagonal) B and S, a1, a2 ≠ 0, oblate body."""

RM_START = rm.State(k=1.0, rho=1.2, sigma=0.3, psi=0.2, theta=1.0, phi=0.1)
"""ϑ and ρ away from 0 and π (§13.2), upper hemisphere, a3 > 0: no crossing of π/2 (§13.6)."""

RM_PROLATE = (
    rm.Params(
        eps=0.01,
        kappa=-0.4,
        a=np.array([0.05, 0.1, -0.2]),
        b=np.array([[0.15, -0.02, 0.0], [0.03, 0.1, 0.01], [0.0, 0.02, 0.2]]),
        s=np.array([[0.05, 0.01, 0.0], [0.0, 0.08, 0.0], [0.01, 0.0, 0.1]]),
    ),
    rm.State(1.2, 2.0, -1.0, 1.0, 2.2, -0.5),
)
"""Theory §13.6: the other hemisphere and a prolate body (a3 < 0 keeps ϑ > π/2)."""


def medium(
    alpha: float = 0.0,
    beta: float = 0.0,
    gamma: float = 0.0,
    delta: float = 0.0,
    a3: float = 0.0,
    eps: float = 0.01,
    a12: tuple[float, float] = (0.0, 0.0),
) -> rm.Params:
    """Params with the given α, β, γ, δ of (2.2): diagonal b, s inverting the definitions of
    §6 (α = (b11+b22)/2, β = b33/(1+κ), γ = 4(s11+s22)/(3π), δ = s33/(1+κ)²)."""
    k1 = 1.0 + RM_KAPPA
    b = np.diag([alpha, alpha, beta * k1])
    s = np.diag([gamma * 3.0 * math.pi / 8.0, gamma * 3.0 * math.pi / 8.0, delta * k1 * k1])
    return rm.Params(eps=eps, kappa=RM_KAPPA, a=np.array([*a12, a3]), b=b, s=s)


def state(k: float, theta: float, phi: float = 0.0) -> rm.State:
    """The closed-form cases' initial state: k [1], ϑ and φ [rad], with ρ = 1, σ = 0.2, ψ = 0."""
    return rm.State(k=k, rho=1.0, sigma=0.2, psi=0.0, theta=theta, phi=phi)


def random_states(n: int, seed: int) -> list[tuple[rm.Params, float, float, float]]:
    """Random media (full B, S, a1, a2 ≠ 0) and states for the pointwise checks of §13.3–4."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        kappa = float(rng.choice([-1.0, 1.0]) * rng.uniform(0.2, 0.9))
        p = rm.Params(
            eps=0.01,
            kappa=kappa,
            a=rng.uniform(-0.5, 0.5, 3),
            b=rng.uniform(-0.3, 0.5, (3, 3)),
            s=rng.uniform(-0.2, 0.4, (3, 3)),
        )
        out.append((p, rng.uniform(0.5, 2.0), rng.uniform(0.3, 2.8), rng.uniform(0.2, 2.9)))
    return out


RM_AXIAL_CASES = {
    name: (medium(*abgd, a3=a3), state(*start), 10.0, printed)
    for name, abgd, a3, start, printed in (
        # name, (α, β, γ, δ), a3, (k0, ϑ0), the printed formula checked before τ1 (None: no
        # printed formula); every case over the slow-time horizon ετ ≤ 10
        ("(2.5) a3 > 0, upper", (0.2, 0.3, 0.1, 0.2), 0.4, (1.0, 1.0), "axial_upper_exp"),
        ("(2.6) → (2.7)", (0.1, 0.2, 0.1, 0.3), -0.5, (1.0, 0.8), "axial_upper_tan"),
        ("(2.7) a3 > 0 → (2.5)", (0.1, 0.5, 0.1, 0.1), 0.2, (1.5, 2.5), "axial_lower_exp"),
        ("(2.8) → (2.5)", (0.2, 0.1, 0.1, 0.2), 0.6, (1.0, 2.6), "axial_lower_tan"),
        ("(2.5) small a3 < 0 → (2.7)", (0.1, 0.6, 0.1, 0.1), -0.05, (1.0, 1.2), "axial_upper_exp"),
        ("upper double root", (0.1, 0.2, 0.1, 0.1), -0.1, (1.0, 1.0), "axial_upper_double_root"),
        ("lower double root", (0.1, 0.2, 0.1, 0.1), 0.1, (1.0, 2.0), "axial_lower_double_root"),
        ("δ = 0", (0.2, 0.3, 0.1, 0.0), -0.2, (1.0, 1.0), None),
        ("β = δ = 0", (0.2, 0.0, 0.1, 0.0), 0.2, (1.0, 2.0), None),
        ("β = 0, δ > 0", (0.2, 0.0, 0.1, 0.2), -0.3, (1.0, 0.9), "axial_upper_tan"),
    )
}
"""Theory §13.5: every branch of (2.5)–(2.8), the switches of §8.4, the double roots, δ = 0."""
