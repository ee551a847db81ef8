"""Claims rf-1 … rf-4: the eddy-current torque (1.2)/(1.3), the equations of motion (1.4), (1.5),
the linearization (2.4) with its characteristic polynomial (2.5) and its roots (2.6)."""

from __future__ import annotations

import math

import numpy as np

from tumble.analysis import fitted_order
from tumble.analysis.claims.base import Measurement, Panel, Series, claim
from tumble.analysis.claims.common import (
    Difference,
    Tolerances,
    by_forms,
    converged,
    eps_panel,
    judged,
    max_abs,
    threshold_panel,
    within,
    wrap,
)
from tumble.analysis.claims.rotating_field.cases import RF, RF_BODY, XI3, params
from tumble.analysis.stability import analyze, match_roots, polynomial_roots
from tumble.integrate import simulate
from tumble.models import rotating_field as rf
from tumble.torques import EddyCurrentTorque


@claim(
    "rf-1",
    RF,
    "eddy-current torque (1.2)/(1.3)",
    "(1.2) M_ξ = k_f H_ξ × (H_ξ × Ω_ξ + Ḣ_ξ); (1.3) M_ξ = M0 Bᵀĥĥ(BΩ_ξ − ωξ3), M0 = k_f H².",
    "docs/theory/rotating-field.md §3; corrections C1, C2",
    name="eddy_current_torque_follows_1_2_and_1_3",
)
def rf_1() -> Measurement:
    """Eddy-current torque (1.2)/(1.3) (§3, corrections C1, C2).

    Returns
    -------
    Claim
        Measured: max |(1.2) − tumble's (1.3)| relative to max(1, |Ω|) [1] over 200 random fields,
        rates and times; holds at ≤ 1e-13 with zero torque at co-rotation.
    """
    rng = np.random.default_rng(11)
    errs, ocr_corot, corot, power, spinup = [], [], [], [], []
    for _ in range(200):
        beta = float(rng.uniform(0.0, math.pi))
        omega = float(rng.uniform(0.2, 3.0))
        t = float(rng.uniform(0.0, 10.0))
        w = rng.normal(size=3) * 2.0
        torque = EddyCurrentTorque(M0=1.0, omega=omega, beta=beta)  # k_f = H = 1
        H = torque.field_direction(t)
        H_dot = omega * np.cross(XI3, H)  # (1.1): dH/dt = ω ξ3 × H
        paper = np.cross(H, np.cross(H, w) + H_dot)  # (1.2) with the dot restored (correction C1)
        errs.append(
            np.linalg.norm(paper - torque.inertial(t, w)) / max(1.0, float(np.linalg.norm(w)))
        )
        corot.append(np.linalg.norm(torque.inertial(t, omega * XI3)))
        # The OCR'd (1.2), H* read as H: H × (H × Ω + H) = H × (H × Ω) — no co-rotation zero.
        ocr_corot.append(np.linalg.norm(np.cross(H, np.cross(H, omega * XI3) + H)) / omega)
        static = EddyCurrentTorque(M0=1.0, omega=0.0, beta=beta)
        power.append(float(w @ static.inertial(t, w)))  # §3: Ω·M ≤ 0 in a static field
        spinup.append(
            float(torque.inertial(t, np.zeros(3))[2]) / (omega * math.sin(beta) ** 2 + 1e-300)
        )
    worst = float(np.max(errs))
    betas = np.linspace(0.0, math.pi, 91)
    panels = (
        threshold_panel(
            (Series(np.arange(len(errs), dtype=float), np.maximum(errs, 1e-18), style="markers"),),
            1e-13,
            "sample",
            "|(1.2) − tumble's −k_fH²[(Ω−ωξ3)]⊥H| / |Ω|",
        ),
        Panel(
            series=(
                Series(betas, np.sin(betas) ** 2, "dL3/dt from rest / (k_fH²ω) = sin²β"),
                Series(betas, np.abs(np.sin(betas)), "OCR'd (1.2) at co-rotation / ω", "dashed"),
            ),
            xlabel="β [rad]",
        ),
    )
    # Criterion: two algebraic forms of one vector, round-off of a few operations (1e-13),
    # while the printed reading differs by O(|Ω|).
    holds = (
        worst <= 1e-13
        and max(corot) <= 1e-13
        and max(power) <= 1e-13
        and abs(float(np.median(spinup)) - 1.0) <= 1e-12
    )
    return judged(
        holds,
        panels,
        worst,
        "1 (relative to max(1, |Ω|))",
        "max |k_f H×(H×Ω + Ḣ) − M0 Bᵀĥĥ(BΩ − ωξ3)| over 200 random fields, rates and times",
        1e-13,
        "value ≤ 1e-13, torque 0 at co-rotation, Ω·M ≤ 0 in a static field, dL3/dt = k_fH²ω "
        "sin²β from rest",
        "correction C1: the second term is dH/dt (the OCR shows H*); correction C2: M0 = k_f H²",
        qualified=True,
        max_torque_at_corotation=max(corot),
        ocr_reading_torque_at_corotation_over_omega=max(ocr_corot),
        max_power_static_field=max(power),
        spinup_over_omega_sin2beta_median=float(np.median(spinup)),
    )


