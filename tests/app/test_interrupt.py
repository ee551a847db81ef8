"""Ctrl-C during a long compiled run: exit 130 with one line, no crash, nothing written.

The compiled integrator runs in chunks of steps with SIGINT held during each compiled call:
an interrupt that arrived while the call built its result used to crash the interpreter
(segmentation fault) in about half the tries.
"""

import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from files import EXAMPLES

TUMBLE = str(Path(sys.executable).with_name("tumble"))


def _long_run(tmp_path, samples=801, warm=True):
    """The gravity-gradient example over t = 1e6 (seconds of integration), written to
    ``long.toml``; with ``warm``, its kernels compiled first by a run to t = 1 (a fresh clone
    has no cache: the trials interrupt the integration, not numba's first compilation, which
    takes longer than their window)."""
    text = (EXAMPLES / "tb_gravity_gradient.toml").read_text()
    text = text.replace("t_end = 200.0", "t_end = 1e6")
    text = text.replace("samples = 801", f"samples = {samples}")
    assert "t_end = 1e6" in text  # the example's horizon as written there
    scenario = tmp_path / "long.toml"
    scenario.write_text(text)
    if warm:
        short = tmp_path / "warm.toml"
        short.write_text(text.replace("t_end = 1e6", "t_end = 1.0"))
        subprocess.run([TUMBLE, "run", str(short), "-o", str(tmp_path / "warm")], check=True,
                       capture_output=True)  # fmt: skip
    return scenario


