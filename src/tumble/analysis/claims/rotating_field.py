"""Claims of Yu. G. Martynenko (1979) on a body in a rotating magnetic field (``rotating_field``).

One function per claim, :func:`rf_1` … :func:`rf_18`, in the order of the paper. Each runs its
check with tumble's public API and returns a :class:`~tumble.analysis.claims.base.Claim`: the
paper's statement with its equation numbers, the sections of the theory page that qualify
it, one measured figure against a threshold justified in a comment, the verdict computed from
it, and the figure as a :class:`~tumble.analysis.claims.base.FigureSpec`. Time is the paper's
τ = ωt, angles are radians, rates are z = Ω/ω. Parameters are the test cases of §15, tumble's
example scenarios or the theory page's own counterexamples; none is tuned toward an expected
number.

References
----------
Yu. G. Martynenko (1979); sections (§) and corrections (C1–C7) are those of
docs/theory/rotating-field.md.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from typing import Any, Literal

import numpy as np

from tumble._typing import BoolArray, FloatArray
from tumble.analysis import averaging_error_study, fitted_order
from tumble.analysis.claims.base import Measurement, Panel, Series, claim
from tumble.analysis.claims.common import (
    FIRST_ORDER,
    Difference,
    Tolerances,
    cache_per_scale,
    converged,
    max_abs,
    measured,
    measured_by,
    quiet,
    tolerances,
    wrap,
)
from tumble.analysis.stability import CRITICAL_TOL, analyze, match_roots, polynomial_roots
from tumble.analysis.stability_maps import inertia_map
from tumble.dynamics import rigid_body_kernel, rigid_body_rhs
from tumble.integrate import integrate, simulate
from tumble.models import rotating_field as rf
from tumble.rotations import euler313_to_matrix, matrix_to_quat, quat_to_matrix
from tumble.torques import EddyCurrentTorque, ZeroTorque
from tumble.unperturbed import EulerPoinsot, mean_square_rate, modulus_squared

__all__ = [
    "RF",
    "rf_1",
    "rf_2",
    "rf_3",
    "rf_4",
    "rf_5",
    "rf_6",
    "rf_7",
    "rf_8",
    "rf_9",
    "rf_10",
    "rf_11",
    "rf_12",
    "rf_13",
    "rf_14",
    "rf_15",
    "rf_16",
    "rf_17",
    "rf_18",
]

RF = "rotating_field"
RF_BODY = (1.0, 1.6, 2.2)
"""A triaxial body, I1 < I2 < I3, away from the thin plate (I1 + I2 − I3 = 0.4)."""

XI3 = np.array([0.0, 0.0, 1.0])


def _params(inertia: Sequence[float], beta: float, eps: float) -> rf.Params:
    """``rf.Params`` of the moments (I1, I2, I3) [inertia unit], field angle β [rad] and ε."""
    return rf.Params(np.asarray(inertia, dtype=float), beta, eps)


def _rf_transient() -> tuple[rf.Params, rf.State]:
    """The example of §12 / examples/rf_transient_x1.toml: from regime x1 through the
    separatrix into x3 (ε = 0.01, β = π/2, body (1, 2, 2.5))."""
    p = _params((1.0, 2.0, 2.5), math.pi / 2, 0.01)
    return p, rf.state_from_elements(p, 1.5, 0.6, 0.0, 0.5, "x1")


@cache_per_scale
def _rf_transient_runs() -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, np.ndarray]]:
    p, st = _rf_transient()
    tau = np.linspace(0.0, 300.0, 601)
    full = quiet(simulate, rf.MODEL, p, st, tau, "full").columns
    avg = quiet(simulate, rf.MODEL, p, st, tau, "averaged").columns
    return tau, full, avg


@claim(
    "rf-1",
    RF,
    "eddy-current torque (1.2)/(1.3)",
    "(1.2) M_ξ = k_f H_ξ × (H_ξ × Ω_ξ + Ḣ_ξ); (1.3) M_ξ = M0 Bᵀĥĥ(BΩ_ξ − ωξ3), M0 = k_f H².",
    "docs/theory/rotating-field.md §3; corrections C1, C2",
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
        Panel(
            series=(
                Series(np.arange(len(errs), dtype=float), np.maximum(errs, 1e-18), style="markers"),
            ),
            xlabel="sample",
            ylabel="|(1.2) − tumble's −k_fH²[(Ω−ωξ3)]⊥H| / |Ω|",
            yscale="log",
            hlines=((1e-13, ""),),
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
    m = measured(
        worst,
        "1 (relative to max(1, |Ω|))",
        "max |k_f H×(H×Ω + Ḣ) − M0 Bᵀĥĥ(BΩ − ωξ3)| over 200 random fields, rates and times",
        1e-13,
        "value ≤ 1e-13, torque 0 at co-rotation, Ω·M ≤ 0 in a static field, dL3/dt = k_fH²ω "
        "sin²β from rest",
        "correction C1: the second term is dH/dt (the OCR shows H*); correction C2: M0 = k_f H²",
        max_torque_at_corotation=max(corot),
        ocr_reading_torque_at_corotation_over_omega=max(ocr_corot),
        max_power_static_field=max(power),
        spinup_over_omega_sin2beta_median=float(np.median(spinup)),
    )
    return Measurement(holds, True, m, panels)


@claim(
    "rf-2",
    RF,
    "equations of motion (1.4), (1.5)",
    "(1.5): Iz′ + z × Iz = εΓᵀĥĥ(Γz − ξ3), Γ′ = Γz⁺ − ξ3⁺Γ⁺, the rotating-frame form of "
    "(1.4) with τ = ωt, z = Ω/ω, ε = M0/ω.",
    "docs/theory/rotating-field.md §4; correction C3; §15",
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
    p = _params(RF_BODY, 1.0, 0.01)
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
    panels = (
        Panel(
            series=tuple(Series(tau, np.maximum(d, 1e-17), name) for name, d in diffs.items()),
            xlabel="τ",
            ylabel="|(1.5) − (1.4)|",
            title="body (1, 1.6, 2.2), β = 1, ε = 0.01",
            yscale="log",
            hlines=((conv.budget, "round-off budget"),),
        ),
    )
    holds = conv.holds
    m = measured_by(
        conv,
        "1 (z, L, T), rad (angles)",
        "max |Δ| of L, ρ, σ, T, z between the rotating-frame form (1.5) and the inertial form "
        "(1.4) with quaternions, τ ≤ 1/ε",
        "correction C3: Γ′ = Γẑ − ξ̂3Γ (the OCR prints ξ̂3Γ⁺); only this reading agrees with (1.4)",
        per_variable={n: max_abs(d) for n, d in diffs.items()},
    )
    return Measurement(holds, True, m, panels)


@claim(
    "rf-3",
    RF,
    "linearization (2.4), characteristic polynomial (2.5)",
    "(2.4) the linearized equations about z = ξ3, Γ = E; (2.5) a0λ⁵ + … + a5 = 0 with the "
    "printed a0 … a5.",
    "docs/theory/rotating-field.md §5, §6; §15",
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
                rep = analyze(rf.MODEL, _params(inertia, beta, eps), family=False)
                c, cj = np.asarray(rep.coefficients), np.asarray(rep.coefficients_jacobian)
                err = float(np.max(np.abs(c - cj)) / np.max(np.abs(c)))
                worst = max(worst, err)
                rows.append((eps, err))
    r = np.array(rows)
    # The ε of each point is jittered by ±10 % so that the 30 points of one ε stay apart.
    jitter = np.exp(np.random.default_rng(0).uniform(-0.1, 0.1, len(r)))
    panels = (
        Panel(
            series=(Series(r[:, 0] * jitter, np.maximum(r[:, 1], 1e-18), style="markers"),),
            xlabel="ε",
            ylabel="max |a_k(2.5) − a_k(Jacobian of (1.5))| / max|a_k|",
            xscale="log",
            yscale="log",
            hlines=((1e-12, "threshold"),),
        ),
    )
    # Criterion: the complex-step Jacobian of (1.5) is exact to round-off and the principal
    # minors are summed exactly (fsum): 1e-12 relative, while a wrong term is O(ε) or O(1).
    holds = worst <= 1e-12
    m = measured(
        worst,
        "1 (relative to max|a_k|)",
        "max difference between (2.5)'s printed a0…a5 and the characteristic polynomial of the "
        "automatic Jacobian of (1.5) at Γ = E, z = ξ3; 5 bodies × 6 β × 4 ε (10⁻³ … 10)",
        1e-12,
        "value ≤ 1e-12",
        n_cases=len(rows),
    )
    return Measurement(holds, False, m, panels)


@claim(
    "rf-4",
    RF,
    "first-order roots (2.6)",
    "(2.6): λ1 = −ε sin²β/I3, λ2,3 = ±iω0 − (ε/2)[(I3−I2)/(I2I3) + (I3−I1)/(I1I3) cos²β], "
    "λ4,5 = ±i − ε(1 + cos²β)/(2I3), ω0² = (I3−I2)(I3−I1)/(I1I2).",
    "docs/theory/rotating-field.md §6",
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
            p = _params(inertia, beta, float(e))
            exact = polynomial_roots(rf.characteristic_coefficients(p))
            approx = rf.approximate_roots(p)
            err.append(float(np.max(np.abs(exact - approx[match_roots(exact, approx)]))))
        slopes[name] = fitted_order(eps, err)
        series.append(
            Series(eps, np.array(err), f"{name}: slope {slopes[name]:.3f}", "line+markers")
        )
    series.append(Series(eps, 1.0 * eps**2, "slope 2", "dotted"))
    panels = (
        Panel(
            series=tuple(series),
            xlabel="ε",
            ylabel="max |exact root − (2.6)|",
            xscale="log",
            yscale="log",
        ),
    )
    # Thin plate at β = π/2 (§6 validity): (2.6) predicts Re λ4,5 = −ε/(2I3) < 0, the exact
    # pair ±i has zero real part.
    pt = _params((1.0, 2.0, 3.0), math.pi / 2, 0.05)
    exact_t = polynomial_roots(rf.characteristic_coefficients(pt))
    approx_t = rf.approximate_roots(pt)
    near_i = exact_t[np.argmin(np.abs(exact_t - 1j))]
    worst = min(slopes.values(), key=lambda s: -abs(s - 2.0))
    # First-order perturbation of simple roots: error O(ε²); ±0.1 absorbs the O(ε³) term at
    # ε = 1e-2.
    holds = all(abs(s - 2.0) <= 0.1 for s in slopes.values())
    m = measured(
        worst,
        "1 (fitted order)",
        "fitted order of max|exact root − (2.6)| against ε ∈ [1e-3, 1e-2] (the slope farthest "
        "from 2 of three bodies)",
        0.1,
        "|order − 2| ≤ 0.1",
        "valid only where the unperturbed roots are simple (ω0² ≠ 0, 1; ε/I ≪ |1 − ω0|): for "
        "the thin plate I3 = I1 + I2 at β = π/2 (2.6) gives Re λ4,5 < 0 for an exact root ±i",
        slopes=slopes,
        thin_plate_exact_root_near_i=[near_i.real, near_i.imag],
        thin_plate_approx_re_lambda45=float(approx_t[3].real),
    )
    return Measurement(holds, True, m, panels)


@claim(
    "rf-5",
    RF,
    "largest axis: asymptotically stable",
    "§2: rotation about the axis of the largest moment of inertia (I3 > I1, I2) is "
    "asymptotically stable in the first approximation (for real bodies).",
    "docs/theory/rotating-field.md §7 table row 1, 'for real bodies'",
)
def rf_5() -> Measurement:
    """Largest axis: asymptotically stable in the first approximation (§7 table, row 1).

    Returns
    -------
    Claim
        Measured: the largest max Re λ [1/τ] over bodies with x3 the largest axis; holds at < −1e-10
        with every point asymptotically stable.
    """
    ds = inertia_map(beta=math.pi / 4, eps=0.05, n=31)
    x = ds["I1_over_I3"].values
    y = ds["I2_over_I3"].values
    X, Y = np.meshgrid(x, y)
    code = ds["classification"].values
    lead = ds["max_real"].values
    largest = (X < 1.0) & (Y < 1.0) & (code >= 0)
    map_max = float(np.max(lead[largest]))
    map_ok = bool(np.all(code[largest] == 0))  # 0: "asymptotically stable"
    # A random sweep over bodies with I3 largest, β ∈ (0, π/2), ε ∈ [1e-3, 10] (§7, "for real
    # bodies": the Routh–Hurwitz sweep of §7).
    rng = np.random.default_rng(5)
    sweep_max, sweep_bad, n = -math.inf, 0, 0
    while n < 150:
        I1, I2 = rng.uniform(0.05, 1.0, 2)
        if I1 + I2 < 1.0 or max(I1, I2) >= 1.0:
            continue  # not a body, or x3 not the largest axis
        beta = float(rng.uniform(0.01, math.pi / 2 - 0.01))
        eps = float(10.0 ** rng.uniform(-3.0, 1.0))
        rep = analyze(rf.MODEL, _params((I1, I2, 1.0), beta, eps), family=False)
        sweep_max = max(sweep_max, float(rep.max_real))
        sweep_bad += rep.classification != "asymptotically stable"
        n += 1
    value = max(map_max, sweep_max)
    panels = (Panel(kind="stability_map", data={"ds": ds}),)
    holds = map_ok and sweep_bad == 0 and value < -CRITICAL_TOL
    m = measured(
        value,
        "1/τ",
        "largest max Re λ over every body with x3 the largest axis: the (I1/I3, I2/I3) map at "
        "β = π/4, ε = 0.05 (31×31) and 150 random bodies, β ∈ (0, π/2), ε ∈ [1e-3, 10]",
        -CRITICAL_TOL,
        "every such point classified asymptotically stable (max Re λ < −1e-10)",
        "asymptotic stability in the first approximation; exceptions are the critical cases "
        "(thin plate I3 = I1 + I2 at β = π/2, β = 0, I3 equal to another moment); the sweep "
        "of §7 also covers 'non-physical' I3 > I1 + I2, which tumble's Params reject",
        sweep_points=n,
        sweep_not_stable=int(sweep_bad),
        map_points_largest=int(np.count_nonzero(largest)),
    )
    return Measurement(holds, True, m, panels)


def _rf_axis_roots_panel(inertia: tuple[float, float, float], eps: float) -> Panel:
    """Exact roots of (2.5) for each choice of the spin axis x3 of one body (§7)."""
    s, mid, large = sorted(inertia)
    series = []
    for label, order in (
        ("x3 largest", (s, mid, large)),
        ("x3 middle", (s, large, mid)),
        ("x3 smallest", (mid, large, s)),
    ):
        r = polynomial_roots(rf.characteristic_coefficients(_params(order, math.pi / 4, eps)))
        series.append(Series(r.real, r.imag, label, "markers"))
    return Panel(
        series=tuple(series),
        xlabel="Re λ",
        ylabel="Im λ",
        title=f"roots of (2.5), body {inertia}, ε = {eps}",
        vlines=((0.0, ""),),
    )


@claim(
    "rf-6",
    RF,
    "middle axis: unstable",
    "§2: rotation about the middle axis is unstable (ω0² < 0: ±iω0 becomes a real pair).",
    "docs/theory/rotating-field.md §6, §7 table row 2",
)
def rf_6() -> Measurement:
    """Middle axis: unstable, a real root ≈ |ω0| (§7 table, row 2).

    Returns
    -------
    Claim
        Measured: |nonlinear growth rate of (1.5) / exact real root − 1| [1]; holds at ≤ 1e-2.
    """
    p = _params((1.0, 2.0, 1.5), 1.0, 1e-3)
    rep = analyze(rf.MODEL, p, family=False)
    w0 = math.sqrt(-p.derived()["omega0_squared"])
    root_rel = abs(rep.roots[0].real / w0 - 1.0)
    # Nonlinear check (§7, last paragraph): (1.5) from a generic small perturbation.
    pn = _params((1.0, 2.0, 1.5), math.pi / 3, 0.05)
    lead = analyze(rf.MODEL, pn, family=False).roots[0]
    st = rf.State(XI3 + 1e-7 * np.array([0.3, -0.5, 0.2]), euler313_to_matrix(0.2, 4e-8, -0.2))
    tau = np.linspace(0.0, 60.0, 3001)
    full = simulate(rf.MODEL, pn, st, tau, "full", **tolerances()).columns
    d = np.sqrt((full["z1"]) ** 2 + (full["z2"]) ** 2 + (full["z3"] - 1.0) ** 2)
    # Fit while the deviation is small (≤ 1e-3) but the unstable mode dominates (≥ 1e-5).
    sel = (d > 1e-5) & (d < 1e-3)
    growth = float(np.polyfit(tau[sel], np.log(d[sel]), 1)[0])
    rel = abs(growth / lead.real - 1.0)
    guide = d[sel][0] * np.exp(lead.real * (tau - tau[sel][0]))
    inside = (guide >= 1e-8) & (guide <= 10.0)  # the figure's window 1e-8 … 10, cut from the data
    panels = (
        Panel(
            series=(
                Series(tau, d, "|z − ξ3| of (1.5)"),
                Series(tau[inside], guide[inside], "e^{λτ}", "dotted"),
            ),
            xlabel="τ",
            ylabel="deviation",
            yscale="log",
        ),
        _rf_axis_roots_panel((1.0, 1.5, 2.0), 0.05),
    )
    # Criteria: the exact real root is |ω0| to first order (relative shift ≤ ε/min I); the
    # nonlinear growth rate equals it (the damped modes excited at the start leave ~3e-3 of the
    # deviation where the fit begins: 1e-2).
    holds = (
        rep.classification == "unstable"
        and rep.roots[0].imag == 0.0
        and root_rel <= p.eps / 1.0
        and rel <= 1e-2
    )
    m = measured(
        rel,
        "1",
        "|nonlinear growth rate of (1.5) / exact real root − 1| (body (1, 2, 1.5), β = π/3, "
        "ε = 0.05)",
        1e-2,
        "value ≤ 1e-2, classification unstable, real root within ε/min I of |ω0| (ε = 1e-3)",
        growth_rate=growth,
        exact_root=float(lead.real),
        root_over_omega0_minus_1_at_eps_1e_3=root_rel,
    )
    return Measurement(holds, False, m, panels)


@claim(
    "rf-7",
    RF,
    "smallest axis: unstable (footnote 1)",
    "§2 and footnote 1: rotation about the smallest axis is unstable (Re λ2,3 > 0), "
    "refuting an earlier claim that it is asymptotically stable.",
    "docs/theory/rotating-field.md §7 table row 3",
)
def rf_7() -> Measurement:
    """Smallest axis: unstable, slow oscillatory growth (§7 row 3; footnote 1).

    Returns
    -------
    Claim
        Measured: |max Re λ / the §7 first-order rate − 1| [1]; holds at ≤ ε/I3.
    """
    eps, beta = 1e-2, math.pi / 4
    I1, I2, I3 = 2.0, 2.5, 1.5
    rep = analyze(rf.MODEL, _params((I1, I2, I3), beta, eps), family=False)
    c2 = math.cos(beta) ** 2
    growth = 0.5 * eps * ((I2 - I3) / (I2 * I3) + (I1 - I3) / (I1 * I3) * c2)  # §7 table
    rel = abs(rep.max_real / growth - 1.0)
    panels = (_rf_axis_roots_panel((1.5, 2.0, 2.5), 0.05),)
    # Criterion: the §7 rate is first order, relative error O(ε/I): ε/I3 bounds it.
    holds = (
        rep.classification == "unstable"
        and rep.roots[0].imag != 0.0
        and rep.roots[1] == np.conj(rep.roots[0])
        and rel <= eps / I3
    )
    m = measured(
        rel,
        "1",
        "|max Re λ (exact) / (ε/2)[(I2−I3)/(I2I3) + (I1−I3)/(I1I3)cos²β] − 1|, body (2, 2.5, 1.5), "
        "β = π/4, ε = 0.01",
        eps / I3,
        "value ≤ ε/I3, classification unstable with a complex leading pair",
        max_re_lambda=rep.max_real,
        first_order_rate=growth,
    )
    return Measurement(holds, False, m, panels)


@claim(
    "rf-8",
    RF,
    "thin plate at β = π/2: critical case",
    "Footnote 2: a thin plate (I3 = I1 + I2) in a field rotating in a plane (β = π/2) is a "
    "critical case of the stability analysis.",
    "docs/theory/rotating-field.md §6, §7 'critical cases'",
)
def rf_8() -> Measurement:
    """Thin plate I3 = I1 + I2 in a planar field: a critical case (footnote 2).

    Returns
    -------
    Claim
        Measured: max |P(±i)| of (2.5) relative to Σ|a_k| [1] for thin plates at β = π/2; holds at ≤
        16 ulp with every case critical.
    """
    bodies = [(1.0, 2.0, 3.0), (0.3, 0.7, 1.0), (1.0, 1.0, 2.0)]
    worst, labels = 0.0, {}
    for inertia in bodies:
        for eps in (1e-4, 1e-2, 0.05, 1.0, 10.0):
            p = _params(inertia, math.pi / 2, eps)
            c = rf.characteristic_coefficients(p)
            for lam in (1j, -1j):
                worst = max(worst, float(abs(np.polyval(c, lam))) / float(np.sum(np.abs(c))))
            labels[f"{inertia}, ε = {eps}"] = analyze(rf.MODEL, p, family=False).classification
    conical = {
        beta: analyze(rf.MODEL, _params((1.0, 2.0, 3.0), beta, 0.05), family=False).classification
        for beta in (0.3, math.pi / 4, 1.2)
    }
    betas = np.linspace(0.05, math.pi / 2, 60)
    lead = [
        analyze(rf.MODEL, _params((1.0, 2.0, 3.0), float(b), 0.05), family=False).max_real
        for b in betas
    ]
    panels = (
        Panel(
            series=(Series(betas, np.maximum(-np.array(lead), 1e-18), style="line+markers"),),
            xlabel="β [rad]",
            ylabel="−max Re λ",
            title="thin plate (1, 2, 3), ε = 0.05",
            yscale="log",
        ),
    )
    # Criterion: P(±i) = ε(I3 ∓ iε)(I1 + I2 − I3) = 0 to the rounding of the sum (16 ulp of
    # Σ|a_k|), the exact root ±i gives "critical"; β < π/2 stays asymptotically stable.
    ulp16 = 16 * float(np.finfo(float).eps)
    holds = (
        worst <= ulp16
        and all(v == "critical" for v in labels.values())
        and all(v == "asymptotically stable" for v in conical.values())
    )
    m = measured(
        worst,
        "1 (relative to Σ|a_k|)",
        "max |P(±i)| of (2.5) for three thin plates at β = π/2, ε = 1e-4 … 10",
        ulp16,
        "value ≤ 16 ulp, all classified critical; β = 0.3, π/4, 1.2 asymptotically stable",
        "(2.6) is invalid there (it predicts damping of the ±i pair); the critical mode is not "
        "damped linearly and decays only through nonlinear terms (not proven, rf-9)",
        classifications=labels,
        conical_field=conical,
    )
    return Measurement(holds, True, m, panels)


@claim(
    "rf-9",
    RF,
    "thin plate: critical mode decays nonlinearly (§7)",
    "Not in the paper (footnote 2 only names the critical case). Theory §7: in the nonlinear "
    "model this mode is observed to decay, at a rate proportional to the square of the "
    "amplitude, i.e. amplitude ~ τ^(−1/2).",
    "docs/theory/rotating-field.md §7 'critical cases' (an observation)",
)
def rf_9() -> Measurement:
    """The observation of §7: the critical thin-plate mode decays at a rate ∝ amplitude².

    Returns
    -------
    Claim
        Measured: the exponent n [1] of the decay rate ∝ Aⁿ of the critical thin-plate mode; holds
        at n = 2 ± 0.5 or n/2 = 2 ± 0.5.
    """
    p = _params((1.0, 2.0, 3.0), math.pi / 2, 0.05)
    tb, A, rate = _thin_plate_decay(p)
    ok = rate > 0.0
    n_lin = float(np.polyfit(np.log(A[ok]), np.log(rate[ok]), 1)[0])
    p_lin = float(np.polyfit(np.log(tb[5:]), np.log(A[5:]), 1)[0])
    half = int(np.count_nonzero(ok)) // 2  # the law is not a clean power: local exponents
    n_large_A = float(np.polyfit(np.log(A[ok][:half]), np.log(rate[ok][:half]), 1)[0])
    n_small_A = float(np.polyfit(np.log(A[ok][half:]), np.log(rate[ok][half:]), 1)[0])
    others = min(
        abs(z.real) for z in analyze(rf.MODEL, p, family=False).roots if abs(z.real) > 1e-9
    )
    panels = _rf_9_panels(tb, A, rate, ok, n_lin)
    # "Rate ∝ amplitude²", read for the linear amplitude A: rate ∝ A² (A ~ τ^(−1/2)); read
    # for a quadratic measure (A², e.g. k² or the energy of the mode): rate ∝ (A²)², i.e.
    # rate_A ∝ A⁴, which is what §7 of the theory page states (measured here). ±0.5 on the
    # exponent separates the two readings.
    linear_reading = abs(n_lin - 2.0) <= 0.5
    quadratic_reading = abs(n_lin / 2.0 - 2.0) <= 0.5
    nonlinear_only = bool(np.all(np.diff(A) < 0.0)) and float(np.max(rate)) < 0.1 * others
    holds = nonlinear_only and (linear_reading or quadratic_reading)
    m = measured(
        n_lin,
        "1 (exponent)",
        "exponent n of the decay rate −d ln A/dτ ∝ Aⁿ of the critical mode (A the linear "
        "deviation |(x, γ1, γ2)|, A: 0.26 → 0.10 over τ ≤ 6000), thin plate (1, 2, 3), β = π/2, "
        "ε = 0.05",
        2.0,
        "n = 2 ± 0.5 (rate ∝ A², A ~ τ^(−1/2)), or n/2 = 2 ± 0.5 (rate ∝ amplitude² for a "
        "quadratic measure of it, as §7 states); the decay must be slower than every linear rate",
        "observed, not proven; "
        + (
            "holds only if 'amplitude' means a quadratic measure (k², energy): for the linear "
            f"deviation the rate goes as A^{n_lin:.1f} and A ~ τ^{p_lin:.2f}"
            if quadratic_reading and not linear_reading
            else "holds for the linear deviation"
            if linear_reading
            else "contradicted for both readings"
        ),
        theory_consistent=quadratic_reading,
        amplitude_power_law_in_tau=p_lin,
        local_exponent_larger_amplitudes=n_large_A,
        local_exponent_smaller_amplitudes=n_small_A,
        max_rate_over_slowest_linear_rate=float(np.max(rate)) / others,
    )
    return Measurement(holds, True, m, panels)


def _thin_plate_decay(p: rf.Params) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The critical mode of the thin plate from amplitude 0.3: its envelope A of
    |(x, γ1, γ2)| smoothed over 60 half-periods, at times tb, and −d ln A/dτ."""
    w, V = np.linalg.eig(rf.linear_matrix(p))
    v = V[:, int(np.argmin(np.abs(w - 1j)))]
    v = v / v[np.argmax(np.abs(v))]
    r = np.real(v) / np.linalg.norm(np.real(v))
    A0 = 0.3
    g = A0 * np.array([r[3], r[4], 0.0])  # tilt of x3: Γ = exp(γ̂), as a rotation of angle |γ|
    ang = float(np.linalg.norm(g))
    gamma = quat_to_matrix(np.r_[math.cos(ang / 2), math.sin(ang / 2) * g / ang])
    st = rf.State(XI3 + A0 * r[:3], gamma)
    tau_end = 6000.0
    sol = integrate(
        lambda t, y: rf.full_rhs(t, y, p),
        rf.full_from_slow(p, st),
        tau_end,
        **tolerances({"rtol": 1e-10, "atol": 1e-13}),
        kernel=rf.full_kernel(p),
    )
    t = np.linspace(0.0, tau_end, 60001)
    Y = sol(t)
    G = Y[:, 3:].reshape(-1, 3, 3)
    x = Y[:, :3] - XI3
    # |(x, γ1, γ2)|: the third row of Γ is (−γ2, γ1, 1) for every phase of the family.
    d = np.sqrt(np.sum(x * x, axis=1) + G[:, 2, 0] ** 2 + G[:, 2, 1] ** 2)
    starts = np.arange(0.0, tau_end - math.pi, math.pi)
    env = np.maximum.reduceat(d, np.searchsorted(t, starts))[: starts.size]
    nb = env.size // 60  # smooth over 60 half-periods of the ±i mode
    A = env[: nb * 60].reshape(nb, 60).mean(axis=1)
    tb = starts[: nb * 60].reshape(nb, 60).mean(axis=1)
    rate = -np.gradient(np.log(A), tb)
    return tb, A, rate


