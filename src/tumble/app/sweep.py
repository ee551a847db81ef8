"""Sweeps on Dask: the library function behind ``tumble sweep``.

Usable from a notebook::

    import tumble
    result = tumble.sweep("examples/sweeps/rf_beta_eps.toml", "out/sweep")  # local cores
    result = tumble.sweep(path, "out/sweep", scheduler="tcp://10.0.0.5:8786")  # a cluster
    result.dataset                                                           # xarray

The points are cut into chunks (``[sweep] chunk``); each chunk is one Dask task, and its
records are written to the output directory as soon as it returns. A worker that dies has its
tasks rerun by the scheduler; a sweep that is stopped and started again with the same
command computes only the chunks that have no records yet. Every point is computed from its
own inputs alone, so the results do not depend on the workers, their number or the order of
the tasks.
"""

from __future__ import annotations

import contextlib
import logging
import os
import time
import uuid
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
import xarray as xr

from tumble.analysis.run import RunRequest
from tumble.analysis.sweep import (
    Keep,
    Record,
    failed_record,
    internal_reason,
    records_to_dataset,
    run_point,
)
from tumble.errors import ScenarioError, TumbleError, shorten
from tumble.integrate import Trajectory, simulate_batch
from tumble.integrate.limits import USER_CODE_TIMEOUT_S, user_code_timeout
from tumble.io.scenario import parse_scenario
from tumble.io.sweep import Sweep, SweepStore, load_sweep, point_scenario
from tumble.plot.settings import figure_settings
from tumble.plot.sweep import sweep_png

__all__ = ["SweepResult", "compute_chunk", "sweep"]

WRITE_EVERY = 5.0
"""Seconds between rewrites of ``sweep.nc`` while a sweep runs (each chunk's records are
on disk at once; the Dataset is their summary)."""


@dataclass(frozen=True)
class SweepResult:
    """What :func:`sweep` did.

    Attributes
    ----------
    dataset : xarray.Dataset
        Every point's record (see :func:`tumble.analysis.sweep.records_to_dataset`).
    files : list of Path
        ``sweep.nc``, ``sweep.json``, the figure.
    computed, resumed, failed : int
        Points computed by this call, found finished on disk, and failed (of all).
    wall_time : float
        Seconds of this call [s].
    workers : int
        Dask worker threads used.
    """

    dataset: xr.Dataset
    files: list[Path]
    computed: int
    resumed: int
    failed: int
    wall_time: float
    workers: int

    @property
    def throughput(self) -> float:
        """Points computed per second of this call [1/s]."""
        return self.computed / self.wall_time if self.wall_time > 0 else 0.0


def _batchable(req: RunRequest, method: str) -> bool:
    """Whether ``method`` of ``req`` can go through the compiled batch: the full run of a
    compiled full form, or the averaged run of a form with a kernel (decided point by point
    inside the batch; the others run there as :func:`simulate` would)."""
    if method not in req.methods or req.integrator == "scipy":
        return False
    if method == "averaged":
        return req.model.averaged is not None
    full = req.model.full.form()
    return full.kernel is not None and full.kernel(req.params) is not None


def _batched(requests: Sequence[RunRequest | None]) -> list[dict[str, Trajectory]]:
    """The full and averaged trajectories of every batchable request, integrated together
    per (model, method, number of samples, tolerances, averaging), each point at its own
    sample times (a physical scenario's points each have their own time unit); the others
    get no entry and are run point by point. Averaged ensembles keep their dense output: a
    point's validity checks evaluate it anywhere, as for a run of its own."""
    out: list[dict[str, Trajectory]] = [{} for _ in requests]
    groups: dict[tuple[Any, ...], list[int]] = {}
    for i, req in enumerate(requests):
        if req is None:
            continue
        for method in ("full", "averaged"):
            if _batchable(req, method):
                extra = req.averaging if method == "averaged" else None
                key = (req.model.name, method, req.tau.size, req.rtol, req.atol,
                       req.max_steps, extra)  # fmt: skip
                groups.setdefault(key, []).append(i)
    for key, members in groups.items():
        which: Literal["full", "averaged"] = "averaged" if key[1] == "averaged" else "full"
        first = requests[members[0]]
        assert first is not None
        try:
            trajs = simulate_batch(
                first.model,
                [requests[i].params for i in members],  # type: ignore[union-attr]
                [requests[i].initial for i in members],  # type: ignore[union-attr]
                np.stack([requests[i].tau for i in members]),  # type: ignore[union-attr]
                rtol=first.rtol,
                atol=first.atol,
                max_steps=first.max_steps,
                method=which,
                averaging=first.averaging,
                dense=which == "averaged",
            )
        except Exception:  # each point then runs, and fails, on its own
            continue
        for i, traj in zip(members, trajs, strict=True):
            # A point that failed in the batch is run again on its own, so that its failure
            # is reported by run() exactly as ``tumble run`` would report it.
            if isinstance(traj, Trajectory):
                out[i][which] = traj
    return out


