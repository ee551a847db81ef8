"""Command-line interface: ``tumble run | verify | models | init | stability | stability-map |
bench | sweep | reproduce``.

Commands only translate arguments: the work is done by library functions a notebook can call.
Bad input prints one red line to stderr and exits 2; a failed integration exits 3.

Messages, paths and anything else that echoes input are printed as written: rich reads no
markup in them (a message's ``[km]`` or ``[conductor]`` is a word, not a tag). Only the
labels and styles this module writes itself are markup.
"""

from __future__ import annotations

import collections
import contextlib
import inspect
import os
import re
import sys
import typing
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Annotated, Any, Literal

import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table
from rich.text import Text

from tumble.errors import TumbleError, TumbleWarning

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    help="tumble: slow evolution of rigid-body rotation under small torques.",
)
out = Console()
err = Console(stderr=True)


def _print_version(value: bool) -> None:
    if value:
        from tumble._version import __version__

        out.print(f"tumble {__version__}", highlight=False)
        raise typer.Exit(0)


@app.callback()
def _main(
    version: Annotated[
        bool,
        typer.Option(
            "--version", callback=_print_version, is_eager=True, help="print the version and exit"
        ),
    ] = False,
) -> None:
    """tumble: slow evolution of rigid-body rotation under small torques."""
    # The consoles read the terminal's settings (COLUMNS) when made: made again for every
    # command, so that a program that invokes several in one process (a notebook, the tests)
    # gets each one's.
    global out, err
    out, err = Console(), Console(stderr=True)


def _say(console: Console, text: str, label: str = "", style: str = "") -> None:
    """Print ``text`` exactly as written (no rich markup is read in it), after an optional
    ``label`` in ``style``: one line, however long."""
    line = Text.assemble((label, style), " ", text) if label else Text(text)
    console.print(line, highlight=False, soft_wrap=True)


def _shortened(message: str) -> str:
    """``message`` with every run of more than 120 characters without a space cut to 80: an
    error line never repeats a huge input (a path or a value of ordinary length is kept)."""
    return re.sub(r"\S{121,}", lambda m: m.group(0)[:77] + "...", message)


def _guarded(work: Callable[[], Any], interrupted: str = "interrupted") -> Any:
    """Run ``work``; turn tumble's errors into one red line and its exit code, and Ctrl-C into
    one line (``interrupted``) and exit 130."""
    try:
        return work()
    except KeyboardInterrupt:
        _interrupted(interrupted)
    except TumbleError as exc:
        _say(err, _shortened(str(exc)), "error:", "red")
        if exc.written is not None:  # what ran before the error, kept and marked
            ended = getattr(exc.partial, "ended_early", None) or {}
            upto = f" (t ≤ {ended['t']:.6g})" if "t" in ended else ""
            _say(
                err,
                f"what the run computed until then{upto} is written to {exc.written}, marked "
                "as ending early (summary.json: ended_early)",
            )
        raise typer.Exit(exc.exit_code) from None
    except Exception as exc:
        from tumble._interrupt import from_interrupt

        if from_interrupt(exc):  # an interrupt that a library wrapped in its own error
            _interrupted(interrupted)
        if os.environ.get("TUMBLE_DEBUG"):
            raise
        text = f"{type(exc).__name__}: {exc} (set TUMBLE_DEBUG=1 for a traceback)"
        _say(err, text, "internal error:", "red")
        raise typer.Exit(1) from None


ScenarioFile = Annotated[Path, typer.Argument(help="TOML scenario file", metavar="SCENARIO")]

Overwrite = Annotated[
    bool,
    typer.Option(
        "--overwrite",
        help="replace OUT even if it holds another run's results or files tumble did not write",
    ),
]

AllowModule = Annotated[
    list[str] | None,
    typer.Option(
        "--allow-module",
        metavar="MODULE",
        help="let the scenario name functions of this installed module (repeatable); by "
        "default a torque function is loaded only from a Python file beside the scenario",
    ),
]


Quiet = Annotated[
    bool,
    typer.Option(
        "-q", "--quiet", help="no progress display (shown only on a terminal, after 1 s of work)"
    ),
]

PROGRESS_AFTER_S = 1.0
"""The progress display appears once a command has worked this long [s]: a quick command
prints its results without it."""