@claim(
    "rf-2",
    RF,
    "equations of motion (1.4), (1.5)",
    "(1.5): Iz′ + z × Iz = εΓᵀĥĥ(Γz − ξ3), Γ′ = Γz⁺ − ξ3⁺Γ⁺, the rotating-frame form of "
    "(1.4) with τ = ωt, z = Ω/ω, ε = M0/ω.",
    "docs/theory/rotating-field.md §4; correction C3; §15",
    name="rotating_frame_equations_1_5_match_inertial_1_4",
)
def rf_2() -> Measurement:
    """(1.5) with the corrected Γ′ = Γẑ − ξ̂3Γ against the inertial form (1.4) (correction C3).

    Returns
    -------
    Claim
        Measured: max |Δ| of L, ρ, σ, T, z [1, rad] between the rotating-frame form (1.5) and the
        inertial form (1.4) over τ ≤ 1/ε; holds if it is integration error (it falls with the
        tolerance).
    """
    p = params(RF_BODY, 1.0, 0.01)
    st = rf.state_from_elements(p, 1.8, 0.8, 0.3, 0.5, "x3")
    tau = np.linspace(0.0, 1.0 / p.eps, 1001)

    def difference(tol: Tolerances) -> tuple[Difference, int, dict[str, np.ndarray]]:
        rot = simulate(rf.MODEL, p, st, tau, "full", **tol)
        ine = simulate(rf.MODEL, p, st, tau, "full", form="inertial", **tol)
        r, i = rot.columns, ine.columns
        diffs = {name: np.abs(r[name] - i[name]) for name in ("L", "rho", "T", "z1", "z2", "z3")}
        diffs["sigma"] = np.abs(wrap(r["sigma"] - i["sigma"]))
        return max(max_abs(d) for d in diffs.values()), rot.nfev + ine.nfev, diffs

    # §15: the best independent check, to integration accuracy (the difference falls with the
    # tolerance); the OCR's Γ′ leaves an O(1) difference.
    conv, diffs = converged(difference)
    return by_forms(
        conv,
        tau,
        diffs,
        "|(1.5) − (1.4)|",
        "body (1, 1.6, 2.2), β = 1, ε = 0.01",
        "1 (z, L, T), rad (angles)",
        "max |Δ| of L, ρ, σ, T, z between the rotating-frame form (1.5) and the inertial form "
        "(1.4) with quaternions, τ ≤ 1/ε",
        "correction C3: Γ′ = Γẑ − ξ̂3Γ (the OCR prints ξ̂3Γ⁺); only this reading agrees with (1.4)",
        per_variable={n: max_abs(d) for n, d in diffs.items()},
    )


@claim(
    "rf-3",
    RF,
    "linearization (2.4), characteristic polynomial (2.5)",
    "(2.4) the linearized equations about z = ξ3, Γ = E; (2.5) a0λ⁵ + … + a5 = 0 with the "
    "printed a0 … a5.",
    "docs/theory/rotating-field.md §5, §6; §15",
    name="linearization_2_4_gives_polynomial_2_5",
)
def rf_3() -> Measurement:
    """Linearization (2.4) and characteristic polynomial (2.5) as printed (§5–§6).

    Returns
    -------
    Claim
        Measured: max |a_k of (2.5) − a_k of the Jacobian of (1.5)| relative to max|a_k| [1]; holds
        at ≤ 1e-12.
    """
    bodies = [(1.0, 1.5, 2.0), (1.0, 2.0, 1.5), (2.0, 2.5, 1.5), (1.0, 2.0, 3.0), (0.6, 0.9, 1.0)]
    betas = [0.0, 0.3, math.pi / 4, 1.2, math.pi / 2, 2.5]
    epss = [1e-3, 0.05, 1.0, 10.0]  # (2.5) is exact for every ε (§6)
    worst, rows = 0.0, []
    for inertia in bodies:
        for beta in betas:
            for eps in epss:
                rep = analyze(rf.MODEL, params(inertia, beta, eps), family=False)
                c, cj = np.asarray(rep.coefficients), np.asarray(rep.coefficients_jacobian)
                err = float(np.max(np.abs(c - cj)) / np.max(np.abs(c)))
                worst = max(worst, err)
                rows.append((eps, err))
    r = np.array(rows)
    # The ε of each point is jittered by ±10 % so that the 30 points of one ε stay apart.
    jitter = np.exp(np.random.default_rng(0).uniform(-0.1, 0.1, len(r)))
    panels = (
        threshold_panel(
            (Series(r[:, 0] * jitter, np.maximum(r[:, 1], 1e-18), style="markers"),),
            1e-12,
            "ε",
            "max |a_k(2.5) − a_k(Jacobian of (1.5))| / max|a_k|",
            label="threshold",
            xscale="log",
        ),
    )
    # Criterion: the complex-step Jacobian of (1.5) is exact to round-off and the principal
    # minors are summed exactly (fsum): 1e-12 relative, while a wrong term is O(ε) or O(1).
    return within(
        worst,
        1e-12,
        panels,
        "1 (relative to max|a_k|)",
        "max difference between (2.5)'s printed a0…a5 and the characteristic polynomial of the "
        "automatic Jacobian of (1.5) at Γ = E, z = ξ3; 5 bodies × 6 β × 4 ε (10⁻³ … 10)",
        n_cases=len(rows),
    )


