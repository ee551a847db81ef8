"""A physical scenario's outputs speak one system of units: its warnings give their times in
seconds or days with the unit, every number of its summary.json has its unit, and the summary
gives the values the terminal prints."""

from __future__ import annotations

import json
import math

import pytest
from files import EXAMPLES, write
from typer.testing import CliRunner

from tumble.analysis.run import issue_in_si
from tumble.cli import app
from tumble.models.torqued_body.inputs import Scaling

SCALING = Scaling(T0=5.7, I0=2.0)  # 1 model time unit = 5.7 s


def _issue(tau: float, message: str) -> dict[str, object]:
    return {"condition": "resonance", "tau": tau, "message": message, "methods": ["averaged"]}


def test_a_warning_gives_its_time_in_days_or_seconds():
    tau = 88065.1
    message = f"at t ≈ {tau:.6g} the averaged motion meets a resonance, for Δτ ≈ {tau:.6g}"
    # A run beyond two days shows days: 88065.1 × 5.7 s = 5.80985 d.
    long = issue_in_si(_issue(tau, message), SCALING, t_end=1e6)
    assert long["message"].startswith("at t ≈ 5.80985 d the averaged motion")
    assert long["message"].endswith(f"Δτ ≈ {tau:.6g}")  # a duration, not the issue's time
    assert long["t_s"] == pytest.approx(tau * 5.7, rel=1e-15)  # one product's round-off
    assert long["tau"] == tau  # the model's time kept, for the figure's marks
    # A run of two days or less shows seconds.
    short = issue_in_si(_issue(tau, f"from τ = {tau:.6g} the spin is slow"), SCALING, 1e3)
    assert short["message"] == "from t = 501971 s the spin is slow"
    # Another number that only begins like the time is left alone.
    other = issue_in_si(_issue(12.5, "from t = 12.55 on"), SCALING, 1e3)
    assert other["message"] == "from t = 12.55 on"


# ---------------------------------------------------------------------------------------------
# summary.json against the printed table, for the shortest orbiting-body example.

SPHERE = EXAMPLES / "ob_aluminium_sphere.toml"


def _numbers(data, path=()):
    """(path, key) of every number in nested tables and lists (the key is the list's for the
    numbers of a list)."""
    if isinstance(data, dict):
        for k, v in data.items():
            yield from _numbers(v, (*path, k))
    elif isinstance(data, list):
        for v in data:
            yield from _numbers(v, path)
    elif isinstance(data, int | float) and not isinstance(data, bool):
        yield path


def _close(printed: str, value: float, digits: int) -> bool:
    """Whether ``value`` printed to ``digits`` significant digits reads ``printed``: the
    printed number is within half a unit of its last digit of the value."""
    return abs(float(printed) - value) <= 0.5 * 10.0 ** (-digits + 1) * abs(value) * 1.0001


@pytest.fixture(scope="module")
def sphere_run(tmp_path_factory):
    """The aluminium sphere for 0.05 day (0.13 s of full run, 0.4 s averaged; the first
    compiled call dominates), full and averaged, run through the command line."""
    tmp = tmp_path_factory.mktemp("sphere")
    text = SPHERE.read_text()
    text = text.replace("t_end_days = 30.0", "t_end_days = 0.05").replace(
        "samples = 301", "samples = 11"
    )
    scenario = write(tmp, text, "sphere.toml")
    res = CliRunner().invoke(app, ["run", str(scenario), "-o", str(tmp / "out")])
    assert res.exit_code == 0, res.output
    return json.loads((tmp / "out" / "summary.json").read_text()), res.output


def test_every_number_of_a_physical_summary_has_its_unit(sphere_run):
    data, _ = sphere_run
    units, inputs = data["units"], data["input_units"]
    for path in _numbers({k: v for k, v in data.items() if k not in ("units", "input_units")}):
        if path[0] == "inputs":  # an input's unit by its table and key, as the scenario names it
            table, key = (path[1], path[2]) if len(path) == 3 else ("", path[1])
            assert key in inputs.get(table, {}), path
        else:
            assert path[-1] in units, path
    # The final state in SI, under the SI files' names: the spin period in seconds (not in
    # units of T0), the orbit angle in radians and degrees.
    final = data["methods"]["full"]["final"]
    assert {"t_s", "t_days", "period_s", "orbit_angle_rad", "orbit_angle_deg"} <= set(final)
    assert "period" not in final and "t" not in final
    assert final["orbit_angle_deg"] == pytest.approx(math.degrees(final["orbit_angle_rad"]))
    assert final["period_s"] == data["full_final_period_s"]
    assert units["orbit_angle_rad"] == "rad" and units["L1_kgm2_s"] == "kg m²/s"
    assert data["input_units"]["initial"]["psi"] == "rad"  # psi_deg echoed in radians


