"""The limits and tolerances of the averaging engines, one definition for both of their forms.

The general averaging engine exists twice: in Python (:mod:`tumble.averaging`, any torque) and
compiled (:mod:`tumble.kernels.triaxial`, :mod:`tumble.kernels.nutation`,
:mod:`tumble.kernels.spinner`, built-in torques). Each refines its quadratures from the same
first grids, up to the same largest ones, and accepts a result by the same tests; the numbers
that say so are written here once and read by both (numba reads these module-level globals as
compile-time constants).
"""

from __future__ import annotations

__all__ = [
    "AVERAGE_RTOL",
    "MAX_GRID",
    "MODULUS_ROUNDOFF",
    "MOMENTUM_FLOOR",
    "NUTATION_MAX",
    "NUTATION_START",
    "PHASE_MAX",
    "PHASE_START",
    "POLHODE_MAX",
    "POLHODE_START",
    "SPIN_MAX",
    "SPIN_START",
    "SQUARING_SAFETY",
    "X2_CLOSED_DIST",
]

AVERAGE_RTOL = 1e-12
"""Default relative tolerance of the averages (the engine's right-hand sides are then exact
to about this, far below any integration tolerance in use)."""

# ---------------------------------------------------------------------------------------------
# The triaxial setting: quadrature over the polhode, the precession about L and the forcing.

MOMENTUM_FLOOR = 1e-12
"""L ≤ MOMENTUM_FLOOR·max I·Ω_ref is refused as "L → 0" (Ω_ref the forcing frequency, or
1 rad per unit of τ without forcing): every fast frequency is then ≲ 1e-12 Ω_ref, the motion
is not fast against anything, and the direction of L is set by the last digits of L_ξ."""

MAX_GRID = 2**18
"""Largest number of nodes of the product grid (a few MB per array): beyond it the average
is reported as not converging rather than computed for seconds."""

POLHODE_START = 16
"""First number of nodes over the polhode (a multiple of 4: the quarter shifts of the polhode
map nodes to nodes)."""

PHASE_START = 4
"""First number of nodes over the precession about L and over the forcing phase. The
trapezoidal rule with n nodes is exact for trigonometric polynomials of degree < n; 4 → 8
settles the degree-≤2 dependence on χ and on the field phase of the usual torques (eddy
current, gravity gradient) in one doubling."""

POLHODE_MAX = 2**14
"""Most nodes over the polhode."""

PHASE_MAX = 2**9
"""Most nodes over the precession and over the forcing phase."""

SQUARING_SAFETY = 100.0
"""Margin of the squaring shortcut of the triaxial quadrature. Measured for the eddy-current
torque over 3000 random bodies and states (both regimes, k² ≤ 1 − 10⁻⁴) at rtol = 1e-12: the
shortcut saved a doubling in 57 % of them and its results differed from those of the plain
test by at most 5e-13 of the integrand's size, within rtol."""

# ---------------------------------------------------------------------------------------------
# The nutation setting: the time average over one nutation period, the mean over the spin φ.

NUTATION_START = 16
"""First number of nodes over the nutation period."""

NUTATION_MAX = 1 << 14
"""Most nodes over the nutation period (a near-separatrix orbit needs more: refused)."""

SPIN_START = 4
"""First number of nodes over the spin φ of a moment of the body rate only."""

SPIN_MAX = 4096
"""Most nodes over the spin φ."""

# The nutation's orbit: the turning points of the frozen motion and its period averages, as the
# compiled well (:func:`tumble.kernels.nutation.well_averages`) forms them; the Python orbit
# (:mod:`tumble.unperturbed.symmetric_body`) writes the same numbers.

ROOT_MAXITER = 200
"""Newton–bisection steps of a turning point before giving up (bisection alone needs ≤ ~1100
from [−1, 1])."""

MODULUS_ROUNDOFF = 1e-12
"""How far below 0 the computed modulus m = k² or its complement 1 − k² may fall by round-off
(then clipped to 0); further is no bounded motion."""

X2_CLOSED_DIST = 0.02
"""⟨X²⟩ by ∂R_J/∂p only when p is this far from its removable singularities (p = 1 − k² and
p = 1); nearer, by quadrature."""
