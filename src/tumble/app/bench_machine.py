"""The benchmark's measurements in fresh processes, and the machine they ran on: how fast
``tumble`` answers at start-up, the compile time of every kernel kind from an empty disk cache
(numba's compile, once per installation) and its load from the cache
(:func:`tumble.app.bench.run_benchmark` reports them)."""

from __future__ import annotations

import json
import os
import platform
import re
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from tumble.app import heyoka_peer
from tumble.catalogue import CATALOGUE
from tumble.errors import IntegrationError
from tumble.integrate import dop853
from tumble.io.scenario import template

__all__ = ["STARTUP_REPEAT", "compile_times", "machine", "startup_times"]

# Compile time, in a fresh process with an empty cache.
_COLD = """
import json, sys, time
start = time.perf_counter()
from tumble.app import bench
from tumble.integrate import dop853
out = {"import_s": time.perf_counter() - start}
for case in bench.full_cases(1e5):
    start = time.perf_counter()
    dop853.solve(case.kernel, case.y0, 1.0, rtol=1e-10, atol=1e-12, record=False, dense=False)
    out[case.name] = time.perf_counter() - start
print("JSON" + json.dumps(out))
"""


STARTUP_REPEAT = 5


def startup_times(log: Callable[[str], None]) -> dict[str, float]:
    """Wall time of ``tumble`` answering at once [s], best of :data:`STARTUP_REPEAT` fresh
    processes: its help, the model list, a template, a scenario file that is missing, a
    scenario of each shipped model with a parameter out of range (validated against the
    model's declaration, before its numerics load) and a sweep file with a bad axis."""
    command = _tumble_command()
    out: dict[str, float] = {}
    with tempfile.TemporaryDirectory(prefix="tumble-bench-startup-") as tmp:
        cases = {
            "--help": ["--help"],
            "models": ["models"],
            "init": ["init", "resisting_medium"],
            "input error: missing file": ["run", str(Path(tmp) / "missing.toml")],
        }
        for name in CATALOGUE:
            bad = Path(tmp) / f"{name}.toml"
            # Every normalised template has one line "eps = <value>" (ε < 0 is out of range);
            # a physical one has "conductivity = <value>" instead (< 0 is out of range).
            text, count = re.subn(r"(?m)^eps = \S+", "eps = -1.0", template(name), count=1)
            if count == 0:
                text, count = re.subn(r"(?m)^conductivity = \S+", "conductivity = -1.0", text,
                                      count=1)  # fmt: skip
            if count != 1:  # a valid scenario would time a whole run, not an input error
                raise RuntimeError(f"start-up: no out-of-range key to set in {name}'s template")
            bad.write_text(text)
            cases[f"input error: {name} parameter out of range"] = ["run", str(bad)]
        sweep = Path(tmp) / "sweep.toml"
        sweep.write_text(
            'base = "resisting_medium.toml"\n[[axis]]\nkey = "parameters.kappa"\n'
            "linspace = [0.1, 0.5, 0]\n"  # num = 0: not an integer in [1, 1e7]
        )
        cases["input error: sweep file"] = ["sweep", str(sweep)]
        for name, args in cases.items():
            log(f"start-up: tumble {' '.join(args[:1])} ({name})")
            times = []
            for _ in range(STARTUP_REPEAT):
                start = time.perf_counter()
                subprocess.run([*command, *args], capture_output=True, check=False, cwd=tmp)
                times.append(time.perf_counter() - start)
            out[name] = min(times)
    return out


def _tumble_command() -> list[str]:
    """The command that runs this installation's ``tumble``."""
    exe = Path(sys.executable).with_name("tumble")
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "tumble.cli"]


def _first_runs(log: Callable[[str], None]) -> dict[str, dict[str, float]]:
    """``tumble run`` of each model's template [s], from an empty disk cache and then from
    the filled one, in fresh processes: what the first run of a newcomer's example compiles is
    the difference (``compile_s``)."""
    out: dict[str, dict[str, float]] = {}
    for name in CATALOGUE:
        with tempfile.TemporaryDirectory(prefix="tumble-bench-first-") as tmp:
            scenario = Path(tmp) / f"{name}.toml"
            scenario.write_text(template(name))
            env = {**os.environ, "NUMBA_CACHE_DIR": str(Path(tmp) / "cache")}
            times = {}
            for phase in ("cold", "warm"):
                log(f"compile: first run of the {name} template ({phase})")
                start = time.perf_counter()
                done = subprocess.run(
                    [*_tumble_command(), "run", str(scenario), "--out", str(Path(tmp) / phase)],
                    env=env, capture_output=True, text=True, check=False, cwd=tmp,
                )  # fmt: skip
                times[phase] = time.perf_counter() - start
                if done.returncode != 0:
                    raise IntegrationError(f"bench compile: {name}: {done.stderr.strip()[-300:]}")
            out[name] = {"cold_s": times["cold"], "warm_s": times["warm"],
                         "compile_s": times["cold"] - times["warm"]}  # fmt: skip
    return out


def compile_times(log: Callable[[str], None]) -> dict[str, Any]:
    """First call of every case's kernel from an empty cache, then from the filled one; and
    the compile of the first run of each model's template (:func:`_first_runs`)."""
    with tempfile.TemporaryDirectory(prefix="tumble-bench-cache-") as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        runs = []
        for phase in ("cold", "warm"):
            log(f"compile: {phase} start in a fresh process")
            done = subprocess.run(
                [sys.executable, "-c", _COLD], env=env, capture_output=True, text=True, check=False
            )
            lines = [ln for ln in done.stdout.splitlines() if ln.startswith("JSON")]
            if done.returncode != 0 or not lines:
                raise IntegrationError(f"bench compile: {done.stderr.strip()[-300:]}")
            runs.append(json.loads(lines[0][4:]))
    cold, warm = runs
    per_case = {k: v for k, v in cold.items() if k != "import_s"}
    first_runs = _first_runs(log)
    return {
        "first_call_s": per_case,
        # A kind compiles once: the first case of each kind carries its compile.
        "total_s": float(sum(per_case.values())),
        "largest_s": float(max(per_case.values())),
        "cached_total_s": float(sum(v for k, v in warm.items() if k != "import_s")),
        "import_s": cold["import_s"],
        "first_run": first_runs,
        "first_run_largest_s": max(r["compile_s"] for r in first_runs.values()),
    }


def machine() -> dict[str, Any]:
    """The machine and the versions the figures were measured with: CPU, cores, numba's
    threads, Python, tumble, numpy, scipy, numba and heyoka (None when not installed)."""
    import numba
    import scipy

    cpu = platform.processor()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    hy = heyoka_peer.available()
    from tumble._version import __version__

    return {
        "cpu": cpu,
        "cores": os.cpu_count(),
        "numba_threads": dop853.available_threads(),
        "python": platform.python_version(),
        "tumble": __version__,
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "numba": numba.__version__,
        "heyoka": getattr(hy, "__version__", None) if hy is not None else None,
    }
