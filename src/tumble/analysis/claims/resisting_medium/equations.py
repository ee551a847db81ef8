"""Claims rm-1 … rm-4: the equations of motion (1.1)/(1.3), the unperturbed precession (2.1),
the averaged system (2.2) and its decoupled W, V form (2.3)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from tumble.analysis.claims.base import Measurement, Panel, Series, claim
from tumble.analysis.claims.common import (
    Difference,
    Tolerances,
    by_forms,
    converged,
    max_abs,
    threshold_panel,
    within,
    wrap,
)
from tumble.analysis.claims.resisting_medium.cases import RM, RM_GENERAL, RM_START, random_states
from tumble.integrate import simulate
from tumble.models import resisting_medium as rm


@claim(
    "rm-1",
    RM,
    "equations of motion (1.1)/(1.3)",
    "(1.1): K dρ/dt = M1, K sinρ dσ/dt = M2, dK/dt = M3 and the ψ, ϑ, φ equations; (1.3) "
    "their normalized standard form with small parameter ε.",
    "docs/theory/resisting-medium.md §2, §3, §4; corrections E1, E2; §13.2",
    name="equations_of_motion_1_1_and_1_3_hold",
)
def rm_1() -> Measurement:
    """Equations of motion (1.1)/(1.3) against Euler + quaternions (§3, §4, E1, E2).

    Returns
    -------
    Claim
        Measured: max |Δ| of k [1] and ϑ, ρ, σ [rad] between Euler + quaternions and the standard
        form (1.3) over τ ≤ 2/ε; holds if it is integration error (it falls with the tolerance).
    """
    p, st = RM_GENERAL, RM_START
    tau = np.linspace(0.0, 2.0 / p.eps, 801)  # §13.2: over τ = 2/ε

    def difference(tol: Tolerances) -> tuple[Difference, int, tuple[Any, Any]]:
        euler = simulate(rm.MODEL, p, st, tau, "full", **tol)
        osc = simulate(rm.MODEL, p, st, tau, "full", form="osculating", **tol)
        e, o = euler.columns, osc.columns
        worst = max(max_abs(e[n] - o[n]) for n in ("k", "theta", "rho"))
        worst = max(worst, max_abs(wrap(e["sigma"] - o["sigma"])))
        return worst, euler.nfev + osc.nfev, (e, o)

    # Criterion (§13.2): the forms agree to integration accuracy — their difference falls with
    # the tolerance; a wrong equation (E1's K dφ/dt = M1, or the flipped cot ρ sign of E2)
    # leaves an O(ε) difference that does not.
    conv, (euler, osc) = converged(difference)
    diffs = {
        "k": np.abs(euler["k"] - osc["k"]),
        "theta": np.abs(euler["theta"] - osc["theta"]),
        "rho": np.abs(euler["rho"] - osc["rho"]),
        "sigma": np.abs(wrap(euler["sigma"] - osc["sigma"])),
    }
    fast = {n: max_abs(wrap(euler[n] - osc[n])) for n in ("psi", "phi")}
    return by_forms(
        conv,
        tau,
        diffs,
        "|Euler+quaternions − (1.3)|",
        "two full forms, GENERAL medium",
        "1 (k), rad (angles)",
        "max |Δ| of k, ϑ, ρ, σ between Euler+quaternions and the standard form (1.3), τ ≤ 2/ε",
        "E1: the first equation is K dρ/dt = M1 (printed: K dφ/dt); E2: ρ, σ are the polar angle "
        "and azimuth of K about the inertial X3 (the paper's labels were lost in OCR)",
        max_diff_psi_phi_mod_2pi=fast,
        eps=p.eps,
    )


@claim(
    "rm-2",
    RM,
    "unperturbed regular precession (2.1)",
    "(2.1): for ε = 0, k, ρ, σ, ϑ are constant, ψ = kτ + ψ0, φ = −kκτ cosϑ/(1+κ) + φ0.",
    "docs/theory/resisting-medium.md §5; §13.1",
    name="unperturbed_motion_is_regular_precession",
)
def rm_2() -> Measurement:
    """Unperturbed motion (2.1): regular precession (§5, §13.1).

    Returns
    -------
    Claim
        Measured: max deviation of k, ϑ, ρ, σ from constants and of ψ, φ from the rates of (2.1),
        relative to the accumulated phase [1], ε = 0; holds if it falls with the tolerance.
    """
    p, st = RM_GENERAL.with_eps(0.0), RM_START
    tau = np.linspace(0.0, 500.0, 1001)
    rate_phi = -st.k * p.kappa * math.cos(st.theta) / (1.0 + p.kappa)
    # ψ and φ accumulate phase ~ kτ = 500 rad: their error is relative to the phase.
    scale = {"psi": max(1.0, st.k * tau[-1]), "phi": max(1.0, abs(rate_phi) * tau[-1])}

    def difference(tol: Tolerances) -> tuple[Difference, int, dict[str, np.ndarray]]:
        run = simulate(rm.MODEL, p, st, tau, "full", **tol)
        c = run.columns
        dev = {
            "k": np.abs(c["k"] - st.k),
            "theta": np.abs(c["theta"] - st.theta),
            "rho": np.abs(c["rho"] - st.rho),
            "sigma": np.abs(wrap(c["sigma"] - st.sigma)),
            "psi": np.abs(c["psi"] - (st.k * tau + st.psi)) / scale["psi"],
            "phi": np.abs(c["phi"] - (rate_phi * tau + st.phi)) / scale["phi"],
        }
        return max(max_abs(d) for d in dev.values()), run.nfev, dev

    conv, dev = converged(difference)  # §13.1: constant to integration accuracy
    rel = {n: max_abs(d) for n, d in dev.items()}
    return by_forms(
        conv,
        tau,
        dev,
        "deviation from (2.1) (ψ, φ relative to phase)",
        "ε = 0",
        "1",
        "max deviation of k, ϑ, ρ, σ from constants and of ψ, φ from kτ and −kκcosϑ τ/(1+κ) "
        "(relative to the accumulated phase), ε = 0, τ ≤ 500",
        per_variable=rel,
    )


@claim(
    "rm-3",
    RM,
    "averaged system (2.2)",
    "(2.2): averaging (1.3) over ψ and φ gives dρ = dσ = 0 and the k, ϑ equations with "
    "α = (b11+b22)/2, β = b33/(1+κ), γ = 4/3 π⁻¹ (s11+s22), δ = s33/(1+κ)².",
    "docs/theory/resisting-medium.md §6; correction E6; §13.3",
    name="averaging_over_psi_and_phi_gives_system_2_2",
)
def rm_3() -> Measurement:
    """Averaged system (2.2) against direct averaging of the full right-hand side (§6, E6).

    Returns
    -------
    Claim
        Measured: max |(2.2) − quadrature average of (1.3)| relative to the rate scale ε(|a|/k + |b|
        + |s|k) [1]; holds at ≤ 1e-9.
    """
    rows = []
    for p, k, rho, theta in random_states(16, seed=3):
        closed = rm.averaged_rhs(0.0, np.array([k, theta]), p)
        numeric = rm.averaged_rhs_numeric(0.0, np.array([k, rho, 0.3, theta]), p)
        scale = p.eps * (
            np.abs(p.a).sum() / k + np.abs(p.b).sum() + np.abs(p.s).sum() * k
        )  # rate scale of (2.2), §6
        rows.append(
            (
                closed[0],
                numeric[0],
                closed[1],
                numeric[3],
                abs(closed[0] - numeric[0]) / scale,
                abs(closed[1] - numeric[3]) / scale,
                max(abs(numeric[1]), abs(numeric[2])) / scale,
            )
        )
    r = np.array(rows)
    worst = float(np.max(r[:, 4:]))
    lim = float(np.max(np.abs(r[:, :4]))) * 1.1
    panels = (
        Panel(
            series=(
                Series(r[:, 1], r[:, 0], "dk/dτ", "markers"),
                Series(r[:, 3], r[:, 2], "dϑ/dτ", "markers"),
                Series(np.array([-lim, lim]), np.array([-lim, lim]), "diagonal", "dotted"),
            ),
            xlabel="numerical average of (1.3) over ψ, φ",
            ylabel="(2.2) with γ = 4(s11+s22)/(3π)",
        ),
    )
    # Criterion: tumble's quadrature engine is converged to 1e-12; 1e-9 of the rate scale
    # leaves a margin of 1e3, while a wrong γ factor or a surviving off-diagonal entry is O(1).
    return within(
        worst,
        1e-9,
        panels,
        "1 (relative to ε(|a|/k + |b| + |s|k))",
        "max |(2.2) − quadrature average of the (1.3) right-hand side| over 16 random states "
        "with full B, S and a1, a2 ≠ 0 (including ⟨dρ/dτ⟩, ⟨dσ/dτ⟩ = 0)",
        "E6: γ = 4(s11+s22)/(3π) (the paper's '4/3 π⁻¹' is ambiguous); the off-diagonal entries "
        "and a1, a2 drop out only while φ rotates (κ ≠ 0, ϑ ≠ π/2, §10)",
    )


@claim(
    "rm-4",
    RM,
    "decoupled W, V form (2.3)",
    "(2.3): dW/dτ = ε(a3 − βW ∓ δW²), dV/dτ = −ε(αV + γV²), − for 0 ≤ ϑ ≤ π/2, + for π/2 < ϑ ≤ π.",
    "docs/theory/resisting-medium.md §7; §13.4",
    name="averaged_system_decouples_in_w_and_v",
)
def rm_4() -> Measurement:
    """(2.2) in W = k cosϑ, V = k sinϑ is the decoupled (2.3) (§7, §13.4).

    Returns
    -------
    Claim
        Measured: max |(2.2) in W, V − (2.3)| relative to the rate scale [1]; holds at ≤ 1e-13.
    """
    errs, thetas = [], []
    rng = np.random.default_rng(4)
    for p, k, _rho, _theta in random_states(40, seed=4):
        theta = float(rng.uniform(0.0, math.pi))
        dk, dth = rm.averaged_rhs(0.0, np.array([k, theta]), p)
        dW = dk * math.cos(theta) - k * math.sin(theta) * dth  # chain rule
        dV = dk * math.sin(theta) + k * math.cos(theta) * dth
        ref = rm.averaged_rhs_wv(0.0, np.array([k * math.cos(theta), k * math.sin(theta)]), p)
        scale = p.eps * (np.abs(p.a).sum() + np.abs(p.b).sum() * k + np.abs(p.s).sum() * k * k)
        errs.append(max(abs(dW - ref[0]), abs(dV - ref[1])) / scale)
        thetas.append(theta)
    worst = float(np.max(errs))
    panels = (
        threshold_panel(
            (Series(np.array(thetas), np.maximum(errs, 1e-18), style="markers"),),
            1e-13,
            "ϑ [rad]",
            "|chain rule of (2.2) − (2.3)| / rate scale",
            label="threshold",
        ),
    )
    # Criterion: round-off of a handful of operations on O(1) terms (a few ulp ≈ 1e-15); 1e-13
    # leaves 100×, while a sign error in ∓δW² (hemisphere) is O(1).
    return within(
        worst,
        1e-13,
        panels,
        "1 (relative to the rate scale)",
        "max |(2.2) transformed to W, V − (2.3)| over 40 random states, ϑ ∈ [0, π]",
    )