@contextlib.contextmanager
def _working(quiet: bool, first: str) -> Iterator[None]:
    """A progress display on stderr while the command works: a spinner, the stage
    (``first``, then "averaged", "drawing the figure", the compile notice, …), how far an
    integration has got and the time spent. It appears after :data:`PROGRESS_AFTER_S`, on a
    terminal only, not with ``--quiet``, and is gone when the command prints its results."""
    if quiet or not err.is_terminal:
        yield
        return
    import threading

    from rich.progress import (
        BarColumn,
        Progress,
        SpinnerColumn,
        TaskProgressColumn,
        TextColumn,
        TimeElapsedColumn,
    )

    from tumble import _progress

    bar = Progress(
        SpinnerColumn(),
        TextColumn("{task.description}"),
        BarColumn(),
        TaskProgressColumn(),
        TimeElapsedColumn(),
        console=err,
        transient=True,
    )
    task = bar.add_task(first, total=None)
    lock = threading.Lock()
    ended = False

    def show(stage: str, fraction: float | None) -> None:
        if fraction is None:
            bar.update(task, description=stage, total=None, completed=0)
        else:
            bar.update(task, description=stage, total=1.0, completed=fraction)

    def start() -> None:
        with lock:
            if not ended:
                bar.start()

    def stop() -> None:
        nonlocal ended
        with lock:
            ended = True
            bar.stop()

    timer = threading.Timer(PROGRESS_AFTER_S, start)
    timer.daemon = True
    previous = _progress.set_display(show, stop)
    timer.start()
    try:
        yield
    finally:
        timer.cancel()
        stop()
        _progress.set_display(*previous)


def _consent(origins: tuple[str, ...]) -> None:
    """Name every file of user code a valid scenario runs, before the first is loaded."""
    for origin in origins:
        _say(err, f"runs user code from {origin}")


def _load(scenario: Path, allow_module: list[str] | None) -> Any:
    """The validated scenario. A file that cannot be read or is not TOML is reported before
    the models load (in a few tenths of a second); user code it names is loaded only once the
    whole scenario is valid, after a line naming each file."""
    from tumble.io.toml import read_file

    data = read_file(scenario)
    from tumble.io.scenario import parse_scenario

    return parse_scenario(data, str(scenario), allow_modules=allow_module or (), consent=_consent)


def _interrupted(message: str = "interrupted") -> None:
    """Exit 130 at once after Ctrl-C, with one line (:func:`tumble._interrupt.interrupted`)."""
    from tumble._interrupt import interrupted

    interrupted(message)


@app.command("run")
def run_cmd(
    scenario: ScenarioFile,
    out_dir: Annotated[
        Path | None,
        typer.Option("-o", "--out", help="output directory [default: out/SCENARIO-NAME]"),
    ] = None,
    allow_module: AllowModule = None,
    overwrite: Overwrite = False,
    aem: Annotated[
        bool,
        typer.Option(
            "--aem",
            help="also write the attitude as CCSDS messages: METHOD.aem (Attitude Ephemeris) "
            "and initial.apm (Attitude Parameter); needs an orbiting body in SI units (its "
            "orbit.epoch) and a full run",
        ),
    ] = False,
    quiet: Quiet = False,
) -> None:
    """Run a scenario: CSV per method, summary.json, a figure and manifest.json in OUT.

    OUT is checked before the computation and its contents replaced as one set once the run
    has succeeded; a directory holding another scenario's results is refused (--overwrite).

    A scenario that names a torque function (torque = "file:function") runs that code: it
    is loaded from the Python file beside the scenario, and tumble prints which.
    """
    with warnings.catch_warnings(record=True) as caught, _working(quiet, "reading the scenario"):
        warnings.simplefilter("always", TumbleWarning)
        sc = _guarded(lambda: _load(scenario, allow_module))
        from tumble.app.runner import run

        out_dir = out_dir or Path("out") / scenario.stem
        result = _guarded(lambda: run(sc, out_dir, overwrite=overwrite, aem=aem))
    from tumble.app.summary import run_lines, run_table
    from tumble.plot.settings import figure_settings

    _print_warnings(caught)

    model = result.request.model
    shown = figure_settings(model.name).variables
    out.print(run_table(result, shown, escape(f"{model.name} — {scenario}"), out.width))
    for line in run_lines(result, shown):
        _say(out, line)
    if result.verification is not None:
        _say(out, f"verify: {result.verification.verdict}")
    _say(out, f"outputs written to {out_dir}/")


