"""A scenario in, its results (and files) out: the library functions behind ``tumble run`` and
``tumble verify``, exported as :func:`tumble.run` and :func:`tumble.verify`.

From a notebook::

    import tumble
    result = tumble.run("examples/a3_positive.toml")                       # in memory
    result = tumble.run("examples/a3_positive.toml", "out/a3_positive")    # and the files
"""

from __future__ import annotations

import contextlib
import io
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from tumble._progress import stage
from tumble.analysis import RunResult, VerifyResult
from tumble.analysis import run as run_request
from tumble.analysis import verify as verify_request
from tumble.analysis.run import si_dataset, si_time
from tumble.app.guard import user_code_guard
from tumble.errors import TumbleError
from tumble.io.ccsds import ccsds_outputs, check_ccsds
from tumble.io.fileset import OutputSet, output_set
from tumble.io.output import NonFiniteOutput, render_outputs, verify_outputs
from tumble.io.scenario import Scenario, load_scenario
from tumble.plot import (
    FigureSettings,
    figure_settings,
    plot_comparison,
    plot_envelope,
    plot_verify,
)

__all__ = ["run", "verify"]


def _relative_curve(result: RunResult, settings: FigureSettings) -> tuple[Any, Any, str] | None:
    """The column the figure draws relative to its initial value (``settings.relative``,
    e.g. the nonlinear moment's a(t)/a(0)), from the first run along which it varies."""
    if settings.relative is None:
        return None
    name, label = settings.relative
    for ds in result.datasets.values():
        if name in ds and ds[name].values[0] != 0.0 and np.ptp(ds[name].values) > 0.0:
            return ds["tau"].values, ds[name].values / ds[name].values[0], label
    return None


def _settings(result: RunResult) -> FigureSettings:
    """The model's figure, drawing the averaged columns where it names none."""
    req = result.request
    settings = figure_settings(req.model.name)
    if settings.variables or "averaged" not in req.model.methods:
        return settings
    names = tuple(c.name for c in req.model.columns(req.params, "averaged"))
    return replace(settings, variables=names)


def _figure_png(result: RunResult, title: str) -> bytes:
    """The run's figure; a physical scenario's in SI (time in seconds or days)."""
    settings = _settings(result)
    result = in_si(result)
    if settings.kind == "envelope":
        _header, rows = result.report.tables.get(settings.extrema, ((), []))
        fig = plot_envelope(
            result.datasets,
            extrema=rows,
            pressure=_relative_curve(result, settings),
            marks=result.issues,
            title=title,
        )
    else:
        fig = plot_comparison(
            result.datasets,
            variables=settings.variables,
            diagnostics=result.diagnostics.get("averaged"),
            marks=result.issues,
            title=title,
            log=settings.log,
        )
    return _png(fig)


def in_si(result: RunResult) -> RunResult:
    """The run's datasets, diagnostics and warning times in SI where its scenario was given in
    SI (:func:`tumble.analysis.run.si_dataset`), for its figure and its printed table; the
    files keep the normalised columns beside the SI ones."""
    scaling = result.request.scaling
    if scaling is None:
        return result
    t_end = float(result.request.tau[-1])
    marks = [{**m, "tau": float(si_time(scaling, np.array([m["tau"]]), t_end)[0][0])}
             for m in result.issues]  # fmt: skip
    return replace(
        result,
        datasets={m: si_dataset(ds, scaling) for m, ds in result.datasets.items()},
        diagnostics={m: si_dataset(ds, scaling) for m, ds in result.diagnostics.items()},
        issues=marks,
    )


def _png(fig: Any) -> bytes:
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=130)
    plt.close(fig)
    return buf.getvalue()


@contextlib.contextmanager
def _held(
    out_dir: str | Path | None, command: str, sc: Scenario, overwrite: bool
) -> Iterator[OutputSet | None]:
    """The output directory held for a whole run (:func:`tumble.io.fileset.output_set`):
    checked and locked before the computation; None when nothing is to be written."""
    if out_dir is None:
        yield None
        return
    source = Path(sc.source)
    scenario = str(source.resolve()) if source.is_file() else sc.source
    with output_set(
        out_dir, command=command, scenario=scenario, inputs=sc.inputs, overwrite=overwrite
    ) as out:
        yield out


@contextlib.contextmanager
def _loaded(
    scenario: str | Path | Scenario, out_dir: str | Path | None, command: str, overwrite: bool
) -> Iterator[tuple[Scenario, OutputSet | None]]:
    """The scenario (loaded unless given loaded) and its output directory held for the
    whole of ``command`` (see :func:`_held`); a scenario with user code runs under the guard
    of :func:`tumble.app.guard.user_code_guard` (``run.user_code_timeout``)."""
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    guard = (user_code_guard(sc.user_code_timeout, sc.user_functions) if sc.user_code
             else contextlib.nullcontext())  # fmt: skip
    with _held(out_dir, command, sc, overwrite) as out, guard:
        yield sc, out


