"""A guard for user code that never returns, and for Ctrl-C while compiled code runs.

A scenario's torque function runs inside tumble's integrations: a Python one from Python, a
numba one inside the compiled integrator, which holds no lock Python could use to stop it.
A function that never returns (a loop that does not end) would hang the run for good. While a
run with user code goes on, a watcher thread follows two heartbeats: the calls of the user's
Python torques (:data:`tumble.torques.PYTHON_CALLS`) and of its compiled ones (their fault
records count them, :func:`tumble.kernels.user.calls`). The integrators call a torque at every
evaluation of the right-hand side, thousands of times a second; if neither heartbeat moves for
``run.user_code_timeout`` seconds while a user call or a compiled run is in progress, the
function did not return:

* in a Python function, the watcher raises :class:`UserCodeTimeout` in the main thread, inside
  the function: the run ends as on any fault of the user's code (one line, exit 2);
* in compiled code, which no exception reaches, it prints that line itself and ends the
  process (exit 2); the outputs of the run are not written. This is the ensembles' case
  (:mod:`tumble.integrate.ensemble`): a single run calls its compiled code in a thread of its
  own and is stopped from outside it, its outputs kept
  (:meth:`tumble.integrate.dop853.Integration.advance`).

Ctrl-C is deferred while a compiled call runs (its results would otherwise be half-built), so
it would not stop a compiled function that never returns: the watcher also hears SIGINT (by
the wakeup file descriptor of :func:`signal.set_wakeup_fd`, written by the C handler even
while the main thread is busy) and, if the compiled call has not returned a second later,
ends the process with the usual "interrupted" line (exit 130).
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import signal
import socket
import sys
import threading
import time
from collections.abc import Iterator, Sequence

from tumble.errors import UserCodeError, UserCodeTimeout
from tumble.integrate.limits import user_code_timeout
from tumble.torques import PYTHON_CALLS

__all__ = ["UserCodeTimeout", "user_code_guard"]
_POLL_S = 0.1  # how often the watcher looks [s]
_INTERRUPT_GRACE_S = 1.0  # a deferred Ctrl-C's wait for the compiled call to return [s]


def _compiled_calls() -> float:
    """The compiled user torques' heartbeat (0 where none is loaded)."""
    user = sys.modules.get("tumble.kernels.user")
    return 0.0 if user is None else float(user.calls())


def _compiled_running() -> bool:
    """Whether a compiled run is in progress (not compiling)."""
    driver = sys.modules.get("tumble.integrate.dop853.driver")
    return driver is not None and driver.IN_CALL[0] > 0


def _stop(line: str, code: int) -> None:
    """Print ``line`` on stderr and end the process at once with ``code``."""
    try:
        sys.stderr.write(line + "\n")
        sys.stderr.flush()
    finally:
        os._exit(code)


class _Watcher(threading.Thread):
    """The watcher thread of :func:`user_code_guard`."""

    def __init__(self, timeout_s: float, names: Sequence[str], wakeup: socket.socket | None):
        super().__init__(name="tumble-user-code-guard", daemon=True)
        self.timeout_s, self.names, self.wakeup = timeout_s, names, wakeup
        self.main = threading.main_thread().ident
        self.done = threading.Event()

    def _said(self) -> str:
        return UserCodeTimeout.said(self.names, self.timeout_s)

    def _interrupt_heard(self) -> bool:
        """Whether SIGINT arrived since the last look (read from the wakeup socket)."""
        if self.wakeup is None:
            return False
        try:
            data = self.wakeup.recv(64)
        except (BlockingIOError, OSError):
            return False
        return signal.SIGINT in data or signal.SIGTERM in data

    def run(self) -> None:
        beats = (PYTHON_CALLS[0], _compiled_calls())
        since = time.monotonic()
        interrupted_at = 0.0
        raised = False
        while not self.done.wait(_POLL_S):
            now = time.monotonic()
            if self._interrupt_heard():
                interrupted_at = now
            if interrupted_at and _compiled_running() and now - interrupted_at > _INTERRUPT_GRACE_S:
                _stop("interrupted", 130)
            if not _compiled_running():
                interrupted_at = 0.0  # Python handles it, as always
            seen = (PYTHON_CALLS[0], _compiled_calls())
            busy = PYTHON_CALLS[1] > 0 or _compiled_running()
            if seen != beats or not busy:
                beats, since, raised = seen, now, False
                continue
            if now - since < self.timeout_s:
                continue
            if PYTHON_CALLS[1] > 0 and not raised and self.main is not None:
                # Inside a Python function: raise there, as any fault of the user's code.
                UserCodeTimeout.message = self._said()
                ctypes.pythonapi.PyThreadState_SetAsyncExc(
                    ctypes.c_ulong(self.main), ctypes.py_object(UserCodeTimeout)
                )
                since, raised = now, True
                continue
            _stop(f"error: {self._said()}", UserCodeError.exit_code)


@contextlib.contextmanager
def user_code_guard(timeout_s: float, names: Sequence[str] = ()) -> Iterator[None]:
    """Watch the user's code for the block (module notes): a function that does not return
    within ``timeout_s`` seconds stops the run, and Ctrl-C stops a compiled call that does
    not return. ``names`` name the user's functions, for the message. From the main thread
    only (elsewhere, nothing is watched)."""
    if threading.current_thread() is not threading.main_thread():
        with user_code_timeout(timeout_s):
            yield
        return
    reader: socket.socket | None = None
    writer: socket.socket | None = None
    previous = -1
    try:
        reader, writer = socket.socketpair()
        reader.setblocking(False)
        writer.setblocking(False)
        previous = signal.set_wakeup_fd(writer.fileno(), warn_on_full_buffer=False)
    except (OSError, ValueError):  # no wakeup fd here: the timeout guard alone
        for end in (reader, writer):
            if end is not None:
                end.close()
        reader = writer = None
    watcher = _Watcher(timeout_s, names, reader)
    watcher.start()
    try:
        with user_code_timeout(timeout_s):
            yield
    finally:
        watcher.done.set()
        watcher.join()
        if writer is not None:
            signal.set_wakeup_fd(previous)
            writer.close()
        if reader is not None:
            reader.close()
