"""Sweep throughput: points per second of the example sweeps on a local cluster.

For each sweep in ``examples/sweeps/`` this runs ``sweep`` on a LocalCluster of N single-
threaded workers (N = 1 and N = the cores), and the same points one after the other in this
process without Dask (the floor of what a sweep can cost). It prints a table and writes
``benchmarks/sweep_throughput.json``:

    python benchmarks/sweep_throughput.py [--workers 2] [--out FILE]

The cluster's start (about 2 s) and the workers' first calls (numba's cache, imports) are
inside the sweep's wall time, as a user sees it; ``points_per_s_steady`` leaves them out by
timing a second run of the same sweep into a fresh directory on the cluster it started.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import tempfile
import time
from pathlib import Path

import tumble
from tumble.app.sweep import compute_chunk
from tumble.io.sweep import load_sweep

ROOT = Path(__file__).resolve().parent.parent
SWEEPS = sorted((ROOT / "examples" / "sweeps").glob("*.toml"))


def sequential(path: Path) -> float:
    """Seconds to run every point of a sweep in this process, chunk by chunk, no Dask."""
    sweep = load_sweep(path)
    # Warm up as the cluster's workers are warmed: one point, untimed (imports, numba's cache,
    # first calls of the compiled entry points).
    compute_chunk(sweep.base, sweep.source, [sweep.plan.assignments(0)], sweep.keep, sweep.batch)
    start = time.perf_counter()
    for c in range(sweep.chunks):
        points = [sweep.plan.assignments(i) for i in sweep.chunk_points(c)]
        compute_chunk(sweep.base, sweep.source, points, sweep.keep, sweep.batch)
    return time.perf_counter() - start


def on_cluster(path: Path, workers: int) -> dict[str, float]:
    """Wall time of ``sweep`` on a LocalCluster it starts, and of a second run."""
    with tempfile.TemporaryDirectory() as tmp:
        first = tumble.sweep(path, Path(tmp) / "a", workers=workers, plot=False)
    # Steady state: the same points again on a cluster of the same size, started before the
    # clock (Client(LocalCluster)) so that only the tasks are timed.
    from distributed import Client, LocalCluster

    with (
        LocalCluster(
            n_workers=workers, threads_per_worker=1, dashboard_address=":0", host="127.0.0.1"
        ) as cluster,
        Client(cluster) as client,
        tempfile.TemporaryDirectory() as tmp,
    ):
        # Warm every worker (imports, numba's cache) with one chunk each, untimed.
        sweep = load_sweep(path)
        points = [sweep.plan.assignments(0)]
        client.run(compute_chunk, sweep.base, sweep.source, points, sweep.keep, sweep.batch)
        start = time.perf_counter()
        second = tumble.sweep(
            path, Path(tmp) / "b", scheduler=cluster.scheduler_address, plot=False
        )
        steady = time.perf_counter() - start
    return {
        "points": first.dataset.attrs["points"],
        "failed": first.failed,
        "wall_time_s": first.wall_time,
        "points_per_s": first.throughput,
        "steady_wall_time_s": steady,
        "points_per_s_steady": second.computed / steady,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "sweep_throughput.json")
    args = parser.parse_args()
    rows = []
    for path in SWEEPS:
        seq = sequential(path)
        one = on_cluster(path, 1)
        many = on_cluster(path, args.workers)
        n = many["points"]
        row = {
            "sweep": path.name,
            "points": n,
            "sequential_s": seq,
            "sequential_points_per_s": n / seq,
            "workers_1": one,
            f"workers_{args.workers}": many,
            # Steady throughput on N workers over N × the sequential one: 1 is perfect.
            "parallel_efficiency": many["points_per_s_steady"] / (args.workers * n / seq),
        }
        rows.append(row)
        print(
            f"{path.name:28s} {n:5d} points: sequential {n / seq:7.2f}/s, 1 worker "
            f"{one['points_per_s']:6.2f}/s ({one['points_per_s_steady']:6.2f} steady), "
            f"{args.workers} workers {many['points_per_s']:6.2f}/s "
            f"({many['points_per_s_steady']:6.2f} steady), efficiency "
            f"{row['parallel_efficiency']:.2f}",
            flush=True,
        )
    doc = {
        "machine": {"cpu": platform.processor() or platform.machine(), "cores": os.cpu_count()},
        "workers": args.workers,
        "sweeps": rows,
    }
    args.out.write_text(json.dumps(doc, indent=1) + "\n")
    print(f"written: {args.out}")


if __name__ == "__main__":
    main()
