"""The resisting medium's passage of ϑ = π/2 as an asymptotic step (theory §10.2): the mean
phase the averaged run carries, the jump by stationary phase, the inner solution in its
columns, and the same step on every integration path."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tumble.integrate import simulate
from tumble.integrate.ensemble import averaged_batch
from tumble.integrate.ode import integrate
from tumble.kernels import evaluate_rhs
from tumble.kernels.fresnel import BLEND, TABLE_END, fresnel_table, interpolated_fresnel
from tumble.models import resisting_medium as rm
from tumble.models.base import AveragingOptions
from tumble.models.resisting_medium import passage as ps
from tumble.models.resisting_medium.averaged import plane_kernel

M = rm.MODEL
# An antisymmetric drag turns φ on the mean (b21 ≠ b12, s21 ≠ s12): the stationary time of
# the phase moves off τ1; a1, a2 and b11 ≠ b22 give harmonics 1 and 2.
SKEW = rm.Params(
    eps=1e-3,
    kappa=0.5,
    a=[0.2, -0.1, -0.6],
    b=[[0.6, 0.05, 0.0], [0.15, 0.5, 0.0], [0.0, 0.0, 0.2]],
    s=[[0.1, 0.02, 0.0], [-0.03, 0.1, 0.0], [0.0, 0.0, 0.1]],
)
START = rm.State(1.0, 0.8, 0.0, 0.0, 0.8, 0.3)


def _through(p: rm.Params, st: rm.State, samples: int = 601) -> np.ndarray:
    tau1 = rm.crossing_time(st.W, p)
    return np.linspace(0.0, tau1 + 1.0 / p.eps, samples)


def _fresnel_reference(crossing, u, rel, omega):
    """η by scipy's Fresnel integrals of each harmonic at every sample (the formula of
    ``Passage.correction`` without its expansion, table or interpolation)."""
    from scipy.special import fresnel

    acc = crossing.accel
    n = crossing.orders[:, None]
    sign = np.sign(n * acc)
    scale = np.sqrt(math.pi / np.abs(n * acc))
    s_int, c_int = fresnel(u[None, :] / scale)
    after = u >= 0.0
    inner = scale * ((0.5 + c_int) + 1j * sign * (0.5 + s_int) - after * (1.0 + 1j * sign))
    near = np.abs(u) * math.sqrt(abs(acc) / math.pi) < BLEND
    with np.errstate(divide="ignore", invalid="ignore"):
        tail = np.where(near, 0.0, 1.0 / omega - 1.0 / (acc * u))
    inner = inner + tail * np.exp(1j * n * rel) / (1j * n)
    weights = crossing.harmonics[:, None] * np.exp(1j * n * crossing.phase)
    return np.sum(weights * inner, axis=0)


def test_the_mean_phase_rate_is_the_average_of_the_phase_equation():
    """The kernel's third rate equals −κW/(1+κ) + ⟨ε(m1 cos φ − m2 sin φ)⟩/V over φ by
    quadrature of (1.3) on the law (1.2) (both hemispheres, both forms)."""
    p = SKEW
    phi = 2.0 * math.pi * np.arange(4096) / 4096
    for k, theta in ((1.1, 0.7), (0.4, 2.3)):
        W, V = k * math.cos(theta), k * math.sin(theta)
        w = np.stack([V * np.sin(phi), V * np.cos(phi), np.full(phi.size, W / (1 + p.kappa))])
        m = p.a[:, None] - p.b @ w - p.s @ (w * np.abs(w))
        mean = p.eps * np.mean(m[0] * np.cos(phi) - m[1] * np.sin(phi)) / V
        expected = -p.kappa * W / (1.0 + p.kappa) + mean
        for form, y in ((0, [k, theta, 0.0]), (1, [W, V, 0.0])):
            got = evaluate_rhs(plane_kernel(p, form), 0.0, np.array(y))[2]
            # the quadrature of a |·|-kinked integrand on 4096 points: ~1e-9 of its scale
            assert got == pytest.approx(expected, abs=1e-9), (form, got, expected)
        plain = evaluate_rhs(plane_kernel(p, 0), 0.0, np.array([k, theta]))
        assert plain.size == 2  # two states: (2.2) alone, as before


def test_the_phase_at_the_passage_is_converged(monkeypatch):
    """The Gauss–Legendre quadrature of the mean phase over [0, τ1] on the closed forms:
    doubling its nodes moves φ* by round-off of its size (|φ*| ≈ 120 rad here)."""
    one = ps.passage(SKEW, START)
    monkeypatch.setattr(ps, "PHASE_NODES", 2 * ps.PHASE_NODES)
    two = ps.passage(SKEW, START)
    assert one is not None and two is not None
    assert abs(one.phase) > 50.0
    assert two.phase == pytest.approx(one.phase, abs=1e-11 * abs(one.phase))
    # ... and the phase the compiled averaged equations carry to τ1 (φ* less the stretch
    # from τ1 to τs, ½φ̈(τs − τ1)²): rtol 1e-12 on a phase of ~120 rad
    form = M.averaged.form(SKEW, START, AveragingOptions())
    assert form.slow == ("k", "theta", "phi")
    y0 = form.initial_state(SKEW, START)
    kernel = plane_kernel(SKEW, 0)
    sol = integrate(lambda t, y: y, y0, one.tau1, rtol=1e-12, atol=1e-14, kernel=kernel)
    carried = float(sol(np.array([one.tau1]))[0, 2])
    at_tau1 = one.phase + 0.5 * one.accel * (one.tau_s - one.tau1) ** 2
    assert carried == pytest.approx(at_tau1, abs=1e-8)


@pytest.mark.parametrize("eps", [1e-3, 2.5e-4])
def test_the_stepped_run_follows_the_full_one_through_the_passage(eps):
    """Against the full equations over the whole run, the passage included: O(ε) (the
    averaged equations alone err by O(√ε) after it). Measured 2.3 ε and 1.7 ε; 5 ε bounds
    the O(1) constant, which oscillates with the phase at the passage."""
    p = SKEW.with_eps(eps)
    tau = _through(p, START)
    full = simulate(M, p, START, tau, "full", rtol=1e-12, atol=1e-14)
    stepped = simulate(M, p, START, tau, "averaged")
    alone = simulate(M, p, START, tau, "averaged", averaging=AveragingOptions(averaged_only=True))
    crossing = ps.passage(p, START)
    assert crossing is not None and crossing.tau_s != crossing.tau1
    assert [kind for kind, _, _ in stepped.legs] == ["averaged", "asymptotic", "averaged"]
    assert alone.legs == ()

    def error(run):
        return max(float(np.max(np.abs(full.columns[v] - run.columns[v]))) for v in ("k", "theta"))

    assert error(stepped) < 5.0 * eps, error(stepped) / eps
    assert error(alone) > 10.0 * eps, error(alone) / eps  # measured 18 ε and 73 ε


def test_every_path_takes_the_step_alike():
    """The jump is a restart map at a known time: the streamed compiled run, the ensemble
    and scipy's integrator take it alike (to the tolerance of the runs)."""
    p, st = SKEW.with_eps(1e-3), START
    tau = _through(p, st, 201)
    single = simulate(M, p, st, tau, "averaged")
    other = rm.State(1.0, 0.8, 0.0, 0.0, 0.8, 2.0)  # another phase: another jump
    batch = averaged_batch(M, [p, p], [st, other], [tau, tau], rtol=1e-10, atol=1e-12,
                           averaging=AveragingOptions(), threads=1)  # fmt: skip
    scipy = simulate(M, p, st, tau, "averaged", integrator="scipy")
    for v in ("k", "theta"):
        # the same compiled equations and steps: round-off
        np.testing.assert_allclose(batch[0].columns[v], single.columns[v], rtol=0, atol=1e-12)
        # scipy's DOP853 at the same tolerances takes other steps: the mean phase, ~1e3 rad,
        # differs by ~1e-7 (rtol 1e-10), and so does the inner solution that turns with it
        # (measured 1.1e-7 at one sample in the passage)
        np.testing.assert_allclose(scipy.columns[v], single.columns[v], rtol=0, atol=1e-6)
    assert np.max(np.abs(batch[1].columns["k"] - single.columns["k"])) > 1e-3
    assert batch[0].legs == single.legs


