"""The benchmark's targets, and each target judged on the figure it reads from a result of
:func:`tumble.app.bench.run_benchmark`."""

from __future__ import annotations

import math
from typing import Any

__all__ = ["TARGETS", "verdicts"]

TARGETS: dict[str, float] = {
    "full_speedup_vs_scipy": 50.0,  # at least this many times faster
    "full_time_ratio_vs_heyoka": 1.5,  # at most this multiple of heyoka's time
    "full_time_ratio_vs_heyoka_stretch": 1.0,
    "averaged_speedup_1e-3": 100.0,  # averaged vs full at the same rtol, at least, ε = 1e-3
    "averaged_speedup_1e-4": 1000.0,  # the same at ε = 1e-4
    "averaged_equal_accuracy_1e-4": 300.0,  # against the full run of equal slow error, ε = 1e-4
    "averaged_eval_us": 1.0,  # one evaluation of a paper model's averaged equations, at most
    "engine_speedup_1e-4": 100.0,  # the general engine's averaged vs full, at least, ε = 1e-4
    "engine_eval_us": 20.0,  # one evaluation of the engine's averaged right-hand side, at most
    "averaged_error": 0.01,  # at most, on the slow variables
    "batch_efficiency": 0.8,  # throughput on 2 cores over twice that on 1, at least
    "averaged_batch_efficiency": 0.8,  # the same for an averaged ensemble, on all cores
    "compile_s": 10.0,  # what the first run of a model's template compiles, the largest, at most
    "compile_all_s": 15.0,  # first calls of every full kind from an empty cache, in all, at most
    "compile_cached_s": 0.5,  # the same calls loading from the disk cache, at most
    "startup_s": 0.5,  # tumble --help, tumble models, an input error: the answer, at most
    "second_order_eval_ratio": 3.0,  # one evaluation of order 2 over one of order 1, at most
    "orbit_year_speedup": 1000.0,  # an averaged year of a LEO object over the full one, at least
    "orbit_monte_carlo_full_runs": 5.0,  # 1000 averaged years in full 30-day runs ("a handful")
    "orbit_period_agreement": 0.01,  # the averaged year's spin period against the full one
    "rocket_year_integration_s": 0.1,  # a symmetric rocket body's averaged year, at most
    "rocket_year_over_one_day": 1.1,  # its run end to end (a warm process) over one day's
    "rocket_twin_agreement": 1e-3,  # its final spin period against a slightly triaxial twin's
    "shell_rate_agreement": 0.01,  # a shell's averaged year through its floor: rate vs full
    "shell_year_speedup": 100.0,  # the same year, averaged over full, at least
    "capture_rate_agreement": 0.01,  # a captured box's rate against n, full and hybrid alike
    "sunlight_period_agreement": 0.02,  # a GEO box-wing's averaged year: spin period vs full
    "sunlight_direction_deg": 5.0,  # the same: the direction of L against the full run's
    "sunlight_year_speedup": 1000.0,  # the same year, averaged over full, at least
    "sunlight_eval_us": 20.0,  # one evaluation of its averaged equations, at most
    "crossing_error_in_eps": 10.0,  # through a separatrix or resonance: slow error / ε, at most
    "crossing_speedup_1e-4": 300.0,  # the same runs at ε = 1e-4, averaged over full, at least
    "capture_probability": 0.03,  # 1000 crossings: |frequency − predicted probability|, at most
}
"""The targets, printed beside the measurements."""


class _Rows(list[dict[str, Any]]):
    """The verdict rows, in the order they are added."""

    def add(self, what: str, value: float, target: float, at_least: bool) -> None:
        """A row: the figure ``value`` judged against ``target`` (a floor when ``at_least``,
        else a ceiling)."""
        met = value >= target if at_least else value <= target
        self.append(
            {"what": what, "value": value, "target": target, "at_least": at_least, "met": bool(met)}
        )


