"""The orbiting body's extreme inputs: a seeded corpus of mutations of its examples and
template, each loaded and run over a short span, is accepted and runs to finite outputs, or
is refused (or stopped) in one line; never an internal error, never a run past its step
budget's pace, never an epoch outside the field's table taken silently.

Mutations: physical inputs scaled by powers of ten up to ±300 and set to the edges of their
allowed ranges, epochs from year 1 to 9999 (with UTC offsets, and two-line element sets of
any year), the field model and its coefficients, fast spins and large residual moments, and
control characters (NUL, escape, line breaks) in every text.
"""

from __future__ import annotations

import copy
import dataclasses
import json
import math
import random
import time
import tomllib
import warnings
from datetime import UTC, datetime

import numpy as np
import pytest
from files import EXAMPLES, leaves

from tumble.analysis import run
from tumble.errors import IntegrationError, TumbleError, TumbleWarning
from tumble.io.output import NonFiniteOutput, render_outputs
from tumble.io.scenario import parse_scenario, template
from tumble.space import DIPOLE_EPOCHS

BASES = {
    "sphere": tomllib.loads((EXAMPLES / "ob_aluminium_sphere.toml").read_text(encoding="utf-8")),
    "envisat": tomllib.loads((EXAMPLES / "ob_envisat_like.toml").read_text(encoding="utf-8")),
    "template": tomllib.loads(template("orbiting_body")),
}
MUTATIONS = 330
SPAN_S = 9_000.0  # 1.5 orbits at 700 km: every torque acts, in a fraction of a second
SAMPLES = 9
STEPS = 200_000  # the corpus runs' step budget: its pace guard scaled with it
LONGEST_MESSAGE = 400  # one line: the key, ≤ 80 characters of the value, the allowed range
# No run of the corpus spends its step budget ("steps spent": it went on past the pace guard);
# the slowest measured takes 1.8 s (a body spun up by a residual moment over 140 000 steps).

TLE = ["1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753",
       "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667"]  # fmt: skip
NUMBERS = {  # key → values around and beyond its allowed range
    ("body", "mass"): [1e9, 1.1e9, 1e-30],
    ("conductor", "conductivity"): [1e9, 2e9, 1e-100],
    ("conductor", "radius"): [1e3, 1e100, 1e-100],
    ("conductor", "length"): [1e3, 1e4, 1e-9],
    ("conductor", "thickness"): [1.0, 1.5, 1e-100],
    ("orbit", "altitude"): [1e6, 1e7, 1e-3],
    ("orbit", "semi_major_axis"): [1e6, 6378.0, 6379.0],
    ("orbit", "eccentricity"): [0.999, 0.5],
    ("initial", "spin_period"): [6.3e-4, 6e-4, 6.3e9, 7e9],
    ("field", "g10"): [1e6, -1e6, 2e6, 1e-100],
}
EPOCHS = ["1800-01-01", "1899-12-31T23:59:59Z", "1900-01-01T00:00:00Z", "2030-01-01T00:00:00Z",
          "2030-01-01T00:00:01Z", "2056-06-01", "2100-01-01", "0001-01-01", "9999-12-31",
          "9999-12-31T23:00:00-05:00", "0001-01-01T01:00:00+05:00", "2013-09-25",
          "2025-13-01", ""]  # fmt: skip
CONTROL = ["\x00", "\x1b[31m", "\n", "\r", "\t", "\x7f", "\x85"]


def _get(d, path):
    for p in path:
        d = d[p]
    return d


def _set(d, path, value):
    for p in path[:-1]:
        d = d.setdefault(p, {}) if isinstance(d, dict) else d[p]
    d[path[-1]] = value


def _is_number(x):
    return isinstance(x, float | int) and not isinstance(x, bool)


def _tle_of_year(year):
    """:data:`TLE` with the epoch's year (two digits: 57–99 are 1957–1999, 00–56 2000–2056)
    replaced, its checksum (the digits' sum, a minus sign counting 1, modulo 10) recomputed."""
    line = TLE[0][:18] + f"{year:02d}" + TLE[0][20:68]
    check = sum(int(c) if c.isdigit() else c == "-" for c in line) % 10
    return [line + str(check), TLE[1]]


