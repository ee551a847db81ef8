"""Performance benchmark: ``tumble bench`` with its figures written for the documentation.

    .venv/bin/python benchmarks/performance.py [-o benchmarks/performance.json]
    .venv/bin/python benchmarks/performance.py --from benchmarks/performance.json

Runs :func:`tumble.app.bench.run_benchmark` with its standard settings (1e5 time units at rtol
1e-10, best of 5; heyoka.py from ``pip install -e .[bench]``; about 30 minutes on 2 cores,
of which scipy's Python right-hand sides take 20),
writes the JSON of ``tumble bench --json`` and prints the tables of docs/performance-tables.md
(included by the performance page) as Markdown. ``--from`` prints the tables of an earlier run.
The exit status is 1 if a target is missed (the performance page says which are, and why).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from tumble.app.bench import run_benchmark
from tumble.io.output import atomic_write


def markdown(r: dict[str, Any]) -> str:
    """The figures of one run as Markdown tables."""
    m, st = r["machine"], r["settings"]
    lines = [
        f"Measured on {m['cpu']} ({m['cores']} cores), Python {m['python']}, numba "
        f"{m['numba']}, scipy {m['scipy']}, heyoka.py {m['heyoka']}; best of {st['repeat']}.",
        "",
    ]
    if r["full_speedup_vs_scipy"]:
        lines += [
            f"Full simulation over {st['horizon']:g} time units at rtol {st['rtol']:g} "
            "(errors: final state against the compiled DOP853 at rtol 1e-13):",
            "",
            "| case | tumble [s] | error | scipy, Python rhs [s] | error | speed-up (≥ 50×) |",
            "|---|---:|---:|---:|---:|---:|",
        ]
        for name, v in r["full_speedup_vs_scipy"].items():
            lines.append(
                f"| {name} | {v['tumble_s']:.3g} | {v['tumble_error']:.1e} | "
                f"{v['scipy_s']:.3g} | {v['scipy_error']:.1e} | {v['speedup']:.0f}× |"
            )
        lines.append("")
    if r["full_time_ratio_vs_heyoka"]:
        lines += [
            "Against heyoka.py at equal error (errors against heyoka at tol 1e-15; heyoka's "
            "time interpolated between the tolerances that bracket tumble's error):",
            "",
            "| case | tumble [s] | error | heyoka [s] | ratio (≤ 1.5; stretch ≤ 1.0) |",
            "|---|---:|---:|---:|---:|",
        ]
        for name, v in r["full_time_ratio_vs_heyoka"].items():
            label = f"{name} without s" if v["note"] else name
            lines.append(
                f"| {label} | {v['tumble_s']:.3g} | {v['tumble_error']:.1e} | "
                f"{v['heyoka_s_at_equal_error']:.3g} | {v['ratio']:.2f} |"
            )
        lines.append("")
    lines += [
        "Averaged (and closed form) against full over the template's slow horizon, error on "
        "the slow variables relative to their scale:",
        "",
        "| model | ε | full [s] | averaged [s] | error (≤ 1 %) | speed-up (≥ 100× at 1e-3, "
        "≥ 1000× at 1e-4) | at equal accuracy (≥ 300× at 1e-4) | nfev ratio "
        "| one evaluation [µs]: averaged (≤ 1) / full | closed form: speed-up |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, by_eps in r["averaged_speedup"].items():
        for eps, v in by_eps.items():
            a, c = v["averaged"], v.get("closed_form")
            eq_text = _equal_accuracy(a)
            cf_text = "—" if c is None else f"{c['speedup']:.3g}×"
            ev = v.get("eval_us")
            ev_text = "—" if ev is None else f"{ev['averaged']:.3g} / {ev['full']:.3g}"
            lines.append(
                f"| {name} | {eps} | {v['full_s']:.3g} | {a['time_s']:.3g} | "
                f"{100 * a['error']:.2f} % | {a['speedup']:.3g}× | "
                f"{eq_text} | {a['nfev_ratio']:.0f} | {ev_text} | {cf_text} |"
            )
    if r.get("engine_speedup"):
        lines += [
            "",
            "The general engine (the torque averaged over the unperturbed motion; compiled in "
            "all three settings for these torques) against full, one built-in torque per "
            "setting:",
            "",
            "| case | ε | full [s] | averaged [s] | error | speed-up (≥ 100× at 1e-4) "
            "| at equal accuracy | nfev ratio | one evaluation [µs] (≤ 20): averaged / full |",
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
        ]
        for label, by_eps in r["engine_speedup"].items():
            for eps, v in by_eps.items():
                a, ev = v["averaged"], v["eval_us"]
                lines.append(
                    f"| {label} | {eps} | {v['full_s']:.3g} | {a['time_s']:.3g} | "
                    f"{100 * a['error']:.2f} % | {a['speedup']:.3g}× | "
                    f"{_equal_accuracy(a)} | {a['nfev_ratio']:.0f} | "
                    f"{ev['averaged']:.3g} / {ev['full']:.3g} |"
                )
    b = r["batch_throughput"]
    lines += [
        "",
        f"Batch of {b['size']} trajectories ({b['case']}; error {b['error']:.1e}):",
        "",
        "| threads | trajectories/s | efficiency (≥ 0.8) |",
        "|---:|---:|---:|",
    ]
    for n, v in b["threads"].items():
        lines.append(f"| {n} | {v['trajectories_per_s']:.4g} | {v['efficiency']:.2f} |")
    ensembles = r.get("averaged_batch_throughput")
    if ensembles:
        lines += [
            "",
            'Averaged ensembles (simulate_batch, method = "averaged"), runs per second:',
            "",
            "| model | size | one simulate() per point | 1 thread | all threads "
            "| efficiency (≥ 0.8) |",
            "|---|---:|---:|---:|---:|---:|",
        ]
        for name, v in ensembles.items():
            most = max(v["threads"], key=int)
            row = v["threads"][most]
            lines.append(
                f"| {name} | {v['size']} | {v['single_runs_per_s']:.4g} | "
                f"{v['threads']['1']['runs_per_s']:.4g} | {row['runs_per_s']:.4g} ({most}) | "
                f"{row['efficiency']:.2f} |"
            )
    # The orbiting body's study has a table of its own (benchmarks/orbit_year.py), which the
    # performance page includes beside these.
    if "compile" in r:
        c = r["compile"]
        first = ", ".join(f"{k} {v:.1f} s" for k, v in c["first_call_s"].items())
        lines += [
            "",
            f"Compile from an empty cache (≤ 15 s): {c['total_s']:.1f} s in all ({first}); "
            f"from the cache {c['cached_total_s']:.2f} s.",
        ]
        if c.get("first_run"):
            runs = ", ".join(f"{k} {v['compile_s']:.1f} s" for k, v in c["first_run"].items())
            lines.append(
                f"What the first run of each model's template compiles (≤ 10 s; its run from "
                f"an empty cache less the same from the filled one): {runs}."
            )
    return "\n".join(lines)


def _equal_accuracy(a: dict) -> str:
    """The speed-up at equal accuracy, or its lower bound (no full run of the ladder is as
    accurate as the averaged one), or a dash."""
    if "speedup_equal_accuracy" in a:
        return f"{a['speedup_equal_accuracy']:.3g}×"
    if "speedup_equal_accuracy_at_least" in a:
        return f"≥ {a['speedup_equal_accuracy_at_least']:.3g}×"
    return "—"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", type=Path, default=Path("benchmarks/performance.json"))
    ap.add_argument("--from", dest="source", type=Path, help="print the tables of a JSON file")
    args = ap.parse_args()
    if args.source is not None:
        result = json.loads(args.source.read_text(encoding="utf-8"))
    else:
        result = run_benchmark(log=lambda msg: print(f"… {msg}", file=sys.stderr, flush=True))
        args.output.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(args.output, json.dumps(result, indent=1, ensure_ascii=False).encode())
    print(markdown(result))
    missed = [v for v in result["verdicts"] if not v["met"]]
    for v in missed:
        print(f"missed: {v['what']}: {v['value']:.3g} (target {v['target']:g})", file=sys.stderr)
    return 1 if missed else 0


if __name__ == "__main__":
    sys.exit(main())
