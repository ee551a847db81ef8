"""Claims nm-5, nm-6: Volosov's averaged equations (2.2)–(2.3) and the averages by complete
elliptic integrals (2.4)–(2.5)."""

from __future__ import annotations

import math
from typing import Any, Literal

import numpy as np
from scipy.integrate import quad

from tumble.analysis.claims.base import Measurement, Series, claim
from tumble.analysis.claims.nonlinear_moment.cases import (
    NM,
    NM_CASES,
    case_ticks,
    per_case_within,
    perturbed,
)
from tumble.models import nonlinear_moment as nm
from tumble.unperturbed import NutationOrbit, potential_slope


@claim(
    "nm-5",
    NM,
    "Volosov's averaged equations (2.2)–(2.3)",
    "(2.2): θ̇ext = ε[⟨Φθθ′⟩ + ⟨Φz·W^z⟩ − ⟨Φz⟩·W^z(θext)]/F(θext, z), ż = ε⟨Φz⟩, with the "
    "averages (2.3) over the unperturbed nutation.",
    "docs/theory/nonlinear-moment.md §6, §7; correction S13",
    name="volosov_averaging_gives_equations_2_2_and_2_3",
)
def nm_5() -> Measurement:
    """Volosov's averaged equations (2.2)–(2.3) (§7, correction S13: no error).

    Returns
    -------
    Claim
        Measured: max relative difference [1] between the numerator of (2.2) and a brute-force time
        average, and between θmax′, θmin′ of (2.2) and the energy form; holds at ≤ 1e-10.
    """
    per = {}
    for name in ("double well b < 0 (case 1)", "b > 0 (case 1)", "overturning a > 0 (case 2)"):
        p0, st = NM_CASES[name]
        p = perturbed(p0, 0.01)
        o = nm.orbit_of(p0, st)
        z = np.array([o.R, o.G, o.a, o.b])
        pert = nm.builtin_perturbation(p)

        def g(t: float, o: NutationOrbit = o, pert: Any = pert, z: np.ndarray = z) -> float:
            th, thd = o.theta(np.array([t])), o.theta_dot(np.array([t]))
            pz = pert.phi_z(0.0, th, z)
            return float(
                pert.phi_theta(0.0, th, thd, z)[0] * thd[0]
                + np.sum(pz[:, 0] * nm.potential_gradient(np.cos(th), z)[:, 0])
            )

        brute = quad(g, 0.0, o.period, epsabs=1e-13, epsrel=1e-12, limit=200)[0] / o.period
        energy = nm.averaged_rhs(0.0, np.array([o.E, *z]), p, u_hint=0.5 * (o.u1 + o.u2))
        closed = float(energy[0]) / p.eps  # ⟨Φθθ′⟩ + ⟨Φz·W^z⟩
        # (2.2) for θmax and θmin against the energy relation dH = F dθext + W^z·dz.
        rel = {"numerator": abs(closed - brute) / max(abs(brute), 1e-300)}
        forms: tuple[tuple[Literal["theta_max", "theta_min"], float], ...] = (
            ("theta_max", o.theta_max),
            ("theta_min", o.theta_min),
        )
        for form, x0 in forms:
            d = nm.averaged_rhs(0.0, np.array([x0, *z]), p, form=form)
            F = float(potential_slope(x0, o.R, o.G, o.a, o.b))  # ∂W/∂θ at the turning point
            wz = nm.potential_gradient(np.array([math.cos(x0)]), z)[:, 0]
            expect = (float(energy[0]) - float(energy[1:] @ wz)) / F
            rel[form] = abs(float(d[0]) - expect) / abs(expect)
        per[name] = {"brute_force": brute, **rel}
    worst = max(max(v for k, v in r.items() if k != "brute_force") for r in per.values())
    names = list(per)
    # Criterion: quad at epsrel 1e-12 over one period of the closed-form motion: 1e-10.
    return per_case_within(
        worst,
        1e-10,
        (
            Series(
                np.arange(len(names), dtype=float) + 0.1 * i,
                np.array([max(per[n][key], 1e-18) for n in names]),
                key,
                "markers",
            )
            for i, key in enumerate(("numerator", "theta_max", "theta_min"))
        ),
        case_ticks(names),
        "relative difference",
        "1",
        "max relative difference between the numerator of (2.2) (closed forms of §8) and a "
        "brute-force time average (quad) over one period; and θmax′, θmin′ of (2.2) against "
        "the energy form H′ = ε⟨…⟩, dH = F dθext + W^z·dz",
        per_case=per,
    )


@claim(
    "nm-6",
    NM,
    "averages by complete elliptic integrals (2.4)–(2.5)",
    "(2.4)–(2.5): for Φ rational in u with real poles the averages reduce to ∫cosⁱθ dt and "
    "∫dt/(1 ± cosθ) over a period, i.e. to complete elliptic integrals.",
    "docs/theory/nonlinear-moment.md §8",
    name="averages_reduce_to_complete_elliptic_integrals",
)
def nm_6() -> Measurement:
    """Reduction of the averages to complete elliptic integrals (2.4)–(2.5) (§8).

    Returns
    -------
    Claim
        Measured: max |average by K, E, Π − periodic trapezoid rule| relative to max(1, |value|)
        [1]; holds at ≤ 1e-10.
    """
    per = {}
    for name, (p, st) in NM_CASES.items():
        if p.b == 0.0:
            continue  # b = 0 is a removable singularity of I2: tumble itself uses quadrature there
        o = nm.orbit_of(p, st)
        checks = {
            "<u>": (o.mean_u_power(1), lambda th, thd: np.cos(th)),
            "<u^2>": (o.mean_u_power(2), lambda th, thd: np.cos(th) ** 2),
            "<u^3>": (o.mean_u_power(3), lambda th, thd: np.cos(th) ** 3),
            "<1/(1+u)>": (o.mean_inverse(1), lambda th, thd: 1.0 / (1.0 + np.cos(th))),
            "<1/(1-u)>": (o.mean_inverse(-1), lambda th, thd: 1.0 / (1.0 - np.cos(th))),
        }
        per[name] = {k: abs(v - o.average(f)) / max(1.0, abs(v)) for k, (v, f) in checks.items()}
    worst = max(max(r.values()) for r in per.values())
    keys = ["<u>", "<u^2>", "<u^3>", "<1/(1+u)>", "<1/(1-u)>"]
    # The periodic trapezoid rule converges geometrically (§8).
    return per_case_within(
        worst,
        1e-10,
        (
            Series(
                np.arange(len(keys), dtype=float),
                np.array([max(r[k], 1e-18) for k in keys]),
                name,
                "line+markers",
            )
            for name, r in per.items()
        ),
        tuple((float(i), k) for i, k in enumerate(keys)),
        "|closed form (K, E, Π) − trapezoid in t| ",
        "1 (relative to max(1, |value|))",
        "max difference between ⟨u⟩, ⟨u²⟩, ⟨u³⟩, ⟨1/(1±u)⟩ by K, E, Π (§8) and the periodic "
        "trapezoid rule in time, four orbits",
        per_case=per,
    )
