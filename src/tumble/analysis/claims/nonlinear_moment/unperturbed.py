"""Claims nm-1 … nm-4: the integrals of the unperturbed motion and its closed form (1.9)–(1.13)."""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np

from tumble.analysis.claims.base import Measurement, Series, claim
from tumble.analysis.claims.common import (
    Difference,
    Tolerances,
    budget_panel,
    by_convergence,
    converged,
    max_abs,
    time_panel,
)
from tumble.analysis.claims.nonlinear_moment.cases import (
    NM,
    NM_CASES,
    UNPERTURBED,
    case_ticks,
    per_case_within,
)
from tumble.integrate import integrate, simulate
from tumble.models import nonlinear_moment as nm
from tumble.unperturbed import NutationOrbit, quartic_coefficients


@functools.cache
def _nm_unperturbed_runs(
    rtol: float, atol: float
) -> tuple[dict[str, tuple[np.ndarray, dict, dict, NutationOrbit]], int]:
    """Full integration and closed form (1.9)–(1.13) over ten periods, and the full runs'
    right-hand-side evaluations."""
    out, nfev = {}, 0
    for name, (p, st) in NM_CASES.items():
        orbit = nm.orbit_of(p, st)
        t = np.linspace(0.0, 10.0 * orbit.period, 1001)
        run = simulate(nm.MODEL, p, st, t, "full", rtol=rtol, atol=atol)
        closed = simulate(nm.MODEL, p, st, t, "closed_form").columns
        out[name] = (t, run.columns, closed, orbit)
        nfev += run.nfev
    return out, nfev


@claim(
    "nm-1",
    NM,
    "integrals R, G, E of the unperturbed motion",
    "(1.1)–(1.6): with M0 along the line of nodes R = Cr/A and G are constant and "
    "E = θ′²/2 + W(θ) is an energy integral.",
    "docs/theory/nonlinear-moment.md §1, §2; corrections S1, S2; §13",
    name="r_g_and_energy_are_integrals_of_unperturbed_motion",
)
def nm_1() -> Measurement:
    """R, G and the energy E are integrals of the unperturbed motion (1.3a), (1.6) (E1, E2).

    Returns
    -------
    Claim
        Measured: max drift of R, G, E over ten nutation periods and max |E, G of the state −
        (1.6)|, relative to max(1, |value|) [1]; holds if it is integration error.
    """

    def difference(tol: Tolerances) -> tuple[Difference, int, tuple[dict[str, Any], list[Series]]]:
        series, per, nfev = [], {}, 0
        for name, (p, st) in NM_CASES.items():
            orbit = nm.orbit_of(p, st)
            t_end = 10.0 * orbit.period
            sol = integrate(
                functools.partial(nm.full_rhs, p=p),
                nm.full_from_slow(p, st),
                t_end,
                **tol,
                kernel=nm.full_kernel(p),
            )
            nfev += sol.nfev
            t = np.linspace(0.0, t_end, 1001)
            inv = nm.invariants(p, sol(t))
            drift = {k: max_abs(v - v[0]) / max(1.0, abs(float(v[0]))) for k, v in inv.items()}
            # The energy from the state must equal the orbit's E of (1.6) (correction S2: G with
            # cos φ).
            drift["E_vs_1.6"] = abs(float(inv["E"][0]) - orbit.E) / max(1.0, abs(orbit.E))
            drift["G_vs_state"] = abs(float(inv["G"][0]) - st.G) / max(1.0, abs(st.G))
            per[name] = drift
            series.append(
                Series(t / orbit.period, np.maximum(np.abs(inv["E"] - inv["E"][0]), 1e-18), name)
            )
        return {c: max(d.values()) for c, d in per.items()}, nfev, (per, series)

    # Criterion: conserved to integration accuracy — the drift falls with the tolerance (a
    # wrong G or E of (1.6) is an O(1) mismatch that does not).
    conv, (per, series) = converged(difference, UNPERTURBED)
    panels = (
        budget_panel(
            series, conv, "t / T", "|E(t) − E(0)|", "unperturbed, quaternion form of (1.1)"
        ),
    )
    return by_convergence(
        conv,
        panels,
        "1 (relative to max(1, |value|))",
        "max drift of R, G, E of the full model over ten nutation periods, and E, G of the "
        "initial state against (1.6) and the definition of G, five orbits",
        "correction S1: A is the equatorial and C the axial moment (the prose swaps them); "
        "correction S2: G = (p sinφ + q cosφ) sinθ + μr cosθ (printed: q sinφ)",
        per_case=per,
    )


