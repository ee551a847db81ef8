"""Sweeps on a real Dask cluster on loopback: a scheduler and two worker processes
started here. A sweep completes; a worker killed mid-sweep changes no result; a sweep killed
and started again gives the Dataset of an uninterrupted run and recomputes nothing finished.
"""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from tumble.app.sweep import sweep
from tumble.io.scenario import template

DASK = str(Path(sys.executable).with_name("dask"))
TUMBLE = str(Path(sys.executable).with_name("tumble"))

# 3 × 4 grid of a short resisting-medium run, 2 points per task: 6 tasks of ~1 s, so both
# workers are busy for a few seconds, long enough to kill one of them (or the client) mid-way.
BASE = (
    template("resisting_medium")
    .replace("tau_end = 400.0", "tau_end = 200.0")
    .replace("samples = 401", "samples = 101")
)
SWEEP = """base = "base.toml"
[[axis]]
key = "parameters.b[2][2]"
values = [0.05, 0.2, 0.4]
[[axis]]
key = "initial.theta"
linspace = [0.4, 1.3, 4]
[sweep]
chunk = 2
"""


def _start(args, log):
    return subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)


def _wait_for(predicate, timeout, what, poll=0.05):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return
        time.sleep(poll)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


class Cluster:
    """A Dask scheduler and worker processes on 127.0.0.1, as ``dask scheduler`` and
    ``dask worker`` start them on a real cluster (no nanny: a killed worker stays dead)."""

    def __init__(self, root: Path, workers: int = 2):
        self.root = root
        self.file = root / "scheduler.json"
        self.log = open(root / "cluster.log", "w")  # closed in stop()
        self.procs = [
            _start(
                [
                    DASK,
                    "scheduler",
                    "--host",
                    "127.0.0.1",
                    "--port",
                    "0",
                    "--no-dashboard",
                    "--scheduler-file",
                    str(self.file),
                ],
                self.log,
            )
        ]
        _wait_for(self.file.exists, 60, "the scheduler")
        self.address = json.loads(self.file.read_text())["address"]
        self.workers = [self.add_worker(f"w{i}") for i in range(workers)]
        from distributed import Client

        with Client(self.address, timeout="30s") as client:
            client.wait_for_workers(workers, timeout=60)

    def add_worker(self, name):
        proc = _start(
            [
                DASK,
                "worker",
                self.address,
                "--nthreads",
                "1",
                "--no-nanny",
                "--no-dashboard",
                "--name",
                name,
                "--host",
                "127.0.0.1",
            ],
            self.log,
        )
        self.procs.append(proc)
        return proc

    def stop(self):
        # A graceful close takes the workers ~10 s each; nothing of it is under test here.
        for proc in self.procs:
            proc.kill()
            proc.wait(timeout=20)
        self.log.close()


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    c = Cluster(tmp_path_factory.mktemp("cluster"))
    yield c
    c.stop()


@pytest.fixture(scope="module")
def sweep_file(tmp_path_factory):
    d = tmp_path_factory.mktemp("sweep")
    (d / "base.toml").write_text(BASE)
    (d / "sweep.toml").write_text(SWEEP)
    return d / "sweep.toml"


@pytest.fixture(scope="module")
def reference(cluster, sweep_file, tmp_path_factory):
    """The uninterrupted sweep on the cluster."""
    out = tmp_path_factory.mktemp("reference")
    result = sweep(sweep_file, out, scheduler=cluster.address)
    return result, out


def _results(ds: xr.Dataset) -> xr.Dataset:
    # Wall times are measurements of each run, not results: they differ between any two runs.
    return ds.drop_vars("wall_time")


def test_sweep_completes_on_the_cluster(reference):
    result, out = reference
    ds = result.dataset
    assert dict(ds["status"].sizes) == {"b_2_2": 3, "theta": 4}
    assert (ds["status"] == 0).all() and result.computed == 12 and result.failed == 0
    assert result.workers == 2
    assert (ds["batch"] == 1).all()  # the full runs went through the compiled batch path
    assert np.isfinite(ds["final_k"]).all() and np.isfinite(ds["difference_theta"]).all()
    on_disk = xr.load_dataset(out / "sweep.nc")
    xr.testing.assert_identical(on_disk, ds)
    assert (out / "sweep.png").stat().st_size > 0
    assert len(list((out / "parts").glob("*.json"))) == 6


