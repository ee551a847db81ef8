"""What a long computation is doing, for a progress display: its stage and how far it has got.

Silent unless a display is set (:func:`set_display`): the command line sets one on a terminal,
so that a run is never quiet for long. The integrators report after every chunk of steps
(:func:`advanced`), the runners name their stages (:func:`stage`), and the compile notice
(:func:`tumble.kernels.jit.compile_notice`) is shown the same way.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator

__all__ = ["Display", "advanced", "close", "notice", "set_display", "stage"]

Display = Callable[[str, "float | None"], None]
"""``display(stage, fraction)``: the stage's name and the fraction of it done (0 … 1), or
None when the fraction is unknown."""

_display: Display | None = None
_close: Callable[[], None] | None = None
_stage = ""


def set_display(
    display: Display | None, close: Callable[[], None] | None = None
) -> tuple[Display | None, Callable[[], None] | None]:
    """Where progress goes from now on (None: nowhere), and how to take the display off the
    terminal at once (:func:`close`, before an exit on Ctrl-C); returns the pair it replaces."""
    global _display, _close
    previous = (_display, _close)
    _display, _close = display, close
    return previous


def close() -> None:
    """Take the display off the terminal now (its cursor restored), if there is one."""
    if _close is not None:
        _close()


def notice(message: str) -> bool:
    """Show ``message`` in the display as the current stage; False if there is no display."""
    if _display is None:
        return False
    _display(message, None)
    return True


@contextlib.contextmanager
def stage(name: str) -> Iterator[None]:
    """Name the work inside the block ("averaged", "drawing the figure", …)."""
    global _stage
    previous, _stage = _stage, name
    if _display is not None:
        _display(name, None)
    try:
        yield
    finally:
        _stage = previous
        if _display is not None and previous:
            _display(previous, None)


def advanced(t: float, t_end: float, t0: float = 0.0) -> None:
    """An integration of the current stage has reached ``t`` of ``t0 … t_end``."""
    if _display is not None and t_end > t0:
        _display(_stage, min(1.0, max(0.0, (t - t0) / (t_end - t0))))
