"""The orbiting body's benchmark runs the examples it names."""

from __future__ import annotations

import tomllib

from files import EXAMPLES

from tumble.app.bench_orbit import BOX_CASE, ROCKET_CASE, SHELL_CASE, YEAR_CASE


def test_the_benchmark_case_is_the_example():
    with open(EXAMPLES / "ob_envisat_like.toml", "rb") as f:
        example = tomllib.load(f)
    assert example == YEAR_CASE


def test_the_rocket_case_is_the_example():
    with open(EXAMPLES / "ob_rocket_body.toml", "rb") as f:
        example = tomllib.load(f)
    assert example == ROCKET_CASE


def test_the_shell_case_is_the_example_over_a_year():
    with open(EXAMPLES / "ob_aluminium_sphere.toml", "rb") as f:
        example = tomllib.load(f)
    example["run"] = {**example["run"], "t_end_days": 365.0, "samples": 366}
    assert example == SHELL_CASE


def test_the_capture_case_is_the_example():
    with open(EXAMPLES / "ob_small_box.toml", "rb") as f:
        assert tomllib.load(f) == BOX_CASE


def test_the_sunlight_cases_are_the_examples():
    from tumble.app.bench_sunlight import CASES

    for name, file in (
        ("spin", "ob_geo_box_wing.toml"),
        ("tumble", "ob_geo_box_wing_tumbling.toml"),
    ):
        with open(EXAMPLES / file, "rb") as f:
            assert tomllib.load(f) == CASES[name], name


def test_the_crossing_cases_are_the_examples():
    from tumble.app.bench_crossings import CASES

    for name, case in CASES.items():
        with open(EXAMPLES / f"{name}.toml", "rb") as f:
            data = tomllib.load(f)
        # The study keeps what sets the motion (samples, methods and tolerances are its own).
        data["run"] = {
            k: v for k, v in data["run"].items() if k in ("tau_end", "t_end", "t_end_days")
        }
        assert data == case, name