def _print_warnings(caught: list[warnings.WarningMessage]) -> None:
    for w in caught:
        if issubclass(w.category, TumbleWarning):
            _say(err, str(w.message), "warning:", "yellow")


@app.command("verify")
def verify_cmd(
    scenario: ScenarioFile,
    out_dir: Annotated[
        Path | None,
        typer.Option("-o", "--out", help="output directory [default: out/SCENARIO-NAME_verify]"),
    ] = None,
    strict: Annotated[
        bool,
        typer.Option("--strict", help="exit 4 unless the verdict is first-order accurate or exact"),
    ] = False,
    allow_module: AllowModule = None,
    overwrite: Overwrite = False,
    quiet: Quiet = False,
) -> None:
    """Measure the averaging error: full and averaged at ε, ε/2, ε/4 over one slow horizon.

    Writes verify.csv, verify_curves.csv, verify.json and verify.png to OUT and prints the
    errors, the fitted orders and the verdict. A torque function the scenario names runs, as
    with run.
    """
    with warnings.catch_warnings(record=True) as caught, _working(quiet, "reading the scenario"):
        warnings.simplefilter("always", TumbleWarning)
        sc = _guarded(lambda: _load(scenario, allow_module))
        from tumble.app.runner import verify

        out_dir = out_dir or Path("out") / f"{scenario.stem}_verify"
        result = _guarded(lambda: verify(sc, out_dir, overwrite=overwrite))
    _print_warnings(caught)
    symbol = {"tau": "τ"}.get(result.time_name, result.time_name)
    horizon = "ε" + symbol if result.eps[0] > 0.0 else symbol
    table = Table(
        title=escape(
            f"verify {result.model} — {scenario} (horizon {horizon} = {result.horizon:.4g})"
        ),
        title_justify="left",
    )
    table.add_column("variable")
    for e in result.eps:
        table.add_column(f"max error, ε = {e:.4g}", justify="right")
    table.add_column("order", justify="right")
    for v in result.variables:
        order = result.orders[v]
        table.add_row(
            v,
            *(f"{x:.3e}" for x in result.errors[v]),
            "—" if result.eps[0] == 0.0 else "at tolerance" if order is None else f"{order:.2f}",
        )
    out.print(table)
    for e, run in zip(result.eps, result.issues, strict=True):
        for issue in run:
            _say(out, str(issue["message"]), f"ε = {e:.4g}:", "dim")
    colour = {"first-order": "green", "exact": "green", "degraded": "yellow", "invalid": "red"}[
        result.status
    ]
    out.print(Text(result.verdict, style=colour), highlight=False, soft_wrap=True)
    _say(out, f"outputs written to {out_dir}/")
    if strict and result.status not in ("first-order", "exact"):
        raise typer.Exit(4)


@app.command("models")
def models_cmd() -> None:
    """List the models, each with its paper."""
    from tumble.catalogue import CATALOGUE

    for name, rec in CATALOGUE.items():
        paper = ("", "") if rec.paper is None else (f"  ({rec.paper})", "dim")
        out.print(Text.assemble((name, "bold"), f": {rec.description}", paper), highlight=False)


@app.command("init")
def init_cmd(
    model: Annotated[str, typer.Argument(help="model name (see `tumble models`)")],
) -> None:
    """Print a commented example scenario for MODEL."""
    from tumble.io import template

    text = _guarded(lambda: template(model))
    sys.stdout.write(text)


def _beta_rad(beta: float, beta_deg: bool) -> float:
    """β from the command line: radians, or degrees with ``--beta-deg`` (checked in degrees)."""
    import math

    from tumble.errors import check_range

    if not beta_deg:
        return beta
    check_range("--beta", beta, low=0.0, high=180.0, low_open=False, high_open=False)
    return math.radians(beta)


def _complex(z: complex) -> str:
    return f"{z.real:+.10g} {'+' if z.imag >= 0 else '−'} {abs(z.imag):.10g}i"


