"""The passage of ϑ = π/2 as an asymptotic step of the averaged run (§10.2 of
``docs/theory/resisting-medium.md``).

At ϑ = π/2 the proper rotation stops (Ω_φ = −κW/(1+κ) with W = k cos ϑ), so the part of the
moment that turns with φ is not averaged while the body passes: V = k sin ϑ jumps by O(√ε),
by an amount that depends on the phase of φ there. In the body frame, with ζ = q + ip =
V e^{iφ}, (1.3) reads

    dW/dτ = ε m3,    dζ/dτ = iΩ_φ ζ + ε (m2 + i m1),

with (m1, m2, m3) the moment on the body axes; in the frame turning with φ, ζ e^{−iφ} = V + η
and dη/dτ = Σ h_n e^{inφ}, the harmonics of ε e^{−iφ}(m2 + i m1) (n = 0 is the averaged
rate). When m3 does not depend on φ (b31 = b32 = 0 and s31 = s32 = 0 in (1.2)), W follows its
averaged equation exactly and φ its mean rate to O(ε) over the whole run, so the phase at the
passage is known from the averaged run. Near the stationary time τs of φ the phase is
φ* + ½φ̈(τ − τs)², and stationary phase gives the jump

    Δη = Σ_{n≠0} h_n e^{inφ*} √(2π/|nφ̈|) e^{i(π/4) sgn(nφ̈)},   φ̈ = −κ ε a3/(1+κ),

with h_n at W = 0, V = V* (the averaged V there): V* becomes |V* + Δη|. The neglected terms
(the cubic term of the phase, the change of V across the inner region, the phase's own
O(ε/V) wobble) change Δη by O(ε).

The averaged run carries the mean phase φ̄ beside (k, ϑ) and restarts at τs from |V* + Δη|;
its columns take the inner solution, the Fresnel integrals of the same harmonics, written
uniformly in the phase of the run (its tail is the first-order oscillation
h_n e^{inφ̄}/(inΩ_φ) of the outer solution), so that they stay O(ε) from the full motion
through the passage too. V is the modulus |V + η|, which stays right where V itself falls
below the forced oscillation (a spin that has died out).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from tumble._typing import ComplexArray, FloatArray
from tumble.kernels.fresnel import fresnel_table, passage_sum
from tumble.models.inputs.resisting_medium import Params, State
from tumble.models.resisting_medium.accuracy import axial_depends_on_phi, moment_depends_on_phi
from tumble.models.resisting_medium.closed_forms import (
    axial_momentum,
    crossing_time,
    equatorial_momentum,
)

__all__ = [
    "INNER",
    "NEGLIGIBLE",
    "PHASE_NODES",
    "SWITCH",
    "Passage",
    "jump_bound",
    "mean_turn",
    "passage",
]

PHASE_NODES = 64
"""Gauss–Legendre nodes of the mean phase's integral from τ = 0 to the passage, on the closed
forms of W and V (analytic there: the quadrature is exact to round-off; a test doubles it)."""
_GRID = 256
"""Points of φ for the harmonics of the equatorial moment at ϑ = π/2: the law (1.2)'s
harmonics fall as n⁻³ (the second derivative of w|w| jumps), to ~5e-7 of the first by the
grid's last bin n = 127, which bounds the aliasing; those kept are far below it."""
_DROPPED = 1e-2
"""The harmonics left out add at most this fraction of ε to the jump (the tail of the sum)."""
SWITCH = 4.0
"""Beyond this many Fresnel units x = |u| √(|nφ̈|/π) a harmonic's inner solution is evaluated
by its expansion rather than its Fresnel integrals (:meth:`Passage.correction`); at most
:data:`tumble.kernels.fresnel.TABLE_END`."""
NEGLIGIBLE = 1.0
"""A passage whose :func:`jump_bound` is at most this many ε moves V by no more than
first-order averaging errs anyway (the quadratic law's weak harmonics at moderate ε): the run
takes no step there, and no method is warned of it."""
INNER = 3.0
"""Half-width of the inner region in Fresnel units x = s √(|φ̈|/π) of the first harmonic: the
span a run reports as its asymptotic leg."""


def mean_turn(p: Params) -> tuple[float, float]:
    """The drag's mean turn of φ: ε times (b21 − b12)/2 and, per unit V, 4(s21 − s12)/(3π),
    the average of ε(m1 cos φ − m2 sin φ)/V on the law (1.2) (the mean phase's rate beyond
    −κW/(1+κ))."""
    b, s = p.b, p.s
    return 0.5 * float(b[1, 0] - b[0, 1]), 4.0 * float(s[1, 0] - s[0, 1]) / (3.0 * math.pi)


