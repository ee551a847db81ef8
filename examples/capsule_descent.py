"""Write examples/capsule_descent.toml: the entry capsule of tumble.analysis.capsule as a
plain nonlinear_moment scenario (a, b, ε and the dynamic-pressure table Q(τ) of its descent).

    python examples/capsule_descent.py

The scenario reproduces the library run (capsule_attitude) up to the piecewise-linear
interpolation of the pressure table (≈ 1e-4 relative with 201 points).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from tumble.analysis.capsule import capsule_attitude

run = capsule_attitude(methods=())
p, st = run.params, run.initial
span = run.t_end - run.t_start
tau = np.linspace(0.0, 1.0, 201)
Q = p.pressure.value(tau)
table = ",\n".join(f"    [{t:.6f}, {q:.9g}]" for t, q in zip(tau, Q, strict=True))
c = run.capsule
text = f"""# tumble scenario: attitude of an uncontrolled entry capsule
# (docs/theory/nonlinear-moment.md §9–§10),
# written by examples/capsule_descent.py from tumble.analysis.capsule.capsule_attitude().
# Time t in seconds from the start of the attitude window (descent time {run.t_start:.3f} s,
# where the capsule's T·|q'|/q has fallen to 0.3) to h = 10 km ({run.t_end:.3f} s).
# Capsule: Soyuz-class, D = {c.D} m, m = {c.m} kg, A = {c.A:.1f} kg m², C = {c.C:.1f} kg m²;
# moment fit c1 = {run.fit.c1:.5f}, c2 = {run.fit.c2:.5f} (modified Newtonian);
# descent V0 = 7.6 km/s, γ0 = −2°, h0 = 100 km.
model = "nonlinear_moment"

[parameters]
mu = {p.mu!r}   # C/A
a = {p.a!r}     # q(t0) S D c1 / A [1/s²]
b = {p.b!r}     # q(t0) S D c2 / A [1/s²]

[perturbation]
eps = {p.eps!r}   # 1/(window length) [1/s]: τ = εt runs over [0, 1]
d = 0.0
nu = 0.0
# Q(τ) = q(t)/q(t0), the descent's dynamic pressure, piecewise linear
pressure = [
{table},
]

[initial]
theta_deg = {math.degrees(st.theta)!r}   # total angle of attack
theta_dot = {st.theta_dot!r}   # [rad/s], mid-swing
R = {st.R!r}   # μ r, roll rate 5°/s
G = {st.G!r}   # R cos θ0: no transverse rate about e_z

[run]
t_end = {span!r}
samples = 2001
methods = ["full", "averaged"]
averaged_init = "exact"   # the paper's; "corrected" removes the O(ε) start error
"""
out = Path(__file__).with_suffix(".toml")
out.write_text(text, encoding="utf-8")
print(f"wrote {out}")
