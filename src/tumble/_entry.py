"""The ``tumble`` console script: Ctrl-C at any moment is one line and exit code 130.

Loaded before the command line itself (typer, rich and tumble's modules), so that an
interrupt while those load, or while typer parses the arguments (which typer turns into a
silent exit 130), reads the same as one during a run; and an interrupt during a long call
into C (a cold compile) ends the run within half a second (:mod:`tumble._interrupt`).
"""

from __future__ import annotations

__all__ = ["main"]


def main() -> None:
    """Entry point of the ``tumble`` console script."""
    from tumble._interrupt import from_interrupt, interrupted, watch

    watch()
    try:
        from tumble.cli import app

        app()
    except KeyboardInterrupt:
        interrupted()
    except SystemExit as exc:
        if exc.code == 130:  # typer's answer to an interrupt outside a command's own handling
            interrupted()
        code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        if _alone():  # the outputs are written and closed: nothing is left to tear down
            _exit_at_once(code)
        raise
    except Exception as exc:
        if from_interrupt(exc):  # wrapped by Python or a library while the modules load
            interrupted()
        raise


def _alone() -> bool:
    """Whether the process runs nothing but its main thread (no worker thread, no child
    process of a local cluster), so that ending it at once cuts nothing short."""
    import multiprocessing
    import threading

    others = [t for t in threading.enumerate() if t is not threading.main_thread()]
    return not any(not t.daemon for t in others) and not multiprocessing.active_children()


def _exit_at_once(code: int) -> None:
    """End the process with ``code`` once the exit handlers have run and the output is
    flushed, without the interpreter's teardown of every loaded module: after an input error
    that teardown (numpy, pydantic, the validated scenario) is a fifth of the answer's time,
    after a warm run (numba's compiled code, scipy, xarray, matplotlib) 0.5–0.7 s of 3.5 s."""
    import atexit
    import os
    import sys

    atexit._run_exitfuncs()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