@dataclass(frozen=True)
class Passage:
    """The passage of ϑ = π/2 of one averaged run (module notes).

    Attributes
    ----------
    tau1 : float
        When the averaged W reaches 0 [1] (§8.4).
    tau_s : float
        When the mean phase stands still, Ω_φ = 0 [1]: τ1 shifted by the drag's mean turn of
        φ (zero for a symmetric b and s), found on the closed forms.
    phase : float
        The mean phase φ* at ``tau_s`` [rad].
    accel : float
        φ̈ = −κ ε a3/(1+κ) [1].
    orders : ndarray of int
        The harmonics n kept, ±1, ±2, … [1].
    harmonics : ndarray of complex
        h_n of ε e^{−iφ}(m2 + i m1) at W = 0, V = V*, for each of ``orders`` [1].
    v_star : float
        The averaged V at the passage [1].
    jump : complex
        Δη: V* becomes |V* + Δη| across the passage [1].
    """

    tau1: float
    tau_s: float
    phase: float
    accel: float
    orders: FloatArray
    harmonics: ComplexArray
    v_star: float
    jump: complex

    @property
    def span(self) -> tuple[float, float]:
        """The inner region, ``tau_s`` ± :data:`INNER` Fresnel units [1]."""
        half = INNER * math.sqrt(math.pi / abs(self.accel))
        return self.tau_s - half, self.tau_s + half

    def restart(self, form: int) -> Callable[[float, FloatArray], FloatArray]:
        """The step at ``tau_s``: V → |V + Δη|, W and φ̄ unchanged, on the state
        ``[k, ϑ, φ̄]`` (``form`` 0) or ``[W, V, φ̄]`` (1)."""
        jump = self.jump

        def step(t: float, y: FloatArray) -> FloatArray:
            out = np.array(y, dtype=float)
            if form == 1:
                out[1] = abs(y[1] + jump)
                return out
            W, V = y[0] * math.cos(y[1]), abs(y[0] * math.sin(y[1]) + jump)
            out[0], out[1] = math.hypot(W, V), math.atan2(V, W)
            return out

        return step

    def correction(self, t: FloatArray, phase: FloatArray, omega: FloatArray) -> ComplexArray:
        """The inner solution η at times ``t`` [1], in the frame turning with φ̄ (its real
        part along V), given the run's mean phase φ̄ and its rate Ω_φ there:
        Σ h_n e^{inφ*} ∫_{−∞}^{τ} e^{in(φ̄ − φ*)} dτ', less the jump past ``tau_s``. Within
        :data:`SWITCH` Fresnel units of the passage (for each harmonic) by Fresnel integrals in
        u (½φ̈u² = φ̄ − φ*) with the uniform tail term (1/Ω_φ − 1/(φ̈u)) e^{in(φ̄ − φ*)}/(in);
        beyond, by their expansion Σ h_n e^{inφ̄} [1/(inΩ_φ) − 1/(n²φ̈²u³)], whose next term
        is 3/(n²φ̈²u⁴) times the last, below 1e-3 of the first there. Compiled
        (:func:`tumble.kernels.fresnel.passage_sum`; a test holds it to scipy's Fresnel
        integrals of every harmonic at every sample). Near the passage u is the time from it
        (there the phase's own error, ~1e-10 of its size, would be magnified by the square
        root), and the tail term, finite there, is left out
        (:data:`~tumble.kernels.fresnel.BLEND`). The body's V is then |V + η|."""
        rel = np.asarray(phase, dtype=float) - self.phase
        s = np.asarray(t, dtype=float) - self.tau_s
        weights = self.harmonics * np.exp(1j * self.orders * self.phase)
        s_tab, c_tab = fresnel_table()
        return passage_sum(  # type: ignore[no-any-return]
            np.ascontiguousarray(s), np.ascontiguousarray(rel),
            np.ascontiguousarray(omega, dtype=float), self.orders, weights, self.accel,
            SWITCH, s_tab, c_tab,
        )  # fmt: skip


@functools.cache
def _gauss(nodes: int) -> tuple[FloatArray, FloatArray]:
    """Gauss–Legendre nodes and weights on [−1, 1] (an eigenproblem: built once)."""
    return np.polynomial.legendre.leggauss(nodes)  # type: ignore[no-any-return]