@claim(
    "nm-2",
    NM,
    "nutation θ(t) in closed form (1.9)–(1.10)",
    "(1.9) cosθ = L + M/(1 + N sin²(δγ)), γ = am(βt + τ0, k), with L, M, N, k, β of case 1 "
    "(four real roots) and case 2 (a complex pair); (1.10) τ0 and γ0.",
    "docs/theory/nonlinear-moment.md §3, §4; corrections S3, S4, S5, S6, S11; §13",
    name="nutation_follows_closed_form_1_9_and_1_10",
)
def nm_2() -> Measurement:
    """Nutation in closed form (1.9)–(1.10) (corrections S3–S6, 11).

    Returns
    -------
    Claim
        Measured: max |θ of (1.9) − θ integrated| [rad] (θ′ relative) over ten periods of five
        orbits; holds if it is integration error (it falls with the tolerance).
    """

    def difference(tol: Tolerances) -> tuple[Difference, int, tuple[dict[str, Any], Any]]:
        runs, nfev = _nm_unperturbed_runs(tol["rtol"], tol["atol"])
        per = {}
        for name, (_t, full, closed, orbit) in runs.items():
            err = max(
                max_abs(full["theta"] - closed["theta"]),
                max_abs(full["theta_dot"] - closed["theta_dot"])
                / max(1.0, max_abs(full["theta_dot"])),
            )
            per[name] = {"error": err, "root_case": orbit.root_case, "k2": orbit.k2}
        return {c: v["error"] for c, v in per.items()}, nfev, (per, runs)

    # Criterion: (1.9) is exact, so θ agrees to integration accuracy (the difference falls
    # with the tolerance); a wrong τ0 exponent, γ0 sign or β (corrections S3–S6) gives O(1) errors
    # (or a wrong period), which do not.
    conv, (per, runs) = converged(difference, UNPERTURBED)
    series = [
        Series(t / orbit.period, np.maximum(np.abs(full["theta"] - closed["theta"]), 1e-18), name)
        for name, (t, full, closed, orbit) in runs.items()
    ]
    panels = (budget_panel(series, conv, "t / T", "|θ(1.9) − θ integrated| [rad]"),)
    return by_convergence(
        conv,
        panels,
        "rad",
        "max |θ(1.9) − θ integrated| (and θ′ relative) over ten periods, five orbits (both root "
        "cases, double well, b = 0 with a > 0)",
        "corrections S3–S6: τ0 = F(γ0, k) (exponent −1/2), γ0 = σ sign(θ′0)…, σ = +1 in case 2; "
        "β = √(−(b/2)(u1−u3)(u2−u4)) (case 1), √(−2bη) (case 2); correction S11 / §4.3: for b = 0 "
        "with a > 0 the alternative anchoring is needed",
        per_case=per,
    )


def _period_by_quadrature(orbit: NutationOrbit) -> float:
    """T = 2∫du/√f over [u2, u1], (1.8), by Gauss–Legendre after u = c + h sin φ, which takes
    the square-root zeros at the turning points into the weight (independent of K(k), β)."""
    g = quartic_coefficients(orbit.R, orbit.G, orbit.a, orbit.b, orbit.E)[::-1]  # high first
    u1, u2 = orbit.u1, orbit.u2
    q, _ = np.polydiv(g, np.poly([u1, u2]))  # f = (u − u1)(u − u2) q, q < 0 on (u2, u1)
    x, w = np.polynomial.legendre.leggauss(200)
    phi = 0.5 * math.pi * x
    u = 0.5 * (u1 + u2) + 0.5 * (u1 - u2) * np.sin(phi)
    return float(2.0 * 0.5 * math.pi * np.sum(w / np.sqrt(-np.polyval(q, u))))