def verdicts(result: dict[str, Any]) -> list[dict[str, Any]]:
    """Each target with the figure it is judged on and whether it is met."""
    rows = _Rows()
    for name, v in (result.get("full_speedup_vs_scipy") or {}).items():
        rows.add(f"full {name}: speed-up vs scipy", v["speedup"],
                 TARGETS["full_speedup_vs_scipy"], True)  # fmt: skip
    for name, v in (result.get("full_time_ratio_vs_heyoka") or {}).items():
        rows.add(f"full {name}: time / heyoka's at equal error", v["ratio"],
                 TARGETS["full_time_ratio_vs_heyoka"], False)  # fmt: skip
    for name, by_eps in result["averaged_speedup"].items():
        for eps, v in by_eps.items():
            if float(eps) <= 1e-3:
                _averaged_rows(rows, f"averaged {name} ε = {eps}", eps, v)
    for label, by_eps in (result.get("engine_speedup") or {}).items():
        v = by_eps.get("0.0001")
        if v is not None:
            where = f"engine {label} ε = 0.0001"
            rows.add(f"{where}: speed-up vs full", v["averaged"]["speedup"],
                     TARGETS["engine_speedup_1e-4"], True)  # fmt: skip
            rows.add(f"{where}: one averaged evaluation [µs]", v["eval_us"]["averaged"],
                     TARGETS["engine_eval_us"], False)  # fmt: skip
    _throughput_rows(rows, result)
    orbit = result.get("orbiting_body")
    if orbit is not None:
        _orbit_rows(rows, orbit)
    for name, by_eps in (result.get("crossings") or {}).items():
        _crossing_rows(rows, name, by_eps)
    for name, ensemble in (result.get("capture") or {}).items():
        rows.add(f"capture, {name}: |frequency − predicted| over {ensemble['crossed']} crossings",
                 ensemble["difference"], TARGETS["capture_probability"], False)  # fmt: skip
        if "averaged_difference" in ensemble:  # (a run before the averaged ensembles: absent)
            rows.add(f"capture, {name}: |frequency − the averaged runs' prediction| over "
                     f"{ensemble['averaged_crossed']} crossings", ensemble["averaged_difference"],
                     TARGETS["capture_probability"], False)  # fmt: skip
    _machine_rows(rows, result)
    return list(rows)


def _crossing_rows(rows: _Rows, name: str, by_eps: dict[str, Any]) -> None:
    """An example through a separatrix or a resonance (:mod:`tumble.app.bench_crossings`): its
    slow error in units of ε at each ε, its speed-up at 1e-4."""
    for eps, v in by_eps.items():
        where = f"crossing {name} ε = {eps} ({v['method']})"
        rows.add(f"{where}: largest slow error over the run / ε", v["error_in_eps"],
                 TARGETS["crossing_error_in_eps"], False)  # fmt: skip
        if float(eps) <= 1e-4:
            rows.add(f"{where}: speed-up vs full", v["speedup"],
                     TARGETS["crossing_speedup_1e-4"], True)  # fmt: skip


def _equal_accuracy(figures: dict[str, Any]) -> tuple[float, str]:
    """The speed-up at equal accuracy of an averaged run (0 when none was measured) and the
    note " (at least)" when it is a lower bound (no full run was as loose)."""
    bound = "speedup_equal_accuracy_at_least" in figures
    value = figures.get("speedup_equal_accuracy", figures.get("speedup_equal_accuracy_at_least"))
    return (value if value is not None else 0.0), (" (at least)" if bound else "")


def _averaged_rows(rows: _Rows, where: str, eps: str, v: dict[str, Any]) -> None:
    """The verdicts of a paper model's averaged run at ``eps`` (≤ 1e-3): its slow error and
    speed-up; at 1e-4 also its speed-up at equal accuracy, its evaluation cost and those of
    the second order."""
    avg, tag = v["averaged"], f"{float(eps):.0e}".replace("e-0", "e-")
    rows.add(f"{where}: slow error", avg["error"], TARGETS["averaged_error"], False)
    rows.add(f"{where}: speed-up vs full", avg["speedup"],
             TARGETS[f"averaged_speedup_{tag}"], True)  # fmt: skip
    if tag != "1e-4":
        return
    value, note = _equal_accuracy(avg)
    rows.add(f"{where}: speed-up at equal accuracy" + note, value,
             TARGETS["averaged_equal_accuracy_1e-4"], True)  # fmt: skip
    rows.add(f"{where}: one averaged evaluation [µs]", v["eval_us"]["averaged"],
             TARGETS["averaged_eval_us"], False)  # fmt: skip
    second = v.get("averaged_order2")
    if second is not None and "failed" in second:
        rows.add(f"{where}: order 2 (failed: {second['failed'][:80]})", 0.0,
                 TARGETS["averaged_equal_accuracy_1e-4"], True)  # fmt: skip
    elif second is not None:
        value, note = _equal_accuracy(second)
        rows.add(f"{where}: order 2, speed-up at equal accuracy" + note, value,
                 TARGETS["averaged_equal_accuracy_1e-4"], True)  # fmt: skip
        rows.add(f"{where}: order 2, evaluation cost over order 1's",
                 v["eval_us"]["averaged_order2"] / v["eval_us"]["averaged"],
                 TARGETS["second_order_eval_ratio"], False)  # fmt: skip


def _throughput_rows(rows: _Rows, result: dict[str, Any]) -> None:
    """The efficiency over cores of the compiled batch and of each averaged ensemble."""
    batch = result["batch_throughput"]["threads"]
    if "2" in batch:
        rows.add("batch: efficiency on 2 cores", batch["2"]["efficiency"],
                 TARGETS["batch_efficiency"], True)  # fmt: skip
    for name, ens in (result.get("averaged_batch_throughput") or {}).items():
        most = max(ens["threads"], key=int)
        if most != "1":
            rows.add(f"averaged ensemble {name}: efficiency on {most} cores",
                     ens["threads"][most]["efficiency"], TARGETS["averaged_batch_efficiency"],
                     True)  # fmt: skip