def _rf_9_panels(
    tb: FloatArray, A: FloatArray, rate: FloatArray, ok: BoolArray, n_lin: float
) -> tuple[Panel, ...]:
    a_ref = np.array([A[ok].min(), A[ok].max()])
    r_mid = float(np.exp(np.mean(np.log(rate[ok]))))
    a_mid = float(np.exp(np.mean(np.log(A[ok]))))
    return (
        Panel(
            series=(
                Series(tb, A, "envelope of |(x, γ1, γ2)|"),
                Series(tb, A[5] * (tb / tb[5]) ** -0.5, "τ^(−1/2) (§7)", "dotted"),
                Series(tb, A[5] * (tb / tb[5]) ** -0.25, "τ^(−1/4)", "dotted"),
            ),
            xlabel="τ",
            ylabel="amplitude A",
            xscale="log",
            yscale="log",
        ),
        Panel(
            series=(
                Series(A[ok], rate[ok], f"fit: rate ∝ A^{n_lin:.2f}", "markers"),
                Series(a_ref, r_mid * (a_ref / a_mid) ** 2, "∝ A² (§7)", "dotted"),
                Series(a_ref, r_mid * (a_ref / a_mid) ** 4, "∝ A⁴", "dotted"),
            ),
            xlabel="A (0.1 … 0.26)",
            ylabel="−d ln A/dτ",
            xscale="log",
            yscale="log",
        ),
    )


