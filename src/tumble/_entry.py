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
    from tumble._interrupt import interrupted, watch

    watch()
    try:
        from tumble.cli import app

        app()
    except KeyboardInterrupt:
        interrupted()
    except SystemExit as exc:
        if exc.code == 130:  # typer's answer to an interrupt outside a command's own handling
            interrupted()
        raise
