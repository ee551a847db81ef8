"""The benchmark's figures as rich tables, each target beside its figure (``tumble bench``).

The tables read the JSON-ready result of :func:`tumble.app.bench.run_benchmark` and compute
nothing. Column headings carry units in brackets ("[s]"): escaped, so that rich does not read
them as markup (``[s]`` is its tag for struck-through text).
"""

from __future__ import annotations

from typing import Any

from rich.markup import escape
from rich.table import Table

__all__ = ["bench_tables"]


def _yes(met: bool) -> str:
    return "[green]yes[/]" if met else "[red]no[/]"


def _efficiency(efficiency: float, target: float, threads: str) -> tuple[str, str]:
    """The cells of a parallel efficiency on ``threads`` threads (throughput over ``threads``
    times that on one [1]) and whether it meets ``target``, left blank on one thread."""
    return f"{efficiency:.2f}", (_yes(efficiency >= target) if threads != "1" else "")


def _full_table(r: dict[str, Any]) -> Table | None:
    """The compiled DOP853 against scipy's calling the right-hand side from Python."""
    tg, st = r["targets"], r["settings"]
    if not r["full_speedup_vs_scipy"]:
        return None
    t = Table(
        title=f"Full simulation, {st['horizon']:g} time units at rtol {st['rtol']:g}: "
        "compiled DOP853 vs scipy DOP853 calling the right-hand side from Python",
        title_justify="left",
    )
    for col in ("case", "tumble [s]", "error", "scipy [s]", "error", "speed-up", "≥ 50×"):
        t.add_column(escape(col), justify="left" if col == "case" else "right")
    for name, v in r["full_speedup_vs_scipy"].items():
        t.add_row(
            name,
            f"{v['tumble_s']:.3g}",
            f"{v['tumble_error']:.1e}",
            f"{v['scipy_s']:.3g}",
            f"{v['scipy_error']:.1e}",
            f"{v['speedup']:.0f}×",
            _yes(v["speedup"] >= tg["full_speedup_vs_scipy"]),
        )
    return t


def _heyoka_table(r: dict[str, Any]) -> Table | None:
    """The compiled DOP853 against heyoka.py at equal error."""
    tg = r["targets"]
    if not r["full_time_ratio_vs_heyoka"]:
        return None
    t = Table(title="Against heyoka.py (Taylor, LLVM) at equal error", title_justify="left")
    for col in ("case", "tumble [s]", "error", "heyoka [s]", "ratio", "≤ 1.5", "≤ 1.0"):
        t.add_column(escape(col), justify="left" if col == "case" else "right")
    for name, v in r["full_time_ratio_vs_heyoka"].items():
        label = f"{name} (no s)" if v["note"] else name
        t.add_row(
            label,
            f"{v['tumble_s']:.3g}",
            f"{v['tumble_error']:.1e}",
            f"{v['heyoka_s_at_equal_error']:.3g}" + ("" if v["bracketed"] else "*"),
            f"{v['ratio']:.2f}",
            _yes(v["ratio"] <= tg["full_time_ratio_vs_heyoka"]),
            _yes(v["ratio"] <= tg["full_time_ratio_vs_heyoka_stretch"]),
        )
    return t


def _averaged_table(r: dict[str, Any], key: str = "averaged_speedup") -> Table | None:
    """Averaged (and closed form) against full: the paper models' equations, or the general
    engine's (``key = "engine_speedup"``)."""
    if not r.get(key):
        return None
    what = (
        "The general engine's averaged" if key == "engine_speedup" else "Averaged (and closed form)"
    )
    t = Table(
        title=f"{what} vs full over the template's slow horizon; error relative, on the slow "
        "variables",
        title_justify="left",
    )
    for col in (
        "model",
        "ε",
        "full [s]",
        "averaged [s]",
        "error",
        "speed-up",
        "at equal accuracy",
        "nfev ratio",
        "eval [µs]: averaged / full",
        "closed form [s]",
        "speed-up",
    ):
        t.add_column(escape(col), justify="left" if col == "model" else "right")
    for name, by_eps in r[key].items():
        for eps, v in by_eps.items():
            a, c = v["averaged"], v.get("closed_form")
            t.add_row(
                name,
                eps,
                f"{v['full_s']:.3g}",
                f"{a['time_s']:.3g}",
                f"{a['error']:.1e}",
                f"{a['speedup']:.3g}×",
                f"{a['speedup_equal_accuracy']:.3g}×"
                if "speedup_equal_accuracy" in a
                else f"≥ {a['speedup_equal_accuracy_at_least']:.3g}×"
                if "speedup_equal_accuracy_at_least" in a
                else "—",
                f"{a['nfev_ratio']:.0f}",
                f"{v['eval_us']['averaged']:.3g} / {v['eval_us']['full']:.3g}"
                if "eval_us" in v
                else "—",
                f"{c['time_s']:.3g}" if c else "—",
                f"{c['speedup']:.3g}×" if c else "—",
            )
    return t


