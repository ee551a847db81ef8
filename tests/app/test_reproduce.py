"""tumble reproduce: the report, claims.json, the CLI; and, as a slow study, every
claim of the three papers with the report opened in headless Chromium."""

import json
import re
import shutil
import subprocess
import time

import numpy as np
import pytest
from typer.testing import CliRunner

import tumble.app.reproduce as rep
from tumble.analysis.claims import CLAIMS
from tumble.analysis.claims.base import (
    CONFIRMED,
    DECLARED,
    REFUTED,
    VERDICTS,
    Claim,
    FigureSpec,
    Panel,
    Series,
    verdict,
)
from tumble.cli import app

runner = CliRunner()


def _fake(cid, holds):
    def check():
        x = np.linspace(0.0, 1.0, 11)
        fig = FigureSpec((Panel((Series(x, x**2, "x²"),), xlabel="x", ylabel="y"),))
        measured = {
            "value": 1e-12,
            "units": "rad",
            "what": "error",
            "threshold": 1e-9,
            "criterion": "≤ threshold",
            "details": {"theory_consistent": holds},
        }
        return Claim(cid, "rotating_field", f"title {cid}", "statement", "§1",
                     verdict(holds, False), measured, fig, name=f"name_{cid[3:]}")  # fmt: skip

    check.__name__ = cid.replace("-", "_")
    return check


def _broken():
    raise ZeroDivisionError("a deliberately broken check")


_broken.__name__ = "rf_3"


@pytest.fixture
def fake_claims(monkeypatch):
    claims = {**CLAIMS, "rotating_field": (_fake("rf-1", True), _fake("rf-2", False), _broken)}
    monkeypatch.setattr(rep, "CLAIMS", claims)
    return claims


def test_reproduce_writes_a_self_contained_report(fake_claims, tmp_path):
    result = rep.reproduce(["rotating_field"], tmp_path)
    assert [r.verdict for r in result.runs] == [CONFIRMED, REFUTED, "error"]
    assert "ZeroDivisionError: a deliberately broken check" in result.errors[0].error
    doc = json.loads((tmp_path / "claims.json").read_text())
    assert doc["counts"] == {**dict.fromkeys(VERDICTS, 0), CONFIRMED: 1, REFUTED: 1, "error": 1}
    first = doc["claims"][0]
    assert first["measured"]["value"] == 1e-12 and first["figure"] == "figures/rf-1.png"
    assert (tmp_path / "figures" / "rf-1.png").read_bytes()[:4] == b"\x89PNG"
    page = (tmp_path / "report.html").read_text()
    # Self-contained: no file or network reference; every figure is a data URI.
    assert not re.search(r'(src|href)="(?!data:|#)', page)
    assert page.count('<img class="figure"') == 2 == page.count('src="data:image/png;base64,')
    assert "a deliberately broken check" in page
    # rf-2's measurement contradicts its layout too: the page says so outside the details.
    assert page.count("contradicts the theory page's own statement") == 1


def test_cli_reproduce_table_and_exit_codes(fake_claims, tmp_path):
    res = runner.invoke(app, ["reproduce", "rotating_field", "-o", str(tmp_path)])
    assert res.exit_code == 1  # a check that could not run
    assert "rf-1" in res.stdout and "refuted" in res.stdout
    bad = runner.invoke(app, ["reproduce", "gyroscope", "-o", str(tmp_path / "x")])
    assert bad.exit_code == 2
    # One line that lists what is allowed: the papers, and every claim by name and id.
    assert bad.stderr.count("\n") == 1
    assert (
        "'gyroscope' is neither a paper nor a claim (allowed: all, resisting_medium" in bad.stderr
    )
    assert f"{DECLARED['rf-6'].name} (rf-6)" in bad.stderr
    assert not (tmp_path / "x").exists()