def compute_chunk(
    base: dict[str, Any],
    source: str,
    points: list[dict[str, float]],
    keep: Keep,
    batch: bool = True,
    allow_modules: tuple[str, ...] = (),
) -> list[Record]:
    """Run the points of one chunk (a Dask task) and return their records.

    Parameters
    ----------
    base : dict
        The base scenario.
    source : str
        Its path (a user torque is imported relative to it).
    points : list of dict
        Per point, scenario key → value.
    keep : Keep
        What to keep.
    batch : bool
        Integrate the chunk's full and averaged runs together with the compiled batch path
        (:func:`tumble.integrate.simulate_batch`); the records are the same either way.

    Returns
    -------
    list of dict
        One record per point, in order (see :func:`tumble.analysis.sweep.run_point`); a
        point whose scenario is invalid gets a failed record with the reason.
    """
    requests: list[RunRequest | None] = []
    invalid: dict[int, str] = {}
    waits: dict[int, float] = {}  # the points that run a user's code: its timeout [s]
    for i, assignments in enumerate(points):
        try:
            point = point_scenario(base, assignments)
            scenario = parse_scenario(point, source, allow_modules=allow_modules)
            requests.append(scenario.request)
            if scenario.user_code:
                waits[i] = scenario.user_code_timeout
        except TumbleError as exc:
            requests.append(None)
            invalid[i] = f"invalid input: {shorten(str(exc))}"
        except Exception as exc:  # a defect met by this point alone: never its chunk's
            requests.append(None)
            invalid[i] = internal_reason(exc)
    # A user's code runs point by point, where a compiled function that never returns is
    # stopped after its timeout (the batch's threads could not be).
    pre = (
        _batched([None if i in waits else r for i, r in enumerate(requests)])
        if batch
        else [{} for _ in requests]
    )
    records = []
    for i, req in enumerate(requests):
        if req is None:
            records.append(failed_record(invalid[i]))
        else:
            with user_code_timeout(waits.get(i, USER_CODE_TIMEOUT_S)):
                rec = run_point(req, keep, pre[i])
            if pre[i]:  # its full or averaged run went through the compiled batch
                rec["batch"] = 1
            records.append(rec)
    return records


@contextlib.contextmanager
def _client(scheduler: str | None, workers: int | None) -> Iterator[Any]:
    """A Dask client: of the cluster at ``scheduler``, or of a LocalCluster started (and
    stopped) here with one single-threaded worker process per core."""
    from distributed import Client, LocalCluster

    # The cluster's own INFO logs would bury the progress bar; its warnings still show.
    logging.getLogger("distributed").setLevel(logging.WARNING)
    if scheduler is not None:
        try:
            client = Client(scheduler, timeout="30s")
        except OSError as exc:
            raise ScenarioError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
        try:
            yield client
        finally:
            client.close()
        return
    n = workers or os.cpu_count() or 1
    # Processes, not threads: averaging and the slow runs are Python, which holds the GIL.
    cluster = LocalCluster(
        n_workers=n,
        threads_per_worker=1,
        processes=True,
        # Any free port on the loopback interface only: a fixed one (8787) may be taken by
        # another cluster, and nothing tumble starts listens beyond this machine.
        dashboard_address="127.0.0.1:0",
        host="127.0.0.1",
        # The workers' warnings and errors (tasks cancelled, a scheduler gone at Ctrl-C, …)
        # would break the progress bar and read as tracebacks; what matters to a sweep (a
        # point's failure, a lost worker's task) is in its records or raised in this process.
        silence_logs=logging.CRITICAL,
    )
    try:
        client = Client(cluster)
        try:
            yield client
        finally:
            client.close()
    finally:
        cluster.close()


def _threads(client: Any) -> int:
    return int(sum(client.nthreads().values()))