@app.command("stability")
def stability_cmd(
    inertia: Annotated[
        tuple[float, float, float],
        typer.Option("--inertia", help="principal moments I1 I2 I3; the rotation is about x3"),
    ],
    beta: Annotated[float, typer.Option("--beta", help="field cone angle β [rad], in [0, π]")],
    eps: Annotated[float, typer.Option("--eps", help="ε = M0/ω > 0 [units of the moments]")],
    beta_deg: Annotated[bool, typer.Option("--beta-deg", help="β is in degrees")] = False,
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object")] = False,
) -> None:
    """Stability of the co-rotation about x3 in a rotating field, (2.5)/(2.6)
    (docs/theory/rotating-field.md §16)."""
    from tumble.analysis.stability import match_roots
    from tumble.analysis.stability_maps import co_rotation_stability

    p, rep, doc = _guarded(lambda: co_rotation_stability(inertia, _beta_rad(beta, beta_deg), eps))
    if as_json:
        import json

        sys.stdout.write(json.dumps(doc, ensure_ascii=False) + "\n")
        return

    out.print(
        f"[bold]{escape(rep.motion)}[/bold]: I = {tuple(p.inertia.tolist())}, "
        f"β = {p.beta:.6g} rad, ε = {p.eps:.6g}",
        highlight=False,
    )
    coeffs = Table(title="characteristic polynomial (2.5)", title_justify="left")
    for col in ("", "closed form (2.5)", "from the Jacobian"):
        coeffs.add_column(col, justify="right")
    for k, (a, b) in enumerate(zip(rep.coefficients, rep.coefficients_jacobian, strict=True)):
        coeffs.add_row(f"a{k}", f"{a:.15g}", f"{b:.15g}")
    out.print(coeffs)
    roots = Table(title="roots: exact (2.5) and first order (2.6)", title_justify="left")
    for col in ("exact λ", "(2.6)", "|difference|"):
        roots.add_column(col, justify="right", no_wrap=True)
    approx = rep.approx_roots
    order = None if approx is None else match_roots(rep.roots, approx)
    for i, z in enumerate(rep.roots):
        if order is None:
            roots.add_row(_complex(z), "", "")
        else:
            a = approx[order[i]]
            roots.add_row(_complex(z), _complex(a), f"{abs(z - a):.3g}")
    out.print(roots)
    colour = {"asymptotically stable": "green", "critical": "yellow", "unstable": "red"}
    out.print(
        f"[{colour[rep.classification]}]{rep.classification}[/]: max Re λ = {rep.max_real:.6g}",
        highlight=False,
    )
    for note in ([rep.approx_note] if rep.approx_note else []) + list(rep.notes):
        _say(out, note, "note:", "dim")


@app.command("stability-map")
def stability_map_cmd(
    output: Annotated[Path, typer.Option("-o", "--output", help="figure file (.png, .pdf, .svg)")],
    over: Annotated[
        Literal["inertia", "beta-eps"],
        typer.Option("--over", help="axes: I1/I3 × I2/I3, or β × ε at a fixed body"),
    ] = "inertia",
    inertia: Annotated[
        tuple[float, float, float] | None,
        typer.Option("--inertia", help="body of the beta-eps map (default 1 1.5 2)"),
    ] = None,
    beta: Annotated[
        float | None, typer.Option("--beta", help="β of the inertia map [rad] (default π/4)")
    ] = None,
    eps: Annotated[
        float | None, typer.Option("--eps", help="ε of the inertia map (default 0.05)")
    ] = None,
    beta_deg: Annotated[bool, typer.Option("--beta-deg", help="β is in degrees")] = False,
    n: Annotated[int, typer.Option("--n", help="grid points per axis")] = 41,
    netcdf: Annotated[
        Path | None, typer.Option("--netcdf", help="also write the map as netCDF")
    ] = None,
) -> None:
    """Map the stability of the co-rotation about x3 over a parameter grid
    (docs/theory/rotating-field.md §§5–7)."""
    from rich.progress import Progress

    from tumble.analysis.stability_maps import rotating_field_map
    from tumble.errors import ParameterError
    from tumble.io.output import atomic_write
    from tumble.plot import stability_map_bytes

    fmt = output.suffix.lower().lstrip(".")

    def work() -> dict[Path, bytes]:
        if fmt not in ("png", "pdf", "svg"):
            raise ParameterError(
                f"--output = {output} must end in .png, .pdf or .svg (the figure format)"
            )
        if over == "beta-eps" and (beta is not None or eps is not None):
            raise ParameterError(
                "--beta and --eps do not apply to --over beta-eps (β and ε are its axes)"
            )
        if over == "inertia" and inertia is not None:
            raise ParameterError(
                "--inertia does not apply to --over inertia (I1/I3 and I2/I3 are its axes)"
            )
        b = None if beta is None else _beta_rad(beta, beta_deg)
        with Progress(console=err, transient=True, disable=not err.is_terminal) as bar:
            task = bar.add_task(f"stability map over {over}", total=n * n)
            ds = rotating_field_map(
                over,
                inertia=inertia,
                beta=b,
                eps=eps,
                n=n,
                progress=lambda done, total: bar.update(task, completed=done, total=total),
            )
        files = {output: stability_map_bytes(ds, fmt)}
        if netcdf is not None:
            files[netcdf] = bytes(ds.to_netcdf(engine="scipy"))
        for path, data in files.items():
            path.parent.mkdir(parents=True, exist_ok=True)
            atomic_write(path, data)
        return files

    files = _guarded(work)
    _say(out, f"written: {', '.join(str(f) for f in files)}")


