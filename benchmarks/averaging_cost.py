"""Cost of one evaluation of the averaged right-hand sides built by the general engine.

    .venv/bin/python benchmarks/averaging_cost.py [--points 60] [--repeat 7] [--seed 5] [--json]

Targets: one evaluation ≤ 1 ms for the symmetric (spinner) and nonlinear-moment (nutation)
settings and ≤ 5 ms for the triaxial one. Each right-hand side is called the way its model
calls it during an averaged run, at the default tolerance AVERAGE_RTOL = 1e-12:

* spinner (the resisting medium): ``resisting_medium.averaged_rhs_numeric`` with the moment (1.2)
  as ``Params.torque``: the constant body moment a, the linear drag b, the quadratic drag s,
  and all three (full random a, b, s in [−1, 1]);
* nutation (the nonlinear moment): ``nonlinear_moment.averaged_rhs`` (energy form) with
  ``engine_perturbation(p)``, the damping d, ν of §9 as a body torque and the pressure law
  Q(τ) = exp τ as prescribed a(τ), b(τ);
* triaxial (the rotating field): ``rotating_field.averaged_rhs_numeric`` (the eddy-current
  torque and the field's rotation), and ``triaxial_average_vector`` as
  ``models/torqued_body/model.py`` calls it for a gravity-gradient torque (forcing period the
  orbital one) and for a moment fixed in inertial space (no forcing); k² ≤ 0.9999.

Each evaluation is timed as the best of ``--repeat`` calls (time.perf_counter; the best is the
cost of the code rather than of the machine's load; the repeats are rounds over all states),
at ``--points`` states drawn with a fixed seed from the model's domain; the table gives the
median and the largest over the states. The exit status is 1 if a median misses its target.

Measured with the defaults (60 points, best of 7) on 2 shared cores, three runs each; a row's
figures move by up to ±30 % with the load of other processes. "Before" is the engine at the
commit that introduced this benchmark's settings, timed by this same script:

    setting   torque                        median ms   max ms  target  met  before: median, max
    spinner   constant a                         0.26     0.30     1.0  yes  0.54–0.81, 0.87
    spinner   linear drag b                      0.26     0.30     1.0  yes  0.52–0.80, 0.90
    spinner   quadratic drag s                   0.26     0.31     1.0  yes  1.57–1.83, 2.92 (no)
    spinner   a + b + s                          0.26     0.30     1.0  yes  1.35–1.74, 2.23 (no)
    nutation  damping d, ν + pressure Q(τ)  0.69–0.73     1.38     1.0  yes  1.35–1.89, 3.68 (no)
    triaxial  eddy current (1.3)              1.6–1.8     2.6      5.0  yes  1.3–1.8, 3.2
    triaxial  gravity gradient                1.7–2.4     3.5      5.0  yes  6.6–7.0, 10.2 (no)
    triaxial  constant inertial moment        0.8–1.2     1.6      5.0  yes  0.8–1.0, 1.3

About half of the nutation figure is the unperturbed orbit (NutationOrbit.from_energy and
its nodes over the period), which the engine does not control.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging import triaxial_average_vector
from tumble.errors import ParameterError
from tumble.models import nonlinear_moment as nm
from tumble.models import resisting_medium as rm
from tumble.models import rotating_field as rf
from tumble.torques import ConstantInertialTorque, GravityGradientTorque
from tumble.unperturbed import energy_from_modulus
from tumble.unperturbed.symmetric_body import NutationOrbit

TARGET_MS = {"spinner": 1.0, "nutation": 1.0, "triaxial": 5.0}
K2_MAX = 0.9999  # the required triaxial range; nearer the separatrix the polhode needs more nodes


@dataclass(frozen=True)
class Row:
    """Cost of one right-hand side over the sample of states."""

    setting: str
    torque: str
    points: int
    median_ms: float
    max_ms: float
    target_ms: float

    @property
    def met(self) -> bool:
        return self.median_ms <= self.target_ms


def best_times(calls: list[Callable[[], object]], repeat: int) -> FloatArray:
    """Best wall time of ``repeat`` calls of each of ``calls`` [s].

    The repeats are rounds over all the calls, not back to back: a burst of load from other
    processes then spoils one round of every state rather than every round of a few.
    """
    for call in calls:
        call()  # the first call builds caches (the batched-call probe, Romberg weights)
    best = np.full(len(calls), math.inf)
    for _ in range(repeat):
        for i, call in enumerate(calls):
            start = time.perf_counter()
            call()
            best[i] = min(best[i], time.perf_counter() - start)
    return best


def row(setting: str, torque: str, calls: list[Callable[[], object]], repeat: int) -> Row:
    times = best_times(calls, repeat) * 1e3
    return Row(
        setting,
        torque,
        len(calls),
        float(np.median(times)),
        float(np.max(times)),
        TARGET_MS[setting],
    )


# ---------------------------------------------------------------------------------------------
# The three settings, sampled from each model's domain.


def spinner_calls(rng: np.random.Generator, points: int) -> dict[str, list[Callable[[], object]]]:
    """``resisting_medium.averaged_rhs_numeric`` at random (κ, k, ρ, σ, ϑ) for each law of (1.2)."""
    laws: dict[str, list[Callable[[], object]]] = {
        "constant a": [],
        "linear drag b": [],
        "quadratic drag s": [],
        "a + b + s": [],
    }
    for _ in range(points):
        kappa = float(rng.choice([rng.uniform(-0.8, -0.05), rng.uniform(0.05, 1.0)]))
        a, b, s = rng.uniform(-1, 1, 3), rng.uniform(-1, 1, (3, 3)), rng.uniform(-1, 1, (3, 3))
        y = np.array(
            [
                rng.uniform(0.2, 3.0),  # k
                rng.uniform(0.1, math.pi - 0.1),  # ρ
                rng.uniform(-math.pi, math.pi),  # σ
                rng.uniform(0.05, math.pi - 0.05),  # ϑ
            ]
        )
        for name, terms in (
            ("constant a", {"a": a}),
            ("linear drag b", {"b": b}),
            ("quadratic drag s", {"s": s}),
            ("a + b + s", {"a": a, "b": b, "s": s}),
        ):
            p = rm.Params(eps=0.02, kappa=kappa, **terms)
            laws[name].append(lambda y=y, p=p: rm.averaged_rhs_numeric(0.0, y, p))
    return laws


def nutation_calls(rng: np.random.Generator, points: int) -> list[Callable[[], object]]:
    """``nonlinear_moment.averaged_rhs`` with the engine, on regular orbits of the domain.

    The domain of tests/averaging/test_averaging_nutation.py: μ ∈ (0.3, 1.8), a ∈ (−2, 0), b, R, G ∈
    (−1.5, 1.5), d, ν ∈ (−1, 1); orbits with 1 − k² < 1e-4 (near a separatrix) or within 0.05
    of a pole are drawn again.
    """
    calls: list[Callable[[], object]] = []
    while len(calls) < points:
        mu, a, b = rng.uniform(0.3, 1.8), rng.uniform(-2.0, 0.0), rng.uniform(-1.5, 1.5)
        R, G = rng.uniform(-1.5, 1.5, 2)
        theta, theta_dot = rng.uniform(0.3, math.pi - 0.3), rng.uniform(-1.0, 1.0)
        d, nu = rng.uniform(-1.0, 1.0, 2)
        try:
            orbit = NutationOrbit.from_state(mu, a, b, R, G, theta, theta_dot)
        except ParameterError:
            continue  # no regular orbit through this state
        if orbit.mc < 1e-4 or min(orbit.theta_min, math.pi - orbit.theta_max) < 0.05:
            continue
        p = nm.Params(mu=mu, a=a, b=b, eps=0.01, d=d, nu=nu, pressure=nm.Pressure("exp"))
        engine = nm.engine_perturbation(p)  # built once per run, as the model does
        y = np.array([orbit.E, R, G, a, b])
        u_hint = 0.5 * (orbit.u1 + orbit.u2)

        def call(y=y, p=p, engine=engine, u_hint=u_hint) -> object:
            return nm.averaged_rhs(1.0, y, p, form="energy", u_hint=u_hint, perturbation=engine)

        calls.append(call)
    return calls


def triaxial_calls(rng: np.random.Generator, points: int) -> dict[str, list[Callable[[], object]]]:
    """The vector form [L_ξ, r] at random triaxial bodies, regimes and k² ∈ [0, K2_MAX]."""
    cases: dict[str, list[Callable[[], object]]] = {
        "eddy current (1.3)": [],
        "gravity gradient": [],
        "constant inertial moment": [],
    }
    for i in range(points):
        I2 = rng.uniform(1.2, 1.8)
        inertia = (1.0, I2, rng.uniform(I2 + 0.1, 1.0 + I2 - 0.05))
        regime = "x3" if i % 2 else "x1"
        L = rng.uniform(0.5, 2.0)
        T = energy_from_modulus(*inertia, L, rng.uniform(0.0, K2_MAX), regime)
        e = rng.normal(size=3)
        y = np.array([*(L * e / np.linalg.norm(e)), 2.0 * T / L**2])
        p = rf.Params(inertia, rng.uniform(0.2, math.pi - 0.2), 0.01)
        cases["eddy current (1.3)"].append(lambda y=y, p=p: rf.averaged_rhs_numeric(0.0, y, p))
        n = rng.uniform(0.2, 2.0)
        gravity = 0.01 * GravityGradientTorque(
            inertia, n, normal=rng.normal(size=3), u0=rng.uniform(0.0, 2.0 * math.pi)
        )
        cases["gravity gradient"].append(
            lambda y=y, tq=gravity, inertia=inertia, n=n: triaxial_average_vector(
                tq, inertia, y, 0.0, forcing_period=2.0 * math.pi / n
            )
        )
        fixed = 0.01 * ConstantInertialTorque(rng.uniform(-1.0, 1.0, 3))
        cases["constant inertial moment"].append(
            lambda y=y, tq=fixed, inertia=inertia: triaxial_average_vector(tq, inertia, y, 0.0)
        )
    return cases


def measure(points: int = 60, repeat: int = 7, seed: int = 5) -> list[Row]:
    """Median and largest cost of one evaluation of each averaged right-hand side.

    Parameters
    ----------
    points : int
        States per setting and torque.
    repeat : int
        Calls per state; the best is kept.
    seed : int
        Seed of the sample of states.

    Returns
    -------
    list of Row
    """
    rng = np.random.default_rng(seed)
    rows = [
        row("spinner", name, calls, repeat) for name, calls in spinner_calls(rng, points).items()
    ]
    rows.append(
        row("nutation", "damping d, ν + pressure Q(τ)", nutation_calls(rng, points), repeat)
    )
    rows += [
        row("triaxial", name, calls, repeat) for name, calls in triaxial_calls(rng, points).items()
    ]
    return rows


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=60, help="states per setting and torque")
    parser.add_argument("--repeat", type=int, default=7, help="calls per state (best kept)")
    parser.add_argument("--seed", type=int, default=5, help="seed of the sample of states")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    rows = measure(args.points, args.repeat, args.seed)
    if args.json:
        print(json.dumps([{**asdict(r), "met": r.met} for r in rows], indent=2))
    else:
        print(
            f"{'setting':9s} {'torque':30s} {'points':>6s} {'median ms':>10s} {'max ms':>8s} "
            f"{'target ms':>10s} {'met':>4s}"
        )
        for r in rows:
            print(
                f"{r.setting:9s} {r.torque:30s} {r.points:6d} {r.median_ms:10.3f} "
                f"{r.max_ms:8.3f} {r.target_ms:10.1f} {'yes' if r.met else 'no':>4s}"
            )
    return 0 if all(r.met for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