def _mutate(base, rng):
    """One to three mutations of ``base`` (a deep copy)."""
    d = copy.deepcopy(base)
    for _ in range(rng.choice([1, 1, 2, 3])):
        kind = rng.randrange(9)
        if kind == 0:  # any number of the scenario, scaled by a power of ten
            paths = [p for p in leaves(d) if p and p[0] != "run" and _is_number(_get(d, p))]
            p = rng.choice(paths)
            _set(
                d, p, float(_get(d, p)) * 10.0 ** rng.choice([-300, -100, -30, -8, 8, 30, 100, 300])
            )
        elif kind == 1:  # a key at or beyond an edge of its range
            (section, key), values = rng.choice(list(NUMBERS.items()))
            _set(d, (section, key), rng.choice(values))
        elif kind == 2:  # the epoch
            d["orbit"].pop("tle", None)
            d["orbit"]["epoch"] = rng.choice(EPOCHS)
        elif kind == 3:  # the field, with or without its own coefficients
            field = {"model": rng.choice(["dipole", "igrf", "none"])}
            if field["model"] == "dipole" and rng.random() < 0.5:
                field.update(g10=-3e4, g11=-1.5e3, h11=4.6e3)
            if field["model"] == "igrf":  # degree 13 costs 5 µs an evaluation: now and then
                field["degree"] = rng.choice([1, 2, 4, 13])
            d["field"] = field
        elif kind == 4:  # an orbit from a TLE of any year
            d["orbit"] = {"tle": _tle_of_year(rng.choice([56, 57, 99, 0, 30, 31, 1]))}
        elif kind == 5:  # a fast spin, up to beyond the allowed range
            for form in ("omega", "omega_deg_s", "omega_rpm", "spin_period", "spin_axis"):
                d["initial"].pop(form, None)
            d["initial"]["omega_deg_s"] = [rng.choice([1e3, 1e5, 5e5, 1e6]), 0.0, 1.0]
        elif kind == 6:  # a residual moment, up to beyond its range
            moment = rng.choice([1e-3, 1.0, 1e3, 1e4, 1e300])
            d.setdefault("torques", {})["residual_moment"] = [moment, 0.0, 0.0]
        elif kind == 7:  # a control character in a text or a key
            texts = [p for p in leaves(d) if isinstance(_get(d, p), str)]
            p = rng.choice(texts)
            text = _get(d, p)
            i = rng.randrange(len(text) + 1)
            _set(d, p, text[:i] + rng.choice(CONTROL) + text[i:])
        else:  # a huge inertia, as principal moments or a tensor
            scale = rng.choice([1e12, 1e13, 1e100, 1e308, 1e-10, 1e-12])
            inertia = [scale * x for x in (1.0, 1.5, 2.0)]
            d["body"]["inertia"] = inertia if rng.random() < 0.5 else np.diag(inertia).tolist()
    for key in ("t_end_days", "t_end_s", "t_days", "t_s"):
        d["run"].pop(key, None)
    d["run"].update(t_end_s=SPAN_S, samples=SAMPLES, max_steps=STEPS)
    return d


def _table_epoch(data, request) -> datetime | None:
    """The run's epoch if the field's coefficients come from a table at it, else None."""
    field = data.get("field") or {}
    if field.get("model") == "none":
        return None
    if field.get("model", "dipole") == "dipole" and all(k in field for k in ("g10", "g11", "h11")):
        return None
    return datetime.fromisoformat(request.params.epoch).astimezone(UTC)


def _one_line(text: str, what: str) -> None:
    assert "\n" not in text and len(text) <= LONGEST_MESSAGE, (what, text[:300])
    assert not text.startswith("internal error"), (what, text)


def _corpus():
    rng = random.Random("orbiting-body-extremes")
    names = sorted(BASES)
    return [
        (name, _mutate(BASES[name], rng)) for name in (rng.choice(names) for _ in range(MUTATIONS))
    ]


