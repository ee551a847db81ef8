"""The orbiting body's benchmark runs the examples it names."""

from __future__ import annotations

import tomllib

from files import EXAMPLES

from tumble.app.bench_orbit import ROCKET_CASE, YEAR_CASE


def test_the_benchmark_case_is_the_example():
    with open(EXAMPLES / "ob_envisat_like.toml", "rb") as f:
        example = tomllib.load(f)
    assert example == YEAR_CASE


def test_the_rocket_case_is_the_example():
    with open(EXAMPLES / "ob_rocket_body.toml", "rb") as f:
        example = tomllib.load(f)
    assert example == ROCKET_CASE
