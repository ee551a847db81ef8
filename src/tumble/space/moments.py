r"""The field moments of the orbit-averaged torques on an orbiting body.

Both torques on a conductor in orbit are quadratic in what the orbit brings: the eddy-current
moment (M x) × B, x = ω × B − Aᵀ dB/dt, is bilinear in B and (B, dB/dt), and the gravity
gradient 3μ/r³ r̂ × (I r̂) is linear in r̂ r̂ᵀ/r³. Averaged over the orbit's mean anomaly and the
Earth's rotation angle, two phases independent of each other and of the body's rotation (no
commensurability among them), each torque is therefore the same expression with these products
replaced by their means:

* S = ⟨B Bᵀ⟩ [T²] and D = ⟨Ḃ Bᵀ⟩ [T²/s], by quadrature over both phases (the mean anomaly on
  a uniform grid doubled to convergence; the Earth angle on max(8, 2N + 2) points, exact: the
  field of degree N holds harmonics up to N of the Earth angle, the products up to 2N; a
  field that does not turn is taken at its angle);
* ⟨3μ r̂ r̂ᵀ/r³⟩ = c (1 − ĥ ĥᵀ) with :math:`c = 3\mu/(2a^3(1 - e^2)^{3/2})`, exactly (r⁻¹
  is linear in cos ν and r̂ r̂ᵀ holds harmonics 0 and 2 of ν only).

After the average over the Earth's rotation the field's distribution is symmetric about ξ3, so
that S and D turn with the orbit's node, Ω̇ t, and nothing else changes on a circular orbit. On
an eccentric orbit they also depend on the argument of perigee, which J2 turns too: the moments
are taken at the epoch's perigee (their change with ω is of order e).
"""

from __future__ import annotations

import math

import numpy as np

from tumble._typing import FloatArray
from tumble.errors import IntegrationError
from tumble.space.geomagnetic import Dipole, Igrf
from tumble.space.orbit import Orbit

__all__ = ["field_moments", "gravity_factor"]

_EARTH_NODES = 8
_FIRST_NODES = 32
_MAX_NODES = 2**16


def field_moments(
    orbit: Orbit, field: Dipole | Igrf, t: float = 0.0, rtol: float = 1e-12
) -> tuple[FloatArray, FloatArray]:
    """S = ⟨B Bᵀ⟩ [T²] and D = ⟨Ḃ Bᵀ⟩ [T²/s], inertial axes, over the mean anomaly and the
    Earth's rotation angle, with the node and perigee of time t [s].

    Raises
    ------
    IntegrationError
        When the mean-anomaly grid reaches 2¹⁶ nodes without converging (an orbit of e close
        to 1).
    """
    from tumble.kernels.space import field_samples  # compiled: loaded on first use

    degree = field.degree if isinstance(field, Igrf) else 1
    if field.rotation != 0.0:  # a phase of its own, averaged
        nodes = max(_EARTH_NODES, 2 * degree + 2)
        angles = 2.0 * math.pi * np.arange(nodes) / nodes
    else:  # a field fixed in inertial space: at its angle
        angles = np.array([field.theta0])
    n_angles = angles.size
    orbit_payload, field_payload = orbit.payload(), field.payload()

    def sums(n: int, offset: float) -> tuple[FloatArray, FloatArray]:
        means = 2.0 * math.pi * (np.arange(n) + offset) / n
        s = field_samples(orbit_payload, field_payload, means, angles, t).reshape(-1, 6)
        b, bdot = s[:, :3], s[:, 3:]
        return b.T @ b, bdot.T @ b

    n = _FIRST_NODES
    S, D = sums(n, 0.0)
    S, D = S / (n * n_angles), D / (n * n_angles)
    while n < _MAX_NODES:
        S_new, D_new = sums(n, 0.5)
        S_next = 0.5 * S + S_new / (2 * n * n_angles)
        D_next = 0.5 * D + D_new / (2 * n * n_angles)
        size = float(np.trace(S_next))
        change = max(
            np.max(np.abs(S_next - S)) / size,
            np.max(np.abs(D_next - D)) / (size * orbit.mean_motion),
        )
        S, D, n = S_next, D_next, 2 * n
        if change <= rtol:
            return S, D
    raise IntegrationError(
        f"field moments: the mean-anomaly quadrature did not converge in {_MAX_NODES} nodes "
        f"(e = {orbit.e:g})"
    )


def gravity_factor(orbit: Orbit) -> float:
    r""":math:`c = 3\mu/(2a^3(1 - e^2)^{3/2})` [1/s²], with ⟨3μ r̂ r̂ᵀ/r³⟩ = c (1 − ĥ ĥᵀ)."""
    return 3.0 * orbit.mu / (2.0 * orbit.a**3 * (1.0 - orbit.e**2) ** 1.5)