def test_no_step_where_the_axial_moment_depends_on_phi():
    """b31 ≠ 0: W oscillates with φ and the phase at the passage is not known to first
    order; the run takes no step and warns that it takes none."""
    b = np.array(SKEW.b)
    b[2, 0] = 0.05
    p = rm.Params(eps=SKEW.eps, kappa=SKEW.kappa, a=SKEW.a, b=b, s=SKEW.s)
    assert ps.passage(p, START) is None
    form = M.averaged.form(p, START, AveragingOptions())
    assert form.steps == () and form.slow == ("k", "theta")
    from tumble.models.resisting_medium.accuracy import validity

    issues = validity(p, START, lambda t: {"k": np.ones_like(t), "theta": np.ones_like(t)}, 1e4)
    crossing = [i for i in issues if i.condition == "theta_crossing"]
    assert crossing and "takes no step" in crossing[0].message


def test_averaged_only_excludes_the_hybrid():
    from tumble.errors import ParameterError

    with pytest.raises(ParameterError, match="averaged_only"):
        AveragingOptions(averaged_only=True, hybrid=True)


def test_the_compiled_fresnel_integrals_are_scipys():
    """Cubic Hermite interpolation of scipy's table with the exact derivatives: within 1e-9
    (its bound (πx)³(Δx)⁴/384 ≈ 7e-11 at x = 4), odd in x."""
    from scipy.special import fresnel

    x = np.linspace(-TABLE_END, TABLE_END, 2001)
    s, c = interpolated_fresnel(x, *fresnel_table())
    s_ref, c_ref = fresnel(x)
    assert np.max(np.abs(s - s_ref)) < 1e-9 and np.max(np.abs(c - c_ref)) < 1e-9