def test_a_worker_killed_mid_sweep_changes_no_result(cluster, sweep_file, reference, tmp_path):
    """SIGKILL a worker while it runs a task: the scheduler reruns the task elsewhere."""
    from distributed import Client

    victim = cluster.add_worker("victim")
    out = tmp_path / "out"
    parts = out / "parts"
    with Client(cluster.address, timeout="30s") as client:
        client.wait_for_workers(3, timeout=60)
        address = next(
            a for a, w in client.scheduler_info()["workers"].items() if w["name"] == "victim"
        )
        proc = subprocess.Popen(
            [TUMBLE, "sweep", str(sweep_file), "-o", str(out), "--scheduler", cluster.address],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )

        def victim_busy():
            return bool(client.processing().get(address)) and parts.is_dir()

        _wait_for(victim_busy, 120, "a task on the victim")
        victim.send_signal(signal.SIGKILL)
        victim.wait(timeout=20)
        finished_at_kill = len(list(parts.glob("*.json")))
    stdout, _ = proc.communicate(timeout=300)
    assert proc.returncode == 0, stdout
    assert finished_at_kill < 6, stdout
    assert "12 computed, 0 already done, 0 failed" in stdout, stdout  # reasons printed if not
    killed = xr.load_dataset(out / "sweep.nc")
    xr.testing.assert_identical(_results(killed), _results(reference[0].dataset))


def test_a_killed_sweep_resumes_to_the_uninterrupted_dataset(
    cluster, sweep_file, reference, tmp_path
):
    out = tmp_path / "out"
    args = [TUMBLE, "sweep", str(sweep_file), "-o", str(out), "--scheduler", cluster.address]
    proc = subprocess.Popen(
        args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True
    )
    parts = out / "parts"

    # Killed as soon as a first chunk is on disk (polled every 5 ms): a chunk of these short
    # runs takes a few ms once the workers are warm, so waiting for more lets the sweep end.
    def first_chunk():
        return parts.is_dir() and any(parts.glob("*.json"))

    _wait_for(first_chunk, 120, "a first chunk", poll=0.005)
    os.killpg(proc.pid, signal.SIGKILL)  # no chance to clean up: killed at an arbitrary point
    proc.wait(timeout=20)
    kept = {p.name: p.stat().st_mtime_ns for p in parts.glob("*.json")}
    assert 1 <= len(kept) < 6, "the sweep should be killed before it ends"
    # The cluster lets go of the dead client's tasks before the second run submits them again.
    time.sleep(1.0)
    done = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    assert f"{12 - 2 * len(kept)} computed, {2 * len(kept)} already done" in done.stdout
    for name, mtime in kept.items():  # finished chunks were not computed or written again
        assert (parts / name).stat().st_mtime_ns == mtime
    resumed = xr.load_dataset(out / "sweep.nc")
    xr.testing.assert_identical(_results(resumed), _results(reference[0].dataset))


