"""The perturbation (2.1) of the nonlinear-moment model: the descending capsule of §9
(pitch and roll damping, the dynamic pressure Q(τ)), its averages in closed form (§8), and
its damping as a torque for the general engine.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging.nutation import Perturbation, torque_perturbation
from tumble.models.inputs.nonlinear_moment import Params
from tumble.torques import LinearDrag
from tumble.unperturbed.symmetric_body import NutationOrbit

# ---------------------------------------------------------------------------------------------
# The perturbation (2.1) in general, and the built-in one of §9.


def builtin_perturbation(p: Params) -> Perturbation:
    """Φθ, Φz of the descending capsule, §9: pitch and roll damping, pressure Q(τ).

    Φθ = −dθ', Φ_R = −νR, Φ_G = −d(G − Ru) − νRu, Φ_a = a0 Q'(τ), Φ_b = b0 Q'(τ); vectorized
    over several slow states (``rows``).

    Parameters
    ----------
    p : Params

    Returns
    -------
    Perturbation
    """

    def phi_theta(tau: float, theta: FloatArray, theta_dot: FloatArray, z: FloatArray) -> Any:
        return -p.d * theta_dot

    def phi_z(tau: float, theta: FloatArray, z: FloatArray) -> FloatArray:
        R, G = z[0], z[1]
        u = np.cos(theta)
        da, db = p.ab_rate(tau)
        one = np.ones_like(u)
        return np.array(
            [-p.nu * R * one, -p.d * (G - R * u) - p.nu * R * u, float(da) * one, float(db) * one]
        )

    return Perturbation(phi_theta, phi_z, name="§9 (pitch/roll damping, pressure)", rows=True)


def _builtin_averages(orbit: NutationOrbit, p: Params, tau: float) -> tuple[float, FloatArray]:
    """The averages of §9 in closed form: ⟨u⟩, ⟨u²⟩ by K, E, Π (§8)."""
    R, G, a, b, E = orbit.R, orbit.G, orbit.a, orbit.b, orbit.E
    m1, m2 = orbit.mean_u_power(1), orbit.mean_u_power(2)
    da, db = (float(v) for v in p.ab_rate(tau))
    g = -p.d * 2.0 * (E - a * m1 - b * m2) + da * m1 + db * m2
    phi_z = np.array([-p.nu * R, -p.d * (G - R * m1) - p.nu * R * m1, da, db])
    return g, phi_z


def damping_torque(p: Params) -> LinearDrag:
    """The damping of §9 as a body-axes torque per unit A and ε: −d(p, q, 0) − ν(0, 0, R).

    With R = μr this is the linear drag −diag(d, d, νμ) ω, so the engine recognises a torque
    of the body rate only and averages it over φ alone.

    Parameters
    ----------
    p : Params

    Returns
    -------
    LinearDrag
        ``(t, q, omega) -> δM/A`` [1/t²] (for ``torque_perturbation``).
    """
    return LinearDrag(np.diag([p.d, p.d, p.nu * p.mu]))


def engine_perturbation(p: Params) -> Perturbation:
    """The perturbation of §9 for the general engine: its damping as a torque, its
    pressure as the prescribed laws of a and b (``averaging = "numeric"``)."""
    return torque_perturbation(
        damping_torque(p),
        p.mu,
        ab_rate=lambda tau: (float(p.ab_rate(tau)[0]), float(p.ab_rate(tau)[1])),
        name="§9 damping through the engine",
    )