@claim(
    "rf-10",
    RF,
    "Euler–Poinsot motion (3.1)",
    "(3.1): z1 = Lk√((I3−I2)/(I1I0)) cn u, z2 = Lk√((I3−I1)/(I2I0)) sn u, z3 = "
    "L√((I2−I1)/(I3I0)) dn u; for the other regime swap the indices 1 and 3.",
    "docs/theory/rotating-field.md §8; correction C7",
)
def rf_10() -> Measurement:
    """Euler–Poinsot motion (3.1) in both regimes (§8, correction C7).

    Returns
    -------
    Claim
        Measured: max |z of (3.1) − z integrated| / |z0| and the quaternion difference [1] over ten
        periods; holds if it is integration error (it falls with the tolerance).
    """
    cases = {
        "regime x3": (RF_BODY, np.array([0.3, 0.2, 1.0])),
        "regime x1": (RF_BODY, np.array([1.2, 0.3, 0.2])),
        "unsorted labels (2.2, 1, 1.6)": ((2.2, 1.0, 1.6), np.array([1.0, 0.3, 0.2])),
    }

    def difference(tol: Tolerances) -> tuple[Difference, int, tuple[dict[str, Any], list[Any]]]:
        per, runs, nfev = {}, [], 0
        for name, (inertia, z0) in cases.items():
            ep = EulerPoinsot.from_state(inertia, z0)
            moments = np.asarray(inertia, dtype=float)
            tau_end = 10.0 * ep.period
            sol = integrate(
                functools.partial(rigid_body_rhs, inertia=moments, torque=None),
                np.concatenate([z0, matrix_to_quat(np.eye(3))]),
                tau_end,
                **tol,
                kernel=rigid_body_kernel(moments, ZeroTorque()),
            )
            tau = np.linspace(0.0, tau_end, 2001)
            Y = sol(tau)
            dz = max_abs(ep.omega(tau) - Y[:, :3]) / float(np.linalg.norm(z0))
            q = ep.quaternion(tau)
            dq = float(
                np.max(
                    np.minimum(
                        np.linalg.norm(q - Y[:, 3:], axis=1), np.linalg.norm(q + Y[:, 3:], axis=1)
                    )
                )
            )
            per[name] = {"omega": dz, "quaternion": dq}
            runs.append((name, ep, tau, Y))
            nfev += sol.nfev
        return {c: max(v.values()) for c, v in per.items()}, nfev, (per, runs)

    # Criterion: (3.1) is exact, so z and the attitude agree to integration accuracy over 10
    # periods (the difference falls with the tolerance); a wrong sign under a root is O(1).
    conv, (per, runs) = converged(difference)
    panels: list[Panel] = []
    regimes = {}
    for name, ep, tau, Y in runs:
        regimes[name] = ep.regime
        z = ep.omega(tau)
        series = []
        for i in range(3):  # closed form (lines) and integration (dots) of z1, z2, z3
            series.append(Series(tau, z[:, i], f"z{i + 1}"))
            series.append(Series(tau[::40], Y[::40, i], style="markers"))
        panels.append(Panel(series=tuple(series), xlabel="τ", title=f"{name} (k² = {ep.k2:.3f})"))
    holds = conv.holds and regimes["regime x1"] == "x1"
    m = measured_by(
        conv,
        "1 (relative to |z0|)",
        "max |z(3.1) − z integrated| and attitude (quaternion) difference over 10 periods, "
        "regimes x3 and x1",
        "correction C7: in regime x1 (indices 1 ↔ 3 swapped) each square root is of the product of "
        "two negative factors (e.g. ν = √((L² − 2TI3)(I1 − I2)/(I1I2I3)))",
        per_case=per,
        regimes=regimes,
    )
    return Measurement(holds, True, m, panels)