def test_the_compiled_inner_solution_is_the_fresnel_integrals():
    """The compiled sum against scipy's Fresnel integrals of every harmonic at every sample:
    to the table's accuracy inside the switch, and beyond it to 2e-3 of |η| (the expansion's
    next term, 3/(π x²)² relative at x = 4, measured 1.2e-3), on the linear phase of the
    passage."""
    p = SKEW.with_eps(1e-4)
    crossing = ps.passage(p, START)
    assert crossing is not None
    scale = math.sqrt(math.pi / abs(crossing.accel))
    u = scale * np.concatenate([np.linspace(-30.0, 30.0, 601), [0.0, 1e-9, 1e-5, -3e-3]])
    rel = 0.5 * crossing.accel * u**2
    omega = crossing.accel * u
    t = crossing.tau_s + u
    compiled = crossing.correction(t, crossing.phase + rel, omega)
    reference = _fresnel_reference(crossing, u, rel, omega)
    inside = np.abs(u) / scale < ps.SWITCH / math.sqrt(np.max(np.abs(crossing.orders)))
    assert np.max(np.abs(compiled - reference)[inside]) < 1e-9 * np.max(np.abs(reference))
    assert np.all(np.abs(compiled - reference) <= 2e-3 * np.abs(reference) + 1e-12)
    # The run's phase errs by ~1e-10 of its size (1e-6 rad here): near the passage, where
    # ½φ̈u² is that small, the sum must not magnify it (the square root and 1/u would).
    noisy = crossing.correction(t, crossing.phase + rel + 1e-6, omega)
    assert np.max(np.abs(noisy - reference)) < 1e-3 * np.max(np.abs(reference))


def test_a_passage_that_moves_v_by_less_than_eps_takes_no_step():
    """The quadratic law's weak harmonics alone (a⊥ = 0, b symmetric): the largest jump is
    below ε at ε = 1e-2, so no step and no warning; it grows as √ε against ε (the jump is
    ∝ ε/√|φ̈| ∝ √ε), so at ε = 1e-6 the step is taken."""
    from tumble.models.resisting_medium.accuracy import validity

    p = rm.Params(eps=1e-2, kappa=0.5, a=[0.0, 0.0, -0.6], b=np.diag([0.6, 0.6, 0.2]),
                  s=np.diag([0.1, 0.1, 0.1]))  # fmt: skip
    bound = ps.jump_bound(p, START)
    assert bound is not None and bound <= ps.NEGLIGIBLE * p.eps
    assert ps.passage(p, START) is None

    def slow(t):
        return {"k": np.ones_like(t), "theta": np.ones_like(t)}

    assert "theta_crossing" not in [i.condition for i in validity(p, START, slow, 1e3)]
    small = p.with_eps(1e-6)
    assert ps.jump_bound(small, START) / small.eps == pytest.approx(100.0 * bound / p.eps)
    assert ps.passage(small, START) is not None