@app.command("bench")
def bench_cmd(
    as_json: Annotated[bool, typer.Option("--json", help="print the figures as JSON")] = False,
    output: Annotated[
        Path | None, typer.Option("-o", "--output", help="also write the JSON to this file")
    ] = None,
    quick: Annotated[
        bool,
        typer.Option(
            "--quick",
            help="horizon 1e3, one repeat, ensembles of 100, no compile, start-up, engine, orbit "
            "or crossings study (a check)",
        ),
    ] = False,
    horizon: Annotated[
        float | None, typer.Option(help="length of the full runs [time units]; default 1e5")
    ] = None,
    repeat: Annotated[int | None, typer.Option(help="timed calls per figure; default 5")] = None,
    scipy: Annotated[bool, typer.Option(help="time scipy with Python right-hand sides")] = True,
    heyoka: Annotated[bool, typer.Option(help="compare with heyoka.py if installed")] = True,
    compile_study: Annotated[
        bool, typer.Option("--compile/--no-compile", help="time the cold compile")
    ] = True,
) -> None:
    """Measure tumble's speed against scipy and heyoka.py, averaged against full, batches
    over cores and the compile time, each figure beside its target."""
    import json

    from rich.status import Status

    from tumble.app.bench import ENSEMBLE_SIZE, BenchSettings, run_benchmark
    from tumble.io.output import atomic_write

    def work() -> dict[str, Any]:
        settings = BenchSettings(
            horizon=horizon if horizon is not None else (1e3 if quick else 1e5),
            repeat=repeat if repeat is not None else (1 if quick else 5),
            scipy=scipy,
            heyoka=heyoka,
            compile=compile_study and not quick,
            startup=not quick,
            engine=not quick,
            orbit=not quick,
            crossings=not quick,
            ensemble_size=100 if quick else ENSEMBLE_SIZE,
        )
        with Status("benchmark", console=err) as status:
            return run_benchmark(settings, log=lambda msg: status.update(escape(msg)))

    result = _guarded(work)
    text = json.dumps(result, indent=1, ensure_ascii=False)
    if output is not None:
        output.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(output, text.encode())
    if as_json:
        print(text)
        return
    from tumble.app.bench_tables import bench_tables

    for table in bench_tables(result):
        out.print(table)
    missed = [v for v in result["verdicts"] if not v["met"]]
    out.print(
        f"{len(result['verdicts']) - len(missed)} of {len(result['verdicts'])} targets met"
        + "".join(
            f"\n  [red]missed:[/] {escape(str(v['what']))}: {v['value']:.3g} "
            f"(target {'≥' if v['at_least'] else '≤'} {v['target']:g})"
            for v in missed
        ),
        highlight=False,
    )


