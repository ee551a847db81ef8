"""How tumble compiles: numba option sets, and a disk cache that notices edits to any compiled
source.

numba's disk cache checks a function against the modification time and size of the file that
defines it, and of no other. A compiled function inlines its callees and freezes the module
constants it reads (the tableau, the torque codes), so an edit to a callee's file would leave
the caller's cached machine code stale. :func:`jit` therefore stamps every cached function with
the stamps of *all* the files compiled code is built from (:data:`COMPILED_SOURCES`): an edit
to any of them recompiles everything once, and a test checks that every module using numba is
in that list.
"""

from __future__ import annotations

import hashlib
import os
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TypeVar

import numba

from tumble._progress import notice

__all__ = [
    "COMPILED_SOURCES",
    "ENTRY",
    "INLINE",
    "INNER",
    "INNER_INLINE",
    "KERNEL",
    "OVERLOAD",
    "compile_lock",
    "compile_notice",
    "jit",
    "set_compile_notifier",
    "source_stamp",
]

F = TypeVar("F", bound=Callable[..., Any])

_PACKAGE = Path(__file__).resolve().parents[1]

COMPILED_SOURCES: tuple[str, ...] = ("kernels", "integrate/dop853")
"""Files and folders, relative to the package, whose code or constants are compiled."""

# Reassociation and contraction (FMA) only: no "nnan"/"ninf", so the checks for non-finite
# states survive optimization.
_FAST = {"contract", "reassoc", "nsz", "arcp"}
# numpy's error model: a division by zero gives inf or NaN (caught as a non-finite state)
# instead of raising from compiled code, and compiles to less code.
_BASE: dict[str, Any] = {"cache": True, "fastmath": _FAST, "nogil": True, "error_model": "numpy"}

INNER: dict[str, Any] = {**_BASE, "no_cpython_wrapper": True, "no_cfunc_wrapper": True}
"""Helpers only compiled code calls: no Python wrapper to build (a large part of the cost of
compiling a small function)."""
ENTRY: dict[str, Any] = {**_BASE, "no_cfunc_wrapper": True}
"""Functions Python calls (the integrator's entry points, kernels evaluated from Python)."""
INNER_INLINE: dict[str, Any] = {**INNER, "forceinline": True}
"""Helpers of the integrator's loop that may allocate (grow a buffer), inlined into it."""
KERNEL: dict[str, Any] = {**INNER, "_nrt": False}
"""Helpers that allocate nothing: without reference counting, calls to them cost less."""
INLINE: dict[str, Any] = {**KERNEL, "forceinline": True}
"""Small helpers LLVM must inline into the integrator's loops (alwaysinline): the right-hand
side's dispatch on the kind then folds away in a specialisation on one kind."""
OVERLOAD: dict[str, Any] = {
    k: v for k, v in INLINE.items() if k not in ("cache", "no_cpython_wrapper", "no_cfunc_wrapper")
}
"""The options of a compiled overload (numba caches it within its callers)."""


def source_stamp() -> tuple[tuple[str, int, int], ...]:
    """(path, mtime in ns, size) of every file in :data:`COMPILED_SOURCES`, sorted."""
    files: list[Path] = []
    for entry in COMPILED_SOURCES:
        path = _PACKAGE / entry
        files += sorted(path.rglob("*.py")) if path.is_dir() else [path]
    stamps = []
    for f in files:
        st = f.stat()
        stamps.append((f.relative_to(_PACKAGE).as_posix(), st.st_mtime_ns, st.st_size))
    return tuple(stamps)


_STAMP = source_stamp()


def jit(options: dict[str, Any]) -> Callable[[F], F]:
    """``numba.njit(**options)`` whose disk cache is stamped with :func:`source_stamp`."""

    def decorate(func: F) -> F:
        dispatcher = numba.njit(**options)(func)
        cache_file = getattr(getattr(dispatcher, "_cache", None), "_cache_file", None)
        # numba keeps the stamp it compares with the index on disk here; replacing it makes an
        # edit to any compiled source invalidate this function's cached code too. (Without the
        # attribute, on a numba that stores it elsewhere, the per-file stamp stays in force; a
        # test pins the attribute.)
        if cache_file is not None and hasattr(cache_file, "_source_stamp"):
            cache_file._source_stamp = (cache_file._source_stamp, _STAMP)
        return dispatcher  # type: ignore[no-any-return]

    return decorate


