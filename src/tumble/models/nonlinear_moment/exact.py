"""The exact unperturbed motion (1.9)–(1.13) of the nonlinear-moment model: the closed
form, the motion as full states, and the orbit's constants (§14).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from tumble._typing import FloatArray
from tumble.models.base import Json
from tumble.models.inputs.nonlinear_moment import Params, State, orbit_of
from tumble.models.nonlinear_moment.full import full_from_slow

# ---------------------------------------------------------------------------------------------
# Closed form (unperturbed), the motion as full states, the orbit's constants.


def closed_form(p: Params, st: State, t: FloatArray) -> dict[str, FloatArray]:
    """The exact unperturbed motion (1.9)–(1.13) at times ``t``.

    Parameters
    ----------
    p : Params
        Unperturbed (ε = 0).
    st : State
    t : ndarray
        Times [t].

    Returns
    -------
    dict
        ``theta``, ``psi``, ``phi`` [rad] (ψ, φ continuous), ``theta_dot`` [rad/t].
    """
    orbit = orbit_of(p, st)
    return {
        "theta": orbit.theta(t),
        "psi": orbit.psi(t),
        "phi": orbit.phi(t),
        "theta_dot": orbit.theta_dot(t),
    }


def exact_motion(p: Params, st: State) -> Callable[[FloatArray], FloatArray]:
    """The motion at ε = 0 through ``st`` (a, b frozen at their initial values, no damping),
    (1.9)–(1.13), as states ``[p, q, r, q0, q1, q2, q3]`` of the quaternion form."""
    orbit = orbit_of(p, st)

    def states(t: FloatArray) -> FloatArray:
        tt = np.ravel(np.asarray(t, dtype=float))
        angles = zip(
            orbit.theta(tt), orbit.theta_dot(tt), orbit.psi(tt), orbit.phi(tt), strict=True
        )
        rows = [full_from_slow(p, State(th, thd, ps, ph, st.R, st.G)) for th, thd, ps, ph in angles]
        return np.array(rows).reshape(tt.size, 7)

    return states


def limits(p: Params, st: State) -> dict[str, Json]:
    """The unperturbed orbit's constants (§14): root case, roots, k², E, θmin, θmax, T,
    mean precession and spin rates. For a perturbed run they describe the initial orbit.

    Parameters
    ----------
    p : Params
        The body and the moment at t = 0 (μ, a, b; the perturbation is ignored).
    st : State
        A state on the orbit (θ [rad], θ' [rad/t], R, G [1/t]).

    Returns
    -------
    dict
        ``root_case`` (1 or 2), ``roots`` u1…u4 [1] (a complex one as [re, im], None at
        infinity), ``k2`` [1], ``E`` [1/t²], ``theta_min``, ``theta_max`` [rad], ``period``
        [t], ``mean_psidot``, ``mean_phidot`` [rad/t] and the orbit's ``kind``.
    """
    orbit = orbit_of(p, st)

    def root(z: complex) -> Json:
        if not math.isfinite(z.real):
            return None  # b = 0: the root at infinity
        return z.real if z.imag == 0.0 else [z.real, z.imag]

    return {
        "root_case": int(orbit.root_case),
        "roots": {f"u{i + 1}": root(complex(z)) for i, z in enumerate(orbit.roots)},
        "k2": orbit.k2,
        "E": orbit.E,
        "theta_min": orbit.theta_min,
        "theta_max": orbit.theta_max,
        "period": orbit.period,
        "mean_psidot": orbit.mean_psidot,
        "mean_phidot": orbit.mean_phidot,
        "kind": orbit.kind,
    }