def test_a_claim_is_selected_by_its_name_or_its_id(fake_claims):
    by_name = rep.select_claims([DECLARED["rf-2"].name])
    assert (
        by_name
        == rep.select_claims(["rf-2"])
        == [("rotating_field", fake_claims["rotating_field"][1])]
    )
    # Mixed with papers: each claim once, the papers in the order first named.
    mixed = rep.select_claims(["rf-3", "rm-2", "rotating_field", DECLARED["rf-1"].name])
    assert [c.__name__ for _, c in mixed] == ["rf_1", "rf_2", "rf_3", "rm_2"]
    assert rep.select_claims([]) == rep.select_claims(["nonlinear_moment", "all"])
    assert [p for p, _ in rep.select_claims([])] == [p for p, cs in fake_claims.items() for _ in cs]


def test_reproduce_one_claim_by_name_labels_it_with_its_id(fake_claims, tmp_path):
    result = rep.reproduce([DECLARED["rf-2"].name], tmp_path)
    assert [(r.name, r.id) for r in result.runs] == [("name_2", "rf-2")]
    doc = json.loads((tmp_path / "claims.json").read_text())
    assert [(c["name"], c["id"]) for c in doc["claims"]] == [("name_2", "rf-2")]
    assert "| `name_2` (rf-2) |" in (tmp_path / "claims.md").read_text()
    page = (tmp_path / "report.html").read_text()
    assert "<code>name_2</code> (rf-2)" in page
    assert "<code>tumble reproduce rf-2</code>" in page


def test_the_number_of_claims_is_known_before_the_first_runs(fake_claims, tmp_path):
    # The progress bar shows "0/3", not "0/?", while the first claim runs.
    calls = []
    rep.reproduce(["rotating_field"], tmp_path, progress=lambda *a: calls.append(a))
    assert calls[0] == (0, 3, "") and [c[:2] for c in calls[1:]] == [(1, 3), (2, 3), (3, 3)]


def test_registry_names_every_paper():
    assert list(CLAIMS) == list(rep.PAPER_NAMES)
    ids = [c.__name__ for p in CLAIMS.values() for c in p]
    assert len(ids) == len(set(ids)) and all(CLAIMS.values())


def test_every_claim_has_a_unique_snake_case_name():
    names = [c.name for c in DECLARED.values()]
    assert len(DECLARED) == sum(len(c) for c in CLAIMS.values())
    assert len(set(names)) == len(names)
    assert all(re.fullmatch(r"[a-z][a-z0-9]*(_[a-z0-9]+)+", n) for n in names), names
    # A name never shadows a paper or "all" (it could not be selected).
    assert not set(names) & {*rep.PAPER_NAMES, "all"}


CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",  # tests run as root in the sandbox
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",  # the machine's closed network refuses these
    "--disable-component-update",
    "--disable-sync",
]


def rendered_figures(page, profile):
    """Figures Chromium decoded in ``page``: the count its inline script writes."""
    chromium = shutil.which("chromium")
    assert chromium, "needs Debian's chromium package (apt-get install chromium)"
    done = subprocess.run(
        [chromium, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", "--virtual-time-budget=20000",
         "--dump-dom", page.as_uri()],
        capture_output=True, text=True, timeout=300, check=True,
    )  # fmt: skip
    found = re.search(r'data-figures-rendered="(\d+)"', done.stdout)
    assert found, "the page's script did not run"
    return int(found.group(1))


@pytest.mark.slow
def test_reproduce_all_renders_every_figure_in_chromium(tmp_path):
    start = time.perf_counter()
    result = rep.reproduce(["all"], tmp_path)
    seconds = time.perf_counter() - start
    assert not result.errors, [r.error for r in result.errors]
    # The budget for the README's main job on 2 cores, with a cold numba cache.
    assert seconds < 600
    page = tmp_path / "report.html"
    figures = page.read_text().count('<img class="figure"')
    assert figures == len(result.runs) == sum(len(c) for c in CLAIMS.values())
    assert rendered_figures(page, tmp_path / "profile") == figures
