"""Check the built documentation site: ``python docs/check_site.py out/docs [--browser]``.

Without ``--browser`` (CI runs this after ``make docs``) it reads every HTML page and fails on

* a resource loaded from outside the site (a script, stylesheet, font, image or frame whose
  address is not relative, in a page or in a stylesheet of ``_static``);
* an image whose file is missing;
* mathematics left untypeset: ``$``, ``^{``, ``_{`` or a TeX command in the text of a page
  outside its equations, code and scripts;
* a page of a section without its section navigation (the left sidebar);
* an equation written as a code block on a theory page (a block without a language).

With ``--browser`` it also opens the pages in headless Chromium (Debian's ``chromium``) and
fails on an equation MathJax did not typeset or could not parse, and on any request that left
the site; it keeps a 1366 × 768 screenshot of one page of each kind in ``OUT/_check``.
Exit status 0 when every check passes, 1 with one line per failure otherwise.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import tempfile
from html.parser import HTMLParser
from pathlib import Path

# Pages with no section of their own (no section navigation is expected there).
TOP_LEVEL = {"index.html", "search.html", "genindex.html", "py-modindex.html"}
# One page of each kind, for the screenshots.
KINDS = [
    "index.html",
    "tutorials/orbiting-body.html",
    "theory/resisting-medium.html",
    "performance.html",
    "reference/cli.html",
    "scenario-keys.html",
]
CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",  # run as root in the sandbox
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",  # a closed network refuses these
    "--disable-component-update",
    "--disable-sync",
]
_EXTERNAL = re.compile(r"^(https?:)?//", re.IGNORECASE)
_UNTYPESET = re.compile(r"\$[^$\s][^$]*\$|\^\{|_\{|\\(frac|mathrm|mathbf|sqrt|langle|sum)\b")
_SKIPPED_TAGS = {"script", "style", "pre", "code", "kbd", "samp", "math", "mjx-container"}


class _Page(HTMLParser):
    """What the checks need of one page."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.resources: list[str] = []
        self.images: list[str] = []
        self.text: list[str] = []
        self.sidenav_links = 0
        self.plain_blocks = 0
        self.math = 0
        self._skip: list[str] = []
        self._in_sidenav = 0

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = {k: v or "" for k, v in attrs}
        classes = a.get("class", "").split()
        if tag in ("script", "img", "iframe", "source", "audio", "video") and a.get("src"):
            self.resources.append(a["src"])
        if tag == "img":
            self.images.append(a.get("src", ""))
        if tag == "link" and {"stylesheet", "preload", "icon", "modulepreload"} & set(
            a.get("rel", "").split()
        ):
            self.resources.append(a.get("href", ""))
        if "style" in a:
            self.resources += re.findall(r"url\(['\"]?([^'\")]+)", a["style"])
        if tag == "nav" and "bd-docs-nav" in classes:
            self._in_sidenav += 1
        if tag == "a" and self._in_sidenav:
            self.sidenav_links += 1
        if tag == "div" and {"highlight-default", "highlight-none", "highlight-text"} & set(
            classes
        ):
            self.plain_blocks += 1
        if "math" in classes:
            self.math += 1
        if tag in _SKIPPED_TAGS or "math" in classes:
            self._skip.append(tag)
        elif self._skip and tag == self._skip[-1]:
            self._skip.append(tag)

    def handle_endtag(self, tag: str) -> None:
        if self._skip and tag == self._skip[-1]:
            self._skip.pop()
        if tag == "nav" and self._in_sidenav:
            self._in_sidenav -= 1

    def handle_data(self, data: str) -> None:
        if not self._skip:
            self.text.append(data)


