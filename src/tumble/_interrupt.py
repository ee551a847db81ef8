"""Ctrl-C answered within half a second, even while Python cannot run.

Python handles a signal between two bytecodes of the main thread, so an interrupt that
arrives during a long call into C — numba compiling a kernel through LLVM, several seconds
from an empty cache — waits for the call to end. :func:`watch` (the console script calls it)
lets the C-level signal handler wake a watcher thread at once (``signal.set_wakeup_fd``): if
the main thread has not taken the interrupt within :data:`GRACE` seconds, the watcher runs the
registered emergency clean-ups (an output set's temporary directory) and exits 130 with the
usual line. Otherwise the interrupt unwinds the work as a KeyboardInterrupt, with its own
clean-up, as before — except inside numba's compiler, which would catch the exception and
report another error (or none): there the watcher ends the process too. An interrupt that
lands where Python ignores exceptions (a garbage-collector callback of Dask's) is delivered
again once that context has returned.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator
from types import FrameType

__all__ = ["GRACE", "REDELIVER", "emergency_cleanup", "from_interrupt", "interrupted", "watch"]

GRACE = 0.3
"""Seconds the main thread has to take an interrupt before the watcher ends the process."""

REDELIVER = 0.01
"""Seconds after which an interrupt lost in a context that ignores exceptions is sent again."""

_TAKEN = threading.Event()
_CLEANUPS: list[Callable[[], None]] = []


def interrupted(message: str = "interrupted") -> None:
    """Say so (one line) and exit 130 at once: the work's own clean-up has run (or the
    emergency ones), and skipping the interpreter's teardown of numba and scipy makes the
    exit immediate."""
    from tumble._progress import close

    with contextlib.suppress(Exception):
        close()  # a progress display leaves the terminal as it found it
        sys.stdout.flush()
    os.write(2, (message + "\n").encode())
    os._exit(130)


def from_interrupt(exc: BaseException) -> bool:
    """Whether ``exc`` is, or was raised while handling, a KeyboardInterrupt.

    Python wraps some exceptions in another one: an interrupt that lands while a class is
    created (in ``__set_name__``, which pydantic's models call for every field while a module
    loads) comes out as a RuntimeError "Error calling __set_name__" on Python 3.11, with the
    interrupt as its cause. Such an error is the interrupt, not an internal error.
    """
    seen: set[int] = set()
    link: BaseException | None = exc
    while link is not None and id(link) not in seen:
        if isinstance(link, KeyboardInterrupt):
            return True
        seen.add(id(link))
        link = link.__cause__ or link.__context__
    return False


@contextlib.contextmanager
def emergency_cleanup(action: Callable[[], None]) -> Iterator[None]:
    """Run ``action`` if the process is ended by the watcher while this block runs."""
    _CLEANUPS.append(action)
    try:
        yield
    finally:
        with contextlib.suppress(ValueError):
            _CLEANUPS.remove(action)


def _compiling(frame: FrameType | None) -> bool:
    """Whether ``frame`` is inside numba or llvmlite (compiling): an exception raised there
    is caught and turned into another error, or lost."""
    roots = tuple(
        os.path.dirname(m.__file__)
        for m in (sys.modules.get("numba"), sys.modules.get("llvmlite"))
        if m is not None and m.__file__
    )
    while roots and frame is not None:
        if frame.f_code.co_filename.startswith(roots):
            return True
        frame = frame.f_back
    return False


def _on_sigint(signum: int, frame: FrameType | None) -> None:
    if _compiling(frame):
        return  # the watcher ends the process once the grace period has passed
    _TAKEN.set()  # the main thread runs: the interrupt unwinds the work
    raise KeyboardInterrupt


def _unraisable(args: object) -> None:
    """An interrupt raised where Python ignores exceptions (a garbage-collector callback, a
    finaliser) is lost, and the work would run on: deliver it again, to be taken once that
    context has returned. Any other ignored exception goes to the previous hook."""
    if getattr(args, "exc_type", None) is KeyboardInterrupt:
        # Sent again from another thread a moment later: raised here, in the hook, it would be
        # handled and ignored at once, inside the same context.
        _TAKEN.clear()
        threading.Timer(REDELIVER, os.kill, (os.getpid(), signal.SIGINT)).start()
        return
    _PREVIOUS_HOOK[0](args)  # type: ignore[arg-type]


_PREVIOUS_HOOK = [sys.unraisablehook]


def _watcher(fd: int) -> None:
    while True:
        try:
            data = os.read(fd, 64)
        except OSError:
            return
        if (signal.SIGINT in data or signal.SIGTERM in data) and not _TAKEN.wait(GRACE):
            for action in list(_CLEANUPS):
                with contextlib.suppress(Exception):
                    action()
            interrupted()


def watch() -> None:
    """Take SIGINT, and SIGTERM alike, with a handler that marks it taken, and start the
    watcher (main thread, before any work)."""
    read, write = os.pipe()
    os.set_blocking(write, False)
    signal.set_wakeup_fd(write, warn_on_full_buffer=False)
    signal.signal(signal.SIGINT, _on_sigint)
    signal.signal(signal.SIGTERM, _on_sigint)  # a termination is answered as an interrupt
    _PREVIOUS_HOOK[0] = sys.unraisablehook
    sys.unraisablehook = _unraisable
    threading.Thread(target=_watcher, args=(read,), name="tumble-sigint", daemon=True).start()
