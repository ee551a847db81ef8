"""An output directory written as one set: all of a run's files, or none of them.

A run's files are written into a temporary directory beside the target
(``.<name>.tumble-new-*``), with ``manifest.json`` last (the command, the scenario, its
inputs and every file's size and SHA-256), and the finished set then takes the target's place
by two renames: the old directory aside (``.<name>.tumble-old-*``), the new one in. A reader
therefore sees the previous set or the new one, never a mixture, and a rerun with fewer
methods leaves no file of the run before it. A run killed between the two renames leaves no
target but the old set aside: the next run into that directory puts it back before anything
else, then removes every temporary a killed run left.

The directory is checked before the computation (created, its parent writable; removed again
if the run ends, interrupted or failed, without writing into the directory it made), locked for
the run (``flock`` on the directory itself; a second run into it is refused while the first
holds it), and a directory holding another run's results, or files tumble did not write, is
replaced only when the caller says so (``overwrite``, the command line's ``--overwrite``).
Only the standard library is used, so that this module loads in milliseconds.
"""

from __future__ import annotations

import contextlib
import datetime
import functools
import glob
import hashlib
import json
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from tumble._interrupt import emergency_cleanup
from tumble._version import __version__
from tumble.errors import OutputError, shorten

try:  # POSIX; elsewhere the directory is checked but not locked
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None  # type: ignore[assignment]

__all__ = ["MANIFEST", "OutputSet", "atomic_write", "output_set", "read_manifest"]

MANIFEST = "manifest.json"
"""The file naming a set's command, scenario, inputs and files (written last)."""

_NEW, _OLD = ".tumble-new-", ".tumble-old-"
_IGNORED = {".tumble.lock"}  # left in a directory by tumble before sets were written whole


