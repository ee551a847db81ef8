"""A newcomer's first hour, timed: how long each step of the README takes on this machine and
the longest stretch in which it printed nothing.

    .venv/bin/python benchmarks/first_hour.py CLONE [-o benchmarks/first_hour.json]

CLONE is a fresh clone of the repository (no ``.venv``, no ``out``): the script runs
``make reproduce`` then ``make test`` in it, each on a pseudo-terminal as a user at a terminal
sees them (progress displays on), and times every chunk of output as it arrives. Then, with
the clone's environment now installed and its kernels compiled, it times a warm
``tumble run examples/ob_envisat_like.toml`` (best and median of 5, each a fresh process)
beside the floor under it (``benchmarks/warm_floor.py``: the libraries it uses doing the same
kinds of work with no tumble code) and ``python -c "import tumble"`` (best of 5). About 10
minutes on 2 cores. Prints the figures and writes them as JSON; the exit status is 1 if a
target is missed (a silence longer than 5 s, a warm run over 2 s, an import over 0.3 s).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

# A newcomer's environment: Python writes its bytecode caches (a sandbox may have turned that
# off, which would add the compilation of every module to each warm run).
_NEWCOMER = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}

SILENCE_S = 5.0
WARM_RUN_S = 2.0
IMPORT_S = 0.3


def _heartbeat() -> Any:
    """tools/heartbeat.py, whose :func:`on_pty` runs a command on a pseudo-terminal."""
    path = Path(__file__).resolve().parents[1] / "tools" / "heartbeat.py"
    spec = importlib.util.spec_from_file_location("heartbeat", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def on_terminal(command: list[str], cwd: Path) -> dict[str, Any]:
    """Run ``command`` on a pseudo-terminal; its wall time, exit status and the longest gap
    between two chunks of its output (from its start to its end)."""
    env = {**_NEWCOMER, "COLUMNS": "100", "LINES": "40", "TERM": "xterm-256color"}
    relay = _heartbeat().on_pty(command, cwd=str(cwd), env=env)
    start = last = time.monotonic()
    longest, at, size = 0.0, 0.0, 0
    while True:
        try:
            now, chunk = next(relay)
        except StopIteration as done:
            status = int(done.value)
            break
        if chunk:
            if now - last > longest:
                longest, at = now - last, last - start
            last, size = now, size + len(chunk)
    end = time.monotonic()
    if end - last > longest:
        longest, at = end - last, last - start
    return {
        "command": " ".join(command),
        "exit": status,
        "wall_s": round(end - start, 2),
        "longest_silence_s": round(longest, 2),
        "silence_starts_at_s": round(at, 2),
        "output_bytes": size,
    }


def timed(command: list[str], cwd: Path, times: int) -> list[float]:
    """Wall times of ``command`` run ``times`` times, each a fresh process (output discarded)."""
    walls = []
    for _ in range(times):
        start = time.perf_counter()
        subprocess.run(command, cwd=cwd, check=True, capture_output=True, env=_NEWCOMER)
        walls.append(time.perf_counter() - start)
    return walls


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("clone", type=Path, help="a fresh clone of the repository")
    ap.add_argument("-o", "--output", type=Path, default=Path("benchmarks/first_hour.json"))
    args = ap.parse_args()
    clone = args.clone.resolve()
    if (clone / ".venv").exists():
        print(f"{clone} has a .venv already: give a fresh clone", file=sys.stderr)
        return 2
    steps = []
    for target in ("reproduce", "test"):
        step = on_terminal(["make", target], clone)
        print(json.dumps(step))
        steps.append(step)
    bin_dir = clone / ".venv" / "bin"
    scenario = "examples/ob_envisat_like.toml"
    run = [str(bin_dir / "tumble"), "run", scenario, "-o", "out/first_hour", "--overwrite"]
    timed(run, clone, 1)  # the scenario's own first run (its field model) is not warm
    runs = timed(run, clone, 5)
    floor_script = [str(bin_dir / "python"), str(clone / "benchmarks" / "warm_floor.py")]
    timed(floor_script, clone, 1)  # its numba function into the cache
    floor = timed(floor_script, clone, 5)
    imports = timed([str(bin_dir / "python"), "-c", "import tumble"], clone, 5)
    result = {
        "machine": {
            "cores": os.cpu_count(),
            "python": platform.python_version(),
            "platform": platform.platform(),
        },
        "steps": steps,
        "warm_run_s": {
            "command": " ".join(run[1:]),
            "best": round(min(runs), 2),
            "median": round(statistics.median(runs), 2),
        },
        "warm_floor_s": {
            "what": "benchmarks/warm_floor.py: the libraries alone",
            "best": round(min(floor), 2),
            "median": round(statistics.median(floor), 2),
        },
        "import_s": {"best": round(min(imports), 3)},
        "targets": {"longest_silence_s": SILENCE_S, "warm_run_s": WARM_RUN_S, "import_s": IMPORT_S},
    }
    met = {
        "silence": all(s["longest_silence_s"] <= SILENCE_S for s in steps),
        "steps succeed": all(s["exit"] == 0 for s in steps),
        "warm run": result["warm_run_s"]["median"] <= WARM_RUN_S,
        "import": result["import_s"]["best"] <= IMPORT_S,
    }
    result["met"] = met
    args.output.write_text(json.dumps(result, indent=1, ensure_ascii=False) + "\n")
    print(json.dumps(result, indent=1, ensure_ascii=False))
    return 0 if all(met.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
