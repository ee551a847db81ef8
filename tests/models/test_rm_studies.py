"""Slow studies (benchmarks, `make bench`): the averaging error over a wider range of ε."""

import numpy as np
import pytest
from test_rm_accuracy import HEMISPHERE_CASES

from tumble.analysis import averaging_error_study
from tumble.models import resisting_medium as rm


@pytest.mark.slow
@pytest.mark.parametrize("name", list(HEMISPHERE_CASES))
def test_first_order_over_five_halvings(name, capsys):
    """Theory §13.6 with ε from 0.04 down to 0.00125: the fitted order stays ≈ 1."""
    p, st = HEMISPHERE_CASES[name]
    eps = [0.04, 0.02, 0.01, 0.005, 0.0025, 0.00125]
    study = averaging_error_study(rm.MODEL, p, st, eps, variables=("k", "theta", "rho", "sigma"))
    with capsys.disabled():
        print(f"\n{name}: ε = {eps}")
        for var, err in study.errors.items():
            print(
                f"  {var:6s} max|Δ| = {np.array2string(err, precision=3)}  "
                f"order {study.slopes[var]:.3f}"
            )
    for var in ("k", "theta"):
        # Six points over a factor 32 in ε: the O(ε²) term at ε = 0.04 shifts the fit by < 0.15.
        assert abs(study.slopes[var] - 1.0) < 0.15