def test_monte_carlo_on_a_local_cluster_started_by_tumble(tmp_path):
    """Without --scheduler, tumble starts and stops a LocalCluster (here of 2 workers)."""
    (tmp_path / "base.toml").write_text(BASE)
    (tmp_path / "mc.toml").write_text(
        'base = "base.toml"\n[monte_carlo]\nsamples = 6\nseed = 11\n'
        '[[monte_carlo.draw]]\nkey = "parameters.eps"\nlog_uniform = [0.005, 0.02]\n'
        '[[monte_carlo.draw]]\nkey = "initial.theta"\nnormal = [1.0, 0.1]\n'
    )
    args = [TUMBLE, "sweep", str(tmp_path / "mc.toml"), "-o", str(tmp_path / "out")]
    done = subprocess.run([*args, "--workers", "2"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "6 computed" in done.stdout and "on 2 worker threads" in done.stdout
    ds = xr.load_dataset(tmp_path / "out" / "sweep.nc")
    assert ds["status"].dims == ("sample",) and (ds["status"] == 0).all()
    assert ds["eps"].attrs["distribution"] == "log_uniform"
    assert np.all((ds["eps"] >= 0.005) & (ds["eps"] <= 0.02))
    np.testing.assert_array_equal(ds["final_theta"].sel({"method": "full"}).notnull(), True)
    assert (tmp_path / "out" / "sweep.png").stat().st_size > 0


def test_ctrl_c_on_a_local_cluster_sweep_is_one_line_and_resumes(sweep_file, tmp_path):
    """SIGINT once the first chunks are on disk: exit 130 with one line (no worker logs, no
    warnings of multiprocessing's resource tracker); the same command finishes the sweep."""
    out = tmp_path / "out"
    args = [TUMBLE, "sweep", str(sweep_file), "-o", str(out), "--workers", "2", "--no-plot"]
    proc = subprocess.Popen(
        args,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),  # as in a terminal
    )
    parts = out / "parts"
    _wait_for(lambda: parts.is_dir() and any(parts.glob("*.json")), 120, "a first chunk")
    proc.send_signal(signal.SIGINT)
    _, stderr = proc.communicate(timeout=60)
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    assert proc.returncode == 130, stderr
    assert len(lines) == 1 and lines[0].startswith("interrupted: the finished points"), stderr
    done = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "already done" in done.stdout


def test_bad_sweep_input_is_one_line_and_exit_2(tmp_path):
    (tmp_path / "base.toml").write_text(BASE)
    (tmp_path / "bad.toml").write_text(
        'base = "base.toml"\n[[axis]]\nkey = "parameters.eps"\nlogspace = [0.0, 0.1, 3]\n'
    )
    done = subprocess.run(
        [TUMBLE, "sweep", str(tmp_path / "bad.toml"), "-o", str(tmp_path / "out")],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2
    assert "axis[0]" in done.stderr and "end points must be > 0" in done.stderr
    assert "Traceback" not in done.stderr and len(done.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()  # nothing is written before the input is valid


def test_failed_points_are_kept_on_resume_unless_retried(cluster, tmp_path):
    """κ = 0 has no averaged method: that point fails with its reason. Resuming keeps it as a
    result; --retry-failed computes its chunk again (and it fails again, the same way)."""
    (tmp_path / "base.toml").write_text(BASE)
    (tmp_path / "k.toml").write_text(
        'base = "base.toml"\n[[axis]]\nkey = "parameters.kappa"\nvalues = [0.5, 0.0, -0.3]\n'
    )
    first = sweep(tmp_path / "k.toml", tmp_path / "out", scheduler=cluster.address)
    ds = first.dataset
    assert ds["status"].values.tolist() == [0, 1, 0] and first.failed == 1
    assert "kappa" in str(ds["reason"].sel(kappa=0.0).values)
    parts = sorted((tmp_path / "out" / "parts").glob("*.json"))
    stamps = {p.name: p.stat().st_mtime_ns for p in parts}
    kept = sweep(tmp_path / "k.toml", tmp_path / "out", scheduler=cluster.address)
    assert kept.computed == 0 and kept.resumed == 3 and kept.failed == 1
    retried = sweep(
        tmp_path / "k.toml", tmp_path / "out", scheduler=cluster.address, retry_failed=True
    )
    assert retried.computed == 1 and retried.resumed == 2 and retried.failed == 1
    changed = [p.name for p in parts if p.stat().st_mtime_ns != stamps[p.name]]
    assert changed == ["000001.json"]  # only the failed point's chunk (chunk = 1 point here)
    xr.testing.assert_identical(_results(retried.dataset), _results(ds))


USER_BASE = """model = "torqued_body"
torque = "user_torques:constant"
[parameters]
inertia = [1.0, 1.6, 2.0]
eps = 0.01
[initial]
omega = [0.3, 0.9, 0.4]
[run]
t_end = 5.0
samples = 11
methods = ["full"]
"""
USER_SWEEP = """base = "base.toml"
[[axis]]
key = "parameters.eps"
values = [0.01, 0.02]
"""


def test_same_named_user_modules_on_one_cluster(cluster, tmp_path):
    """Two sweeps whose folders each hold a user_torques.py, one after the other on the same
    workers: each runs its own file's function (the workers load files by path under names
    of their own, never a module cached from the other sweep)."""
    from tumble.integrate import simulate
    from tumble.io import load_scenario

    finals = {}
    for name, value in (("a", 1.0), ("b", -2.0)):
        d = tmp_path / name
        d.mkdir()
        (d / "user_torques.py").write_text(
            f"def constant(t, q, omega, params):\n    return [{value}, 0.0, 0.0] + 0.0 * omega\n"
        )
        (d / "base.toml").write_text(USER_BASE)
        (d / "sweep.toml").write_text(USER_SWEEP)
        result = sweep(d / "sweep.toml", d / "out", scheduler=cluster.address, plot=False)
        assert result.failed == 0
        finals[name] = result.dataset["final_L1"].values
        # The same scenario run here, in this process, from its own file.
        r = load_scenario(d / "base.toml").request
        here = simulate(r.model, r.params, r.initial, r.tau, "full")
        # One compiled-or-scipy integration of the same equations at rtol 1e-10 each side.
        assert finals[name][0] == pytest.approx(here.columns["L1"][-1], rel=1e-8), name
    assert not np.allclose(finals["a"], finals["b"])


def test_a_point_that_breaks_fails_alone_without_a_traceback(cluster, tmp_path):
    """A point whose run fails in the user's code (here, a user torque that divides by zero
    during one point's run) fails with that reason, naming the function; the other points of
    its chunk, and the sweep, complete; no traceback reaches the workers' output."""
    (tmp_path / "user_torques.py").write_text(
        "def flaky(t, q, omega, params):\n"
        "    if t > 1.0 and params['bad'] == 2:\n"
        "        return 1.0 / 0.0\n"
        "    return [0.1, 0.0, 0.0] + 0.0 * omega\n"
    )
    (tmp_path / "base.toml").write_text(
        USER_BASE.replace(":constant", ":flaky") + "[torque_params]\nbad = 1\n"
    )
    (tmp_path / "sweep.toml").write_text(
        'base = "base.toml"\n[[axis]]\nkey = "torque_params.bad"\nvalues = [1, 2, 3]\n'
        "[sweep]\nchunk = 3\n"
    )
    cluster.log.flush()
    seen = (cluster.root / "cluster.log").stat().st_size
    result = sweep(tmp_path / "sweep.toml", tmp_path / "out", scheduler=cluster.address, plot=False)
    ds = result.dataset
    assert ds["status"].values.tolist() == [0, 1, 0] and result.failed == 1
    reason = str(ds["reason"].values[1])
    assert "user_torques:flaky raised ZeroDivisionError" in reason, reason
    assert "internal error" not in reason, reason
    assert np.isfinite(ds["final_L1"].values[[0, 2]]).all()
    time.sleep(0.5)  # the workers' log lines of this sweep, if any, are written
    with open(cluster.root / "cluster.log", encoding="utf-8", errors="replace") as fh:
        fh.seek(seen)
        assert "Traceback" not in fh.read()


_CHUNK = """
import json, sys
from tumble.app.sweep import compute_chunk
from tumble.io.sweep import load_sweep

plan = load_sweep(sys.argv[1])
points = [{"torque_params.late": v} for v in (1e9, 2.0, 1e9)]
records = compute_chunk(plan.base, plan.source, points, plan.keep)
print(json.dumps([[r["status"], r["reason"]] for r in records]))
"""


def test_a_compiled_torque_that_never_returns_fails_its_point_alone(tmp_path):
    """A point whose numba torque never returns (from t > 2 at that point) fails after the
    scenario's run.user_code_timeout with that reason; the points before and after it in its
    chunk complete (the user's code runs point by point, not in the batch, whose threads
    nothing could stop). In a process of its own: the call left behind keeps a core busy
    until the process ends."""
    (tmp_path / "user_torques.py").write_text(
        "import numba\nimport numpy as np\n\n\n@numba.njit\n"
        "def stuck(t, q, omega, params):\n"
        "    x = 0.0\n"
        "    while t > params[0] or x < 0.0:\n"
        "        x += 1.0\n"
        "    return np.array([1e-3, 0.0, 0.0])\n"
    )
    base = USER_BASE.replace(":constant", ":stuck") + "user_code_timeout = 1.0\n"
    (tmp_path / "base.toml").write_text(base + "[torque_params]\nlate = 1e9\n")
    (tmp_path / "sweep.toml").write_text(
        'base = "base.toml"\n[[axis]]\nkey = "torque_params.late"\nvalues = [1e9, 2.0]\n'
    )
    out = subprocess.run(
        [sys.executable, "-c", _CHUNK, str(tmp_path / "sweep.toml")],
        capture_output=True, text=True, timeout=300, check=True,
    )  # fmt: skip
    records = json.loads(out.stdout)
    assert [r[0] for r in records] == [0, 1, 0], records
    assert "user_torques:stuck did not return within 1 s" in records[1][1], records
