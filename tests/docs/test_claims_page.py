"""The documentation's claims page is a full run's `claims.md` (`tumble reproduce all`), and it
lists exactly the claims the code declares, with their current titles and theory references:
a claim added, renamed or re-referenced without running the report again fails here."""

from __future__ import annotations

from pathlib import Path

from tumble.analysis.claims import CLAIMS  # noqa: F401  (importing registers every claim)
from tumble.analysis.claims.base import DECLARED

PAGE = Path(__file__).resolve().parents[2] / "docs" / "claims.md"


def _rows() -> dict[str, list[str]]:
    rows = {}
    for line in PAGE.read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip("|").split(" | ")]
        if line.startswith("| ") and cells[0] in DECLARED:
            rows[cells[0]] = cells
    return rows


def test_the_page_lists_every_declared_claim_as_declared():
    rows = _rows()
    assert set(rows) == set(DECLARED), "docs/claims.md is stale: copy a new run's claims.md"
    for cid, (_paper, title, theory) in DECLARED.items():
        cells = rows[cid]
        assert cells[1] == " ".join(title.split()).replace("|", "\\|"), cid
        assert cells[4] == " ".join(theory.split()).replace("|", "\\|"), cid
        assert cells[2].strip("*") in ("confirmed", "qualified", "refuted"), cid
