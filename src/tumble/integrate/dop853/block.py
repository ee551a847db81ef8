"""Many short runs of one kernel kind in one compiled call: the averaged ensembles.

An averaged run takes tens of steps: from Python each costs more in the calls around it than in
its steps. :func:`advance_block` advances a block of runs, each by one piece (to its next stop,
or to the first zero of its terminal event), keeping only their samples; a thread runs a block
with the GIL released, so blocks on several threads use every core. The caller restarts the
pieces (a breakpoint at a known time, the map past a surface) between calls.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, cast

import numba
import numpy as np
from numba.typed import List

from tumble._typing import FloatArray
from tumble.integrate.dop853.core import FRESH, Options, Progress, advance
from tumble.integrate.dop853.functions import addresses
from tumble.kernels.jit import ENTRY, compile_lock, jit

__all__ = ["advance_block", "block_entry"]


_PIECE = numba.types.Tuple(
    (numba.int64, numba.int64, numba.int64, numba.float64[::1], numba.float64[::1],
     numba.float64[::1])
)  # fmt: skip
"""A piece of a dense run: (run, steps, evaluations, times, states, interpolants), flat."""


@jit(ENTRY)
def advance_block(
    fns: Any, rows: Any, P: FloatArray, T: FloatArray,
    events: Any, first: FloatArray, t0: FloatArray, ie: Any, rtol: float, atol: float,
    max_steps: int, dense: bool, t_eval: FloatArray, Y: FloatArray, F: FloatArray,
    Y_eval: FloatArray, status: Any, nfev: Any,
) -> Any:  # fmt: skip
    """Advance each run ``i`` of ``rows`` from ``t0[i]`` (state ``Y[i]``) towards ``T[i]``,
    with the right-hand side's compiled functions and the event function of the runs that
    watch one at the addresses ``fns`` (:func:`~.functions.addresses`).

    Run i has parameters ``P[i]``, event code ``events[i]`` (terminal; 0: none), first step
    ``first[i]`` (0: Hairer's estimate), and fills its samples ``Y_eval[i]`` (flat rows, at
    its times ``t_eval[i]``) from index ``ie[i]``. On return ``t0[i]`` is the time reached,
    ``Y[i]`` the state there, ``first[i]`` the step to try next, ``ie[i]`` the next sample,
    ``status[i]`` that of :mod:`tumble.integrate.dop853.core` (``RUNNING``: ``max_steps``
    spent) and ``nfev[i]`` grown by the evaluations of this piece. With ``dense`` every step and its
    interpolant are kept as well, and returned as one ``_PIECE`` per run (else none).
    """
    pieces = List.empty_list(_PIECE)
    for r in range(rows.size):
        i = rows[r]
        ev = events[i]
        opts = Options(rtol, atol, first[i], dense, dense, ev, max_steps, ev != 0)
        prog = Progress(FRESH, t0[i], 0.0, 1.0, 0, 0, ie[i])
        progress, chunk = advance(fns, P[i], T[i], opts, prog, Y[i], F[i],
                                  t_eval[i], Y_eval[i])  # fmt: skip
        status[i] = progress[0]
        t0[i] = progress[1]
        first[i] = progress[2]
        nfev[i] += progress[4]
        ie[i] = progress[6]
        if dense:
            pieces.append((i, chunk[0], progress[4], chunk[1], chunk[2], chunk[3]))
    return pieces


_ENTRIES: dict[tuple[Any, ...], Callable[..., Any]] = {}


def block_entry(kind: int, event: int, args: tuple[Any, ...]) -> Callable[..., Any]:
    """:func:`advance_block` for runs of the kind ``kind`` that watch the event ``event`` or
    none, as ``entry(*args)``: the block compiled once per argument types (for every kind),
    with the kind's and the event's compiled functions bound to it; ``args`` are the
    arguments after the functions."""
    fns = addresses(kind, event)
    key = tuple(_cheap_type(a) for a in args)
    entry = _ENTRIES.get(key)
    if entry is None:
        signature = (numba.typeof(fns), *(numba.typeof(a) for a in args))
        with compile_lock(f"advance_block-{signature}"):
            entry = cast(Any, advance_block).compile(signature)
        _ENTRIES[key] = entry
    return functools.partial(entry, fns)


def _cheap_type(value: Any) -> Any:
    """What numba's type of an argument depends on, read without numba's typeof (from
    Python some 30 µs an array, half a millisecond a call of seventeen arguments: more than
    the block's runs themselves): an array's dtype, dimensions, layout, writability and
    alignment; a scalar's Python type."""
    if isinstance(value, np.ndarray):
        flags = value.flags
        layout = "C" if flags.c_contiguous else "F" if flags.f_contiguous else "A"
        return (value.dtype.str, value.ndim, layout, flags.writeable, flags.aligned)
    return type(value)


def empty_block(n_runs: int, dim: int, n_eval: int) -> dict[str, FloatArray]:
    """The per-run arrays of :func:`advance_block` for ``n_runs`` runs of dimension ``dim``."""
    return {
        "T": np.zeros(n_runs),
        "events": np.zeros(n_runs, dtype=np.int64),
        "first": np.zeros(n_runs),
        "t0": np.zeros(n_runs),
        "ie": np.zeros(n_runs, dtype=np.int64),
        "Y": np.zeros((n_runs, dim)),
        "F": np.zeros((n_runs, dim)),
        "Y_eval": np.full((n_runs, n_eval * dim), np.nan),
        "status": np.zeros(n_runs, dtype=np.int64),
        "nfev": np.zeros(n_runs, dtype=np.int64),
    }