def sweep(
    path: str | Path | Sweep,
    out_dir: str | Path,
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    plot: bool = True,
    retry_failed: bool = False,
    allow_modules: Iterable[str] = (),
) -> SweepResult:
    """Run a sweep file on Dask and write its results to ``out_dir``, resuming if it can.

    Writes ``parts/<chunk>.json`` as each chunk finishes, ``sweep.nc`` (rewritten every
    :data:`WRITE_EVERY` seconds and at the end, also when interrupted), ``sweep.json`` and,
    with ``plot``, ``sweep.png`` (heat maps, lines or histograms).

    Parameters
    ----------
    path : str, Path or Sweep
        The sweep file (see :mod:`tumble.io.sweep`), or the sweep already read from it
        (:func:`tumble.io.sweep.load_sweep`, with its ``allow_modules``).
    out_dir : str or Path
        Output directory; if it holds this sweep's finished chunks they are kept and not
        computed again.
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://HOST:PORT``); by default a LocalCluster
        with one worker per core is started and stopped.
    workers : int, optional
        Workers of the LocalCluster (default: the number of cores).
    progress : callable, optional
        ``progress(done, total)`` in points, after each chunk.
    plot : bool
        Write the figure.
    retry_failed : bool
        Compute again the finished chunks that hold a failed point (e.g. after a worker was
        lost too often, or once a bug is fixed); by default failed points are kept as results.
    allow_modules : iterable of str
        Importable modules the scenario may name functions of (besides files beside it).

    Returns
    -------
    SweepResult
    """
    start = time.perf_counter()
    sweep_plan = path if isinstance(path, Sweep) else load_sweep(path, allow_modules=allow_modules)
    store = SweepStore(out_dir, sweep_plan)
    finished = store.finished()
    if retry_failed:
        finished = {c: recs for c, recs in finished.items() if all(r["status"] == 0 for r in recs)}
    records = store.records(finished)
    resumed = len(records)
    total = sweep_plan.plan.size
    todo = [c for c in range(sweep_plan.chunks) if c not in finished]
    if progress is not None:
        progress(resumed, total)
    threads = 0
    last_write = time.perf_counter()
    try:
        if todo:
            with _client(scheduler, workers) as client:
                threads = _threads(client)
                _run_chunks(client, sweep_plan, store, todo, records, progress, last_write)
    finally:
        ds = _dataset(sweep_plan, records)
        files = [store.write_dataset(ds), store.dir / "sweep.json"]
    if plot:
        files.append(
            _write_figure(sweep_plan, ds, store.dir / "sweep.png", Path(sweep_plan.path).name)
        )
    return SweepResult(
        ds,
        files,
        len(records) - resumed,
        resumed,
        int(ds.attrs["points_failed"]),
        time.perf_counter() - start,
        threads,
    )


def _write_figure(sweep_plan: Sweep, ds: xr.Dataset, figure: Path, name: str) -> Path:
    """The sweep's figure (heat maps, lines or histograms), written atomically."""
    from tumble.io.output import atomic_write

    png = sweep_png(
        ds,
        variables=sweep_plan.plot_variables or None,
        method=sweep_plan.plot_method,
        slow=figure_settings(sweep_plan.model).variables,
        title=f"sweep {name}",
    )
    atomic_write(figure, png)
    return figure


def _run_chunks(
    client: Any,
    sweep: Sweep,
    store: SweepStore,
    todo: list[int],
    records: dict[int, Record],
    progress: Callable[[int, int], None] | None,
    last_write: float,
) -> None:
    """Submit the chunks ``todo`` and keep each one's records as it finishes."""
    from distributed import as_completed

    base = client.scatter(sweep.base, broadcast=True)
    # Keys unique to this invocation: the same sweep run again on a long-lived cluster would
    # otherwise submit the keys the scheduler is still forgetting from the previous client,
    # and see its tasks cancelled ("already forgotten").
    invocation = uuid.uuid4().hex[:8]
    futures = {}
    for c in todo:
        points = [sweep.plan.assignments(i) for i in sweep.chunk_points(c)]
        fut = client.submit(
            compute_chunk,
            base,
            sweep.source,
            points,
            sweep.keep,
            sweep.batch,
            sweep.allow_modules,
            key=f"tumble-sweep-{sweep.digest}-{invocation}-{c}",
            pure=False,
        )
        futures[fut] = c
    for fut in as_completed(futures):
        c = futures[fut]
        try:
            recs = fut.result()
        except Exception as exc:  # the task itself broke: a KilledWorker, or a bug
            reason = f"the task of chunk {c} failed: {type(exc).__name__}: {exc}"
            recs = [failed_record(reason) for _ in sweep.chunk_points(c)]
        store.write_part(c, recs)
        records.update(zip(sweep.chunk_points(c), recs, strict=True))
        if progress is not None:
            progress(len(records), sweep.plan.size)
        if time.perf_counter() - last_write > WRITE_EVERY:
            store.write_dataset(_dataset(sweep, records))
            last_write = time.perf_counter()


def _dataset(sweep: Sweep, records: dict[int, Record]) -> xr.Dataset:
    attrs = {"sweep_file": sweep.path, "sweep_digest": sweep.digest, "base_scenario": sweep.source}
    ds = records_to_dataset(
        sweep.plan,
        records,
        model=sweep.model,
        time_name=sweep.time_name,
        columns=sweep.columns,
        attrs=attrs,
    )
    ds["batch"] = (
        sweep.plan.dims,
        np.array(
            [records.get(i, {}).get("batch", 0) for i in range(sweep.plan.size)], dtype=np.int8
        ).reshape(sweep.plan.shape),
        {"units": "1", "long_name": "full run integrated by the compiled batch path (1)"},
    )
    return ds