@claim(
    "rf-11",
    RF,
    "period average ⟨z²⟩ (3.6)",
    "(3.6): ⟨z²⟩ = (L²/I0){(I3−I2)k²/I1 + (I2−I1)(I1+I2−I3)/(I1I2) + (I2−I1)(I3−I2)(I3−I1)"
    "/(I1I2I3) · E(k)/K(k)}.",
    "docs/theory/rotating-field.md §8",
)
def rf_11() -> Measurement:
    """Period average ⟨z²⟩ of (3.6) (§8).

    Returns
    -------
    Claim
        Measured: max |⟨z²⟩ of (3.6) / numerical period mean − 1| [1]; holds at ≤ 1e-10.
    """
    p = _params(RF_BODY, 1.0, 0.01)
    I1, I2, I3 = p.sorted_inertia
    rows = []
    cases: tuple[tuple[Literal["x3", "x1"], tuple[float, ...]], ...] = (
        ("x3", (0.1, 0.5, 0.9, 0.999)),
        ("x1", (0.2, 0.7, 0.99)),
    )
    for regime, k2s in cases:
        for k2 in k2s:
            st = rf.state_from_elements(p, 1.8, 0.5, 0.0, k2, regime)
            ep = EulerPoinsot.from_state(RF_BODY, st.z)
            n = 1024  # periodic trapezoid rule over one period: converges geometrically
            tau = ep.period * np.arange(n) / n
            numeric = float(np.mean(np.sum(ep.omega(tau) ** 2, axis=1)))
            closed = mean_square_rate(I1, I2, I3, ep.L, ep.T)
            rows.append((regime, k2, abs(closed / numeric - 1.0)))
    worst = max(r[2] for r in rows)
    series = []
    for regime in ("x3", "x1"):
        sel = [r for r in rows if r[0] == regime]
        series.append(
            Series(
                np.array([r[1] for r in sel]),
                np.array([max(r[2], 1e-17) for r in sel]),
                regime,
                "line+markers",
            )
        )
    panels = (
        Panel(
            series=tuple(series),
            xlabel="k²",
            ylabel="|⟨z²⟩(3.6) / numerical period mean − 1|",
            yscale="log",
            hlines=((1e-10, "threshold"),),
        ),
    )
    holds = worst <= 1e-10  # trapezoid of a smooth periodic function: round-off after 1024 nodes
    m = measured(
        worst,
        "1",
        "max relative difference between ⟨z²⟩ of (3.6) and the mean of |z(τ)|² over one period "
        "of (3.1), regimes x3 (k² up to 0.999) and x1",
        1e-10,
        "value ≤ 1e-10",
        per_case=[{"regime": r[0], "k2": r[1], "rel": r[2]} for r in rows],
    )
    return Measurement(holds, False, m, panels)