@claim(
    "rf-4",
    RF,
    "first-order roots (2.6)",
    "(2.6): λ1 = −ε sin²β/I3, λ2,3 = ±iω0 − (ε/2)[(I3−I2)/(I2I3) + (I3−I1)/(I1I3) cos²β], "
    "λ4,5 = ±i − ε(1 + cos²β)/(2I3), ω0² = (I3−I2)(I3−I1)/(I1I2).",
    "docs/theory/rotating-field.md §6",
    name="first_order_roots_follow_2_6",
)
def rf_4() -> Measurement:
    """First-order roots (2.6): error O(ε²) for simple roots (§6).

    Returns
    -------
    Claim
        Measured: the fitted order [1] of the error of (2.6) against ε farthest from 2; holds at
        |order − 2| ≤ 0.1.
    """
    cases = {
        "largest (1, 1.5, 2), β = π/4": ((1.0, 1.5, 2.0), math.pi / 4),
        "largest (2, 3, 4), β = 0.5": ((2.0, 3.0, 4.0), 0.5),
        "middle (1, 2, 1.5), β = 1": ((1.0, 2.0, 1.5), 1.0),
    }
    eps = np.geomspace(1e-3, 1e-2, 6)
    series: list[Series] = []
    slopes = {}
    for name, (inertia, beta) in cases.items():
        err = []
        for e in eps:
            p = params(inertia, beta, float(e))
            exact = polynomial_roots(rf.characteristic_coefficients(p))
            approx = rf.approximate_roots(p)
            err.append(float(np.max(np.abs(exact - approx[match_roots(exact, approx)]))))
        slopes[name] = fitted_order(eps, err)
        series.append(
            Series(eps, np.array(err), f"{name}: slope {slopes[name]:.3f}", "line+markers")
        )
    series.append(Series(eps, 1.0 * eps**2, "slope 2", "dotted"))
    panels = (eps_panel(series, "max |exact root − (2.6)|"),)
    # Thin plate at β = π/2 (§6 validity): (2.6) predicts Re λ4,5 = −ε/(2I3) < 0, the exact
    # pair ±i has zero real part.
    pt = params((1.0, 2.0, 3.0), math.pi / 2, 0.05)
    exact_t = polynomial_roots(rf.characteristic_coefficients(pt))
    approx_t = rf.approximate_roots(pt)
    near_i = exact_t[np.argmin(np.abs(exact_t - 1j))]
    worst = min(slopes.values(), key=lambda s: -abs(s - 2.0))
    # First-order perturbation of simple roots: error O(ε²); ±0.1 absorbs the O(ε³) term at
    # ε = 1e-2.
    holds = all(abs(s - 2.0) <= 0.1 for s in slopes.values())
    return judged(
        holds,
        panels,
        worst,
        "1 (fitted order)",
        "fitted order of max|exact root − (2.6)| against ε ∈ [1e-3, 1e-2] (the slope farthest "
        "from 2 of three bodies)",
        0.1,
        "|order − 2| ≤ 0.1",
        "valid only where the unperturbed roots are simple (ω0² ≠ 0, 1; ε/I ≪ |1 − ω0|): for "
        "the thin plate I3 = I1 + I2 at β = π/2 (2.6) gives Re λ4,5 < 0 for an exact root ±i",
        qualified=True,
        slopes=slopes,
        thin_plate_exact_root_near_i=[near_i.real, near_i.imag],
        thin_plate_approx_re_lambda45=float(approx_t[3].real),
    )
