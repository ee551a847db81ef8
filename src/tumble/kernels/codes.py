"""The integer codes compiled code dispatches on (right-hand sides, events), and the thresholds
it shares with Python (the Euler–Poinsot regimes of :mod:`tumble.unperturbed.euler_poinsot`,
which the compiled averaged equations reproduce). The torque terms' codes are the registry's
(:mod:`tumble.kernels.terms`).

Plain constants, apart from the compiled code that reads them, so that the classes which pack a
kernel's parameters (the models' parameters) load without numba; the compiled modules and the
Python ones import them from here, once.
"""

from __future__ import annotations

KIND_RIGID_BODY = 1
KIND_ROTATING_FIELD = 2
KIND_NONLINEAR_MOMENT = 3
KIND_MEDIUM_AVERAGED = 4
KIND_FIELD_AVERAGED = 5
KIND_NUTATION_AVERAGED = 6
KIND_SPINNER_AVERAGED = 7
KIND_NUTATION_ENGINE = 8
KIND_TRIAXIAL_AVERAGED = 9
KIND_ORBITING_BODY = 10
"""Euler's equations under a program with terms compiled apart (``Term.compiled_apart``: along
an orbit, or calling out to a user's function): the rigid body's, with Kepler's equation, the
geomagnetic field and the callbacks compiled in only here."""
KIND_TRIAXIAL_PHASE_MEANS = 11
"""The triaxial setting for built-in terms without a closed-form average: the polhode phase
refined, the precession angle and the forcing phase exact."""
KIND_TRIAXIAL_CLOSED = 12
"""The triaxial setting for terms whose every average has a closed form
(:mod:`tumble.kernels.triaxial_closed`); ``KIND_TRIAXIAL_AVERAGED`` is the product rule, for
any program."""

EVENT_NONE = 0
EVENT_THETA_DOT = 1
"""Zeros of θ' of the nonlinear-moment quaternion form: the extrema of θ(t)."""
EVENT_FIELD_SEPARATRIX = 2
"""r − 1/I2 of the rotating field's averaged vector form: its separatrix."""
EVENT_NUTATION_SEPARATRIX = 3
"""The nonlinear moment's averaged energy below the barriers of the effective potential."""
EVENT_EQUATOR = 4
"""cos ϑ of a spinner's averaged state [k, ρ, σ, ϑ]: the equator, where its rates kink."""
EVENT_TRIAXIAL_SEPARATRIX = 5
"""r − 1/I2 of the triaxial engine's state [L_ξ, r]: the separatrix."""

SEPARATRIX_RTOL = 1e-12
"""A state is on the separatrix when |L² − 2T·I2| ≤ SEPARATRIX_RTOL·L². L² − 2T·I2 from a
state known to a few ulps carries ~1e-16·L² of round-off, and ~1e-12·L² after an integration
at rtol ~1e-12: inside the band its sign, hence the regime, is not determined by the data."""

DEGENERATE_RTOL = 1e-12
"""Two principal moments count as equal when they differ by ≤ DEGENERATE_RTOL·I3 (all
three when I3 − I1 ≤ 2·DEGENERATE_RTOL·I3). With it each regime x3, x1 spans more than
SEPARATRIX_RTOL·L² in L² − 2T·I2, so the separatrix band never swallows a whole regime;
the symmetric formulas used for such bodies are off by O(DEGENERATE_RTOL)."""

MC_FLOOR = 1e-300
"""k'² below which the Euler–Poinsot motion is the separatrix itself (|d2| ≲ 1e-300 L²):
K = R_F(0, mc, 1) overflows for subnormal mc."""

NUTATION_SEPARATRIX_TOL = 1e-9
"""A nutation counts as at a separatrix (infinite period) when 1 − k² < NUTATION_SEPARATRIX_TOL.

Near a separatrix 1 − k² ∝ (E − E_s) on the case-2 side (above a hump of W) but
∝ sqrt(E_s − E) on the case-1 side (inside a well), where an E known to ε_machine fixes
1 − k² only to ~1e-8: there values below 1e-9 arise only from an exact double root. The period
grows like ln(16/(1 − k²))/β, so its relative uncertainty is
δ(1 − k²)/((1 − k²) ln(16/(1 − k²)))."""

REACHED_MARGIN = 1e-3
"""How far, as a fraction of 1/I1 (the range's upper end: the width 1/I1 − 1/I3 vanishes for
a sphere), an integrated 2T/L² may step beyond the range before
:func:`tumble.unperturbed.euler_poinsot.reached_ratio` refuses it."""

__all__ = sorted(name for name in dir() if name.isupper())
"""Every constant above: its upper-case names, so that a new code is public where it is defined
(and :mod:`tumble.kernels` lists those of the right-hand sides and their events)."""
