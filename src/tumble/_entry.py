"""The ``tumble`` console script: Ctrl-C at any moment is one line and exit code 130.

Loaded before the command line itself (typer, rich and tumble's modules), so that an
interrupt while those load, or while typer parses the arguments (which typer turns into a
silent exit 130), reads the same as one during a run.
"""

from __future__ import annotations

import os
import sys

__all__ = ["interrupted", "main"]


def interrupted() -> None:
    """Say so and exit 130 at once: the work's own cleanup (temporary files) has run while the
    interrupt unwound it, and skipping the interpreter's teardown of numba and scipy (a few
    tenths of a second) makes the exit immediate."""
    sys.stdout.flush()
    sys.stderr.write("interrupted\n")
    sys.stderr.flush()
    os._exit(130)


def main() -> None:
    """Entry point of the ``tumble`` console script."""
    try:
        from tumble.cli import app

        app()
    except KeyboardInterrupt:
        interrupted()
    except SystemExit as exc:
        if exc.code == 130:  # typer's answer to an interrupt outside a command's own handling
            interrupted()
        raise