@claim(
    "rf-12",
    RF,
    "averaged equations (3.5)–(3.7)",
    "(3.5) L′, Lρ′, σ′ = 0; (3.6) T′ = ε{−¼[2(1+cos²β) + (1−3cos²β)sin²ρ]⟨z²⟩ + "
    "(1−3cos²β)(1−3sin²ρ)T²/L² + 2 sin²β cosρ T/L}; (3.7) dk²/dτ = ε(I3−I1)/(4I1I3)·A·F(k²).",
    "docs/theory/rotating-field.md §10; correction C5",
)
def rf_12() -> Measurement:
    """Averaged equations (3.5), (3.6) corrected, (3.7) (§10, correction C5).

    Returns
    -------
    Claim
        Measured: max |(3.5)–(3.6) − quadrature average| relative to ε(1 + L) [1]; holds at ≤ 1e-9
        with (3.7) = chain rule to 1e-6.
    """
    rng = np.random.default_rng(12)
    I3 = RF_BODY[2]
    errs_engine, errs_tform, errs_k2 = [], [], []
    for beta in (0.4, 1.0, math.pi / 2):
        p = _params(RF_BODY, beta, 0.01)
        for _ in range(5):
            e_engine, e_tform, e_k2 = _averaged_forms_at(p, _random_slow_state(rng))
            errs_engine.append(e_engine)
            errs_tform.append(e_tform)
            errs_k2.append(e_k2)
    # Correction C5 at the stationary rotation ρ = 0, k = 0, L = I3, T = I3/2 (β = 1).
    p = _params(RF_BODY, 1.0, 0.01)
    corrected = float(rf.averaged_rhs(0.0, np.array([I3, 0.0, 0.0, 0.5 * I3]), p)[3])
    # The printed middle term (1 − 3c²)(1 − 3 sin²ρ) T²/L² differs from the corrected one by
    # (1 − 3c²)·3(cos²ρ − sin²ρ)·T²/L² = (1 − 3c²)·3/4 at ρ = 0, T/L = 1/2.
    printed = corrected + p.eps * (1.0 - 3.0 * p.c2) * 0.75
    worst = max(max(errs_engine), max(errs_tform))
    panels = (
        Panel(
            series=tuple(
                Series(np.arange(len(e), dtype=float), np.maximum(e, 1e-18), name, "markers")
                for name, e in (
                    ("vector form vs quadrature engine", errs_engine),
                    ("T-form (3.5)/(3.6) vs vector form", errs_tform),
                    ("(3.7) vs chain rule", errs_k2),
                )
            ),
            xlabel="random state",
            ylabel="relative difference",
            yscale="log",
            hlines=((1e-9, ""),),
        ),
    )
    # Criteria: the engine averages the torque numerically to 1e-12 (1e-9 leaves 1e3); the
    # T-form and vector form are one system (round-off); (3.7) vs a central difference of
    # k²(r) with h = 1e-6 r (truncation ~1e-11, cancellation ~1e-10): 1e-6.
    holds = (
        worst <= 1e-9
        and max(errs_k2) <= 1e-6
        and abs(corrected) <= 1e-15
        and abs(printed) > 1e-3 * p.eps
    )
    m = measured(
        worst,
        "1 (relative to ε(1 + L))",
        "max |(3.5)–(3.6) − quadrature average of the eddy torque over polhode, precession and "
        "field phase| over 15 random states (3 values of β), and T-form vs vector form",
        1e-9,
        "value ≤ 1e-9, (3.7) = chain rule to 1e-6, corrected T′ = 0 at the stationary rotation",
        "correction C5: (3.6)'s middle term is (1 − 3cos²β)(1 − 3cos²ρ)T²/L² (printed: "
        "1 − 3 sin²ρ); "
        "the printed form gives T′ = −¾ε(3cos²β − 1) ≠ 0 at the stationary rotation; the "
        "averaging needs non-resonance (§12)",
        k2_form_vs_chain_rule=max(errs_k2),
        corrected_T_prime_at_stationary=corrected,
        printed_T_prime_at_stationary=printed,
    )
    return Measurement(holds, True, m, panels)


