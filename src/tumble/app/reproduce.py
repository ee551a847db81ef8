"""Reproduce the papers: run every claim, write the report. The library behind
``tumble reproduce``.

Usable from a notebook::

    from tumble.app.reproduce import reproduce
    result = reproduce(["rotating_field"], "out/reproduce")
    [(r.id, r.verdict) for r in result.runs]
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
from tumble.analysis.claims.base import PAPERS, Claim
from tumble.errors import ParameterError, TumbleWarning
from tumble.io.fileset import output_set
from tumble.io.report import ClaimRun, claims_json, claims_markdown, report_html
from tumble.plot.claims import claim_png

__all__ = ["PAPER_NAMES", "ReproduceResult", "check_claim", "reproduce"]

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


def _papers(papers: Sequence[str]) -> list[str]:
    chosen = list(PAPER_NAMES) if not papers or "all" in papers else list(dict.fromkeys(papers))
    for p in chosen:
        if p not in PAPERS:
            raise ParameterError(
                f"paper {p!r} is not reproduced (allowed: {', '.join(PAPER_NAMES)}, all)"
            )
    return chosen


def check_claim(paper: str, check: Callable[[], Claim]) -> ClaimRun:
    """Run one claim's check and draw its figure; an exception becomes the run's ``error``.

    tumble's validity warnings are silenced: a claim that enters a region where averaging
    loses accuracy does so on purpose and says so in its own measurement.
    """
    cid = check.__name__.replace("_", "-")
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", TumbleWarning)
            claim = check()
        png = claim_png(claim.figure)
    except Exception as exc:  # a broken check is reported in the report, never hidden
        where = traceback.extract_tb(exc.__traceback__)[-1]
        error = f"{type(exc).__name__}: {exc} (at {Path(where.filename).name}:{where.lineno})"
        return ClaimRun(cid, paper, None, b"", time.perf_counter() - start, error)
    return ClaimRun(claim.id, paper, claim, png, time.perf_counter() - start)


def reproduce(
    papers: Sequence[str],
    out_dir: str | Path,
    *,
    progress: Callable[[int, int, str], None] | None = None,
    overwrite: bool = False,
) -> ReproduceResult:
    """Check every claim of the chosen papers and write the report to ``out_dir``.

    Writes ``report.html`` (self-contained: figures embedded, opens offline),
    ``claims.json`` (every claim's verdict, measured figure, time and figure file) and
    ``figures/<id>.png`` and ``manifest.json``, as one set once every claim has run (the
    directory is checked first: :func:`tumble.io.fileset.output_set`).

    Parameters
    ----------
    papers : sequence of str
        Model names from :data:`PAPER_NAMES`, or ``"all"`` (also the default when empty).
    out_dir : str or Path
        Output directory (created if needed).
    progress : callable, optional
        ``progress(done, total, claim_id)`` after each claim.
    overwrite : bool
        Replace the directory's contents even when they are another run's results.

    Returns
    -------
    ReproduceResult
    """
    chosen = _papers(papers)
    with output_set(
        out_dir, command="reproduce", scenario=" ".join(chosen), overwrite=overwrite
    ) as out:
        start = time.perf_counter()
        checks = [(p, c) for p in chosen for c in CLAIMS[p]]
        runs = []
        for i, (paper, check) in enumerate(checks):
            runs.append(check_claim(paper, check))
            if progress is not None:
                progress(i + 1, len(checks), runs[-1].id)
        wall = time.perf_counter() - start
        files = {f"figures/{r.id}.png": r.png for r in runs if r.png}
        files["claims.json"] = claims_json(runs, chosen, wall).encode()
        files["claims.md"] = claims_markdown(json.loads(files["claims.json"])).encode()
        files["report.html"] = report_html(runs, chosen, wall).encode()
        return ReproduceResult(runs, out.commit(files), wall)