def atomic_write(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file and ``os.replace``."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        # mkstemp creates 0600; give the file the permissions a plain open() would.
        umask = os.umask(0)
        os.umask(umask)
        os.fchmod(fd, 0o666 & ~umask)
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def read_manifest(out_dir: str | Path) -> dict[str, Any] | None:
    """The manifest of the set in ``out_dir``; None when there is none or it is unreadable."""
    try:
        doc = json.loads((Path(out_dir) / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return doc if isinstance(doc, dict) else None


def _temporaries(out: Path, kind: str) -> list[Path]:
    """The temporaries of ``kind`` (new or old) that runs into ``out`` left, newest first."""
    found = list(out.parent.glob(glob.escape(f".{out.name}{kind}") + "*"))
    return sorted(found, key=lambda p: p.lstat().st_mtime, reverse=True)


def _remove(path: Path) -> None:
    if path.is_symlink() or not path.is_dir():
        path.unlink(missing_ok=True)
    else:
        shutil.rmtree(path, ignore_errors=True)


def _abandon(staging: Path, out: Path, created: bool = False) -> None:
    """Drop an unfinished set: its temporary directory, the previous set put back, and the
    directory itself when this run ``created`` it and wrote nothing there."""
    _remove(staging)
    _restore(out)
    if created:
        _drop_if_empty(out)


def _drop_if_empty(out: Path) -> None:
    """Remove the directory ``out`` if it is empty (a run that made it and wrote nothing)."""
    with contextlib.suppress(OSError):
        out.rmdir()  # refused (OSError) when anything is in it


def _restore(out: Path) -> None:
    """Put back the previous set when a run was killed between its two renames."""
    if out.exists() or out.is_symlink():
        return
    aside = _temporaries(out, _OLD)
    if aside:
        with contextlib.suppress(OSError):
            os.rename(aside[0], out)


def _refuse_dangerous(out: Path) -> None:
    """Never replace the working directory, a directory above it, the home directory or /."""
    target = out.resolve()
    here = Path.cwd().resolve()
    if target == here or target in here.parents or target == Path.home().resolve():
        raise OutputError(
            f"-o {shorten(str(out))}: will not replace the current, home or a parent "
            "directory; name a directory of its own (e.g. out/run1)"
        )
    if os.path.ismount(target):  # replaced by a rename, which a mount point refuses (EBUSY)
        raise OutputError(
            f"-o {shorten(str(out))}: is a mount point, which tumble cannot replace as one set; "
            f"name a directory inside it (e.g. {shorten(str(out))}/run1)"
        )


_LEGACY = {"summary.json": "run", "verify.json": "verify", "claims.json": "reproduce"}


def _legacy(out: Path) -> dict[str, Any] | None:
    """What a directory written by tumble before its outputs had a manifest is the result of,
    read from its summary (None: not such a directory)."""
    for name, command in _LEGACY.items():
        try:
            doc = json.loads((out / name).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        if isinstance(doc, dict) and "tumble_version" in doc:
            papers = doc.get("papers")
            scenario = " ".join(papers) if isinstance(papers, dict) else doc.get("scenario")
            return {"command": command, "scenario": scenario}
    return None


def _same_scenario(recorded: Any, scenario: str) -> bool:
    """The same scenario: the same text, or paths to the same file."""
    if recorded == scenario:
        return True
    try:
        return isinstance(recorded, str) and os.path.samefile(recorded, scenario)
    except OSError:  # not a file (a scenario built in memory, a file since removed)
        return False


def _check_owner(out: Path, identity: dict[str, Any], overwrite: bool) -> None:
    """Refuse to replace another run's results or files tumble did not write, unless asked."""
    if overwrite:
        return
    manifest = read_manifest(out) or _legacy(out)
    if manifest is not None:
        same = manifest.get("command") == identity["command"] and _same_scenario(
            manifest.get("scenario"), identity["scenario"]
        )
        if same:
            return
        raise OutputError(
            f"-o {shorten(str(out))}: holds the results of `tumble {manifest.get('command')}` "
            f"for {shorten(str(manifest.get('scenario')), 60)}; choose another directory, or "
            "pass --overwrite to replace them"
        )
    others = sorted(p.name for p in out.iterdir() if p.name not in _IGNORED)
    if others:
        raise OutputError(
            f"-o {shorten(str(out))}: holds files tumble did not write as a set "
            f"({shorten(', '.join(others[:3]), 60)}); choose an empty or new directory, or pass "
            "--overwrite to replace its contents"
        )


class OutputSet:
    """A held output directory: :meth:`commit` puts a whole set of files in its place."""

    def __init__(self, target: Path, staging: Path, identity: dict[str, Any]) -> None:
        self.target = target
        self._staging = staging
        self._identity = identity
        self.committed: list[Path] = []

    def commit(self, files: dict[str, bytes]) -> list[Path]:
        """Write ``files`` (name, which may contain ``/``, → content) and the manifest, then
        make them the directory's contents as one set; return the paths written."""
        if self.committed:
            raise RuntimeError("an output set is committed once")
        listing = {}
        for name, data in files.items():
            path = self._staging / name
            path.parent.mkdir(parents=True, exist_ok=True)
            with open(path, "wb") as fh:
                fh.write(data)
                fh.flush()
                os.fsync(fh.fileno())
            listing[name] = {"bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()}
        manifest = {
            "tumble_version": __version__,
            **self._identity,
            "written": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
            "files": listing,
        }
        text = json.dumps(manifest, indent=2, ensure_ascii=False, default=str) + "\n"
        with open(self._staging / MANIFEST, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        aside = self._staging.with_name(self._staging.name.replace(_NEW, _OLD))
        os.rename(self.target, aside)
        os.rename(self._staging, self.target)
        _sync_directory(self.target.parent)
        _remove(aside)
        self.committed = [self.target / name for name in files]
        return self.committed


def _sync_directory(path: Path) -> None:
    with contextlib.suppress(OSError):  # not every file system syncs directories
        fd = os.open(path, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def _lock(out: Path) -> int:
    """An open descriptor of ``out`` holding an exclusive lock on it (refused if held)."""
    fd = os.open(out, os.O_RDONLY)
    if fcntl is None:  # pragma: no cover - Windows
        return fd
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        raise OutputError(
            f"-o {shorten(str(out))}: another tumble run is writing there; wait for it or "
            "choose another directory"
        ) from None
    return fd


@contextlib.contextmanager
def output_set(
    out_dir: str | Path,
    *,
    command: str,
    scenario: str,
    inputs: Any = None,
    overwrite: bool = False,
) -> Iterator[OutputSet]:
    """Hold ``out_dir`` for one run, from before its computation to its last file.

    Parameters
    ----------
    out_dir : str or Path
        The target directory (created if needed; a symbolic link there is replaced, not
        followed).
    command, scenario : str
        What the set is the result of (``run``, ``verify``, ``reproduce``; the scenario's
        source). A rerun of the same command and scenario replaces the set; a directory holding
        anything else is refused unless ``overwrite``.
    inputs : JSON-able, optional
        The run's inputs, recorded in the manifest.
    overwrite : bool
        Replace whatever the directory holds.

    Yields
    ------
    OutputSet
        Call its ``commit(files)`` once the results are rendered; leaving the block without
        a commit (an error, Ctrl-C) leaves the directory as it was.

    Raises
    ------
    OutputError
        The directory cannot take the results, is held by another run, or holds other
        results (one line, exit code 2), before anything is computed.
    """
    out = Path(os.path.abspath(out_dir))
    _refuse_dangerous(out)
    if (out.exists() or out.is_symlink()) and not out.is_dir():
        raise OutputError(f"-o {shorten(str(out_dir))}: exists and is not a directory")
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        _restore(out)
        created = not out.exists()
        if created:
            out.mkdir()
        fd = _lock(out)
    except OSError as exc:
        raise OutputError(
            f"-o {shorten(str(out_dir))}: cannot write there ({exc.strerror})"
        ) from None
    staging = None
    try:
        for stale in (*_temporaries(out, _NEW), *_temporaries(out, _OLD)):
            _remove(stale)  # a killed run's: live runs into ``out`` hold the lock
        identity = {"command": command, "scenario": scenario, "inputs": inputs}
        _check_owner(out, identity, overwrite)
        try:
            staging = Path(tempfile.mkdtemp(dir=out.parent, prefix=f".{out.name}{_NEW}"))
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(staging, 0o777 & ~umask)  # mkdtemp makes 0700; a plain mkdir would not
        except OSError as exc:
            raise OutputError(
                f"-o {shorten(str(out_dir))}: cannot write beside it ({exc.strerror})"
            ) from None
        held = OutputSet(out, staging, identity)
        with emergency_cleanup(functools.partial(_abandon, staging, out, created)):
            yield held
    finally:
        if staging is not None and staging.exists():
            _remove(staging)
        _restore(out)  # an interrupt between the commit's two renames: the previous set back
        os.close(fd)
        if created:  # nothing committed into the directory this run made: no empty one left
            _drop_if_empty(out)