NOTICE_AFTER_S = 1.0
"""A compile is announced once it has run this long [s]: a load from the disk cache takes less
(every kind of the benchmark together in 0.43 s)."""


def _to_terminal(message: str) -> None:
    """The default notifier: one line on stderr, and only when it is a terminal (a pipe or a
    log file gets nothing)."""
    if notice(message):  # a progress display is shown: the notice is its stage
        return
    stream = sys.stderr
    if stream is not None and stream.isatty():
        print(message, file=stream, flush=True)


_notify: Callable[[str], None] = _to_terminal


def set_compile_notifier(notify: Callable[[str], None] | None) -> None:
    """Where the compile notice goes: ``notify(message)``, or nowhere (None); the default
    writes to stderr when it is a terminal."""
    global _notify
    _notify = notify if notify is not None else (lambda message: None)


@contextmanager
def compile_notice(estimate_s: float) -> Iterator[None]:
    """Around a call that may compile what takes about ``estimate_s`` [s] to compile: if it
    lasts more than :data:`NOTICE_AFTER_S`, the notifier hears "compiling tumble's kernels
    (first run only, about N s)" while it runs."""
    message = f"compiling tumble's kernels (first run only, about {estimate_s:.0f} s) …"

    timer = threading.Timer(NOTICE_AFTER_S, _notify, (message,))
    timer.daemon = True
    timer.start()
    try:
        yield
    finally:
        timer.cancel()


COMPILE_WAIT_S = 600.0
"""Longest wait for another process's compile of the same function [s]; then this process
compiles it too (a compile from an empty cache takes at most about a minute)."""

_LOCK_POLL_S = 0.05
_HELD = threading.local()  # .names: the locks this thread holds


def _lock_path(name: str) -> str:
    """A lock file for ``name``, private to this user, this installation and its numba cache
    (a temporary directory is writable where the package's own may not be)."""
    where = f"{_PACKAGE}|{getattr(numba.config, 'CACHE_DIR', '')}|{sys.version_info[:2]}"
    digest = hashlib.sha256(f"{where}|{name}".encode()).hexdigest()[:24]
    uid = os.getuid() if hasattr(os, "getuid") else 0
    return os.path.join(tempfile.gettempdir(), f"tumble-compile-{uid}-{digest}.lock")


@contextmanager
def compile_lock(name: str) -> Iterator[None]:
    """Around the compilation of the function ``name``: one process of this machine compiles
    it at a time, so that the others, started together (a Dask cluster's workers, the test
    suite's), load it from the disk cache instead of compiling it again, each for up to a
    minute.

    An advisory lock (``fcntl.flock``) on a file per name, released when its holder finishes or
    dies; waited for up to :data:`COMPILE_WAIT_S`, then not at all. Where there is no
    ``fcntl`` (Windows) or no lock file can be made, every process compiles on its own, as
    numba alone does. Re-entered by the same thread (a compile that compiles another locked
    function), it does not lock again; another thread waits as another process does.
    """
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not on POSIX
        yield
        return
    held: set[str] = _HELD.__dict__.setdefault("names", set())
    if name in held:
        yield
        return
    try:
        handle = os.open(_lock_path(name), os.O_RDWR | os.O_CREAT, 0o600)
    except OSError:
        yield
        return
    try:
        deadline = time.monotonic() + COMPILE_WAIT_S
        while True:
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
                locked = True
                break
            except BlockingIOError:
                if time.monotonic() > deadline:
                    locked = False
                    break
                time.sleep(_LOCK_POLL_S)
            except OSError:  # a file system without locks
                locked = False
                break
        held.add(name)
        try:
            yield
        finally:
            held.discard(name)
            if locked:
                fcntl.flock(handle, fcntl.LOCK_UN)
    finally:
        os.close(handle)