@app.command("sweep")
def sweep_cmd(
    sweep_file: Annotated[Path, typer.Argument(help="TOML sweep file (base scenario + axes)")],
    out_dir: Annotated[Path, typer.Option("-o", "--out", help="output directory")] = Path(
        "out/sweep"
    ),
    scheduler: Annotated[
        str | None,
        typer.Option("--scheduler", help="a running Dask scheduler, tcp://HOST:PORT"),
    ] = None,
    workers: Annotated[
        int | None,
        typer.Option("--workers", min=1, help="local worker processes (default: every core)"),
    ] = None,
    plot: Annotated[bool, typer.Option(help="write sweep.png")] = True,
    retry_failed: Annotated[
        bool, typer.Option("--retry-failed", help="compute failed points again when resuming")
    ] = False,
    allow_module: AllowModule = None,
) -> None:
    """Run a scenario over grid axes and Monte Carlo draws on Dask: sweep.nc and sweep.png.

    Started again with the same command, a sweep keeps the points it finished and computes
    only the others. A torque function the base scenario names (torque = "file:function")
    runs on every worker: each loads it from the Python file beside the scenario.
    """
    if scheduler is not None and workers is not None:
        _say(err, "--workers applies to the local cluster, not --scheduler", "error:", "red")
        raise typer.Exit(2)
    from tumble.io.sweep import load_sweep

    # Validated before Dask, xarray and the integrators load: a bad key answers at once.
    sweep_plan = _guarded(
        lambda: load_sweep(sweep_file, allow_modules=allow_module or (), consent=_consent)
    )
    # At Ctrl-C the local cluster's processes are ended, not shut down: multiprocessing's
    # resource tracker (a child) would then warn about their semaphores on this terminal.
    os.environ.setdefault("PYTHONWARNINGS", "ignore::UserWarning:multiprocessing.resource_tracker")
    from tumble.app.sweep import sweep

    resume = (
        f"interrupted: the finished points are kept in {out_dir}/; run the same command to resume"
    )
    with _sweep_progress() as progress:
        result = _guarded(
            lambda: sweep(
                sweep_plan,
                out_dir,
                scheduler=scheduler,
                workers=workers,
                progress=progress,
                plot=plot,
                retry_failed=retry_failed,
                allow_modules=allow_module or (),
            ),
            interrupted=resume,
        )
    _report_sweep(result)


@contextlib.contextmanager
def _sweep_progress() -> Iterator[Callable[[int, int], None]]:
    """A progress bar on stderr (points, points/s, time left), as the callback a sweep calls
    with (points done, points in all)."""
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        ProgressColumn,
        Task,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )
    from rich.text import Text

    class Rate(ProgressColumn):
        def render(self, task: Task) -> Text:
            speed = task.speed
            return Text("" if speed is None else f"{speed:.3g} points/s")

    columns = (
        TextColumn("sweep"),
        BarColumn(),
        MofNCompleteColumn(),
        Rate(),
        TimeElapsedColumn(),
        TextColumn("left"),
        TimeRemainingColumn(),
    )
    with Progress(*columns, console=err, disable=not err.is_terminal) as bar:
        task = bar.add_task("sweep", total=None)
        started: list[int] = []

        def progress(done: int, total: int) -> None:
            if not started:  # points found on disk are not part of the rate
                started.append(done)
                bar.reset(task, total=total, completed=done)
            else:
                bar.update(task, completed=done, total=total)

        yield progress


def _report_sweep(result: Any) -> None:
    """What a sweep did: points, failures by reason, files."""
    ds = result.dataset
    shape = " × ".join(f"{d} {n}" for d, n in ds["status"].sizes.items())
    _say(
        out,
        f"{ds.attrs['points']} points ({shape}): "
        f"{result.computed} computed, {result.resumed} already done, {result.failed} failed; "
        f"{result.wall_time:.1f} s on {result.workers} worker threads"
        + (f", {result.throughput:.3g} points/s" if result.computed else ""),
    )
    if result.failed:
        reasons = collections.Counter(
            str(r) for r, s in zip(ds["reason"].values.ravel(), ds["status"].values.ravel(),
                                    strict=True) if s == 1
        )  # fmt: skip
        for reason, count in reasons.most_common(3):
            _say(out, reason, f"failed ×{count}:", "yellow")
    _say(out, f"written: {', '.join(str(f) for f in result.files)}")