def _random_slow_state(rng: np.random.Generator) -> FloatArray:
    """[L_ξ, r] with |L| in (0.8, 2.5) and r = 2T/L² between 1/I3 and 1/I1, at least 2 % from
    the separatrix 1/I2 (the body RF_BODY)."""
    I1, I2, I3 = RF_BODY
    while True:
        r = float(rng.uniform(1.0 / I3, 1.0 / I1))
        if abs(r * I2 - 1.0) > 0.02:
            break
    L_xi = rng.normal(size=3)
    L_xi *= rng.uniform(0.8, 2.5) / np.linalg.norm(L_xi)
    return np.array([*L_xi, r])


def _averaged_forms_at(p: rf.Params, y: FloatArray) -> tuple[float, float, float]:
    """At the slow state y = [L_ξ, r]: the vector form against the quadrature engine (relative
    to ε(1 + L)), (3.5) + corrected (3.6) in (L, ρ, σ, T) against the vector form projected (in
    units of ε), and (3.7) against dk²/dr · dr/dτ (relative, central difference h = 1e-6 r)."""
    I1, I2, I3 = RF_BODY
    L_xi, r = y[:3], float(y[3])
    vec = rf.averaged_rhs_vector(0.0, y, p)
    num = rf.averaged_rhs_numeric(0.0, y, p)
    e_engine = max_abs(vec - num) / (p.eps * (1.0 + np.linalg.norm(L_xi)))
    L = float(np.linalg.norm(L_xi))
    perp = math.hypot(L_xi[0], L_xi[1])
    rho = math.atan2(perp, L_xi[2])
    T = 0.5 * r * L * L
    tf = rf.averaged_rhs(0.0, np.array([L, rho, 0.0, T]), p)
    dL = float(L_xi @ vec[:3]) / L
    dperp = (L_xi[0] * vec[0] + L_xi[1] * vec[1]) / perp
    drho = (L_xi[2] * dperp - perp * vec[2]) / (L * L)
    dT = 0.5 * (vec[3] * L * L + 2.0 * r * L * dL)
    e_tform = max(abs(tf[0] - dL), abs(tf[1] - drho) * L, abs(tf[3] - dT)) / p.eps
    k2, reg = modulus_squared(I1, I2, I3, 1.0, 0.5 * r)
    h = 1e-6 * r
    dk2dr = (
        modulus_squared(I1, I2, I3, 1.0, 0.5 * (r + h))[0]
        - modulus_squared(I1, I2, I3, 1.0, 0.5 * (r - h))[0]
    ) / (2 * h)
    rate = rf.modulus_rate(p, k2, (perp / L) ** 2, reg)
    return float(e_engine), float(e_tform), float(abs(rate - dk2dr * vec[3]) / abs(rate))


@claim(
    "rf-13",
    RF,
    "k² decreases monotonically 1 → 0; end about the largest axis",
    "§3: by (3.7) k² decreases monotonically from 1 to 0: the body tends to the unique stable "
    "motion, rotation about the axis of the largest moment of inertia.",
    "docs/theory/rotating-field.md §10 (monotonicity proof), §11 items 4–5",
)
def rf_13() -> Measurement:
    """k² decreases monotonically from 1 to 0; the body ends about its largest axis (§11.4).

    Returns
    -------
    Claim
        Measured: the largest dk²/dτ of (3.7) in regime x3 [1/τ]; holds at < 0 with the long
        averaged run ending about the largest axis.
    """
    rates = _modulus_rates()
    max_x3 = float(np.max(rates[:, 0]))
    min_x1 = float(np.min(rates[:, 1]))
    # The long averaged run (§11.5): k² → 0, ρ → 0, L → I3.
    p = _params(RF_BODY, 1.0, 0.02)
    st = rf.state_from_elements(p, 1.8, 0.8, 0.3, 0.9, "x3")
    tau = np.linspace(0.0, 3000.0, 301)
    avg = quiet(simulate, rf.MODEL, p, st, tau, "averaged").columns
    mono = float(np.max(np.diff(avg["k2"])))
    end_ok = (
        avg["k2"][-1] < 1e-3
        and abs(avg["L"][-1] / RF_BODY[2] - 1.0) < 1e-3
        and avg["rho"][-1] < 1e-3
    )
    # The x1 transient: k̃² first rises to the separatrix, then k² falls (§10, §11.4).
    tt, full, tavg = _rf_transient_runs()
    peak = float(np.max(tavg["k2"]))
    full_up = float(np.max(np.diff(full["k2"][tt > tt[np.argmax(tavg["k2"])] + 20.0])))
    panels = (
        Panel(
            series=(
                Series(tt, full["k2"], "full (1.5)"),
                Series(tt, tavg["k2"], "averaged (3.5)–(3.7)"),
            ),
            xlabel="τ",
            ylabel="k² of the current regime",
            title="from regime x1, ε = 0.01",
        ),
        Panel(
            series=(Series(tau, np.maximum(avg["k2"], 1e-18)),),
            xlabel="τ",
            ylabel="averaged k²",
            title="regime x3, β = 1, ε = 0.02",
            yscale="log",
        ),
    )
    # Criteria: F < 0 on (0, 1) makes dk²/dτ < 0 in regime x3 (and > 0 in x1); k² decreases
    # (round-off of k² recovered from r: 1e-12) to below 1e-3, with L → I3, ρ → 0 (1e-3).
    holds = max_x3 < 0.0 and min_x1 > 0.0 and mono <= 1e-12 and end_ok
    # Qualification, measured: the full k² is monotone only on average, and from regime x1
    # the modulus first rises to the separatrix.
    qualified = full_up > 0.0 and peak > 0.999
    m = measured(
        max_x3,
        "1/τ",
        "largest dk²/dτ of (3.7) in regime x3 over k² ∈ (0, 1), 4 values of ρ, 3 of β "
        "(must be < 0)",
        0.0,
        "value < 0 (and > 0 in regime x1), a long averaged run ends at k² < 1e-3, L = I3, ρ = 0",
        "proven for the averaged equation; in the full model k² decreases only on average "
        "(O(ε) oscillation); from the smallest axis k̃² first rises to 1 (separatrix), then k² "
        "falls from 1 to 0",
        min_rate_regime_x1=min_x1,
        averaged_end={
            "k2": float(avg["k2"][-1]),
            "L": float(avg["L"][-1]),
            "rho": float(avg["rho"][-1]),
        },
        full_k2_largest_increase_between_samples=full_up,
        x1_transient_peak_k2=peak,
    )
    return Measurement(holds, qualified, m, panels)


def _modulus_rates() -> FloatArray:
    """dk²/dτ of (3.7) in regimes x3 and x1 (columns) over k² ∈ (0, 1), 4 values of ρ and
    3 of β."""
    rows = []
    for beta in (0.3, 1.0, math.pi / 2):
        p = _params(RF_BODY, beta, 0.01)
        for k2 in np.linspace(0.001, 0.999, 50):
            for rho in (0.0, 1.0, math.pi / 2, 3.0):
                s2 = math.sin(rho) ** 2
                rows.append(
                    (
                        rf.modulus_rate(p, float(k2), s2, "x3"),
                        rf.modulus_rate(p, float(k2), s2, "x1"),
                    )
                )
    return np.array(rows)