def test_the_orbiting_bodys_extreme_inputs_are_refused_or_run_in_one_line(tmp_path):
    source = str(tmp_path / "ob.toml")
    # Compile first, so that no run of the corpus is timed with the compiler's seconds.
    warm = copy.deepcopy(BASES["template"])
    warm["run"].update(t_end_days=0.01, samples=3)
    run(parse_scenario(warm, source).request)
    counts = {"refused": 0, "ran": 0, "stopped": 0, "paced": 0, "spent": 0, "non_finite": 0}
    slowest = 0.0
    for i, (name, data) in enumerate(_corpus()):
        what = f"mutation {i} of {name}"
        try:
            request = parse_scenario(data, source).request
        except TumbleError as exc:
            _one_line(str(exc), what)
            counts["refused"] += 1
            continue
        except Exception as exc:  # an internal error: the defect this corpus looks for
            pytest.fail(f"{what}: {type(exc).__name__}: {str(exc)[:200]}")
        epoch = _table_epoch(data, request)
        if epoch is not None:  # no epoch outside the field's table accepted silently
            assert DIPOLE_EPOCHS[0] <= epoch <= DIPOLE_EPOCHS[1], (what, epoch)
        start = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", TumbleWarning)
                result = run(request)
                files = render_outputs(result, data, source)
        except NonFiniteOutput as exc:
            _one_line(str(exc), what)
            counts["non_finite"] += 1
            continue
        except IntegrationError as exc:
            _one_line(str(exc), what)
            # "far beyond": stopped by its pace early; "steps spent": it ran past the pace
            # guard to the end of its budget.
            counts["paced" if "far beyond run.max_steps" in str(exc) else "stopped"] += 1
            counts["spent"] += "steps spent at" in str(exc)
            continue
        except TumbleError as exc:
            _one_line(str(exc), what)
            counts["stopped"] += 1
            continue
        except Exception as exc:
            pytest.fail(f"run of {what}: {type(exc).__name__}: {str(exc)[:200]}")
        finally:
            slowest = max(slowest, time.perf_counter() - start)  # (printed: no timed assert)
        counts["ran"] += 1
        # An exit-0 run: every value of every output is finite.
        for file, content in files.items():
            if file.endswith(".csv"):
                rows = np.loadtxt(content.decode().splitlines()[1:], delimiter=",", ndmin=2)
                assert np.all(np.isfinite(rows)), (what, file)
        assert "failed" not in json.loads(files["summary.json"]), what
    print(counts, f"slowest run {slowest:.2f} s")
    # The corpus reaches every outcome but an overflow (the bounds stop those first).
    assert counts["ran"] >= 50 and counts["refused"] >= 100 and counts["paced"] >= 3, counts
    assert counts["non_finite"] == 0 and counts["spent"] == 0, counts


def test_the_cases_that_failed_before_get_one_line():
    base = copy.deepcopy(BASES["sphere"])
    base["run"].update(t_end_days=0.2, samples=5)
    cases = [
        (("conductor", "radius"), 1e100, "conductor.radius [m] = 1e+100 is outside"),
        (("orbit", "epoch"), "9999-12-31", "outside the field's table 1900–2030"),
        (("orbit", "epoch"), "1800-01-01", "outside the field's table 1900–2030"),
        (("orbit", "epoch"), "2100-01-01", "outside the field's table 1900–2030"),
        (("orbit", "epoch"), "0001-01-01", "outside the field's table 1900–2030"),
        (("orbit", "epoch"), "9999-12-31T23:00:00-05:00", "from year 1 to 9999"),
        (("body", "inertia"), [1e308] * 3, "body.inertia: an entry of magnitude 1e+308"),
        (("torques", "residual_moment"), [1e4, 0.0, 0.0], "within ±1000"),
        (("orbit", "epoch"), "2025-01-01\x00", "control character U+0000"),
    ]
    for path, value, needle in cases:
        data = copy.deepcopy(base)
        _set(data, path, value)
        with pytest.raises(TumbleError) as caught:
            parse_scenario(data, "ob.toml")
        assert needle in str(caught.value), (path, value, str(caught.value))
        _one_line(str(caught.value), f"{path} = {value!r}")
    pytest.importorskip("sgp4.api")
    data = copy.deepcopy(base)
    data["orbit"] = {"tle": _tle_of_year(56)}
    with pytest.raises(TumbleError, match=r"orbit\.epoch = 2056-06-27 is outside the field's"):
        parse_scenario(data, "ob.toml")
    # The same epochs with the user's own coefficients: no table, accepted.
    data = copy.deepcopy(base)
    data["orbit"]["epoch"] = "1800-01-01"
    data["field"] = {"g10": -3e4, "g11": -1.5e3, "h11": 4.6e3}
    assert parse_scenario(data, "ob.toml").request.params.epoch.startswith("1800-01-01")


