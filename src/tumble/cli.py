"""Command-line interface: ``tumble run | models | init``.

Commands only translate arguments: the work is done by library functions a notebook can call.
Bad input prints one red line to stderr and exits 2; a failed integration exits 3.
"""

from __future__ import annotations

import os
import sys
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console
from rich.table import Table

from tumble.errors import TumbleError, TumbleWarning

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    help="tumble: slow evolution of rigid-body rotation under small torques.",
)
out = Console()
err = Console(stderr=True)


def _guarded(work: Callable[[], Any]) -> Any:
    """Run ``work``; turn tumble's errors into one red line and its exit code."""
    try:
        return work()
    except TumbleError as exc:
        err.print(f"[red]error:[/red] {exc}", highlight=False, soft_wrap=True)
        raise typer.Exit(exc.exit_code) from None
    except Exception as exc:
        if os.environ.get("TUMBLE_DEBUG"):
            raise
        err.print(
            f"[red]internal error:[/red] {type(exc).__name__}: {exc} "
            "(set TUMBLE_DEBUG=1 for a traceback)",
            highlight=False,
            soft_wrap=True,
        )
        raise typer.Exit(1) from None


@app.command("run")
def run_cmd(
    scenario: Annotated[Path, typer.Argument(help="TOML scenario file")],
    out_dir: Annotated[Path, typer.Option("-o", "--out", help="output directory")] = Path("out"),
) -> None:
    """Run a scenario: CSV per method, summary.json and a figure in OUT."""
    from tumble.runner import run_scenario

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", TumbleWarning)
        result = _guarded(lambda: run_scenario(scenario, out_dir))
    for w in caught:
        if issubclass(w.category, TumbleWarning):
            err.print(f"[yellow]warning:[/yellow] {w.message}", highlight=False, soft_wrap=True)

    model = result.request.model
    shown = model.plot_variables
    table = Table(title=f"{model.name} — {scenario}", title_justify="left")
    for col in ("method", "form", "wall time [s]", *(f"final {v}" for v in shown)):
        table.add_column(col)
    for m, ds in result.datasets.items():
        table.add_row(
            m,
            ds.attrs["form"],
            f"{ds.attrs['wall_time_s']:.3g}",
            *(f"{ds[v].values[-1]:.6g}" for v in shown),
        )
    out.print(table)
    for pair, diffs in result.differences.items():
        text = ", ".join(f"{k} {v:.2e}" for k, v in diffs.items())
        out.print(f"max |difference| {pair}: {text}", highlight=False)
    lim = result.limits
    if lim:
        text = ", ".join(
            f"{v} → {'undefined' if lim[v] is None else f'{lim[v]:.6g}'}" for v in shown if v in lim
        )
        note = lim.get("statement") or lim.get("end_state")
        out.print(f"predicted limits: {text}" + (f" ({note})" if note else ""), highlight=False)
    out.print(f"outputs written to {out_dir}/", highlight=False)


@app.command("models")
def models_cmd() -> None:
    """List the models, each with its paper."""
    from tumble.models import MODELS

    for name, rec in MODELS.items():
        out.print(
            f"[bold]{name}[/bold]: {rec.description}  [dim]({rec.paper})[/dim]", highlight=False
        )


@app.command("init")
def init_cmd(
    model: Annotated[str, typer.Argument(help="model name (see `tumble models`)")],
) -> None:
    """Print a commented example scenario for MODEL."""
    from tumble.io import template

    text = _guarded(lambda: template(model))
    sys.stdout.write(text)


def main() -> None:
    """Entry point of the ``tumble`` console script."""
    app()


if __name__ == "__main__":  # pragma: no cover
    main()