def static_failures(site: Path) -> list[str]:
    """Every failure of the checks that need no browser, one line each."""
    failures = []
    for css in sorted((site / "_static").rglob("*.css")):
        for url in re.findall(r"url\(\s*['\"]?([^'\")]+)", css.read_text(errors="replace")):
            if _EXTERNAL.match(url):
                failures.append(f"{css.relative_to(site)}: loads {url}")
    for path in sorted(site.rglob("*.html")):
        rel = path.relative_to(site).as_posix()
        if rel.startswith(("_static/", "_sources/", "_check/")):
            continue
        page = _Page()
        page.feed(path.read_text(errors="replace"))
        for url in page.resources:
            if _EXTERNAL.match(url):
                failures.append(f"{rel}: loads {url} from outside the site")
        for src in page.images:
            if src.startswith("data:"):
                continue
            if not (path.parent / src.split("#")[0].split("?")[0]).is_file():
                failures.append(f"{rel}: image {src} is missing")
        text = " ".join(page.text)
        for m in _UNTYPESET.finditer(text):
            failures.append(f"{rel}: untypeset mathematics {m.group(0)[:40]!r}")
        if rel not in TOP_LEVEL and page.sidenav_links == 0:
            failures.append(f"{rel}: no section navigation")
        if rel.startswith("theory/") and page.plain_blocks:
            failures.append(f"{rel}: {page.plain_blocks} code block(s) without a language")
    return failures


def _chromium(args: list[str], profile: Path) -> str:
    chromium = shutil.which("chromium")
    if chromium is None:
        sys.exit("check_site: the browser check needs Debian's chromium (apt-get install chromium)")
    done = subprocess.run(
        [chromium, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", *args],
        capture_output=True, text=True, timeout=120, check=True,
    )  # fmt: skip
    return done.stdout


def _hosts(net_log: Path) -> set[str]:
    """The hosts of every http(s) address in one of Chromium's network logs."""
    urls = re.findall(r'"url":"([^"]+)"', net_log.read_text(errors="replace"))
    return {m.group(1) for u in urls if (m := re.match(r"https?://([^/:?]+)", u))}


def browser_failures(site: Path, only: str = "") -> list[str]:
    """Every failure Chromium finds: untypeset or unparsed equations, requests off the site."""
    failures = []
    shots = site / "_check"
    shots.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        profile = Path(tmp) / "profile"
        pages = sorted(p for p in site.rglob("*.html") if "_static" not in p.parts)
        pages = [p for p in pages if "_sources" not in p.parts and "_check" not in p.parts]
        pages = [p for p in pages if p.relative_to(site).as_posix().startswith(only)]
        # Chromium's own services call home even with the flags above (update, time and account
        # checks): what it requests for an empty page is its own, not the site's.
        blank = Path(tmp) / "blank.html"
        blank.write_text("<!doctype html><title>blank</title>")
        log = Path(tmp) / "net.json"
        _chromium(["--virtual-time-budget=15000", f"--log-net-log={log}", "--dump-dom",
                   blank.as_uri()], profile)  # fmt: skip
        own = _hosts(log)
        for path in pages:
            rel = path.relative_to(site).as_posix()
            page = _Page()
            page.feed(path.read_text(errors="replace"))
            if not page.math and rel not in KINDS:
                continue
            log = Path(tmp) / "net.json"
            dom = _chromium(
                ["--virtual-time-budget=15000", f"--log-net-log={log}", "--dump-dom",
                 path.as_uri()],
                profile,
            )  # fmt: skip
            typeset = dom.count("<mjx-container")
            if typeset < page.math:
                failures.append(f"{rel}: {page.math - typeset} of {page.math} equations untypeset")
            if "<mjx-merror" in dom:
                failures.append(f"{rel}: MathJax could not parse an equation")
            for host in sorted(_hosts(log) - own):
                failures.append(f"{rel}: the browser made a request to {host}")
            if rel in KINDS:
                shot = shots / (rel.replace("/", "-").removesuffix(".html") + ".png")
                _chromium(
                    ["--virtual-time-budget=15000", "--window-size=1366,768", "--hide-scrollbars",
                     f"--screenshot={shot}", path.as_uri()],
                    profile,
                )  # fmt: skip
    return failures


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("site", type=Path, help="the built site, e.g. out/docs")
    parser.add_argument("--browser", action="store_true", help="also check in headless Chromium")
    parser.add_argument("--only", default="", help="browser check of the pages under this path")
    args = parser.parse_args()
    if not (args.site / "index.html").is_file():
        print(f"check_site: no built site at {args.site} (make docs builds it)", file=sys.stderr)
        return 2
    failures = static_failures(args.site)
    if args.browser:
        failures += browser_failures(args.site, args.only)
    for line in failures:
        print(line)
    summary = {"site": str(args.site), "failures": len(failures), "browser": args.browser}
    print(json.dumps(summary), file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
