"""Shared test settings, and a heartbeat on the terminal during long tests."""

from __future__ import annotations

import sys
import threading
import time

import pytest
from hypothesis import HealthCheck, settings

# Integration inside properties is slower than hypothesis' default 200 ms deadline.
settings.register_profile("tumble", deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("tumble")

HEARTBEAT_S = 4.0
"""On a terminal, a line naming the longest-running test once no test has ended for this long
[s]: pytest's dots stop while both workers are in long tests, which can take tens of seconds."""


class _Heartbeat:
    """Which tests run now (as the controller hears of them) and when the last one ended."""

    def __init__(self, config: pytest.Config) -> None:
        self.config = config
        self.running: dict[str, float] = {}
        self.begun = self.last = time.monotonic()
        self.collecting = True  # until the first test starts
        self.lock = threading.Lock()
        self.done = threading.Event()
        threading.Thread(target=self._beat, name="test heartbeat", daemon=True).start()

    def started(self, nodeid: str) -> None:
        with self.lock:
            self.running[nodeid] = time.monotonic()
            self.collecting = False

    def finished(self, nodeid: str) -> None:
        with self.lock:
            self.running.pop(nodeid, None)
            self.last = time.monotonic()

    def _beat(self) -> None:
        while not self.done.wait(0.5):
            with self.lock:
                now = time.monotonic()
                if now - self.last < HEARTBEAT_S or not (self.running or self.collecting):
                    continue
                if self.running:
                    nodeid, since = min(self.running.items(), key=lambda item: item[1])
                    line = f"  … {nodeid} running for {now - since:.0f} s"
                else:
                    waited = now - self.begun
                    line = f"  … starting the workers and collecting the tests ({waited:.0f} s)"
                self.last = now
            reporter = self.config.pluginmanager.get_plugin("terminalreporter")
            if reporter is not None:
                reporter.write_line(line)


def pytest_configure(config: pytest.Config) -> None:
    if hasattr(config, "workerinput") or not sys.stdout.isatty():
        return  # an xdist worker reports to the controller; a pipe or a log file needs no beat
    config.stash[_KEY] = _Heartbeat(config)


def pytest_unconfigure(config: pytest.Config) -> None:
    beat = config.stash.get(_KEY, None)
    if beat is not None:
        beat.done.set()


def pytest_runtest_logstart(nodeid: str, location: object) -> None:
    beat = _CONFIG[0].stash.get(_KEY, None) if _CONFIG else None
    if beat is not None:
        beat.started(nodeid)


def pytest_runtest_logfinish(nodeid: str, location: object) -> None:
    beat = _CONFIG[0].stash.get(_KEY, None) if _CONFIG else None
    if beat is not None:
        beat.finished(nodeid)


@pytest.hookimpl(tryfirst=True)
def pytest_sessionstart(session: pytest.Session) -> None:
    _CONFIG[:] = [session.config]


_KEY = pytest.StashKey[_Heartbeat]()
_CONFIG: list[pytest.Config] = []