@functools.cache
def _basis() -> tuple[FloatArray, ComplexArray]:
    """The orders n = ±1 … ±(_GRID/2 − 1) and, by rows, the harmonics n of e^{−iφ} times 1,
    sin φ, cos φ, sin φ|sin φ| and cos φ|cos φ| (an FFT on _GRID points): built once."""
    phi = 2.0 * math.pi * np.arange(_GRID) / _GRID
    sin, cos = np.sin(phi), np.cos(phi)
    rows = np.stack([np.ones(_GRID), sin, cos, sin * np.abs(sin), cos * np.abs(cos)])
    h = np.fft.fft(np.exp(-1j * phi) * rows, axis=1) / _GRID
    n = np.fft.fftfreq(_GRID, 1.0 / _GRID)
    keep = (n != 0) & (np.abs(n) < _GRID // 2)
    return n[keep], np.ascontiguousarray(h[:, keep])


def _harmonics(p: Params, v: float) -> tuple[FloatArray, ComplexArray]:
    """The orders n = ±1 … ±(_GRID/2 − 1) and the harmonics h_n of ε e^{−iφ}(m2 + i m1), the
    moment across the axis in the frame turning with φ, on the law (1.2) at W = 0, V = v
    (body rates w = (v sin φ, v cos φ, 0)): m2 + i m1 = (a2 + i a1)
    − v[(b21 + i b11) sin φ + (b22 + i b12) cos φ] − v²[(s21 + i s11) sin φ|sin φ|
    + (s22 + i s12) cos φ|cos φ|], each term's harmonics from :func:`_basis`."""
    n, basis = _basis()
    a, b, s = p.a, p.b, p.s
    weights = np.array([
        complex(a[1], a[0]),
        -v * complex(b[1, 0], b[0, 0]),
        -v * complex(b[1, 1], b[0, 1]),
        -v * v * complex(s[1, 0], s[0, 0]),
        -v * v * complex(s[1, 1], s[0, 1]),
    ])  # fmt: skip
    return n, p.eps * (weights @ basis)


def _at_passage(
    p: Params, st: State
) -> tuple[float, float, float, FloatArray, ComplexArray, FloatArray] | None:
    """τ1, V* and φ̈ of the passage of ϑ = π/2 from ``st``, with the harmonics' orders, values
    and the size of each one's jump, |h_n| √(2π/|nφ̈|); None without a passage that theory
    bridges (see :func:`passage`)."""
    a3, kappa = float(p.a[2]), p.kappa
    W0, V0 = st.W, st.k * math.sin(st.theta)
    tau1 = crossing_time(W0, p)
    if not 0.0 < tau1 < math.inf or a3 == 0.0 or kappa == 0.0 or V0 <= 0.0:
        return None
    if not moment_depends_on_phi(p) or axial_depends_on_phi(p):
        return None
    v_star = float(equatorial_momentum(np.array([tau1]), V0, p)[0])
    accel = -kappa * p.eps * a3 / (1.0 + kappa)
    n, h = _harmonics(p, v_star)
    size = np.abs(h) * np.sqrt(2.0 * math.pi / np.abs(n * accel))
    return tau1, v_star, accel, n, h, size


def jump_bound(p: Params, st: State) -> float | None:
    """The largest jump the passage of ϑ = π/2 from ``st`` can give V, over every phase at the
    passage: the sum of its harmonics' jumps [1]; None without a passage that theory bridges
    (see :func:`passage`)."""
    at = _at_passage(p, st)
    return None if at is None else float(np.sum(at[5]))


def passage(p: Params, st: State) -> Passage | None:
    """The passage of ϑ = π/2 of the averaged run from ``st``, or None if it has none that
    theory bridges: W does not reach 0, the moment does not depend on φ (then (2.2) is exact
    through it), ϑ0 ∈ {0, π} (k passes through 0), or the axial moment depends on φ
    (:func:`~tumble.models.resisting_medium.accuracy.axial_depends_on_phi`: the run warns
    instead, §10.2); or none that matters, its :func:`jump_bound` at most
    :data:`NEGLIGIBLE` ε.

    Parameters
    ----------
    p : Params
        The body, the moment and the medium, and ε.
    st : State
        The initial state (k, ϑ, φ).
    """
    at = _at_passage(p, st)
    if at is None:
        return None
    tau1, v_star, accel, n, h, size = at
    if float(np.sum(size)) <= NEGLIGIBLE * p.eps:
        return None
    kappa, W0, V0 = p.kappa, st.W, st.k * math.sin(st.theta)
    phase_b, phase_s = mean_turn(p)

    def rate(tau: FloatArray) -> FloatArray:
        W, V = axial_momentum(tau, W0, p), equatorial_momentum(tau, V0, p)
        return -kappa * W / (1.0 + kappa) + p.eps * (phase_b + phase_s * V)  # type: ignore[no-any-return]

    # Ω_φ at τ1 is the drag's mean turn (zero for symmetric b and s); Newton on the closed
    # forms finds where it vanishes, to round-off (Ω' = φ̈ to O(ε) there). The inner solution
    # is centred there: an offset δτ would enter it as δτ/(φ̈u²).
    tau_s = tau1
    for _ in range(8 if phase_b or phase_s else 0):  # W(τ1) = 0: Ω vanishes at τ1 itself
        step = float(rate(np.array([tau_s]))[0]) / accel
        tau_s -= step
        if abs(step) <= 1e-13 * max(1.0, tau_s):
            break
    x, w = _gauss(PHASE_NODES)
    nodes = 0.5 * tau_s * (x + 1.0)
    phase = st.phi + 0.5 * tau_s * float(np.dot(w, rate(nodes)))
    # The smallest harmonics whose jumps add up to at most _DROPPED·ε are left out.
    order = np.argsort(size, kind="stable")
    dropped = np.cumsum(size[order]) <= _DROPPED * p.eps
    keep = np.sort(order[~dropped])
    n, h, size = n[keep], h[keep], size[keep]
    turn = np.exp(1j * (n * phase + 0.25 * math.pi * np.sign(n * accel)))
    jump = complex(np.sum(h * turn * np.sqrt(2.0 * math.pi / np.abs(n * accel))))
    return Passage(tau1, tau_s, phase, accel, n, h, v_star, jump)
