"""The documentation's figures: what draws each one, and the gallery page that shows them.

    .venv/bin/python docs/figures.py                 # redraw every figure, rewrite gallery.md
    .venv/bin/python docs/figures.py NAME [NAME ...] # redraw only these (file names)
    .venv/bin/python docs/figures.py --gallery       # rewrite gallery.md only

Every figure under ``docs/figures/`` is drawn by tumble itself from a scenario in
``examples/`` (or a benchmark script), never by hand; ``FIGURES`` lists the commands. The
commands run in a scratch directory from the repository root, and the figure they write is
copied into ``docs/figures/``. The gallery page is generated from the same list, and a test
holds ``docs/gallery.md`` equal to ``gallery()`` and every file of ``docs/figures/`` to an
entry here.

The tutorials are MyST pages, not sphinx-gallery scripts: tumble's examples are TOML scenarios
run by the command line, so the figure a reader sees is the one ``tumble run`` writes, drawn
by this script from the very command the tutorial shows, and the docs build runs no
simulation (it stays within CI's time).
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent


@dataclass(frozen=True)
class Figure:
    """One figure of the documentation.

    Attributes
    ----------
    name : str
        File name under ``docs/figures/``.
    title, caption : str
        The gallery's heading and one-sentence description.
    page : str
        The documentation page (relative to ``docs/``, without suffix) that explains it.
    commands : tuple of str
        Shell commands, run from the repository root with ``OUT`` set to a scratch directory.
    output : str
        The file the commands write, relative to ``OUT``.
    """

    name: str
    title: str
    caption: str
    page: str
    commands: tuple[str, ...]
    output: str


TUMBLE = ".venv/bin/tumble"
PYTHON = ".venv/bin/python"

FIGURES: tuple[Figure, ...] = (
    Figure(
        "comparison_a3_negative.png",
        "A fast gyroscope in a resisting medium",
        "Full, averaged and closed-form k and ϑ: the axis turns over, the spin slows and recovers.",
        "tutorials/resisting-medium",
        (f"{TUMBLE} run examples/a3_negative.toml -o $OUT",),
        "comparison.png",
    ),
    Figure(
        "evolution_rf_transient_x1.png",
        "A triaxial conductor in a rotating magnetic field",
        "L, ρ, T, k² and the fast frequencies, full against averaged, through the separatrix.",
        "tutorials/rotating-field",
        (f"{TUMBLE} run examples/rf_transient_x1.toml -o $OUT",),
        "evolution.png",
    ),
    Figure(
        "stability_map_inertia.png",
        "Stability of the co-rotation",
        "Verdict and leading Re λ of the stationary rotation over the body's inertia ratios.",
        "tutorials/rotating-field",
        (f"{TUMBLE} stability-map -o $OUT/map.png",),
        "map.png",
    ),
    Figure(
        "capsule_envelope.png",
        "An entry capsule's nutation envelope",
        "Dynamic pressure and the θmax envelope along a ballistic descent, full against averaged.",
        "tutorials/nonlinear-moment",
        (f"{PYTHON} benchmarks/capsule.py --figure $OUT/capsule.png",),
        "capsule.png",
    ),
    Figure(
        "ob_envisat_spin.png",
        "How fast will this object spin next year?",
        "A large defunct satellite's spin period, rate and axis over a year, averaged.",
        "tutorials/orbiting-body",
        (f"{TUMBLE} run examples/ob_envisat_like.toml -o $OUT",),
        "spin.png",
    ),
    Figure(
        "ob_rocket_spin.png",
        "A rocket body's year",
        "A spent upper stage (two equal moments) tumbling at 10 °/s: its year, averaged.",
        "tutorials/orbiting-body",
        (f"{TUMBLE} run examples/ob_rocket_body.toml -o $OUT",),
        "spin.png",
    ),
    Figure(
        "ob_small_box_capture.png",
        "Through the floor to capture",
        "A 4 kg box spun down by eddy currents and captured by the gravity gradient: full "
        "against hybrid.",
        "tutorials/orbiting-body",
        (f"{TUMBLE} run examples/ob_small_box.toml -o $OUT",),
        "spin.png",
    ),
    Figure(
        "ob_geo_decade_spin.png",
        "A dead GEO satellite over ten years",
        "A GOES-class box-wing tumbling under sunlight, the gravity gradient and a one-year "
        "damper: ten years of spin period, rate and axis, averaged, in two seconds.",
        "tutorials/dead-geo-satellite",
        (f"{TUMBLE} run examples/ob_geo_decade.toml -o $OUT",),
        "spin.png",
    ),
    Figure(
        "ob_envisat_monte_carlo.png",
        "A year ahead, with uncertainty",
        "200 averaged years of the same satellite: the spin period's median and bands.",
        "tutorials/orbiting-body",
        (f"{TUMBLE} sweep examples/sweeps/ob_envisat_monte_carlo.toml -o $OUT",),
        "sweep.png",
    ),
    Figure(
        "tb_bdot_evolution.png",
        "Your own torque: B-dot detumbling",
        "A user torque from a Python file, averaged numerically over the Euler–Poinsot motion.",
        "tutorials/own-torque",
        (f"{TUMBLE} run examples/tb_bdot.toml -o $OUT",),
        "evolution.png",
    ),
    Figure(
        "verify_bdot.png",
        "Is the averaged model right here?",
        "tumble verify: the averaging error against ε and its measured order.",
        "tutorials/own-torque",
        (f"{TUMBLE} verify examples/tb_bdot.toml -o $OUT",),
        "verify.png",
    ),
    Figure(
        "sweep_rf_beta_eps.png",
        "A parameter sweep on a Dask cluster",
        "Final state, averaging error, stability and wall time over a β × ε grid.",
        "guide/sweeps",
        (f"{TUMBLE} sweep examples/sweeps/rf_beta_eps.toml -o $OUT",),
        "sweep.png",
    ),
    Figure(
        "second_order_errors.png",
        "Second-order averaging",
        "The averaging error against ε at orders 1 and 2 for the three papers' settings.",
        "second-order-averaging",
        (
            f"{PYTHON} benchmarks/second_order.py --from benchmarks/second_order.json"
            " --figure $OUT/second_order.png",
        ),
        "second_order.png",
    ),
    Figure(
        "reproduce_report.png",
        "The papers' claims, checked",
        "The top of the report `tumble reproduce all` writes, as Chromium shows it.",
        "guide/reproduce",
        (
            f"{TUMBLE} reproduce all -o $OUT/reproduce",
            "chromium --headless --no-sandbox --disable-gpu --hide-scrollbars"
            " --user-data-dir=$OUT/chromium --window-size=1400,1000"
            " --screenshot=$OUT/report.png file://$OUT/reproduce/report.html",
        ),
        "report.png",
    ),
    Figure(
        "kernels.svg",
        "Declared terms, kinds and layouts",
        "A term module, the registry generated from it, the kinds and a model package.",
        "architecture",
        (),
        "",
    ),
    Figure(
        "layers.svg",
        "The layers of tumble",
        "Its parts top to bottom; imports point down only (the import-linter contract).",
        "architecture",
        (),
        "",
    ),
)


def draw(figure: Figure) -> None:
    """Run ``figure.commands`` in a scratch directory and copy the result into ``docs/figures``."""
    if not figure.commands:
        print(f"{figure.name}: drawn by hand, kept")
        return
    with tempfile.TemporaryDirectory() as out:
        for command in figure.commands:
            print(f"{figure.name}: {command}")
            subprocess.run(command, shell=True, check=True, cwd=ROOT, env=_env(out))
        shutil.copyfile(Path(out) / figure.output, DOCS / "figures" / figure.name)


def _env(out: str) -> dict[str, str]:
    import os

    return {**os.environ, "OUT": out, "MPLBACKEND": "Agg"}


def gallery() -> str:
    """The text of ``docs/gallery.md``: every figure with its caption, command and page."""
    lines = [
        "# Gallery",
        "",
        "Every figure in this documentation, drawn by tumble from a scenario in `examples/` or a",
        "benchmark script, with the command that draws it (`OUT` is any output directory) and the",
        "page that explains it. `python docs/figures.py` draws them all again.",
        "",
    ]
    for f in FIGURES:
        lines += [f"## {f.title}", "", f"![{f.caption}](figures/{f.name})", "", f.caption]
        if f.commands:
            lines += ["", "```bash", *(c.replace(".venv/bin/", "") for c in f.commands), "```"]
        lines += ["", f"Explained in [{_title(f.page)}]({f.page}.md).", ""]
    return "\n".join(lines)


def _title(page: str) -> str:
    """The first heading of ``docs/<page>.md``."""
    text = (DOCS / f"{page}.md").read_text(encoding="utf-8")
    return next(line[2:].strip() for line in text.splitlines() if line.startswith("# "))


def main(argv: list[str]) -> None:
    """Redraw the named figures (all without names) and rewrite the gallery page."""
    if argv != ["--gallery"]:
        chosen = [f for f in FIGURES if not argv or f.name in argv]
        unknown = set(argv) - {f.name for f in FIGURES}
        if unknown:
            sys.exit(f"docs/figures.py: unknown figure(s) {sorted(unknown)}")
        for f in chosen:
            draw(f)
    (DOCS / "gallery.md").write_text(gallery(), encoding="utf-8")


if __name__ == "__main__":
    main(sys.argv[1:])