def run(
    scenario: str | Path | Scenario,
    out_dir: str | Path | None = None,
    *,
    overwrite: bool = False,
    aem: bool = False,
) -> RunResult:
    """Run a scenario, and write its outputs to ``out_dir`` if one is given.

    The outputs are ``<method>.csv`` and ``<method>.nc`` (the same columns with their units as
    NetCDF attributes; a full run's include its attitude quaternion and body angular
    velocity) for every method (plus ``<method>_si.csv`` for
    physical-units scenarios and ``averaged_diagnostics.csv`` where the model has diagnostics),
    ``summary.json`` and the model's figure (``comparison.png``, ``evolution.png``); with
    ``[run] verify = true`` also the files of :func:`verify` and the verdict in
    ``summary.json``, and ``manifest.json`` (inputs, file sizes and hashes). The directory is
    checked before the computation and its files replaced as one set once the whole run has
    succeeded (:func:`tumble.io.fileset.output_set`). With ``aem``, the attitude as CCSDS
    Attitude Data Messages too (:mod:`tumble.io.ccsds`): ``<method>.aem`` of every method
    that carries it and ``initial.apm``.

    Parameters
    ----------
    scenario : str, Path or Scenario
        A TOML scenario file, or a scenario already loaded (:func:`tumble.load_scenario`).
    out_dir : str or Path, optional
        Output directory (created if needed); None writes nothing.
    overwrite : bool
        Replace the directory's contents even when they are another run's results.
    aem : bool
        Write the CCSDS AEM and APM files; a run without an absolute epoch (an orbiting body
        in SI units) or without a full method is refused before the computation.

    Returns
    -------
    RunResult

    Raises
    ------
    ScenarioError
        With ``aem``, if the run has no epoch or no method carrying the attitude.
    """
    with _loaded(scenario, out_dir, "run", overwrite) as (sc, out):
        if aem:
            check_ccsds(sc.request)
        try:
            result = run_request(sc.request)
        except TumbleError as exc:
            if out is not None and isinstance(exc.partial, RunResult):
                # What ran until the error: written, marked as ending early (summary.json's
                # "ended_early"), then the error goes on to the caller.
                try:
                    files = render_outputs(exc.partial, sc.inputs, sc.source, None)
                except NonFiniteOutput as bad:  # what it computed left the finite numbers
                    files = bad.files
                out.commit(files)
                exc.written = str(out_dir)
            raise
        verification = None
        if sc.request.verify:
            with stage("verifying"):
                verification = verify_request(sc.request)
        if out is not None:
            try:
                with stage("writing the outputs"):
                    files = render_outputs(result, sc.inputs, sc.source, verification)
            except NonFiniteOutput as exc:
                out.commit(exc.files)  # what it computed, marked failed; no figure of it
                raise
            if aem:
                files.update(ccsds_outputs(result, sc.source))
            title = f"{sc.request.model.name}: {Path(sc.source).name}"
            with stage("drawing the figure"):
                files[_settings(result).file] = _figure_png(result, title)
                if verification is not None:
                    files["verify.png"] = _png(plot_verify(verification, title=f"verify {title}"))
            out.commit(files)
    return replace(result, verification=verification)


def verify(
    scenario: str | Path | Scenario, out_dir: str | Path | None = None, *, overwrite: bool = False
) -> VerifyResult:
    """Measure the averaging error of a scenario at ε, ε/2 and ε/4, and write its files to
    ``out_dir`` if one is given.

    Runs full and averaged at each ε over the scenario's slow horizon ε·t_end
    (:func:`tumble.analysis.verify`); the files are ``verify.csv``, ``verify_curves.csv``,
    ``verify.json``, ``verify.png`` and ``manifest.json``, written as one set once all runs are
    done.

    Parameters
    ----------
    scenario : str, Path or Scenario
        A TOML scenario file or a loaded scenario (its ``methods`` are ignored: full and
        averaged always run).
    out_dir : str or Path, optional
    overwrite : bool
        As in :func:`run`: the output directory (created if needed; None writes nothing), and
        whether to replace its contents even when they are another run's results.

    Returns
    -------
    VerifyResult
    """
    with _loaded(scenario, out_dir, "verify", overwrite) as (sc, out):
        result = verify_request(sc.request)
        if out is not None:
            with stage("writing the outputs"):
                files = verify_outputs(result, sc.source)
                title = f"verify {sc.request.model.name}: {Path(sc.source).name}"
                files["verify.png"] = _png(plot_verify(result, title=title))
            out.commit(files)
    return result