def _table_rows(output: str) -> dict[str, list[str]]:
    """Method → its cells (method, form, integrator, wall time, finals) of the run table as
    printed: one row per method, or transposed (one column per method) where that is too
    wide for the terminal."""
    head = next(line for line in output.splitlines() if line.startswith("┃") and "┃ " in line)
    body = [[c.strip() for c in line.split("│")[1:-1]] for line in output.splitlines()
            if line.startswith("│")]  # fmt: skip
    names = [c.strip() for c in head.split("┃")[1:-1]]
    if names[0] == "method":
        return {cells[0]: cells for cells in body}
    return {m: [m, *(cells[j] for cells in body)] for j, m in enumerate(names) if j > 0}


def test_the_run_table_fits_the_terminal(sphere_run):
    # CliRunner's terminal is 80 columns: the table is transposed, nothing is cut.
    _, output = sphere_run
    assert "…" not in output and all(len(line) <= 80 for line in output.splitlines()
                                     if line.startswith(("┃", "│")))  # fmt: skip


def test_the_summary_says_what_the_table_prints(sphere_run):
    data, output = sphere_run
    from tumble.models.orbiting_body.display import FIGURE

    shown = {"period": "period_s", "rate_deg_s": "rate_deg_s", "orbit_angle": "orbit_angle_rad"}
    assert tuple(shown) == FIGURE.variables  # the table's columns, in its order
    rows = _table_rows(output)
    assert set(rows) == {"full", "averaged"}
    for method, cells in rows.items():
        final = data["methods"][method]["final"]
        # The table prints 6 significant digits (.6g), the summary the full value.
        for printed, key in zip(cells[4:], shown.values(), strict=True):
            assert _close(printed, final[key], 6), (method, key, printed)
    # The averaged form is the general engine's, in the table and the summary alike.
    assert rows["averaged"][1] == "numeric" == data["averaging"]
    # The differences, printed to 3 significant digits (.2e) with their SI unit.
    line = next(x for x in output.splitlines() if x.startswith("max |difference| averaged_vs_full"))
    diffs = data["max_differences"]["averaged_vs_full"]
    pairs = line.split(": ", 1)[1].split(", ")
    assert len(pairs) == len(diffs)
    for pair in pairs:
        name, printed, *unit = pair.split(" ", 2)
        si_name = {"k2": "k2", "rate_deg_s": "rate_deg_s"}.get(name) or next(
            k for k in diffs if k.startswith(f"{name}_")
        )
        assert _close(printed, diffs[si_name], 3), pair
        assert (unit or ["1"])[0] == data["units"][si_name], pair
    # The e-folding times, printed to 4 significant digits (.4g), in days.
    for method in ("full", "averaged"):
        text = next(x for x in output.splitlines() if x.startswith(f"{method}: e-folding time"))
        printed = text.split("rate ", 1)[1].split(" d", 1)[0]
        assert _close(printed, data[f"{method}_efolding_days"], 4), text


def _without_unit(data):
    """The paths of the numbers of a physical summary that have no unit."""
    units, inputs = data["units"], data["input_units"]
    missing = []
    for path in _numbers({k: v for k, v in data.items() if k not in ("units", "input_units")}):
        if path[0] == "inputs":
            table, key = (path[1], path[2]) if len(path) == 3 else ("", path[1])
            if key not in inputs.get(table, {}):
                missing.append(path)
        elif path[-1] not in units:
            missing.append(path)
    return missing


@pytest.mark.parametrize(
    "example", ["rf_physical.toml", "physical_units.toml", "tb_gravity_gradient_leo.toml"]
)
def test_every_model_speaks_si_in_its_physical_summary(tmp_path, example):
    # The other models' physical scenarios: their derived parameters (pure numbers), the
    # rotating field's fast frequencies along the run (rad/s), ranges of predicted limits, a
    # forcing period (s) all carry their units.
    res = CliRunner().invoke(app, ["run", str(EXAMPLES / example), "-o", str(tmp_path / "out")])
    assert res.exit_code == 0, res.output
    data = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert _without_unit(data) == []


def test_a_verified_hybrid_summary_speaks_si_too(tmp_path):
    # [run] verify's errors, slopes, horizon and issues, and a hybrid run's legs.
    text = SPHERE.read_text().replace("t_end_days = 30.0", "t_end_days = 0.05")
    text = text.replace("samples = 301", "samples = 11")
    text = text.replace("[run]", '[run]\nverify = true\naveraged_method = "hybrid"')
    scenario = write(tmp_path, text, "sphere.toml")
    res = CliRunner().invoke(app, ["run", str(scenario), "-o", str(tmp_path / "out")])
    assert res.exit_code == 0, res.output
    data = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert _without_unit(data) == []
    assert "slow_horizon_s" in data["verify"] and "legs" in data["methods"]["averaged"]
