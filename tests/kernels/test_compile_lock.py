"""One process at a time compiles a function: the others wait, then load it from the cache
(:func:`tumble.kernels.jit.compile_lock`)."""

import subprocess
import sys
import textwrap
import time
import uuid

import pytest

from tumble.kernels.jit import compile_lock

pytest.importorskip("fcntl")  # the lock is POSIX's; elsewhere every process compiles alone

# A process that takes the lock, says so, holds it for a while (or until killed), and exits.
HOLDER = textwrap.dedent(
    """
    import sys, time
    from tumble.kernels.jit import compile_lock
    with compile_lock(sys.argv[1]):
        print("held", flush=True)
        time.sleep(float(sys.argv[2]))
    """
)


def _holder(name: str, seconds: float) -> subprocess.Popen[str]:
    proc = subprocess.Popen([sys.executable, "-c", HOLDER, name, str(seconds)],
                            stdout=subprocess.PIPE, text=True)  # fmt: skip
    assert proc.stdout is not None and proc.stdout.readline().strip() == "held"
    return proc


def test_a_second_process_waits_for_the_first():
    name = f"test-{uuid.uuid4().hex}"
    holder = _holder(name, 1.0)
    start = time.monotonic()
    with compile_lock(name):
        waited = time.monotonic() - start
    holder.wait(timeout=30)
    # The holder sleeps 1 s after saying it holds the lock; this process can have it only
    # after that (less the holder's start-up, already past), and well before the 600 s bound.
    assert 0.5 < waited < 30.0, waited


def test_a_killed_holder_releases_the_lock():
    name = f"test-{uuid.uuid4().hex}"
    holder = _holder(name, 600.0)
    holder.kill()  # a run interrupted while it compiles
    holder.wait(timeout=30)
    start = time.monotonic()
    with compile_lock(name):
        waited = time.monotonic() - start
    assert waited < 5.0, waited  # the lock went with the process (a poll is 0.05 s)


def test_the_same_thread_may_enter_again_and_other_names_do_not_wait():
    name = f"test-{uuid.uuid4().hex}"
    holder = _holder(f"{name}-other", 600.0)
    try:
        start = time.monotonic()
        with compile_lock(name), compile_lock(name), compile_lock(f"{name}-third"):
            pass
        assert time.monotonic() - start < 5.0  # no wait on itself, nor on another name
    finally:
        holder.kill()
        holder.wait(timeout=30)