@pytest.mark.parametrize(
    ("change", "budget"),
    [
        # The fast spin: 8.7e3 rad/s, a steady pace 30 times beyond the default budget.
        ({"initial": {"omega_deg_s": [5e5, 0.0, 1.0]}}, None),
        # The residual moment of 1 N m spins a 0.8 kg m² sphere up 20 000-fold in 0.2 days:
        # its steps shrink as it goes, and at today's step alone the ~1.2e8 steps it needs
        # would look like fewer than the default budget until 80 s into the run.
        ({"torques": {"residual_moment": [1.0, 0.0, 0.0]}}, None),
    ],
    ids=["fast_spin", "spun_up"],
)
def test_the_pace_guard_stops_a_physical_run_that_cannot_finish(change, budget):
    data = copy.deepcopy(BASES["sphere"])
    data["run"].update(t_end_days=0.2, samples=5, methods=["full"])
    if budget is not None:
        data["run"]["max_steps"] = budget
    for section, values in change.items():
        if section == "initial":
            data["initial"].pop("omega_rpm")
        data.setdefault(section, {}).update(values)
    request = parse_scenario(data, "ob.toml").request
    # Stopped by its pace ("far beyond"), a few chunks of 20 000 steps in (measured 1.1 and
    # 0.4 s), not after its budget ("steps spent", minutes).
    with pytest.raises(IntegrationError, match=r"far beyond run\.max_steps"):
        run(dataclasses.replace(request))


def test_a_non_finite_output_fails_in_one_line_and_is_kept_marked(tmp_path, monkeypatch):
    # An overflow the bounds did not foresee: the writer refuses it (exit 3) and keeps the
    # outputs, marked as failed in summary.json.
    from typer.testing import CliRunner

    import tumble.app.runner as runner
    from tumble.cli import app

    computed = runner.run_request

    def overflowing(request):
        result = computed(request)
        ds = result.datasets["averaged"]
        values = ds["L"].values.copy()
        values[-1] = math.inf
        datasets = {
            **result.datasets,
            "averaged": ds.assign(L=(ds["L"].dims, values, ds["L"].attrs)),
        }
        return dataclasses.replace(result, datasets=datasets)

    monkeypatch.setattr(runner, "run_request", overflowing)
    text = (EXAMPLES / "ob_envisat_like.toml").read_text(encoding="utf-8")
    path = tmp_path / "ob.toml"
    path.write_text(text.replace("t_end_days = 365.0", "t_end_days = 2.0"), encoding="utf-8")
    out = tmp_path / "out"
    res = CliRunner().invoke(app, ["run", str(path), "-o", str(out)])
    assert res.exit_code == 3, res.output
    lines = [line for line in res.output.splitlines() if line.strip()]
    assert len(lines) == 1 and "averaged.csv: column L is inf at t = " in lines[0], res.output
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["failed"].startswith("averaged.csv: column L is inf")
    assert (out / "averaged.csv").exists() and not (out / "comparison.png").exists()