@claim(
    "rf-14",
    RF,
    "σ = const (L in a fixed vertical plane)",
    "§3, from (3.5): σ′ = 0 — the angular momentum stays in the vertical plane through ξ3 "
    "and its initial position.",
    "docs/theory/rotating-field.md §11 item 1",
)
def rf_14() -> Measurement:
    """σ = const: L stays in a fixed vertical plane (§11.1).

    Returns
    -------
    Claim
        Measured: the fitted order [1] of max |σ_full − σ0| against ε; holds at ≥ 0.75 with the
        averaged σ constant.
    """
    eps = [0.02, 0.01, 0.005]
    exc, avg_dev = [], 0.0
    series = []
    for e in eps:
        p = _params(RF_BODY, 1.0, e)
        st = rf.state_from_elements(p, 1.8, 0.8, 0.3, 0.5, "x3")
        tau = np.linspace(0.0, 1.0 / e, 601)
        full = simulate(rf.MODEL, p, st, tau, "full").columns
        avg = quiet(simulate, rf.MODEL, p, st, tau, "averaged").columns
        exc.append(max_abs(wrap(full["sigma"] - 0.3)))
        avg_dev = max(avg_dev, max_abs(wrap(avg["sigma"] - 0.3)))
        series.append(Series(e * tau, wrap(full["sigma"] - 0.3) / e, f"full, ε = {e}"))
    order = fitted_order(eps, exc)
    panels = (
        Panel(
            series=tuple(series),
            xlabel="ετ",
            ylabel="(σ − σ0)/ε",
            title="averaged σ′ = 0; full σ − σ0 scaled by ε",
        ),
    )
    # Averaged σ′ = 0 exactly (integration tolerance, 1e-9); full excursions O(ε) (order ≥ 0.75).
    holds = avg_dev <= 1e-9 and order >= FIRST_ORDER
    m = measured(
        order,
        "1 (fitted order)",
        "fitted order of max|σ_full − σ0| against ε = 0.02, 0.01, 0.005 over τ ≤ 1/ε",
        FIRST_ORDER,
        "order ≥ 0.75 and averaged σ constant to 1e-9",
        "true to first order: the full σ oscillates by O(ε)",
        excursions=exc,
        averaged_sigma_deviation=avg_dev,
    )
    return Measurement(holds, True, m, panels)


@claim(
    "rf-15",
    RF,
    "ρ → 0 (L aligns with ξ3)",
    "§3: (3.5) implies ρ → 0 — the angular momentum turns to the axis of the field's rotation.",
    "docs/theory/rotating-field.md §11 item 2",
)
def rf_15() -> Measurement:
    """(3.5) implies ρ → 0 — true for β ≠ 0 but not monotone (§11.2).

    Returns
    -------
    Claim
        Measured: the rise of ρ [rad] over τ ≤ 60 in the full model (qualification if > 1e-2); the
        claim holds if the averaged ρ(τ = 8000) < 1e-3 rad.
    """
    p = _params(RF_BODY, math.pi / 2, 0.02)
    st = rf.state_from_elements(p, 3.0 * RF_BODY[2], 0.3, 0.0, 0.1, "x3")  # z3 ≈ 3: T/L ≈ 1.5
    tau = np.linspace(0.0, 60.0, 121)
    full = simulate(rf.MODEL, p, st, tau, "full").columns
    avg = quiet(simulate, rf.MODEL, p, st, tau, "averaged").columns
    rise_full = float(full["rho"][-1] - 0.3)
    rise_avg = float(avg["rho"][-1] - 0.3)
    long_tau = np.linspace(0.0, 8000.0, 161)
    long = quiet(simulate, rf.MODEL, p, st, long_tau, "averaged").columns
    # β = 0: both ρ = 0 and ρ = π attract; from ρ0 > π/2 the averaged ρ goes to π.
    p0 = _params(RF_BODY, 0.0, 0.02)
    st0 = rf.state_from_elements(p0, 1.8, 2.2, 0.0, 0.4, "x3")
    beta0 = quiet(simulate, rf.MODEL, p0, st0, np.linspace(0.0, 1500.0, 31), "averaged").columns
    panels = (
        Panel(
            series=(Series(tau, full["rho"], "full"), Series(tau, avg["rho"], "averaged")),
            xlabel="τ",
            ylabel="ρ [rad]",
            title="β = π/2, fast spin T/L ≈ 1.5: ρ first grows",
        ),
        Panel(
            series=(Series(long_tau, long["rho"]),),
            xlabel="τ",
            ylabel="averaged ρ [rad]",
            title="… and then → 0",
        ),
    )
    # Holds: ρ → 0 (1e-3 at slow time 160); qualification measured: ρ grows first by more than
    # the full model's O(ε) wobble of ρ (~5e-3 at ε = 0.02): 1e-2, in both models.
    holds = float(long["rho"][-1]) < 1e-3
    qualified = rise_full > 1e-2 and rise_avg > 1e-2
    m = measured(
        rise_full,
        "rad",
        "increase of ρ over τ ≤ 60 in the full model (β = π/2, z3 ≈ 3, ρ0 = 0.3, ε = 0.02)",
        1e-2,
        "limit: averaged ρ(τ = 8000) < 1e-3; qualification: ρ rises by > 1e-2 in both models",
        "true in the end for β ≠ 0 but not monotone: ρ′ > 0 while (1 − 3cos²β)cosρ T/L > "
        "sin²β; for β = 0 both ρ = 0 and ρ = π attract",
        rise_averaged=rise_avg,
        rho_end_long_run=float(long["rho"][-1]),
        beta_zero_rho_end_from_rho0_2_2=float(beta0["rho"][-1]),
    )
    return Measurement(holds, qualified, m, panels)


@claim(
    "rf-16",
    RF,
    "(3.7) decouples at ρ = 0 and cos²β = 1/3",
    "§3: at ρ = 0 (and for cos²β = 1/3) (3.7) is the equation of a body with a cavity "
    "filled with viscous fluid and of a heavy body in a weakly resisting medium.",
    "docs/theory/rotating-field.md §11 item 3",
)
def rf_16() -> Measurement:
    """At ρ = 0 and at cos²β = 1/3 (3.7) decouples: A is constant (§11.3).

    Returns
    -------
    Claim
        Measured: max relative variation of dk²/dτ of (3.7) over sin²ρ at cos²β = 1/3 [1]; holds at
        ≤ 1e-13.
    """
    beta_c = math.acos(1.0 / math.sqrt(3.0))
    s2 = np.linspace(0.0, 1.0, 11)
    variation, contrast = 0.0, 0.0
    series = []
    for beta in (beta_c, 1.0):
        p = _params(RF_BODY, beta, 0.01)
        for k2 in (0.1, 0.5, 0.9):
            r = np.array([rf.modulus_rate(p, k2, float(s), "x3") for s in s2])
            v = float(np.max(np.abs(r / r[0] - 1.0)))
            if beta == beta_c:
                variation = max(variation, v)
            else:
                contrast = max(contrast, v)
            series.append(
                Series(
                    s2,
                    r / r[0],
                    f"β = {beta:.3f}, k² = {k2}",
                    "line" if beta == beta_c else "dashed",
                )
            )
    panels = (Panel(series=tuple(series), xlabel="sin²ρ", ylabel="dk²/dτ relative to ρ = 0"),)
    holds = variation <= 1e-13  # round-off: A = 8/3 exactly when 1 − 3cos²β = 0
    m = measured(
        variation,
        "1",
        "max relative variation of dk²/dτ of (3.7) over sin²ρ ∈ [0, 1] at cos²β = 1/3",
        1e-13,
        "value ≤ 1e-13 (A = 8/3 for every ρ); at β = 1 the variation is O(1)",
        "the decoupling is correct; its identification with Chernousko's viscous-fluid body and "
        "the heavy body in a weakly resisting medium was not checked",
        variation_at_beta_1=contrast,
    )
    return Measurement(holds, True, m, panels)