def test_sigint_during_a_long_run_exits_cleanly(tmp_path):
    scenario = _long_run(tmp_path, samples=1001)
    rng = random.Random(7)  # seeded moments, each well inside the integration
    for trial in range(3):
        out = tmp_path / f"out{trial}"
        proc = subprocess.Popen(
            [TUMBLE, "run", str(scenario), "-o", str(out)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            # A library earlier in the test session may leave SIGINT ignored in this process,
            # and an ignored signal stays ignored in children: give tumble the terminal's default.
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        )
        # Start-up (imports, scenario) takes ~1.5 s; the full run takes far longer than 4 s.
        time.sleep(2.0 + 2.0 * rng.random())
        assert proc.poll() is None, proc.communicate()
        proc.send_signal(signal.SIGINT)
        _, stderr = proc.communicate(timeout=30)
        assert proc.returncode == 130, (proc.returncode, stderr)
        assert stderr.strip() == "interrupted", stderr
        # The directory (made and locked before the run, if start-up got that far) is gone
        # again: no output written, no empty directory left.
        assert not out.exists(), list(out.iterdir())
        assert not list(tmp_path.glob(f".{out.name}.tumble-*"))  # nor a temporary set


def test_sigterm_is_answered_as_an_interrupt(tmp_path):
    # A termination (a job scheduler's, a container's stop) ends the run as Ctrl-C does: one
    # line, exit 130, no temporaries, no empty directory.
    assert _sigterm_trials(tmp_path, (0.3, 3.0)) == [130, 130]  # starting up; integrating


@pytest.mark.slow
def test_twenty_sigterms_at_random_moments(tmp_path):
    # Seeded moments from the start-up to the integration (the run takes 7-9 s warm).
    rng = random.Random(36)
    codes = _sigterm_trials(tmp_path, tuple(rng.uniform(0.05, 4.0) for _ in range(20)))
    assert codes.count(130) >= 15, codes  # seeded: all but the one at 0.05 s


def _sigterm_trials(tmp_path, moments):
    """Exit codes of runs sent SIGTERM ``moments`` [s] after their start: each says
    "interrupted" and exits 130, or, terminated before Python has loaded tumble's handler (the
    first tens of milliseconds), dies of the signal (the shell's 143) having printed and made
    nothing; either way no temporaries and no directory are left."""
    scenario = _long_run(tmp_path)
    codes: list[int] = []
    for trial, moment in enumerate(moments):
        out = tmp_path / f"out{trial}"
        command = [TUMBLE, "run", str(scenario), "-o", str(out)]
        proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        time.sleep(moment)
        proc.send_signal(signal.SIGTERM)
        _, stderr = proc.communicate(timeout=30)
        outcome = (proc.returncode, stderr.strip())
        assert outcome in {(130, "interrupted"), (-signal.SIGTERM, "")}, (moment, stderr)
        assert not out.exists() and not list(tmp_path.glob(f".{out.name}.tumble-*"))
        codes.append(proc.returncode)
    return codes


def test_sigint_during_a_cold_compile_exits_cleanly(tmp_path):
    """From an empty numba cache the first seconds of a run compile kernels through LLVM, where
    Python cannot take a signal (and numba's compiler would swallow a KeyboardInterrupt): the
    watcher ends the run with the same line and code, and the output set's temporaries go."""
    scenario = _long_run(tmp_path, warm=False)  # each trial with an empty cache of its own
    for trial, moment in enumerate((1.5, 3.0, 4.5)):  # start-up, validation, compiling
        cache = tmp_path / f"cache{trial}"
        out = tmp_path / f"out{trial}"
        proc = subprocess.Popen(
            [TUMBLE, "run", str(scenario), "-o", str(out)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env={**os.environ, "NUMBA_CACHE_DIR": str(cache)},
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        )
        time.sleep(moment)
        proc.send_signal(signal.SIGINT)
        _, stderr = proc.communicate(timeout=60)
        assert (proc.returncode, stderr.strip()) == (130, "interrupted"), (moment, stderr)
        assert not out.exists(), list(out.iterdir())
        assert not list(tmp_path.glob(f".{out.name}.tumble-*"))


LOST_IN_GC = """
import gc, signal, sys, time
from tumble._interrupt import watch
watch()
fired = []
def callback(phase, info):
    if phase == "start" and not fired:
        fired.append(1)
        signal.raise_signal(signal.SIGINT)  # handled inside this callback: the raise is ignored
        sum(range(1000))
gc.callbacks.append(callback)
try:
    gc.collect()
    end = time.monotonic() + 2.0
    while time.monotonic() < end:
        sum(range(1000))
except KeyboardInterrupt:
    print("taken")
    sys.exit(0)
print("lost")
"""


def test_an_interrupt_inside_a_gc_callback_is_not_lost():
    # Python ignores an exception raised in a garbage-collector callback (Dask's GC diagnosis
    # installs one); the interrupt must reach the work once the callback returns.
    proc = subprocess.run([sys.executable, "-c", LOST_IN_GC], capture_output=True, text=True,
                          timeout=60)  # fmt: skip
    assert proc.stdout.strip() == "taken", (proc.stdout, proc.stderr)


WRAPPED = """
import sys
from tumble.cli import _guarded

class Field:
    def __set_name__(self, owner, name):
        raise KeyboardInterrupt  # as if Ctrl-C landed while pydantic built a model

def load():
    class Model:
        x = Field()

_guarded(load)
print("not interrupted")
"""


def test_an_interrupt_wrapped_in_another_error_is_an_interrupt():
    # Python 3.11 reports an exception raised in __set_name__ as a RuntimeError with the
    # interrupt as its cause; a Ctrl-C while a pydantic model's module loaded read as an
    # "internal error" with exit code 1.
    proc = subprocess.run([sys.executable, "-c", WRAPPED], capture_output=True, text=True,
                          timeout=60)  # fmt: skip
    assert (proc.returncode, proc.stderr.strip(), proc.stdout) == (130, "interrupted", "")


def test_from_interrupt_follows_causes_and_contexts():
    from tumble._interrupt import from_interrupt

    try:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt:
            raise ValueError("while unwinding") from None  # suppressed, but still the context
    except ValueError as exc:
        wrapped = exc
    assert from_interrupt(RuntimeError("wrapper").with_traceback(None)) is False
    outer = RuntimeError("outer")
    outer.__cause__ = wrapped
    assert from_interrupt(outer) and from_interrupt(wrapped)
    looped = RuntimeError("a")  # a cycle in the chain ends the walk
    looped.__context__ = RuntimeError("b")
    looped.__context__.__context__ = looped
    assert from_interrupt(looped) is False