@app.command("reproduce")
def reproduce_cmd(
    papers: Annotated[
        list[str] | None,
        typer.Argument(
            help="resisting_medium, rotating_field, nonlinear_moment, a claim by name or id "
            "(rotation_about_middle_axis_is_unstable or rf-6), or all (default: all)"
        ),
    ] = None,
    out_dir: Annotated[Path, typer.Option("-o", "--out", help="output directory")] = Path(
        "out/reproduce"
    ),
    overwrite: Overwrite = False,
    quiet: Quiet = False,
) -> None:
    """Check the claims of the papers: report.html (figures embedded), claims.json,
    claims.md, figures/.

    Choose papers by model name, single claims by name or by id (the name's short alias), or
    all of them.

    Each claim gets a verdict computed from its measured figure: confirmed, confirmed with
    qualification (as tumble's theory pages correct or restrict it), or refuted. Exits 1 if a
    check could not run (the report says which and why).
    """
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        SpinnerColumn,
        TextColumn,
        TimeElapsedColumn,
    )

    from tumble import _progress
    from tumble.app.reproduce import reproduce
    from tumble.io.report import measured_text

    columns = (
        SpinnerColumn(),
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
    )
    shown = not quiet and err.is_terminal
    with Progress(*columns, console=err, transient=True, disable=not shown) as bar:
        task = bar.add_task("claims", total=None)
        label = "claims"

        def progress(done: int, total: int, cid: str) -> None:
            nonlocal label
            label = f"claims ({cid})" if cid else "claims"
            bar.update(task, completed=done, total=total, description=label)

        def show(stage: str, fraction: float | None) -> None:
            if stage.startswith("compiling"):  # the claims' own stages would only flicker
                bar.update(task, description=f"{label}: {stage}")

        previous = _progress.set_display(show, bar.stop) if shown else None
        try:
            result = _guarded(
                lambda: reproduce(
                    papers or ["all"], out_dir, progress=progress, overwrite=overwrite
                )
            )
        finally:
            if previous is not None:
                _progress.set_display(*previous)
    colour = {"confirmed": "green", "confirmed with qualification": "yellow", "refuted": "red"}
    table = Table(title=f"claims of the papers ({result.wall_time:.0f} s)", title_justify="left")
    table.add_column("name (id)", overflow="fold")  # a name wraps, never cut: it selects
    for col in ("claim", "verdict", "measured"):
        table.add_column(col)
    for r in result.runs:
        if r.claim is None:
            table.add_row(escape(r.label), escape(str(r.error)), "[red]error[/]", "")
            continue
        table.add_row(
            escape(r.label),
            escape(r.claim.title),
            f"[{colour.get(r.verdict, 'white')}]{r.verdict}[/]",
            escape(measured_text(r.claim.measured)),
        )
    out.print(table)
    _say(out, f"report: {Path(out_dir) / 'report.html'}")
    if result.errors:
        err.print(f"[red]{len(result.errors)} check(s) could not run[/red] (see the report)")
        raise typer.Exit(1)


if __name__ == "__main__":  # pragma: no cover
    from tumble._entry import main

    main()


def _one_line_paragraphs(text: str) -> str:
    """A docstring with each paragraph on one line: the terminal wraps it at its own width
    (kept as written, its lines would be wrapped again where the terminal is narrower)."""
    paragraphs = inspect.cleandoc(text).split("\n\n")
    return "\n\n".join(" ".join(p.split()) for p in paragraphs)


def _polish_help() -> None:
    """Every command's help in paragraphs the terminal wraps, read as written (a unit such as
    ``[rad]`` is not rich markup, which would drop it), and no ``<bool>`` beside a flag (a flag
    takes no value)."""
    for info in app.registered_commands:
        if info.callback is None:
            continue
        if info.callback.__doc__:
            info.help = escape(_one_line_paragraphs(info.callback.__doc__))
        # The annotations evaluated once and kept (each evaluation of a written one makes new
        # OptionInfo objects), so that typer reads the ones changed here.
        hints = typing.get_type_hints(info.callback, include_extras=True)
        info.callback.__annotations__ = hints
        for hint in hints.values():
            if typing.get_origin(hint) is not Annotated:
                continue
            kind, *metadata = typing.get_args(hint)
            for meta in metadata:
                if isinstance(meta, typer.models.ParameterInfo) and meta.help:
                    meta.help = escape(meta.help)
                if kind is bool and isinstance(meta, typer.models.OptionInfo) and not meta.metavar:
                    meta.metavar = " "


_polish_help()