@claim(
    "nm-3",
    NM,
    "nutation period and β of (1.10)",
    "§1: T = 2K(k)/β with β = [2b(u1−u3)(u2−u4)]^{1/2} (case 1) and β = (2bη)^{1/2} (case 2).",
    "docs/theory/nonlinear-moment.md §4.1, §4.2; corrections S5, S6",
    name="nutation_period_follows_from_beta_of_1_10",
)
def nm_3() -> Measurement:
    """Nutation period T = 2K/β (case 1), 4K/β (case 2) with the corrected β (corrections S5, S6).

    Returns
    -------
    Claim
        Measured: max |T of (1.10) / 2∫du/√f − 1| [1] over five orbits; holds at ≤ 1e-10.
    """
    rows = {}
    for name, (p, st) in NM_CASES.items():
        orbit = nm.orbit_of(p, st)
        T_quad = _period_by_quadrature(orbit)
        row = {
            "period": orbit.period,
            "quadrature": T_quad,
            "rel": abs(orbit.period / T_quad - 1.0),
            "root_case": orbit.root_case,
        }
        if (
            orbit.root_case == 1
            and math.isfinite(orbit.roots[2].real)
            and math.isfinite(orbit.roots[3].real)
        ):
            u1, u2, u3, u4 = (float(z.real) for z in orbit.roots)
            # The paper's β = [2b(u1 − u3)(u2 − u4)]^{1/2}: negative radicand, modulus 2× too big.
            radicand = 2 * orbit.b * (u1 - u3) * (u2 - u4)
            row["seed_radicand"] = radicand
            # Period with |β_seed| over the true period: β/|β_seed|.
            row["seed_period_over_true"] = orbit.beta / math.sqrt(abs(radicand))
        rows[name] = row
    worst = max(r["rel"] for r in rows.values())
    names = list(rows)
    # Gauss–Legendre on a smooth integrand: round-off.
    return per_case_within(
        worst,
        1e-10,
        (
            Series(
                np.arange(len(names), dtype=float),
                np.array([max(rows[n]["rel"], 1e-17) for n in names]),
                style="bar",
            ),
        ),
        case_ticks(names),
        "|T(2K/β or 4K/β) / 2∫du/√f − 1|",
        "1",
        "max relative difference between the period 2K/β (case 1) or 4K/β (case 2) and "
        "2∫_{u2}^{u1} du/√f(u) by quadrature, five orbits",
        "corrections S5, S6: the printed β radicands are negative (case 1: 2b(u1−u3)(u2−u4), "
        "modulus giving half the period; case 2: 2bη with b < 0)",
        per_case=rows,
    )


@claim(
    "nm-4",
    NM,
    "precession and spin (1.11)–(1.13)",
    "(1.13): ψ − ψ0 and φ − φ0 are the secular terms P_ψ t, P_φ t plus χ±Π(γ, w±, k) and, "
    "in case 2, w± L±(γ).",
    "docs/theory/nonlinear-moment.md §5; corrections S7, S8, S9, S10, S14",
    name="precession_and_spin_follow_1_11_to_1_13",
)
def nm_4() -> Measurement:
    """Precession and spin (1.11)–(1.13) (corrections S7–S10).

    Returns
    -------
    Claim
        Measured: max |ψ, φ of (1.13) − integrated| relative to max(1, |phase|) [1] over ten
        periods; holds if it is integration error (it falls with the tolerance).
    """

    def difference(tol: Tolerances) -> tuple[Difference, int, tuple[dict[str, Any], Any]]:
        runs, nfev = _nm_unperturbed_runs(tol["rtol"], tol["atol"])
        per = {}
        for name, (t, full, closed, orbit) in runs.items():
            e = {}
            for v in ("psi", "phi"):
                scale = max(1.0, max_abs(full[v]))  # phases accumulate over ten periods
                e[v] = max_abs(full[v] - closed[v]) / scale
            # Mean rates (§5) against the accumulated phase of the full run over ten periods.
            e["mean_psidot"] = abs(
                (full["psi"][-1] - full["psi"][0]) / t[-1] - orbit.mean_psidot
            ) / max(1.0, abs(orbit.mean_psidot))
            per[name] = e
        return {c: max(e["psi"], e["phi"]) for c, e in per.items()}, nfev, (per, runs)

    # Same criterion as nm-2, relative to the accumulated phase; the mean rate over ten periods
    # equals ⟨ψ′⟩ only up to the periodic part of ψ, O(1)/(10 T) relative (recorded only).
    conv, (per, runs) = converged(difference, UNPERTURBED)
    psi_series, phi_series = [], []
    for name, (t, full, closed, orbit) in runs.items():
        psi_series.append(
            Series(t / orbit.period, np.maximum(np.abs(full["psi"] - closed["psi"]), 1e-18), name)
        )
        phi_series.append(
            Series(t / orbit.period, np.maximum(np.abs(full["phi"] - closed["phi"]), 1e-18))
        )
    worst_rate = max(e["mean_psidot"] for e in per.values())
    panels = (
        time_panel(
            psi_series,
            "|ψ(1.13) − ψ integrated|",
            xlabel="t / T",
            yscale="log",
        ),
        time_panel(
            phi_series,
            "|φ(1.13) − φ integrated|",
            xlabel="t / T",
            yscale="log",
        ),
    )
    return by_convergence(
        conv,
        panels,
        "1 (relative to max(1, |phase|))",
        "max |ψ, φ of (1.13) − integrated| over ten periods, five orbits",
        "corrections S7–S9: χ± of case 2 re-bracketed, λ± = (k² + w±)^{+1/2} and L±(γ) with "
        "sin²γ, coefficients of L± are ϰ± = (G±R)(u1−u2)/[4β(1±u1)(1±u2)] (printed: w±); "
        "correction S10: Π has the plus-sign convention (n = −w)",
        per_case=per,
        worst_mean_rate_mismatch_ten_periods=worst_rate,
    )
