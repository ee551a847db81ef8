"""Reproduce the papers: run every claim, write the report. The library behind
``tumble reproduce``.

Usable from a notebook::

    from tumble.app.reproduce import reproduce
    result = reproduce(["rotating_field"], "out/reproduce")
    [(r.name, r.id, r.verdict) for r in result.runs]

A claim is selected by its name (``rotation_about_middle_axis_is_unstable``) or by its id, the
name's short alias (``rf-6``); a paper by its model name; every claim by ``"all"``.
"""

from __future__ import annotations

import json
import time
import traceback
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from tumble.analysis.claims import CLAIMS
from tumble.analysis.claims.base import DECLARED, PAPERS, Claim, claim_id
from tumble.errors import ParameterError, TumbleWarning
from tumble.io.fileset import output_set
from tumble.io.report import ClaimRun, claims_json, claims_markdown, report_html
from tumble.plot.claims import claim_png

__all__ = ["PAPER_NAMES", "ReproduceResult", "check_claim", "reproduce", "select_claims"]

PAPER_NAMES = tuple(PAPERS)
"""The papers ``tumble reproduce`` knows, by model name, in report order."""


@dataclass(frozen=True)
class ReproduceResult:
    """What :func:`reproduce` did: every claim as run, the files written, the wall time [s]."""

    runs: list[ClaimRun]
    files: list[Path]
    wall_time: float

    @property
    def errors(self) -> list[ClaimRun]:
        """Claims whose check raised instead of giving a verdict."""
        return [r for r in self.runs if r.claim is None]


def _claim_id(check: Callable[[], Claim]) -> str:
    """The id of a registered check, known without running it (``rm_3`` → ``rm-3``)."""
    return check.__name__.replace("_", "-")


def _unknown(selector: str) -> ParameterError:
    claims = ", ".join(
        f"{c.name} ({c.id})" for p in PAPER_NAMES for c in DECLARED.values() if c.paper == p
    )
    return ParameterError(
        f"{selector!r} is neither a paper nor a claim (allowed: all, {', '.join(PAPER_NAMES)}, "
        f"or a claim's name or id: {claims})"
    )


def select_claims(selectors: Sequence[str]) -> list[tuple[str, Callable[[], Claim]]]:
    """The (paper, check) pairs that ``selectors`` choose, each once: the papers in the order
    first named (all of them in report order if ``"all"`` is one), each paper's claims in its
    own order.

    Parameters
    ----------
    selectors : sequence of str
        ``"all"`` (also when empty), model names from :data:`PAPER_NAMES`, and claims by name
        or by id (``rotation_about_middle_axis_is_unstable`` or ``rf-6``), mixed freely.

    Raises
    ------
    ParameterError
        For a selector that is none of these; the message lists what is allowed, in one line.
    """
    selectors = list(selectors) or ["all"]
    papers = dict.fromkeys(PAPER_NAMES if "all" in selectors else [])
    wanted: set[str] = set()
    for s in selectors:
        if s == "all" or s in PAPERS:
            chosen = PAPER_NAMES if s == "all" else (s,)
            wanted |= {_claim_id(c) for p in chosen for c in CLAIMS[p]}
            papers.update(dict.fromkeys(chosen))
            continue
        try:
            cid = claim_id(s)
        except ParameterError:
            raise _unknown(s) from None
        wanted.add(cid)
        papers.setdefault(DECLARED[cid].paper)
    return [(p, c) for p in papers for c in CLAIMS[p] if _claim_id(c) in wanted]


def _selection(checks: Sequence[tuple[str, Callable[[], Claim]]]) -> list[str]:
    """The selection as a command line would write it: a paper whose every claim was chosen
    by its model name, any other chosen claim by its id (for ``scenario`` and the report)."""
    words: list[str] = []
    for paper in dict.fromkeys(p for p, _ in checks):
        mine = [_claim_id(c) for p, c in checks if p == paper]
        whole = len(mine) == len(CLAIMS[paper])
        words += [paper] if whole else mine
    return words


def check_claim(paper: str, check: Callable[[], Claim]) -> ClaimRun:
    """Run one claim's check and draw its figure; an exception becomes the run's ``error``.

    tumble's validity warnings are silenced: a claim that enters a region where averaging
    loses accuracy does so on purpose and says so in its own measurement.
    """
    cid = _claim_id(check)
    name = DECLARED[cid].name if cid in DECLARED else ""
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", TumbleWarning)
            claim = check()
        png = claim_png(claim.figure)
    except Exception as exc:  # a broken check is reported in the report, never hidden
        where = traceback.extract_tb(exc.__traceback__)[-1]
        error = f"{type(exc).__name__}: {exc} (at {Path(where.filename).name}:{where.lineno})"
        return ClaimRun(cid, paper, None, b"", time.perf_counter() - start, error, name=name)
    return ClaimRun(claim.id, paper, claim, png, time.perf_counter() - start, name=claim.name)


def reproduce(
    papers: Sequence[str],
    out_dir: str | Path,
    *,
    progress: Callable[[int, int, str], None] | None = None,
    overwrite: bool = False,
) -> ReproduceResult:
    """Check the chosen claims (of the chosen papers) and write the report to ``out_dir``.

    Writes ``report.html`` (self-contained: figures embedded, opens offline),
    ``claims.json`` (every claim's verdict, measured figure, time and figure file) and
    ``figures/<id>.png`` and ``manifest.json``, as one set once every claim has run (the
    directory is checked first: :func:`tumble.io.fileset.output_set`).

    Parameters
    ----------
    papers : sequence of str
        Model names from :data:`PAPER_NAMES`, claims by name or by id, or ``"all"`` (also the
        default when empty); see :func:`select_claims`.
    out_dir : str or Path
        Output directory (created if needed).
    progress : callable, optional
        ``progress(done, total, claim_id)`` before the first claim (0, the total, "") and
        after each claim (the id, its short alias).
    overwrite : bool
        Replace the directory's contents even when they are another run's results.

    Returns
    -------
    ReproduceResult
    """
    checks = select_claims(papers)
    chosen = list(dict.fromkeys(p for p, _ in checks))
    selection = _selection(checks)
    with output_set(
        out_dir, command="reproduce", scenario=" ".join(selection), overwrite=overwrite
    ) as out:
        start = time.perf_counter()
        runs = []
        if progress is not None:  # the number of claims known before the first one runs
            progress(0, len(checks), "")
        for i, (paper, check) in enumerate(checks):
            runs.append(check_claim(paper, check))
            if progress is not None:
                progress(i + 1, len(checks), runs[-1].id)
        wall = time.perf_counter() - start
        files = {f"figures/{r.id}.png": r.png for r in runs if r.png}
        files["claims.json"] = claims_json(runs, chosen, wall).encode()
        files["claims.md"] = claims_markdown(json.loads(files["claims.json"])).encode()
        files["report.html"] = report_html(runs, chosen, wall, selection=selection).encode()
        return ReproduceResult(runs, out.commit(files), wall)
