"""The compiled spinner average (a moment of the body rate only, in closed form) against the
Python engine's quadrature."""

from __future__ import annotations

import numpy as np
import pytest
from compiled_runs import numba_and_scipy

from tumble.averaging.spinner import spinner_average
from tumble.kernels.rhs import evaluate
from tumble.models import resisting_medium as rm
from tumble.models.base import AveragingOptions

NUMERIC = AveragingOptions(averaging="numeric")

LAWS = {
    # Each part of the law (1.2) alone and all together, off-diagonal terms included.
    "constant": {"a": [0.1, -0.2, 0.4]},
    "linear": {"b": [[0.5, 0.1, 0.0], [0.0, 0.4, 0.2], [0.1, 0.0, 0.3]]},
    "quadratic": {"s": np.diag([0.2, 0.3, 0.1])},
    "all": {"a": [0.05, 0.0, 0.6], "b": np.diag([0.6, 0.6, 0.2]), "s": np.diag([0.1, 0.1, 0.1])},
}


@pytest.mark.parametrize("law", sorted(LAWS))
@pytest.mark.parametrize("kappa", [-0.4, 0.5, 1.0])
def test_compiled_average_equals_the_python_engine(law, kappa):
    p = rm.Params(eps=0.01, kappa=kappa, **LAWS[law])
    kernel = rm.spinner_kernel(p)
    assert kernel is not None
    rng = np.random.default_rng(5)
    for _ in range(40):
        y = np.array([rng.uniform(0.2, 3.0), rng.uniform(0.05, 3.09), rng.uniform(0.0, 6.3),
                      rng.uniform(0.05, 3.09)])  # fmt: skip
        got = evaluate(kernel.kind, 0.0, y, kernel.params)
        ref = spinner_average(p.torque, p.kappa, 1.0, *y)
        # The compiled means are the closed forms; the Python engine's quadrature stops when
        # two levels agree to 1e-12 of the largest moment on the torus: they agree to that
        # tolerance, ~1e-12 of the largest rate (measured 1e-15).
        assert np.max(np.abs(got - ref)) <= 1e-12 * max(float(np.max(np.abs(ref))), 1e-300)


def test_outside_the_domain_the_rates_are_not_finite():
    p = rm.Params(eps=0.01, kappa=0.5, **LAWS["all"])
    kernel = rm.spinner_kernel(p)
    for y in ([0.0, 1.0, 0.0, 1.0], [1.0, 0.0, 0.0, 1.0], [1.0, 1.0, 0.0, np.pi]):
        assert np.all(np.isnan(evaluate(kernel.kind, 0.0, np.array(y), kernel.params)))


def test_compiled_engine_run_equals_the_python_one_across_the_equator():
    # A body-fixed axial moment a3 < 0 turns K through the equator ϑ = π/2 (a kink of the
    # averaged rates): the compiled run stops at the event there and restarts, as scipy's.
    p = rm.Params(eps=0.01, kappa=0.5, a=[0.0, 0.0, -0.5], b=np.diag([0.3, 0.3, 0.1]),
                  s=np.diag([0.05, 0.05, 0.05]))  # fmt: skip
    st = rm.State(k=1.0, rho=0.8, sigma=0.0, psi=0.0, theta=1.0, phi=0.0)
    tau = np.linspace(0.0, 300.0, 61)
    runs = numba_and_scipy(
        rm.MODEL, p, st, tau, "averaged", rtol=1e-10, atol=1e-12, averaging=NUMERIC
    )
    theta = runs["numba"].columns["theta"]
    assert theta[0] < np.pi / 2 < theta[-1]  # the run crosses the equator
    for name, ref in runs["scipy"].columns.items():
        # The same DOP853 on rates equal to 1e-12: the runs agree to their tolerance.
        assert np.max(np.abs(runs["numba"].columns[name] - ref)) < 1e-8, name
