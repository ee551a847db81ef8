"""The floor under a warm ``tumble run``: the libraries it stands on, doing the same kinds of
work with no tumble code, in a fresh process that ends as tumble's does (without the
interpreter's teardown): a typer, rich and pydantic command line; numba's first call of a
function from its disk cache; an xarray Dataset of 366 samples written as NetCDF; a 3-panel
matplotlib figure of them as PNG.

    .venv/bin/python benchmarks/warm_floor.py

Prints each step's time; benchmarks/first_hour.py times the whole process beside a warm run of
the Envisat-like example. Run it once first: numba's cache of its function must exist.
"""

from __future__ import annotations

import io
import os
import sys
import time

start = time.perf_counter()
steps: list[tuple[str, float]] = []


def mark(what: str) -> None:
    steps.append((what, time.perf_counter()))


import numpy as np  # noqa: E402
import pydantic  # noqa: E402, F401
import rich.console  # noqa: E402, F401
import typer  # noqa: E402, F401

mark("numpy, typer, rich, pydantic")

import numba  # noqa: E402


@numba.njit(cache=True)
def _affine(x: np.ndarray) -> np.ndarray:
    return x * 2.0 + 1.0


_affine(np.ones(3))
mark("numba, first call from the cache")

import xarray as xr  # noqa: E402

t = np.linspace(0.0, 365.0, 366)
ds = xr.Dataset({f"v{i}": ("tau", np.sin(t / 50.0 + i)) for i in range(6)}, coords={"tau": t})
netcdf = bytes(ds.to_netcdf(engine="scipy"))
mark("xarray Dataset as NetCDF")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, axes = plt.subplots(3, 1, sharex=True, figsize=(8, 8), layout="constrained")
for ax in axes:
    ax.plot(t, np.sin(t / 50.0), lw=2, label="averaged")
    ax.set_ylabel("a quantity [unit]")
    ax.grid(alpha=0.3)
axes[0].legend()
axes[-1].set_xlabel("time t [d]")
fig.suptitle("title")
png = io.BytesIO()
fig.savefig(png, format="png", dpi=130)
mark("matplotlib figure as PNG")

previous = start
for what, at in steps:
    print(f"{what:34s} {at - previous:6.3f} s")
    previous = at
print(f"{'in the process':34s} {previous - start:6.3f} s")
sys.stdout.flush()
os._exit(0)  # as the tumble command ends: no teardown