@pytest.mark.parametrize("char", CONTROL)
def test_a_control_character_in_a_reference_or_a_path_is_refused_in_one_line(char):
    # A torque reference ("file:function") and a sweep's base path: before any import or
    # file system call, where a NUL byte was an internal error.
    from tumble.io.sweep import parse_sweep

    data = tomllib.loads((EXAMPLES / "tb_inertial_torque.toml").read_text(encoding="utf-8"))
    data["torque"] = f"user_torques{char}:spin_down"
    with pytest.raises(TumbleError, match=r"^torque = .*: holds the control character U\+"):
        parse_scenario(data, str(EXAMPLES / "tb.toml"))
    data["torque"] = [{"kind": "user", "function": f"user_torques:spin{char}down"}]
    with pytest.raises(TumbleError, match=r"^torque\[0\]\.function = .*control character"):
        parse_scenario(data, str(EXAMPLES / "tb.toml"))
    sweep = EXAMPLES / "sweeps" / "ob_envisat_monte_carlo.toml"
    data = tomllib.loads(sweep.read_text(encoding="utf-8"))
    data["base"] += char
    with pytest.raises(TumbleError, match=r"^base = .*: holds the control character U\+"):
        parse_sweep(data, sweep)


def _plausible(base, rng):
    """A mutation of ``base`` within every range: the shapes debris has (symmetric bodies,
    spheres, boxes), spins from near the orbital rate to fast, LEO to GEO-like altitudes, and
    the averaged run plain or hybrid."""
    d = copy.deepcopy(base)
    shape = rng.choice(["triaxial", "prolate", "oblate", "sphere"])
    a, b, c = sorted(rng.uniform(0.5, 1.0) for _ in range(3))
    a = max(a, c - b + 0.01)  # the triangle inequality
    inertia = {"triaxial": [a, b, c], "prolate": [a, c, c], "oblate": [a, a, min(c, 2 * a)],
               "sphere": [b, b, b]}[shape]  # fmt: skip
    scale = 10.0 ** rng.uniform(-2, 5)
    d["body"]["inertia"] = [scale * x for x in inertia]
    for form in ("omega", "omega_deg_s", "omega_rpm", "spin_period", "spin_axis"):
        d["initial"].pop(form, None)
    size = 10.0 ** rng.uniform(-1.5, 1.5)
    d["initial"]["omega_deg_s"] = [size * rng.uniform(-1, 1), size * rng.uniform(-1, 1), size]
    d["orbit"] = {"altitude": rng.choice([300.0, 550.0, 800.0, 1400.0, 20000.0, 35786.0]),
                  "inclination_deg": rng.uniform(0.0, 180.0),
                  "epoch": "2024-06-01T00:00:00Z"}  # fmt: skip
    d["run"] = {"t_end_s": SPAN_S, "samples": SAMPLES, "max_steps": STEPS,
                "methods": rng.choice([["full"], ["averaged"], ["full", "averaged"]])}  # fmt: skip
    if rng.random() < 0.3:
        d["run"]["averaged_method"] = "hybrid"
    return d


PLAUSIBLE = 200


def test_plausible_objects_run_to_their_end_or_keep_what_they_computed(tmp_path):
    # 200 objects within every range, run: each ends with its outputs, or stops in one line
    # with what it computed kept (an error's partial result); never an internal error.
    source = str(tmp_path / "ob.toml")
    rng = random.Random("orbiting-body-plausible")
    names = sorted(BASES)
    outcomes = {"ran": 0, "kept": 0}
    for i in range(PLAUSIBLE):
        name = rng.choice(names)
        data = _plausible(BASES[name], rng)
        what = f"object {i} from {name}"
        try:
            request = parse_scenario(data, source).request
        except Exception as exc:  # every input is within its range
            pytest.fail(f"{what}: {type(exc).__name__}: {str(exc)[:200]}")
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", TumbleWarning)
                render_outputs(run(request), data, source)
        except TumbleError as exc:
            _one_line(str(exc), what)
            assert exc.partial is not None, (what, str(exc)[:200])  # never nothing
            outcomes["kept"] += 1
            continue
        except Exception as exc:
            pytest.fail(f"run of {what}: {type(exc).__name__}: {str(exc)[:200]}")
        outcomes["ran"] += 1
    print(outcomes)
    assert outcomes["ran"] + outcomes["kept"] == PLAUSIBLE
