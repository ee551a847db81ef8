"""A first compile is announced while it runs ("compiling tumble's kernels …"), on a terminal
only; a load from the disk cache is not."""

from __future__ import annotations

import io
import sys
import time

from tumble.kernels import jit


def test_a_long_compile_is_announced_while_it_runs(monkeypatch):
    heard: list[str] = []
    monkeypatch.setattr(jit, "NOTICE_AFTER_S", 0.05)
    monkeypatch.setattr(jit, "_notify", heard.append)
    with jit.compile_notice(12.4):
        time.sleep(0.5)  # ten times the threshold: the timer has fired before the end
        assert len(heard) == 1  # said during the compile, not after it
    assert heard[0] == "compiling tumble's kernels (first run only, about 12 s) …"


def test_a_load_from_the_cache_is_not(monkeypatch):
    heard: list[str] = []
    monkeypatch.setattr(jit, "_notify", heard.append)
    with jit.compile_notice(12.4):
        pass  # well under NOTICE_AFTER_S
    time.sleep(0.05)
    assert heard == []


class _Stream(io.StringIO):
    def __init__(self, tty: bool) -> None:
        super().__init__()
        self.tty = tty

    def isatty(self) -> bool:
        return self.tty


def test_the_default_notice_goes_to_a_terminal_only(monkeypatch):
    for tty in (True, False):
        stream = _Stream(tty)
        monkeypatch.setattr(sys, "stderr", stream)
        jit._to_terminal("compiling")
        assert stream.getvalue() == ("compiling\n" if tty else "")


def test_a_notifier_can_be_set_and_silenced(monkeypatch):
    heard: list[str] = []
    monkeypatch.setattr(jit, "NOTICE_AFTER_S", 0.01)
    monkeypatch.setattr(jit, "_notify", jit._notify)  # restored after the test
    jit.set_compile_notifier(heard.append)
    with jit.compile_notice(12.4):
        time.sleep(0.2)
    jit.set_compile_notifier(None)
    with jit.compile_notice(12.4):
        time.sleep(0.2)
    assert len(heard) == 1