def _batch_table(r: dict[str, Any]) -> Table:
    """Trajectories per second of the batches."""
    tg = r["targets"]
    b = r["batch_throughput"]
    t = Table(
        title=f"Batch: {b['size']} trajectories, {b['case']} (error {b['error']:.1e})",
        title_justify="left",
    )
    for col in ("threads", "trajectories/s", "efficiency", "≥ 0.8"):
        t.add_column(escape(col), justify="right")
    for n, v in b["threads"].items():
        t.add_row(
            n,
            f"{v['trajectories_per_s']:.4g}",
            *_efficiency(v["efficiency"], tg["batch_efficiency"], n),
        )
    return t


def _ensemble_table(r: dict[str, Any]) -> Table | None:
    """Averaged runs per second of the ensembles."""
    tg = r["targets"]
    ens = r.get("averaged_batch_throughput")
    if not ens:
        return None
    t = Table(title="Averaged ensembles: runs per second (ε = 0.001)", title_justify="left")
    for col in ("model", "size", "one simulate() per point", "1 thread", "all threads",
                "efficiency", "≥ 0.8"):  # fmt: skip
        t.add_column(escape(col), justify="right" if col != "model" else "left")
    for name, v in ens.items():
        most = max(v["threads"], key=int)
        row = v["threads"][most]
        t.add_row(
            name,
            str(v["size"]),
            f"{v['single_runs_per_s']:.4g}",
            f"{v['threads']['1']['runs_per_s']:.4g}",
            f"{row['runs_per_s']:.4g} ({most})",
            *_efficiency(row["efficiency"], tg["averaged_batch_efficiency"], most),
        )
    return t


def _compile_table(r: dict[str, Any]) -> Table | None:
    """The first call of each case from an empty cache."""
    tg = r["targets"]
    if "compile" not in r:
        return None
    c = r["compile"]
    t = Table(
        title="Compile: first call of each case from an empty cache (fresh process)",
        title_justify="left",
    )
    t.add_column("case")
    t.add_column(escape("first call [s]"), justify="right")
    for name, sec in c["first_call_s"].items():
        t.add_row(name, f"{sec:.2f}")
    every = tg.get("compile_all_s", tg["compile_s"])  # a result from before the two targets
    t.add_row(
        "[bold]total[/]",
        f"{c['total_s']:.2f} (≤ {every:g}: {'yes' if c['total_s'] <= every else 'no'})",
    )
    for name, run in (c.get("first_run") or {}).items():
        t.add_row(
            f"first run of the {name} template (cold − warm)",
            f"{run['compile_s']:.2f} (≤ {tg['compile_s']:g}: "
            f"{'yes' if run['compile_s'] <= tg['compile_s'] else 'no'})",
        )
    cached = c["cached_total_s"]
    t.add_row("from the cache, all", f"{cached:.2f} (≤ {tg['compile_cached_s']:g}: "
              f"{'yes' if cached <= tg['compile_cached_s'] else 'no'})")  # fmt: skip
    return t


def _startup_table(r: dict[str, Any]) -> Table | None:
    """How fast tumble answers, from a fresh process."""
    if not r.get("startup_s"):
        return None
    target = r["targets"]["startup_s"]
    t = Table(title="Start-up: the answer from a fresh process (best of 3)", title_justify="left")
    t.add_column("command")
    t.add_column(escape("wall time [s]"), justify="right")
    for name, sec in r["startup_s"].items():
        t.add_row(name, f"{sec:.2f} (≤ {target:g}: {'yes' if sec <= target else 'no'})")
    return t


