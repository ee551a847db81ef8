"""Run a command and say that it is still working when it has printed nothing for a while.

    python3 tools/heartbeat.py LABEL -- COMMAND [ARG ...]

On a terminal the command runs on a pseudo-terminal of its own (its progress bars and colours
are kept), and after 4 s without a byte of output a line "… LABEL (N s)" is written, then every
4 s more of silence: pip prints nothing while it installs the wheels it has fetched, which
takes tens of seconds for numba, scipy and matplotlib. Off a terminal (CI, a log file) the
command simply runs. The exit status is the command's. Standard library only: the Makefile
runs it with the system's python3 before the virtual environment exists (and
benchmarks/first_hour.py times commands through :func:`on_pty`).
"""

from __future__ import annotations

import os
import pty
import select
import subprocess
import sys
import time
from collections.abc import Iterator

QUIET_S = 4.0


def on_pty(
    command: list[str], cwd: str | None = None, env: dict[str, str] | None = None
) -> Iterator[tuple[float, bytes]]:
    """Run ``command`` on a pseudo-terminal of its own and yield ``(time, chunk)`` for every
    chunk of its output as it arrives, and ``(time, b"")`` every half second without any;
    the generator's return value (``StopIteration.value``) is the exit status."""
    leader, follower = pty.openpty()
    proc = subprocess.Popen(command, cwd=cwd, env=env, stdin=follower, stdout=follower,
                            stderr=follower, close_fds=True)  # fmt: skip
    os.close(follower)
    try:
        while True:
            ready, _, _ = select.select([leader], [], [], 0.5)
            now = time.monotonic()
            if ready:
                try:
                    chunk = os.read(leader, 65536)
                except OSError:  # the terminal closed with the command
                    break
                if not chunk:
                    break
                yield now, chunk
            elif proc.poll() is not None:
                break
            else:
                yield now, b""
    finally:
        os.close(leader)
    return proc.wait()


def main() -> int:
    args = sys.argv[1:]
    if len(args) < 3 or args[1] != "--":
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    label, command = args[0], args[2:]
    if not sys.stdout.isatty():
        return subprocess.call(command)
    start = last = time.monotonic()
    out = sys.stdout.buffer
    at_line_start = True
    relay = on_pty(command)
    while True:
        try:
            now, chunk = next(relay)
        except StopIteration as done:
            return int(done.value)
        if chunk:
            out.write(chunk)
            out.flush()
            last, at_line_start = now, chunk.endswith(b"\n")
        elif now - last >= QUIET_S:
            start_line = b"" if at_line_start else b"\r\n"
            out.write(start_line + f"  … {label} ({now - start:.0f} s)\r\n".encode())
            out.flush()
            last, at_line_start = now, True


if __name__ == "__main__":
    sys.exit(main())
