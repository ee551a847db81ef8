"""A triaxial rigid body under any small torque, averaged by the general engine.

No paper derives these averaged equations: they are built numerically by
:func:`tumble.averaging.triaxial_average_vector` over the Euler–Poinsot motion, as
Martynenko (1979) averages the eddy-current torque, with that torque replaced by any
other. The full equations are Euler's equations with quaternion kinematics,

    I dω/dt = −ω × Iω + ε M(t, q, ω),    dq/dt = ½ q ⊗ (0, ω),

in the body's principal axes (any order of the moments) and a time t in which the body's
rotation rates are O(1); M is a sum of built-in torques (:mod:`tumble.torques`: the
gravity gradient of a circular orbit, a moment fixed in inertial space, a constant body
moment, linear and quadratic drag) and user functions ``f(t, q, omega, params)``. The slow
variables are the inertial angular momentum L_ξ and r = 2T/L² (§10, vector form); the fast
phases are the polhode phase, the precession about L and, for a torque with explicit periodic
time dependence (the orbit of the gravity gradient, a user forcing of given period), the
forcing phase, all averaged independently: the non-resonant case of §12. Where the averaged
trajectory meets a resonance, the separatrix L² = 2T·I2, or slow rates that are no longer
small against the fast frequencies, :func:`validity` says so with the first time.

Time is the model's t (the ``tau`` column of the outputs); the slow time is εt.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass

import numpy as np

from tumble._typing import BoolArray, FloatArray
from tumble.averaging import (
    branch_kernel,
    nearest_relations,
    precession_harmonic,
    rotation_sense,
    sense_turn,
)
from tumble.averaging.triaxial import triaxial_average_stage
from tumble.bodies import proper_sorting
from tumble.dynamics import rigid_body_rhs
from tumble.errors import IntegrationError, ParameterError, TumbleError
from tumble.kernels import EVENT_TRIAXIAL_SEPARATRIX, Kernel, evaluate_rhs
from tumble.kernels.codes import SEPARATRIX_RTOL
from tumble.kernels.rhs import rigid_body
from tumble.models.base import (
    AveragedForm,
    AveragingOptions,
    Breakpoint,
    Column,
    Full,
    FullForm,
    Model,
    Report,
    Sampled,
    SlowPath,
    Unperturbed,
    Validity,
    ValidityIssue,
    attitude_columns,
    attitude_values,
    fixed_columns,
    mean_columns,
    separatrix_issue,
)
from tumble.models.inputs.torqued_body import (
    DECLARED,
    TORQUE_KINDS,
    Params,
    State,
    torque_from_terms,
)
from tumble.models.triaxial_mean import MEAN_SLOW, triaxial_mean_form
from tumble.rotations import matrix_to_quat, quat_normalize, quat_to_matrix
from tumble.unperturbed.euler_poinsot import (
    EulerPoinsot,
    fast_frequencies_of_states,
    modulus_squared_of_states,
    polhode_point,
)

__all__ = [
    "MODEL",
    "TORQUE_KINDS",
    "VALIDITY_RATIO",
    "Params",
    "State",
    "averaged_rhs",
    "full_rhs",
    "torque_from_terms",
    "validity",
]

VALIDITY_RATIO = 0.1
"""Averaging is trusted while the slow rates stay below this fraction of the slowest fast
frequency (the same judgement of "≪" as in the rotating-field model)."""

SEPARATRIX_STEP = 1e-10
"""Relative step in r = 2T/L² across the separatrix when the averaged run restarts there (as
in the rotating-field model: r ≡ 1/I2 is a spurious solution of the averaged equations)."""

# ---------------------------------------------------------------------------------------------
# Full equations.


def full_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    """Euler's equations with quaternion kinematics under ε M, for ``y = [ω, q]``.

    Parameters
    ----------
    t : float
        Time t [1].
    y : ndarray, shape (7,)
        Body angular velocity [rad/t] and attitude quaternion [1].
    p : Params

    Returns
    -------
    ndarray, shape (7,)
        dy/dt.
    """
    if p.kernel is not None:  # the integrator's own code
        return rigid_body(t, np.ascontiguousarray(y, dtype=np.float64), p.kernel.params)  # type: ignore[no-any-return]
    return rigid_body_rhs(t, y, p.inertia, p.scaled)


def _full_from_slow(p: Params, st: State) -> FloatArray:
    return np.concatenate([st.omega, st.q])


def _momentum_columns(L_xi: FloatArray, T: FloatArray, p: Params) -> dict[str, FloatArray]:
    L = np.linalg.norm(L_xi, axis=-1)
    return {
        "L1": L_xi[:, 0],
        "L2": L_xi[:, 1],
        "L3": L_xi[:, 2],
        "L": L,
        "rho": np.arctan2(np.hypot(L_xi[:, 0], L_xi[:, 1]), L_xi[:, 2]),
        "sigma": np.arctan2(L_xi[:, 1], L_xi[:, 0]),
        "T": T,
        "k2": modulus_squared_of_states(*p.sorted_inertia, L, T),
    }


def _momentum(p: Params, Y: FloatArray) -> FloatArray:
    """Inertial angular momentum L_ξ = A I ω of states ``[ω, q]``, shape (n, 3)."""
    w = Y[:, :3]
    return np.einsum("nij,nj->ni", quat_to_matrix(quat_normalize(Y[:, 3:])), p.inertia * w)


def _full_angles(p: Params, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    """σ alone (the column unwrapped on every step): without the modulus k²."""
    L_xi = _momentum(p, Y)
    return {"sigma": np.arctan2(L_xi[:, 1], L_xi[:, 0])}


def _full_columns(p: Params, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    w = Y[:, :3]
    L_xi = _momentum(p, Y)
    cols = _momentum_columns(L_xi, 0.5 * np.sum(p.inertia * w * w, axis=1), p)
    return cols | attitude_values(Y[:, 3:], w)


# ---------------------------------------------------------------------------------------------
# Averaged equations: the engine.


def averaged_rhs(t: float, y: FloatArray, p: Params, branch: float = 1.0) -> FloatArray:
    """Averaged rates of ``y = [L_ξ1, L_ξ2, L_ξ3, r]``, r = 2T/L², by quadrature.

    ε ⟨A M⟩ and 2ε⟨(ω − r Iω)·M⟩/L² over the polhode, the precession about L and the forcing
    period: for a sum of built-in torques the compiled engine the integrator runs
    (:func:`averaged_kernel`); for a torque given as a Python function, or where the
    compiled engine refuses the state (NaN), the Python engine
    (:func:`tumble.averaging.triaxial_average_vector`), which raises with the reason. The two
    agree to the averages' tolerance (AVERAGE_RTOL).

    Parameters
    ----------
    t : float
        Time t [1]: the phase origin of the forcing, or the frozen time of a torque that
        varies only slowly.
    y : ndarray, shape (4,)
        [inertia unit · rad/t, 1/inertia unit].
    p : Params
    branch : {1.0, -1.0}
        The sense of rotation about the axis the polhode encircles
        (:func:`tumble.averaging.rotation_sense` of the initial state): the state does not
        hold it, and a torque fixed in the body turns the two senses differently.

    Returns
    -------
    ndarray, shape (4,)
        dy/dt [moment unit, 1/(inertia unit · t)].
    """
    kernel = averaged_kernel(p, branch)
    if kernel is not None:
        rates = evaluate_rhs(kernel, t, y)
        if not np.isnan(rates).any():
            return rates
    torque, period = p.averaging
    return p.eps * triaxial_average_stage(torque, p.inertia, y, t, period, branch)


def _vector_from_slow(p: Params, st: State) -> FloatArray:
    L_xi = quat_to_matrix(st.q) @ (p.inertia * st.omega)
    L2 = float(L_xi @ L_xi)
    if L2 == 0.0:
        raise ParameterError(
            "initial.omega = [0, 0, 0]: the averaged method needs a rotating body (|ω| > 0)"
        )
    return np.array([*L_xi, float(st.omega @ (p.inertia * st.omega)) / L2])


def _vector_columns(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    L_xi = Y[:, :3]
    L = np.linalg.norm(L_xi, axis=1)
    return _momentum_columns(L_xi, 0.5 * Y[:, 3] * L * L, p)


def _vector_angles(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    """σ of :func:`_vector_columns` alone (the column unwrapped on every step)."""
    return {"sigma": np.arctan2(Y[:, 1], Y[:, 0])}


def _mean_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """The averaged equations of order 2 in mean variables (L̄_ξ, T̄) and the mean angle
    variables of the Euler–Poinsot motion (and the forcing phase)
    (:class:`tumble.averaging.triaxial_second.TriaxialSystem`), from the mean state of the
    given one (``options.initial = "osculating"``) or from it; the columns are those of the
    osculating variables rebuilt at each time asked for, the mean ones beside them."""
    torque, period = p.averaging
    return triaxial_mean_form(torque, p.inertia, p.eps, st.omega, quat_to_matrix(st.q),
                              period, options,
                              lambda L_xi, T: _momentum_columns(L_xi, T, p),
                              "Euler's equations", _BODY_STATE)  # fmt: skip


_BODY_STATE = (
    lambda t, omega, A: np.concatenate([omega, matrix_to_quat(A)]),
    lambda t, y: (np.asarray(y[:3], dtype=float), quat_to_matrix(quat_normalize(y[3:]))),
)
"""The full state [ω, q] of the body rate and the attitude, and back."""


def _averaged_start(p: Params, st: State) -> FloatArray:
    """The averaged run's initial state [L_ξ, r], refused on the separatrix with the Python
    engine's reason: the compiled engine takes the edge of the separatrix band on a state's
    side, for a run that creeps onto it, but a run that starts inside the band has no side."""
    y = _vector_from_slow(p, st)
    if abs(1.0 - float(y[3]) * p.sorted_inertia[1]) <= SEPARATRIX_RTOL:
        torque, period = p.averaging
        try:
            triaxial_average_stage(torque, p.inertia, y, 0.0, period, _sense(p, st))
        except TumbleError as exc:
            said = f"the averaged equations refuse the initial state: {exc}"
            raise IntegrationError(said) from None
    return y


def _averaged_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """The general engine: the only averaged form of any torque (``averaging`` is moot); of
    order 2 in mean variables (:func:`_mean_form`)."""
    if options.order == 2 or options.hybrid:
        return _mean_form(p, st, options)
    I1, I2, I3 = p.sorted_inertia
    sense = _sense(p, st)
    breakpoints: tuple[Breakpoint, ...] = ()
    if I1 < I2 < I3:
        side = math.copysign(1.0, float(_vector_from_slow(p, st)[3]) - 1.0 / I2)

        def across(t: float, y: FloatArray) -> FloatArray:
            # Leave the separatrix on the side away from where the run came from.
            out = np.array(y, dtype=float)
            out[3] = (1.0 - side * SEPARATRIX_STEP) / I2
            return out

        separatrix = EVENT_TRIAXIAL_SEPARATRIX  # compiled with the kernel
        breakpoints = (Breakpoint(lambda t, y: float(y[3]) - 1.0 / I2, across, event=separatrix),)
    return AveragedForm(
        name="numeric",
        equation="the triaxial averaging (3.5)-(3.7) with the scenario's torque, by quadrature",
        slow=("L1", "L2", "L3", "r"),
        rhs=lambda t, y, p: averaged_rhs(t, y, p, sense),
        initial_state=_averaged_start,
        to_columns=_vector_columns,
        breakpoints=breakpoints,
        kernel=lambda p: averaged_kernel(p, sense),
        angles=_vector_angles,
    )


def _sense(p: Params, st: State) -> float:
    """The sense of rotation of the initial state about the axis its polhode encircles,
    which the averaged run keeps (:func:`tumble.averaging.rotation_sense`)."""
    return rotation_sense(p.inertia, st.omega)


def averaged_kernel(p: Params, branch: float = 1.0) -> Kernel | None:
    """:func:`averaged_rhs` compiled when the torque is a sum of built-in terms
    (:func:`tumble.averaging.triaxial_kernel`), for triaxial and symmetric bodies alike,
    in the sense of rotation ``branch``; None for a torque given as a Python function (the
    Python engine). Its program is packed once per parameter set
    (:attr:`Params.averaged_kernel`)."""
    return branch_kernel(p.averaged_kernel, branch)


# ---------------------------------------------------------------------------------------------
# Validity along the averaged trajectory.


def _slow_rate(tau: FloatArray, cols: dict[str, FloatArray]) -> FloatArray:
    """|dL_ξ/dt|/L + |dT/dt|/(2T) along samples [rad/t]: the relative slow rate."""
    L_xi = np.stack([cols["L1"], cols["L2"], cols["L3"]], axis=1)
    dL = np.gradient(L_xi, tau, axis=0)
    dT = np.gradient(cols["T"], tau)
    return np.linalg.norm(dL, axis=1) / cols["L"] + np.abs(dT) / (2.0 * cols["T"])


def validity(p: Params, st: State, slow: SlowPath, tau_end: float) -> list[ValidityIssue]:
    """Where the averaged trajectory leaves the domain of the non-resonant averaging, §12.

    Parameters
    ----------
    p : Params
    st : State
    slow : callable
        ``slow(t) -> columns`` along the averaged trajectory.
    tau_end : float
        End of the run [t].

    Returns
    -------
    list of ValidityIssue
        ``separatrix`` (L² = 2T·I2 crossed: the polhode frequency ν1 → 0), ``not_fast`` (the
        slow rate exceeds VALIDITY_RATIO times the slowest fast frequency: ν1, |ν2| or the
        forcing), ``resonance`` (n1 ν1 + n2 ν2 = m Ω_f, m ≤ 2, |n1|, |n2| ≤ 2, met or
        approached within the resonance width √(slow rate/Ω_ref); for torques that depend on
        the attitude or on time), or for a torque of the body rate alone the first passage of
        ν2 = k ν1 that turns L by more than ε|L| (:func:`_precession_issue`).
    """
    if p.eps == 0.0 or tau_end <= 0.0:
        return []
    grid = np.linspace(0.0, tau_end, 1001)
    cols = slow(grid)
    I1, I2, I3 = p.sorted_inertia
    scales = _Scales.along(p, grid, cols)
    found = [
        _crossing_issue(p, st, slow, grid, cols) if I1 < I2 < I3 else None,
        _not_fast_issue(grid, scales),
        _resonance_issue(p, grid, scales)
        if p.attitude_dependent
        else _precession_issue(p, st, grid, cols, scales),
        _unstable_rotation_issue(p, grid, cols, tau_end, _sense(p, st)) if I1 < I2 < I3 else None,
    ]
    return sorted((i for i in found if i is not None), key=lambda i: i.tau)


def _crossing_issue(
    p: Params, st: State, slow: SlowPath, grid: FloatArray, cols: dict[str, FloatArray]
) -> ValidityIssue | None:
    """The separatrix issue, with the odds of the rotation the body passes into at the first
    crossing (:func:`tumble.averaging.separatrix_crossing`, for a torque that reads the
    attitude at the direction of L and the time of the crossing, averaged over the precession
    and the forcing phase): the averaged state [L_ξ, r] does not carry the sense of the
    rotation, the phase at the crossing decides it."""
    issue = separatrix_issue(slow, grid, p.sorted_inertia[1], cols=cols)
    if issue is None:
        return issue
    from dataclasses import replace as changed

    from tumble.averaging import separatrix_crossing

    omega = proper_sorting(p.inertia) @ st.omega  # sorted axes: the region it starts in
    axis = 0 if _vector_from_slow(p, st)[3] > 1.0 / p.sorted_inertia[1] else 2
    if omega[axis] == 0.0:
        return issue
    start = ("x1" if axis == 0 else "x3") + ("+" if omega[axis] > 0.0 else "-")
    at = slow(np.array([issue.tau]))
    L_xi = np.array([at["L1"][0], at["L2"][0], at["L3"][0]], dtype=float)
    torque, period = p.averaging
    try:
        odds = separatrix_crossing(torque, p.inertia, float(np.linalg.norm(L_xi)), start,
                                   direction=L_xi, t=issue.tau,
                                   forcing_period=period).probabilities  # fmt: skip
    except TumbleError:
        return issue  # a torque that does not drive it out: the crossing is the averaging's
    said = " and ".join(f"{region} with probability {q:.3g}" for region, q in odds.items())
    kept = ("x3" if axis == 0 else "x1") + start[-1]  # the run keeps its sense
    return changed(
        issue,
        message=f"{issue.message}. From {start} (sorted axes) the body passes into {said}: "
        "which one depends on the phase at the crossing, which the averaged run does not "
        f"follow; it goes on in {kept} (theory of separatrix crossing)",
    )


_PURE_K2 = 1e-9  # k² below this along the whole run: the averaged motion never left the axis
_TRIAL = 1e-4  # the trial departure of r towards 1/I2, in units of the gap |1/I2 − r|


def _unstable_rotation_issue(
    p: Params, grid: FloatArray, cols: dict[str, FloatArray], tau_end: float, sense: float
) -> ValidityIssue | None:
    """A run that stays in a pure rotation about the major or the minor axis from some time to
    its end (from the start, or once a dissipative torque has settled it there), which the
    averaged equations hold exactly (the polhode is a point: no rate moves r off 1/I3 or
    1/I1), while the torque drives r away from it: the rotation is unstable, and the full
    motion, seeded by its oscillations of order ε, leaves it at a time the averaged run cannot
    give. Tested by the averaged rate of r at a trial departure towards the separatrix, at the
    first sample of that stretch: an e-folding time shorter than the rest of the run is
    reported."""
    pure_k2 = np.asarray(cols["k2"]) <= _PURE_K2
    if not pure_k2[-1]:
        return None
    moving = np.flatnonzero(~pure_k2)
    j = int(moving[-1]) + 1 if moving.size else 0  # the stretch that stays pure to the end
    span = tau_end - float(grid[j])
    I1, I2, I3 = p.sorted_inertia
    L_xi = np.array([cols["L1"][j], cols["L2"][j], cols["L3"][j]], dtype=float)
    r0 = 2.0 * float(cols["T"][j]) / float(L_xi @ L_xi)
    pure = 1.0 / I3 if abs(r0 - 1.0 / I3) < abs(r0 - 1.0 / I1) else 1.0 / I1
    trial = np.array([*L_xi, pure + _TRIAL * (1.0 / I2 - pure)])
    try:
        rate = float(averaged_rhs(float(grid[j]), trial, p, sense)[3])
    except (ArithmeticError, ValueError, TumbleError):
        return None
    growth = rate / (trial[3] - pure)  # > 0: r moves away from the pure rotation
    if not math.isfinite(growth) or growth <= 0.0 or 1.0 / growth >= span:
        return None
    axis = "major" if pure == 1.0 / I3 else "minor"
    since = "stays" if j == 0 else f"settles at t = {float(grid[j]):.6g} and stays"
    return ValidityIssue(
        "unstable_rotation",
        float(grid[j]),
        f"the averaged motion {since} in the pure rotation about the {axis} axis, which the "
        "averaged equations hold exactly, but the torque makes it unstable: a tumble grows "
        f"from any departure by e^{growth * span:.3g} over the rest of the run, so the full "
        "motion leaves it (seeded by its own oscillations of order ε) at a time the averaged "
        "run cannot give; compare with the full run, or start off the axis",
        label=f"unstable rotation about the {axis} axis",
    )


@dataclass(frozen=True)
class _Scales:
    """Along the samples: the relative slow rate, the slowest fast frequency (ν1, |ν2|, the
    forcing) [rad/t], where the motion is away from the separatrix band, and the forcing
    frequency (0: none)."""

    rate: FloatArray
    slowest: FloatArray
    away: BoolArray
    forcing: float
    nu: FloatArray  # (ν1, ν2) at each sample [rad/t]

    @classmethod
    def along(cls, p: Params, grid: FloatArray, cols: dict[str, FloatArray]) -> _Scales:
        I1, I2, I3 = p.sorted_inertia
        L, T = cols["L"], cols["T"]
        nu = np.stack(fast_frequencies_of_states(I1, I2, I3, L, T), axis=1)
        forcing = 0.0 if p.forcing_period is None else 2.0 * math.pi / p.forcing_period
        if I1 == I3 or _spin_free(p):
            # A sphere: the rotation about L is its only phase. A symmetric body under a
            # torque symmetric about its axis: the spin about the axis (ν1) does not enter
            # the averages, which hold however slow it is (at the flat spin, ν1 = 0).
            nu[:, 0] = 0.0
            slowest = np.abs(nu[:, 1])
        else:
            slowest = np.minimum(nu[:, 0], np.abs(nu[:, 1]))
        if forcing > 0.0:
            slowest = np.minimum(slowest, forcing)
        away = cols["k2"] < 1.0 - 1e-3  # the separatrix band is reported as such
        if I1 in (I2, I3):  # symmetric body: ν1 is the relative spin, no separatrix
            away[:] = True
        return cls(_slow_rate(grid, cols), slowest, away, forcing, nu)


_AXISYMMETRIC_RTOL = 1e-9  # of the moment's size: round-off of a rotated evaluation


def _spin_free(p: Params) -> bool:
    """Whether the body is symmetric (two equal moments) and its torque symmetric about its
    axis e: M(t, A Rᵀ, R ω) = R M(t, A, ω) for the rotations R about e (in body axes), tested
    at a few seeded states and angles. Then the spin phase about e drops out of the torque,
    and of its averages."""
    inertia = np.asarray(p.inertia, dtype=float)
    I1, I2, I3 = p.sorted_inertia
    if not I1 < I3 or I1 < I2 < I3:
        return False
    from scipy.spatial.transform import Rotation  # only for a symmetric body's torque

    e = np.zeros(3)
    e[int(np.argmin(inertia) if I2 == I3 else np.argmax(inertia))] = 1.0  # the unequal axis
    rng = np.random.default_rng(1979)
    period = 1.0 if p.forcing_period is None else float(p.forcing_period)
    for _ in range(4):
        t = float(rng.uniform(0.0, period))
        a = quat_to_matrix(quat_normalize(rng.normal(size=4)))
        omega = rng.normal(size=3)
        moment = np.asarray(p.torque(t, matrix_to_quat(a), omega), dtype=float)
        size = max(float(np.linalg.norm(moment)), 1e-300)
        for angle in (0.7, 2.3):
            r = Rotation.from_rotvec(angle * e).as_matrix()
            turned = np.asarray(p.torque(t, matrix_to_quat(a @ r.T), r @ omega), dtype=float)
            if np.linalg.norm(turned - r @ moment) > _AXISYMMETRIC_RTOL * size:
                return False
    return True


def _not_fast_issue(grid: FloatArray, sc: _Scales) -> ValidityIssue | None:
    not_fast = sc.away & (sc.rate > VALIDITY_RATIO * sc.slowest)
    if not np.any(not_fast):
        return None
    i = int(np.flatnonzero(not_fast)[0])
    return ValidityIssue(
        "not_fast",
        float(grid[i]),
        f"from t = {grid[i]:.6g} the slow drift ({sc.rate[i]:.3g} rad/t) is not small "
        f"against the slowest fast frequency ({sc.slowest[i]:.3g} rad/t): averaging loses "
        f"accuracy there (ratio > {VALIDITY_RATIO:g})",
    )


def _resonance_issue(p: Params, grid: FloatArray, sc: _Scales) -> ValidityIssue | None:
    """The first resonance met or approached within √(slow rate/Ω_ref)."""
    width = math.sqrt(float(np.max(sc.rate)) / max(float(np.max(sc.slowest)), 1e-300))
    first: tuple[float, tuple[int, int, int]] | None = None
    prev: tuple[tuple[int, int, int], float] | None = None
    found = nearest_relations(sc.nu[:, 0], sc.nu[:, 1], p.forcing_period)
    for i in range(grid.size):
        if not sc.away[i]:
            prev = None
            continue
        key = (int(found.m[i]), int(found.n1[i]), int(found.n2[i]))
        detuning = float(found.detuning[i])
        crossed = prev is not None and prev[0] == key and prev[1] * detuning < 0.0
        if found.relative[i] <= width or crossed:
            first = (float(grid[i]), key)
            break
        prev = (key, detuning)
    if first is None:
        return None
    tau_r, (m, n1, n2) = first
    rhs = f"{m}·Ω_f" if sc.forcing > 0.0 else "0"
    sign = "+" if n2 >= 0 else "−"
    return ValidityIssue(
        "resonance",
        tau_r,
        f"at t ≈ {tau_r:.6g} the averaged motion meets the resonance {n1}·ν1 "
        f"{sign} {abs(n2)}·ν2 = {rhs} (polhode ν1, precession "
        "ν2 about L, forcing Ω_f): the phases are not independent there and the "
        "averaged rates are not the time averages; passing through costs O(√ε), "
        "lingering O(1)",
        label=f"resonance {n1}·ν1 {sign} {abs(n2)}·ν2 = {rhs}",
    )


_MAX_PRECESSION_ORDER = 16
"""The largest k of ν2 = k ν1 whose passage is checked. ν2/ν1 reaches 4–55 at the edge of the
separatrix band (k² = 1 − 1e-3) for the bodies (1, 2, 3) … (10, 10.1, 11), but the harmonics
g_{−k} of a damper, a drag and a body moment fall by 5 to 6 orders from k = 2 to k = 16
there: the kicks beyond are far below ε|L|."""


def _precession_issue(
    p: Params, st: State, grid: FloatArray, cols: dict[str, FloatArray], sc: _Scales
) -> ValidityIssue | None:
    """The first passage of a resonance ν2 = k ν1 that turns L by more than ε|L|, under a
    torque of the body rate alone (:func:`precession_passages`)."""
    for t_r, k, L, kick in precession_passages(p, st, grid, cols, sc):
        if kick > p.eps * L:
            return ValidityIssue(
                "resonance",
                t_r,
                f"at t ≈ {t_r:.6g} the averaged motion passes the resonance ν2 = {k}·ν1 "
                "(polhode ν1, precession ν2 about L): the torque turns L there at a rate the "
                f"averages drop, by about {kick / L:.2g} of |L| (O(√ε)), in a direction set "
                "by the phase at the passage, which the averaged run does not follow; |L| and "
                "T do not see it (docs/theory/separatrix-crossing.md §5)",
                label=f"resonance ν2 = {k}·ν1",
            )
    return None


def precession_passages(
    p: Params, st: State, grid: FloatArray, cols: dict[str, FloatArray], sc: _Scales
) -> Iterator[tuple[float, int, float, float]]:
    """The resonances ν2 = k ν1 an averaged run passes under a torque of the body rate alone,
    away from the separatrix band, in time order: (t, k, |L|, the kick to L there) each, each
    computed when asked for (a few milliseconds: one polhode period of the free motion).

    Its |L| and T do not see the precession angle, but the direction of L does. At each
    integer k that |ν2|/ν1 passes between two samples, the kick |g| √(2π/|Ω̇|) of the
    harmonic that stands still there (:func:`tumble.averaging.precession_harmonic`, at
    (|L|, T) interpolated to the passage; Ω = |ν2| − k ν1 along the samples); none for a
    torque that is not one of the body rate alone."""
    if not p.scaled.rate_only:
        return
    nu1, nu2 = sc.nu[:, 0], np.abs(sc.nu[:, 1])
    ok = sc.away & (nu1 > 0.0)
    ratio = np.where(ok, nu2 / np.where(nu1 > 0.0, nu1, 1.0), np.nan)
    sense = _sense(p, st)
    for i in range(grid.size - 1):
        a, b = ratio[i], ratio[i + 1]
        if not (np.isfinite(a) and np.isfinite(b)) or a == b:
            continue
        low, high = sorted((a, b))
        orders = range(math.floor(low) + 1, min(math.floor(high), _MAX_PRECESSION_ORDER) + 1)
        for k in orders if b > a else reversed(orders):  # in time order
            f = (k - a) / (b - a)
            t_r = float(grid[i] + f * (grid[i + 1] - grid[i]))
            L = float(cols["L"][i] + f * (cols["L"][i + 1] - cols["L"][i]))
            T = float(cols["T"][i] + f * (cols["T"][i + 1] - cols["T"][i]))
            detuning = nu2[i : i + 2] - k * nu1[i : i + 2]
            rate = abs(float(detuning[1] - detuning[0])) / float(grid[i + 1] - grid[i])
            omega = polhode_point(p.inertia, L, T) @ sense_turn(p.inertia, L, T, sense)
            g = abs(precession_harmonic(p.scaled, p.inertia, omega, k))
            kick = g * math.sqrt(2.0 * math.pi / rate) if rate > 0.0 else math.inf
            yield t_r, k, L, kick


# ---------------------------------------------------------------------------------------------
# The record.


_VECTOR_FORM = "docs/theory/rotating-field.md §10"  # the slow variables of the vector form

_COLUMNS_SLOW = (
    *(Column(f"L{i}", f"inertial angular momentum L_ξ{i}", "1", _VECTOR_FORM) for i in (1, 2, 3)),
    Column("L", "angular momentum |L|", "1", _VECTOR_FORM),
    Column("rho", "polar angle ρ of L from ξ3", "rad", _VECTOR_FORM),
    Column("sigma", "inertial azimuth σ of L", "rad", _VECTOR_FORM, angle=True, unwrap=True),
    Column("T", "kinetic energy T", "1", _VECTOR_FORM),
    Column("k2", "Euler–Poinsot modulus k² of the current regime", "1",
           "docs/theory/rotating-field.md §8"),
)  # fmt: skip
_COLUMNS_MEAN = mean_columns(c for c in _COLUMNS_SLOW if c.name in MEAN_SLOW)
_COLUMNS_FULL = (
    *_COLUMNS_SLOW,
    *attitude_columns("t"),
)


def full_kernel(p: Params) -> Kernel | None:
    """:func:`full_rhs` compiled (:mod:`tumble.kernels`); None for a user torque function."""
    return p.kernel


FULL: FullForm[Params, State] = FullForm(
    name="quaternion",
    equation="Euler's equations with quaternion kinematics",
    state=("w1", "w2", "w3", "q0", "q1", "q2", "q3"),
    rhs=full_rhs,
    initial_state=_full_from_slow,
    to_columns=_full_columns,
    state_of=lambda p, y: State(y[:3], y[3:]),
    angles=_full_angles,
    kernel=full_kernel,
)


def _report(p: Params, st: State, trajectories: Mapping[str, Sampled]) -> Report:
    return Report(summary={"torque": p.label, "forcing_period": p.forcing_period})


MODEL: Model[Params, State] = DECLARED.model(
    Full.of(fixed_columns(_COLUMNS_FULL), FULL),
    averaged=DECLARED.averaged(
        _averaged_form,
        fixed_columns((*_COLUMNS_SLOW, *_COLUMNS_MEAN)),
        compare=("L1", "L2", "L3", "T"),
    ),
    unperturbed=Unperturbed(
        "the free body (3.1)",
        lambda p, st: EulerPoinsot.from_rigid_body_state(p.inertia, _full_from_slow(p, st)).states,
        lambda t, y, p: full_rhs(t, y, p.with_eps(0.0)),
    ),
    validity=Validity(check=validity),
    report=_report,
)