def _orbit_table(r: dict[str, Any]) -> Table | None:
    """A year of an orbiting body, averaged against full, and its Monte Carlo."""
    o = r.get("orbiting_body")
    if not o:
        return None
    tg = r["targets"]
    t = Table(title="Orbiting body: one year of a LEO object", title_justify="left")
    for col in ("run", "rtol", "wall time [s]", "evaluations", "spin period vs full"):
        t.add_column(escape(col), justify="left" if col == "run" else "right")
    for method in ("full", "averaged"):
        for rtol, v in o[method].items():
            t.add_row(method, rtol, f"{v['time_s']:.4g}", str(v["nfev"]),
                      f"{v['period_error']:.2e}")  # fmt: skip
    if "speedup" in o:
        met = o["speedup"] >= tg["orbit_year_speedup"]
        t.add_row(f"[bold]speed-up[/] (averaged at rtol {o['rtol']:g})",
                  "", f"{o['speedup']:.0f}× (≥ {tg['orbit_year_speedup']:g}: {_yes(met)})",
                  "", "")  # fmt: skip
    mc = o.get("monte_carlo")
    if mc:
        met = mc["in_full_30_day_runs"] <= tg["orbit_monte_carlo_full_runs"]
        t.add_row(f"{mc['samples']} averaged years (1 core)", "", f"{mc['time_s']:.4g}",
                  f"= {mc['in_full_30_day_runs']:.3g} full 30-day runs "
                  f"(≤ {tg['orbit_monte_carlo_full_runs']:g}: {_yes(met)})", "")  # fmt: skip
    rocket = o.get("rocket_body")
    if rocket:
        fast = rocket["integration_s"] <= tg["rocket_year_integration_s"]
        warm = rocket["year_over_one_day"] <= tg["rocket_year_over_one_day"]
        twin = rocket["twin_final_period_difference"] <= tg["rocket_twin_agreement"]
        t.add_row("rocket body (I2 = I3), averaged year", "",
                  f"{rocket['integration_s']:.3g} (≤ {tg['rocket_year_integration_s']:g}: "
                  f"{_yes(fast)}); end to end × {rocket['year_over_one_day']:.2f} of a day's "
                  f"(≤ {tg['rocket_year_over_one_day']:g}: {_yes(warm)})", "",
                  f"{rocket['twin_final_period_difference']:.2e} vs a triaxial twin "
                  f"(≤ {tg['rocket_twin_agreement']:g}: {_yes(twin)})")  # fmt: skip
    return t


def _crossings_table(r: dict[str, Any]) -> Table | None:
    """The examples through a separatrix or a resonance, averaged against full."""
    c = r.get("crossings")
    if not c:
        return None
    tg = r["targets"]
    t = Table(title="Through a separatrix or a resonance: the default averaged run",
              title_justify="left")  # fmt: skip
    for col in ("example", "ε", "full [s]", "averaged [s]", "speed-up", "slow error / ε"):
        t.add_column(escape(col), justify="left" if col == "example" else "right")
    for name, by_eps in c.items():
        for eps, v in by_eps.items():
            fast = v["speedup"] >= tg["crossing_speedup_1e-4"]
            speed = f"{v['speedup']:.0f}×" + (
                f" (≥ {tg['crossing_speedup_1e-4']:g}: {_yes(fast)})" if float(eps) <= 1e-4 else ""
            )
            near = v["error_in_eps"] <= tg["crossing_error_in_eps"]
            t.add_row(escape(f"{name} ({v['method']})"), eps, f"{v['full_s']:.3g}",
                      f"{v['averaged_s']:.3g}", speed,
                      f"{v['error_in_eps']:.3g} (≤ {tg['crossing_error_in_eps']:g}: "
                      f"{_yes(near)})")  # fmt: skip
    capture = r.get("capture") or {}
    for name, e in capture.items():
        near = e["difference"] <= tg["capture_probability"]
        t.add_row(escape(f"capture, {name}"), "", f"{e['full_s']:.3g}", "",
                  f"{e['crossed']} crossings", f"x3+: {e['frequency']:.3f} against "
                  f"{e['predicted']:.3f} (≤ {tg['capture_probability']:g} apart: "
                  f"{_yes(near)})")  # fmt: skip
        if "averaged_difference" in e:
            near = e["averaged_difference"] <= tg["capture_probability"]
            t.add_row(escape(f"capture, {name}, averaged"), "", "", f"{e['averaged_s']:.3g}",
                      f"{e['averaged_crossed']} crossings", f"x3+: {e['frequency']:.3f} "
                      f"against {e['averaged']:.3f} (≤ {tg['capture_probability']:g} apart: "
                      f"{_yes(near)})")  # fmt: skip
    return t


def bench_tables(r: dict[str, Any]) -> list[Table]:
    """The benchmark's figures as tables, each target beside its figure."""
    tables = (_full_table(r), _heyoka_table(r), _averaged_table(r),
              _averaged_table(r, "engine_speedup"), _batch_table(r), _ensemble_table(r),
              _orbit_table(r), _crossings_table(r), _compile_table(r),
              _startup_table(r))  # fmt: skip
    return [t for t in tables if t is not None]
