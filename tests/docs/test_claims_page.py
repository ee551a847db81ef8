"""The documentation's claims page is a full run's `claims.md` (`tumble reproduce all`), and it
lists exactly the claims the code declares, with their current names, titles and theory
references: a claim added, renamed or re-referenced without running the report again fails
here."""

from __future__ import annotations

import re
from pathlib import Path

from tumble.analysis.claims import CLAIMS  # noqa: F401  (importing registers every claim)
from tumble.analysis.claims.base import DECLARED

PAGE = Path(__file__).resolve().parents[2] / "docs" / "claims.md"

# A row starts with the claim's name and, beside it, its id: "| `name` (rm-3) | …".
LABEL = re.compile(r"`(?P<name>[a-z0-9_]+)` \((?P<id>[a-z]+-[0-9]+)\)")


def _rows() -> dict[str, list[str]]:
    rows = {}
    for line in PAGE.read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip("|").split(" | ")]
        label = LABEL.fullmatch(cells[0]) if line.startswith("| ") else None
        if label and label["id"] in DECLARED:
            rows[label["id"]] = [label["name"], *cells[1:]]
    return rows


def test_the_page_lists_every_declared_claim_as_declared():
    rows = _rows()
    assert set(rows) == set(DECLARED), "docs/claims.md is stale: copy a new run's claims.md"
    for cid, declared in DECLARED.items():
        cells = rows[cid]
        assert cells[0] == declared.name, cid
        assert cells[1] == " ".join(declared.title.split()).replace("|", "\\|"), cid
        assert cells[4] == " ".join(declared.theory_ref.split()).replace("|", "\\|"), cid
        allowed = ("confirmed", "qualified", "refuted", "agrees", "explains qualitatively",
                   "does not agree")  # fmt: skip
        assert cells[2].strip("*") in allowed, cid
