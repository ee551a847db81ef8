"""The report of ``tumble reproduce``: one self-contained HTML page and ``claims.json``.

The page embeds every figure as a PNG data URI and its style sheet inline, so it opens
offline, from any directory, and can be mailed as one file. A few lines of inline script
count the figures the browser actually decoded and write the count into the page (the
attribute ``data-figures-rendered`` of ``<body>`` and the footer), which is what the headless
browser test reads.
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import json
import platform
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from tumble._version import __version__
from tumble.analysis.claims.base import PAPERS, VERDICTS, Claim, plain

__all__ = ["ClaimRun", "claims_json", "claims_markdown", "measured_text", "report_html"]

_COLOURS = {
    "confirmed": "#1a7f37",
    "confirmed with qualification": "#9a6700",
    "refuted": "#cf222e",
    "agrees": "#1a7f37",
    "explains qualitatively": "#9a6700",
    "does not agree": "#cf222e",
    "error": "#6e7781",
}

_CSS = """
body { font: 15px/1.45 system-ui, -apple-system, "Segoe UI", sans-serif; margin: 0 auto;
       max-width: 1100px; padding: 1.2em 1.6em 3em; color: #1f2328; }
h1 { font-size: 1.6em; margin-bottom: .2em; } h2 { margin-top: 2em; border-bottom: 1px solid
#d0d7de; padding-bottom: .2em; } h3 { margin: 0 0 .3em; font-size: 1.1em; }
.meta { color: #59636e; font-size: .9em; }
table { border-collapse: collapse; margin: .8em 0; font-size: .92em; width: 100%; }
th, td { border: 1px solid #d0d7de; padding: .3em .5em; text-align: left; vertical-align: top; }
th { background: #f6f8fa; }
.badge { display: inline-block; padding: .05em .55em; border-radius: 1em; color: white;
         font-size: .85em; white-space: nowrap; }
.claim { border: 1px solid #d0d7de; border-radius: 6px; padding: .9em 1.1em; margin: 1.2em 0; }
.claim p { margin: .35em 0; } .label { color: #59636e; font-weight: 600; }
.claim img { max-width: 100%; height: auto; display: block; margin-top: .6em;
             border: 1px solid #eaeef2; }
pre { background: #f6f8fa; padding: .5em; overflow-x: auto; font-size: .85em; }
a { color: #0969da; text-decoration: none; }
footer { margin-top: 3em; color: #59636e; font-size: .85em; }
"""

# Counts the <img class="figure"> the browser decoded (complete with a natural width) once the
# page has loaded, and writes the count into the page for the reader and for the tests.
_SCRIPT = """
window.addEventListener("load", function () {
  var imgs = document.querySelectorAll("img.figure"), ok = 0;
  for (var i = 0; i < imgs.length; i++) {
    if (imgs[i].complete && imgs[i].naturalWidth > 0) { ok++; }
  }
  document.body.setAttribute("data-figures-rendered", String(ok));
  document.getElementById("rendered").textContent = ok + " of " + imgs.length;
});
"""


@dataclass(frozen=True)
class ClaimRun:
    """A claim as run: the claim (None if its check raised), its figure and its time.

    Attributes
    ----------
    id, paper : str
        The claim's id and model name (known even when the check failed).
    claim : Claim or None
    png : bytes
        The figure (empty when the check failed).
    seconds : float
        Wall time of the check [s].
    error : str
        Why the check could not run ("" when it ran).
    name : str
        The claim's name, which states it ("" when not declared); the id is its alias.
    """

    id: str
    paper: str
    claim: Claim | None
    png: bytes
    seconds: float
    error: str = ""
    name: str = ""

    @property
    def verdict(self) -> str:
        return "error" if self.claim is None else self.claim.verdict

    @property
    def label(self) -> str:
        """The name with the id beside it, ``name (id)``; the id alone if there is no name."""
        return f"{self.name} ({self.id})" if self.name else self.id


def _counts(runs: Sequence[ClaimRun]) -> dict[str, int]:
    return {v: sum(1 for r in runs if r.verdict == v) for v in (*VERDICTS, "error")}


def claims_json(runs: Sequence[ClaimRun], papers: Sequence[str], wall_time: float) -> str:
    """``claims.json``: every claim with its verdict, measured figure, time and figure file."""
    doc = {
        "tumble_version": __version__,
        "papers": {p: PAPERS[p] for p in papers},
        "wall_time_s": wall_time,
        "counts": _counts(runs),
        "claims": [
            {
                **(
                    r.claim.to_dict()
                    if r.claim is not None
                    else {"id": r.id, "name": r.name, "paper": r.paper}
                ),
                "verdict": r.verdict,
                "error": r.error,
                "seconds": r.seconds,
                "figure": f"figures/{r.id}.png" if r.png else "",
            }
            for r in runs
        ],
    }
    return json.dumps(plain(doc), indent=1, ensure_ascii=False) + "\n"


def claims_markdown(doc: Mapping[str, Any]) -> str:
    """``claims.md``: the claims table of a run, from its ``claims.json`` document — each
    claim, its verdict, the measured figure and the theory sections that qualify it, paper by
    paper (the documentation's claims page is one full run's)."""

    def cell(text: Any) -> str:
        return " ".join(str(text).split()).replace("|", "\\|")

    counts = ", ".join(f"{n} {v}" for v, n in doc["counts"].items() if n)
    lines = [
        "# The papers' claims, checked",
        "",
        f"Every claim of the three papers and every published observation of the set "
        f"`observations`, as `tumble reproduce all` checked them (tumble "
        f"{doc['tumble_version']}, {len(doc['claims'])} claims: {counts}; "
        f'{doc["wall_time_s"]:.0f} s). *qualified* is "confirmed with qualification": the '
        "claim holds in the form the theory page gives it. An observation agrees with tumble "
        "within the band its record states, is explained qualitatively (its form, its size "
        "within a wider factor), or does not agree. Each figure is measured against "
        "the criterion in `claims.json`; the report (`report.html`) draws every check. Each "
        "claim is listed by its name, with its id beside it as its alias; `tumble reproduce` "
        "selects a claim by either.",
    ]
    for paper, citation in doc["papers"].items():
        lines += ["", f"## {citation}", ""]
        lines += ["| name (id) | claim | verdict | measured | theory |", "|---|---|---|---|---|"]
        for c in doc["claims"]:
            if c.get("paper") != paper:
                continue
            verdict = c["verdict"].replace("confirmed with qualification", "qualified")
            if verdict in ("refuted", "does not agree"):
                verdict = f"**{verdict}**"
            m = c.get("measured", {})
            label = f"`{c['name']}` ({c['id']})" if c.get("name") else c["id"]
            lines.append(
                f"| {label} | {cell(c.get('title', ''))} | {verdict} | "
                f"{cell(measured_text(m)) if m else cell(c.get('error', ''))} | "
                f"{cell(c.get('theory_ref', ''))} |"
            )
    return "\n".join(lines) + "\n"


def _badge(verdict: str) -> str:
    colour = _COLOURS.get(verdict, "#6e7781")
    return f'<span class="badge" style="background:{colour}">{html.escape(verdict)}</span>'


def measured_text(measured: Mapping[str, Any]) -> str:
    """A claim's measured figure with its unit, as the report and the CLI print it."""
    value = measured.get("value")
    text = f"{value:.3g}" if isinstance(value, float) else str(value)
    units = str(measured.get("units", ""))
    # A dimensionless figure shows no unit ("1"), only what it is relative to, if anything.
    units = "" if units == "1" else units[2:] if units.startswith("1 (") else units
    return f"{text} {units}".strip()


def _label(r: ClaimRun) -> str:
    """The name in code type with the id beside it, as HTML."""
    e = html.escape
    return f"<code>{e(r.name)}</code> ({e(r.id)})" if r.name else e(r.id)


def _claim_section(r: ClaimRun) -> str:
    e = html.escape
    title = e(r.claim.title) if r.claim else ""
    head = f'<h3 id="{e(r.id)}">{_label(r)}: {title} {_badge(r.verdict)}</h3>'
    if r.claim is None:
        return (
            f'<div class="claim">{head}<p><span class="label">The check raised:</span> '
            f"<code>{e(r.error)}</code></p></div>"
        )
    c, m = r.claim, r.claim.measured
    rows = [
        ("Claim", e(c.statement)),
        ("Theory", e(c.theory_ref)),
        ("Measured", f"{e(str(m.get('what', '')))} = <b>{e(measured_text(m))}</b>"),
        ("Criterion", f"{e(str(m.get('criterion', '')))} (threshold {e(str(m.get('threshold')))})"),
    ]
    if m.get("qualification"):
        rows.append(("Qualification", e(str(m["qualification"]))))
    if isinstance(m.get("details"), Mapping) and m["details"].get("theory_consistent") is False:
        rows.append(
            (
                "Against the theory",
                "<b>the measurement also contradicts the theory page's own statement "
                "here</b> (figures under details)",
            )
        )
    body = "".join(f'<p><span class="label">{k}:</span> {v}</p>' for k, v in rows)
    details = ""
    if m.get("details"):
        text = json.dumps(m["details"], indent=1, ensure_ascii=False)
        details = f"<details><summary>details</summary><pre>{e(text)}</pre></details>"
    data = base64.b64encode(r.png).decode("ascii")
    img = f'<img class="figure" alt="figure of {e(r.label)}" src="data:image/png;base64,{data}">'
    time = f'<p class="meta">checked in {r.seconds:.2f} s</p>'
    return f'<div class="claim">{head}{body}{details}{img}{time}</div>'


def report_html(
    runs: Sequence[ClaimRun],
    papers: Sequence[str],
    wall_time: float,
    *,
    selection: Sequence[str] | None = None,
) -> str:
    """The self-contained HTML report of :func:`tumble.app.reproduce.reproduce`.

    Parameters
    ----------
    runs : sequence of ClaimRun
        The claims in report order.
    papers : sequence of str
        The model names reproduced.
    wall_time : float
        Seconds of the whole run [s].
    selection : sequence of str, optional
        The arguments of ``tumble reproduce`` that chose the claims (papers and claim ids), for
        the footer; ``papers`` when not given.
    """
    e = html.escape
    counts = _counts(runs)
    stamp = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    summary = ", ".join(f"{n} {v}" for v, n in counts.items() if n)
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        "<title>tumble reproduce: the claims of the papers, checked</title>",
        f"<style>{_CSS}</style><script>{_SCRIPT}</script></head>",
        '<body data-figures-rendered="0">',
        "<h1>The claims of the papers, checked</h1>",
        f'<p class="meta">tumble {e(__version__)} · {e(stamp)} · '
        f"{e(platform.python_implementation())} {e(platform.python_version())} · "
        f"{wall_time:.0f} s · {len(runs)} claims: {e(summary)}</p>",
        "<p>Each claim is stated as the paper makes it, with the section of tumble's theory "
        "page (docs/theory/) that states or corrects it. Its verdict is computed from the "
        "measured figure against the criterion shown: <i>confirmed</i> (holds as the paper "
        "states it), <i>confirmed with qualification</i> (holds in the form the theory page "
        "gives it), "
        "<i>refuted</i> (the measurement contradicts the paper). A published observation "
        "<i>agrees</i> (within the band its record states), is <i>explained qualitatively</i> "
        "(the observed form, its size within a wider factor) or <i>does not agree</i>.</p>",
    ]
    for paper in papers:
        mine = [r for r in runs if r.paper == paper]
        parts.append(f'<h2 id="{e(paper)}">{e(PAPERS[paper])}</h2>')
        parts.append(
            "<table><tr><th>name (id)</th><th>claim</th><th>verdict</th><th>measured</th></tr>"
            + "".join(
                f'<tr><td><a href="#{e(r.id)}">{_label(r)}</a></td>'
                f"<td>{e(r.claim.title if r.claim else r.error)}</td><td>{_badge(r.verdict)}</td>"
                f"<td>{e(measured_text(r.claim.measured)) if r.claim else ''}</td></tr>"
                for r in mine
            )
            + "</table>"
        )
        parts.extend(_claim_section(r) for r in mine)
    parts.append(
        f'<footer>Figures rendered by this browser: <span id="rendered">(script off)</span>. '
        f"Produced by <code>tumble reproduce {' '.join(e(p) for p in selection or papers)}"
        "</code>.</footer>"
    )
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"