def _orbit_rows(rows: _Rows, orbit: dict[str, Any]) -> None:
    """The orbiting body's year, averaged against full, and its Monte Carlo."""
    chosen = orbit["rtol"]
    error = orbit["averaged"][f"{chosen:g}"]["period_error"] if chosen else math.inf
    rows.add("orbiting body, a year: averaged spin period against the full one", error,
             TARGETS["orbit_period_agreement"], False)  # fmt: skip
    rows.add("orbiting body, a year: averaged speed-up over the full run",
             orbit.get("speedup", 0.0), TARGETS["orbit_year_speedup"], True)  # fmt: skip
    mc = orbit.get("monte_carlo")
    rows.add("orbiting body: 1000 averaged years, in full 30-day runs",
             mc["in_full_30_day_runs"] if mc else math.inf,
             TARGETS["orbit_monte_carlo_full_runs"], False)  # fmt: skip
    box = orbit.get("capture")
    if box:
        for run in ("full", "hybrid"):
            rows.add(f"small box, a year to capture: the {run} run's rate against n, less 1",
                     abs(box[f"{run}_rate_over_n"] - 1.0), TARGETS["capture_rate_agreement"],
                     False)  # fmt: skip
    shell = orbit.get("shell")
    if shell:
        rows.add("shell, a year through its floor: averaged spin rate against the full one",
                 shell["rate_difference"], TARGETS["shell_rate_agreement"], False)  # fmt: skip
        rows.add("shell, a year through its floor: averaged speed-up over the full run",
                 shell["speedup"], TARGETS["shell_year_speedup"], True)  # fmt: skip
    for name, sun in (orbit.get("sunlight") or {}).items():
        _sunlight_rows(rows, name, sun)
    rocket = orbit.get("rocket_body")
    if rocket:
        rows.add("rocket body, an averaged year: integration [s]", rocket["integration_s"],
                 TARGETS["rocket_year_integration_s"], False)  # fmt: skip
        rows.add(
            "rocket body, an averaged year end to end, in warm one-day runs",
            rocket["year_over_one_day"],
            TARGETS["rocket_year_over_one_day"],
            False,
        )
        rows.add("rocket body, a year: final spin period against a slightly triaxial twin",
                 rocket["twin_final_period_difference"], TARGETS["rocket_twin_agreement"],
                 False)  # fmt: skip


def _sunlight_rows(rows: _Rows, name: str, sun: dict[str, Any]) -> None:
    """A GEO box-wing's year in sunlight (:mod:`tumble.app.bench_sunlight`)."""
    where = f"box-wing in GEO ({name}), a year"
    chosen = sun["averaged"].get(f"{sun['rtol']:g}") if sun["rtol"] else None
    rows.add(f"{where}: averaged spin period against the full one",
             chosen["period_error"] if chosen else math.inf,
             TARGETS["sunlight_period_agreement"], False)  # fmt: skip
    rows.add(f"{where}: averaged direction of L against the full one [deg]",
             chosen["direction_deg"] if chosen else math.inf,
             TARGETS["sunlight_direction_deg"], False)  # fmt: skip
    rows.add(f"{where}: averaged speed-up over the full run", sun["speedup"],
             TARGETS["sunlight_year_speedup"], True)  # fmt: skip
    rows.add(f"{where}: one averaged evaluation [µs]", sun["eval_us"],
             TARGETS["sunlight_eval_us"], False)  # fmt: skip
    if "expanded_eval_us" in sun:
        rows.add(f"{where}: one averaged evaluation, expanded illumination [µs]",
                 sun["expanded_eval_us"], TARGETS["sunlight_eval_us"], False)  # fmt: skip


def _machine_rows(rows: _Rows, result: dict[str, Any]) -> None:
    """The start-up times and the compile times, from fresh processes."""
    for name, seconds in (result.get("startup_s") or {}).items():
        rows.add(f"start-up: {name} [s]", seconds, TARGETS["startup_s"], False)
    if "compile" in result:
        c = result["compile"]
        rows.add("compile: first calls from an empty cache, all kinds [s]",
                 c["total_s"], TARGETS["compile_all_s"], False)  # fmt: skip
        for name, run in (c.get("first_run") or {}).items():
            rows.add(f"compile: the first run of the {name} template [s]", run["compile_s"],
                     TARGETS["compile_s"], False)  # fmt: skip
        rows.add("compile: the same first calls from the disk cache [s]",
                 result["compile"]["cached_total_s"], TARGETS["compile_cached_s"],
                 False)  # fmt: skip