@claim(
    "rf-17",
    RF,
    "final nutation decay at the (3.7) rate",
    "§3: near the stationary rotation (ρ = 0, k → 0) k² decays by (3.7), "
    "dk²/dτ ≈ −ε(I3−I1)(1 + cos²β)(3 + κ)k²/(4I1I3).",
    "docs/theory/rotating-field.md §11 item 5, §12 'co-rotation is itself resonant'",
)
def rf_17() -> Measurement:
    """The final nutation decay near co-rotation: (3.7) vs (2.6) vs the settling phase (§12).

    Returns
    -------
    Claim
        Measured: max |fitted k² decay rate of the full model / linearized (3.7) rate − 1| [1];
        holds at ≤ 0.05.
    """
    p = _params(RF_BODY, 1.0, 0.02)
    lim = rf.predicted_limits(p, rf.State(XI3, np.eye(3)))
    r37, r26 = lim["nutation_decay_rate_averaged"], lim["nutation_decay_rate_phase0"]
    series = []
    rows = []
    for psi0 in (0.0, 1.0, 2.0):  # three precession phases: the body settles at different φ
        row, line = _settling(p, psi0)
        rows.append(row)
        series.append(line)
    t = np.linspace(100.0, 600.0, 2)
    for guide_rate, name in ((r37, "(3.7) linearized"), (r26, "(2.6), φ = 0")):
        series.append(
            Series(
                t, 1e-3 * np.exp(guide_rate * (t - 100.0)), f"{name}: {guide_rate:.4f}", "dotted"
            )
        )
    panels = (
        Panel(
            series=tuple(series),
            xlabel="τ",
            ylabel="k²",
            title="near co-rotation, body (1, 1.6, 2.2), β = 1, ε = 0.02",
            yscale="log",
        ),
    )
    lin = _end_linearization(p)
    dev37 = max(abs(r["rate"] / r37 - 1.0) for r in rows)
    dev26 = max(abs(r["rate"] / r26 - 1.0) for r in rows)
    devphi = max(abs(r["rate"] / r["phase_formula"] - 1.0) for r in rows)
    # First-order rates against an envelope fit: O(ε) corrections and fit noise, 5 %.
    holds = dev37 <= 0.05
    m = measured(
        dev37,
        "1",
        "max |fitted k² decay rate of the full model / linearized (3.7) rate − 1| over three "
        "settling phases (β = 1, ε = 0.02)",
        0.05,
        "the paper's rate holds if value ≤ 0.05",
        "§12: the final decay follows the phase φ at which the body settles, "
        "2 Re λ2,3(φ) = rate(3.7) + (ε sin²β/2)(I2 − I1)/(I1 I2) cos 2φ: (2.6) is its slowest "
        "value (φ = 0), (3.7) its mean over φ",
        theory_consistent=devphi <= 0.05,
        deviation_from_2_6=dev26,
        deviation_from_phase_formula=devphi,
        rate_3_7=r37,
        rate_2_6=r26,
        runs=rows,
        averaged_linearization_at_end=lin,
    )
    return Measurement(holds, False, m, panels)


def _settling(p: rf.Params, psi0: float) -> tuple[dict[str, float], Series]:
    """A body near co-rotation from precession phase ψ0: its fitted k² decay rate, the phase
    φ it settles at, the rate of the linearization at that phase, and its k²(τ) curve."""
    st = rf.state_from_elements(p, RF_BODY[2], 0.0, 0.0, 1e-3, "x3", psi0=psi0)
    sol = integrate(
        lambda t, y: rf.full_rhs(t, y, p), rf.full_from_slow(p, st), 600.0, kernel=rf.full_kernel(p)
    )
    tau = np.linspace(100.0, 600.0, 5001)
    Y = sol(tau)
    k2 = rf.slow_from_full(p, tau, Y)["k2"]
    seg = np.array_split(np.arange(tau.size), 10)  # ~4 nutation periods each: envelope
    rate = float(np.polyfit([tau[s].mean() for s in seg], np.log([k2[s].max() for s in seg]), 1)[0])
    G = Y[-1, 3:].reshape(3, 3)
    phase = math.atan2(G[1, 0], G[0, 0])
    row = {
        "psi0": psi0,
        "rate": rate,
        "phase": phase,
        "phase_formula": rf.final_nutation_decay_rate(p, phase),
    }
    return row, Series(tau, k2, f"full, settles at φ = {phase:.2f}: rate {rate:.4f}")


def _end_linearization(p: rf.Params) -> dict[str, float]:
    """§11.5: the averaged system linearized at the end state (L_ξ = I3 ξ3, r = 1/I3) gives λ1
    and Re λ4,5 of (2.6) exactly: ∂(dL_ξ/dτ)/∂L_ξ by central differences (linear in L_ξ, so
    exact to round-off)."""
    I3 = RF_BODY[2]
    y_end = np.array([0.0, 0.0, I3, 1.0 / I3])
    jac = []
    for i in range(3):
        h = np.zeros(4)
        h[i] = 1e-6
        up = rf.averaged_rhs_vector(0.0, y_end + h, p)
        down = rf.averaged_rhs_vector(0.0, y_end - h, p)
        jac.append((up - down)[i] / 2e-6)
    approx = rf.approximate_roots(p)
    return {
        "lambda1_averaged": float(jac[2]),
        "lambda1_2_6": float(approx[0].real),
        "re_lambda45_averaged": float(jac[0]),
        "re_lambda45_2_6": float(approx[3].real),
    }


@claim(
    "rf-18",
    RF,
    "averaged model is first-order accurate",
    "§3: for ε ≪ 1 the averaged equations (3.5)–(3.7) describe the evolution of the slow "
    "variables L, ρ, σ, T (k²).",
    "docs/theory/rotating-field.md §10 assumptions, §12",
)
def rf_18() -> Measurement:
    """Averaged vs full: O(ε) in non-resonant transients (§12).

    Returns
    -------
    Claim
        Measured: the slowest fitted order [1] of max |full − averaged| of L, ρ, T, k² against ε;
        holds at ≥ 0.75.
    """
    p = _params(RF_BODY, 1.0, 0.01)
    st = rf.state_from_elements(p, 1.8, 0.8, 0.3, 0.5, "x3")
    eps = [0.02, 0.01, 0.005]
    study = quiet(
        averaging_error_study,
        rf.MODEL,
        p,
        st,
        eps,
        slow_time=3.0,
        variables=("L", "rho", "T", "k2"),
        samples=601,
        reference="averaged",
    )
    worst = min(study.slopes.values())
    # The separatrix crossing of the x1 transient (ε = 0.01): O(ε), theory allows ε|ln ε|.
    _, full, tavg = _rf_transient_runs()
    sep = {
        "L": max_abs(full["L"] - tavg["L"]),
        "k2": max_abs(full["k2"] - tavg["k2"]),
        "eps_abs_ln_eps": 0.01 * abs(math.log(0.01)),
    }
    study_eps = np.asarray(study.eps)
    panels = (
        Panel(
            series=(
                *(
                    Series(study_eps, e, f"{v}: order {study.slopes[v]:.2f}", "line+markers")
                    for v, e in study.errors.items()
                ),
                Series(study_eps, study_eps * 2, "slope 1", "dotted"),
            ),
            xlabel="ε",
            ylabel="max |full − averaged| over ετ ≤ 3",
            xscale="log",
            yscale="log",
        ),
    )
    holds = worst >= FIRST_ORDER
    m = measured(
        worst,
        "1 (fitted order)",
        "slowest fitted order of max|Δ| of L, ρ, T, k² (full − averaged) against ε = 0.02, 0.01, "
        "0.005 over ετ ≤ 3 (body (1, 1.6, 2.2), β = 1, regime x3)",
        FIRST_ORDER,
        "order ≥ 0.75",
        "O(ε) only in non-resonant transients: resonances m = n1ν1 + n2ν2 (k², T off by O(√ε) "
        "or O(1)), the thin plate, L → 0 and the co-rotation stage are excluded; a separatrix "
        "crossing stays first order in practice (theory: ε|ln ε|)",
        slopes=study.slopes,
        errors={v: e.tolist() for v, e in study.errors.items()},
        separatrix_crossing_eps_0_01=sep,
    )
    return Measurement(holds, True, m, panels)
