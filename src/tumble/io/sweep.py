"""Sweep files (TOML) and the sweep's output directory.

A sweep file names a base scenario and the keys to vary::

    base = "rf_physical.toml"          # a scenario file beside this one, or an inline [base]

    [[axis]]                           # one grid dimension per axis
    key = "parameters.beta"            # any scenario key; nested: "parameters.b[2][2]"
    linspace = [0.1, 3.0, 30]          # or values = [...], or logspace = [1e-3, 1e-1, 5]

    [monte_carlo]                      # a "sample" dimension
    samples = 200
    seed = 1
    [[monte_carlo.draw]]
    key = "initial.theta"
    uniform = [0.2, 1.2]               # or normal = [mean, sd], log_uniform = [low, high]

    [keep]                             # what is kept of every run
    final = true
    verify = false
    series = ["period"]                # slow variables at every sample time (percentile bands)

The output directory holds ``sweep.nc`` (the Dataset, rewritten atomically as results come
in), ``sweep.json`` (the manifest: the sweep's hash, its points and chunks) and
``parts/<chunk>.json`` (the records of every finished chunk, each written atomically). A
sweep started again finds the parts it has and computes only the others.
"""

from __future__ import annotations

import copy
import hashlib
import json
import math
import re
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from tumble._version import __version__
from tumble.analysis.plan import Axis, Draw, Keep, Record, SweepPlan
from tumble.errors import ParameterError, ScenarioError, shorten
from tumble.io.fileset import atomic_write
from tumble.io.scenario import Consent, _one_line, key_units, load_user_code, parse_scenario
from tumble.io.text import check_text
from tumble.io.toml import read_file, read_toml

if TYPE_CHECKING:
    import xarray as xr

    from tumble.analysis import RunRequest

__all__ = [
    "Sweep",
    "SweepStore",
    "load_sweep",
    "parse_key",
    "point_scenario",
    "set_key",
]

MAX_CHUNK = 64
"""Largest default number of points per task."""


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid")


class AxisSpec(_Section):
    key: str = Field(description='a scenario key, e.g. "parameters.beta" or "parameters.b[2][2]"')
    name: str | None = Field(None, description="a dimension name")
    values: list[float] | None = Field(None, description="a list of numbers")
    linspace: list[float] | None = Field(None, description="[start, stop, num]")
    logspace: list[float] | None = Field(None, description="[start, stop, num], start, stop > 0")
    units: str | None = Field(None, description="a unit string")
    long_name: str | None = Field(None, description="a description")


class DrawSpec(_Section):
    key: str = Field(description="a scenario key")
    name: str | None = Field(None, description="a variable name")
    uniform: list[float] | None = Field(None, description="[low, high]")
    normal: list[float] | None = Field(None, description="[mean, standard deviation]")
    log_uniform: list[float] | None = Field(None, description="[low, high], 0 < low")
    units: str | None = Field(None, description="a unit string")
    long_name: str | None = Field(None, description="a description")


class MonteCarloSpec(_Section):
    samples: int = Field(description="an integer ≥ 1")
    seed: int = Field(description="an integer ≥ 0")
    draw: list[DrawSpec] = Field(description="[[monte_carlo.draw]] tables")


class KeepSpec(_Section):
    final: bool = Field(True, description="true or false")
    differences: bool = Field(True, description="true or false")
    limits: bool = Field(True, description="true or false")
    stability: bool | None = Field(
        None, description="true or false (default: true where the model has a stationary motion)"
    )
    verify: bool = Field(False, description="true or false")
    series: list[str] = Field(
        default_factory=list, description="names of slow variables kept at every sample time"
    )


class RunSpec(_Section):
    chunk: int | None = Field(None, description="points per task, an integer ≥ 1")
    batch: bool = Field(True, description="true or false")


class PlotSpec(_Section):
    variables: list[str] | None = Field(None, description="names of the Dataset's variables")
    method: str | None = Field(None, description="a method of the base scenario")


class SweepFile(_Section):
    base: str | dict[str, Any] = Field(description="a scenario file name or an inline table")
    axis: list[AxisSpec] = Field(default_factory=list, description="[[axis]] tables")
    monte_carlo: MonteCarloSpec | None = Field(None, description="a [monte_carlo] table")
    keep: KeepSpec = Field(
        default_factory=lambda: KeepSpec.model_validate({}), description="a [keep] table"
    )
    sweep: RunSpec = Field(
        default_factory=lambda: RunSpec.model_validate({}), description="a [sweep] table"
    )
    plot: PlotSpec = Field(
        default_factory=lambda: PlotSpec.model_validate({}), description="a [plot] table"
    )


Key = tuple[str | int, ...]
_PART = re.compile(r"([A-Za-z0-9_-]+)((?:\[\d+\])*)$")


def parse_key(key: str) -> Key:
    """Split ``"parameters.b[2][2]"`` into ``("parameters", "b", 2, 2)``.

    Raises
    ------
    ScenarioError
        If the key is not dotted names with optional ``[index]`` suffixes.
    """
    path: list[str | int] = []
    for part in key.split("."):
        m = _PART.match(part)
        if m is None:
            raise ScenarioError(
                f"key = {key!r} is not a scenario key (expected dotted names with optional "
                'indices, e.g. "parameters.b[2][2]")'
            )
        path.append(m.group(1))
        path += [int(i) for i in re.findall(r"\[(\d+)\]", m.group(2))]
    return tuple(path)


def _container(data: dict[str, Any], path: Key, key: str) -> Any:
    """The table or list holding the last element of ``path``; ScenarioError if absent."""
    node: Any = data
    for part in path[:-1]:
        if isinstance(part, int):
            if not isinstance(node, list) or part >= len(node):
                size = len(node) if isinstance(node, list) else 0
                raise ScenarioError(
                    f"key = {key!r}: index {part} is outside the base scenario's list of {size}"
                )
            node = node[part]
        else:
            if not isinstance(node, dict) or part not in node:
                raise ScenarioError(
                    f"key = {key!r}: the base scenario has no {part!r} there (give it in the "
                    "base to sweep inside it)"
                )
            node = node[part]
    last = path[-1]
    if isinstance(last, int) and not (isinstance(node, list) and last < len(node)):
        raise ScenarioError(f"key = {key!r}: index {last} is outside the base scenario's list")
    if isinstance(last, str) and not isinstance(node, dict):
        raise ScenarioError(f"key = {key!r}: {last!r} is not inside a table")
    return node


def set_key(data: dict[str, Any], key: str, value: float) -> None:
    """Set a scenario key in place; an integer key (``samples``) stays an integer.

    Raises
    ------
    ScenarioError
        If the key's tables or list elements are not in ``data``, or an integer key would get
        a fractional value.
    """
    path = parse_key(key)
    node = _container(data, path, key)
    last = path[-1]
    old = node[last] if (isinstance(last, int) or last in node) else None
    if isinstance(old, bool):
        raise ScenarioError(f"key = {key!r} is true/false in the base scenario: not sweepable")
    if isinstance(old, int):
        if value != int(value):
            raise ScenarioError(f"key = {key!r} takes integers, got {value!r}")
        node[last] = int(value)
    else:
        node[last] = float(value)


def point_scenario(base: dict[str, Any], assignments: dict[str, float]) -> dict[str, Any]:
    """A copy of ``base`` with every key of ``assignments`` set."""
    data = copy.deepcopy(base)
    for key, value in assignments.items():
        set_key(data, key, value)
    return data


def _name(key: str, given: str | None) -> str:
    """Dimension name: the given one, or the key's last name with its indices (``b_2_2``)."""
    if given is not None:
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", given):
            raise ScenarioError(f"name = {given!r}: expected letters, digits and _")
        return given
    path = parse_key(key)
    names = [i for i, p in enumerate(path) if isinstance(p, str)]
    last = names[-1]
    return "_".join(str(p) for p in path[last:])


@dataclass(frozen=True)
class Sweep:
    """A validated sweep file.

    Attributes
    ----------
    plan : SweepPlan
        The points.
    base : dict
        The base scenario.
    source : str
        The base scenario's path (a user torque is imported relative to it).
    keep : Keep
        What is kept of every run.
    chunk : int
        Points per task.
    batch : bool
        Integrate each chunk's full runs together (the compiled batch path).
    model, time_name : str
        The base scenario's model and its time variable.
    digest : str
        Hash of everything that decides the results (base, points, keep, chunk).
    path : str
        The sweep file.
    plot_variables : tuple of str
        Variables of the figure (empty: the default choice).
    plot_method : str or None
        Method shown for per-method variables.
    columns : dict
        Units, long names and equations of the base scenario's columns.
    """

    plan: SweepPlan
    base: dict[str, Any]
    source: str
    keep: Keep
    chunk: int
    batch: bool
    model: str
    time_name: str
    digest: str
    path: str
    plot_variables: tuple[str, ...] = ()
    plot_method: str | None = None
    columns: dict[str, dict[str, str]] = field(default_factory=dict)
    allow_modules: tuple[str, ...] = ()  # modules the scenario may name functions of

    @property
    def chunks(self) -> int:
        return math.ceil(self.plan.size / self.chunk)

    def chunk_points(self, c: int) -> range:
        """Flat indices of the points of chunk ``c``."""
        return range(c * self.chunk, min((c + 1) * self.chunk, self.plan.size))


def _axis(i: int, table: AxisSpec, base: dict[str, Any]) -> Axis:
    given = [s for s in ("values", "linspace", "logspace") if getattr(table, s) is not None]
    if len(given) != 1:
        raise ScenarioError(f"axis[{i}]: give exactly one of values, linspace or logspace")
    path = parse_key(table.key)
    _container(base, path, table.key)
    try:
        return Axis.spaced(
            _name(table.key, table.name),
            table.key,
            given[0],  # type: ignore[arg-type]
            getattr(table, given[0]),
            table.units if table.units is not None else key_units(base, path),
            table.long_name or table.key,
        )
    except ParameterError as exc:
        raise ScenarioError(f"axis[{i}]: {exc}") from None


def _draw(i: int, table: DrawSpec, base: dict[str, Any]) -> Draw:
    given = [s for s in ("uniform", "normal", "log_uniform") if getattr(table, s) is not None]
    if len(given) != 1:
        raise ScenarioError(
            f"monte_carlo.draw[{i}]: give exactly one of uniform, normal or log_uniform"
        )
    pair = getattr(table, given[0])
    if len(pair) != 2:
        raise ScenarioError(f"monte_carlo.draw[{i}].{given[0]} = {pair!r}: expected 2 numbers")
    path = parse_key(table.key)
    _container(base, path, table.key)
    dist: Literal["uniform", "normal", "log_uniform"] = given[0]  # type: ignore[assignment]
    try:
        return Draw(
            _name(table.key, table.name),
            table.key,
            dist,
            float(pair[0]),
            float(pair[1]),
            table.units if table.units is not None else key_units(base, path),
            table.long_name or table.key,
        )
    except ParameterError as exc:
        raise ScenarioError(f"monte_carlo.draw[{i}]: {exc}") from None


def _default_chunk(size: int) -> int:
    """About 64 tasks or more: enough to balance 2–32 workers, few enough that a task's
    overhead (tens of ms) stays small beside its runs."""
    return max(1, min(MAX_CHUNK, size // 64))


def parse_sweep(
    data: dict[str, Any],
    path: str | Path,
    *,
    allow_modules: Iterable[str] = (),
    consent: Consent | None = None,
) -> Sweep:
    """Validate a sweep given as a dict (as read from TOML) from the file ``path``.

    User code the base scenario names is loaded (and called at its initial state) only once
    the whole sweep file is valid, after ``consent`` has been called with what runs
    (:func:`tumble.io.scenario.parse_scenario`).

    Raises
    ------
    ScenarioError
        With a one-line message naming the key (``axis[1].linspace``, ``base``, …).
    """
    path = Path(path)
    check_text(data)  # a NUL byte in the base's path or a name: one line, before any file
    try:
        sf = SweepFile.model_validate(data)
    except ValidationError as exc:
        raise ScenarioError(f"{path}: {_one_line(exc, SweepFile)}") from None
    source, base = _base(sf, path)
    plan = _plan(sf, base)  # the sweep's own keys, against the base's data, before any model
    try:  # the base itself must be a valid run; points that are not are recorded as failed
        sc = parse_scenario(
            copy.deepcopy(base), str(source), allow_modules=allow_modules, load=False
        )
    except (ScenarioError, ParameterError) as exc:
        raise ScenarioError(f"base scenario {source}: {exc}") from None
    from tumble.analysis.sweep import column_attrs  # the model is loaded: the base is valid

    model = sc.request.model
    keep = _keep(sf, sc.request)
    if sf.sweep.chunk is not None and sf.sweep.chunk < 1:
        raise ScenarioError(f"sweep.chunk = {sf.sweep.chunk} must be ≥ 1")
    chunk = sf.sweep.chunk or _default_chunk(plan.size)
    decisive = {
        "base": base,
        "axes": [[a.key, a.values.tolist()] for a in plan.axes],
        "draws": [[d.key, d.distribution, d.a, d.b] for d in plan.draws],
        "samples": plan.samples,
        "seed": plan.seed,
        "keep": [
            keep.final,
            keep.differences,
            keep.limits,
            keep.stability,
            keep.verify,
            *keep.series,
        ],
        "chunk": chunk,
        "batch": sf.sweep.batch,
    }
    digest = hashlib.sha256(json.dumps(decisive, sort_keys=True).encode()).hexdigest()[:16]
    if sf.plot.method is not None and sf.plot.method not in sc.request.methods:
        raise ScenarioError(
            f"plot.method = {sf.plot.method!r} is not run by the base scenario (allowed: "
            f"{', '.join(sc.request.methods)})"
        )
    try:  # the whole file is valid: now the base's user code may run
        load_user_code(sc, consent)
    except (ScenarioError, ParameterError) as exc:
        raise ScenarioError(f"base scenario {source}: {exc}") from None
    return Sweep(
        plan,
        base,
        str(source),
        keep,
        chunk,
        sf.sweep.batch,
        model.name,
        model.time.name,
        digest,
        str(path),
        tuple(sf.plot.variables or ()),
        sf.plot.method,
        column_attrs(sc.request),
        tuple(allow_modules),
    )


def _base(sf: SweepFile, path: Path) -> tuple[Path, dict[str, Any]]:
    """The base scenario: its file (the sweep file itself for an inline ``[base]``) and data."""
    if not isinstance(sf.base, str):
        return path, sf.base
    source = path.parent / sf.base
    try:
        raw = source.read_bytes()
    except OSError as exc:
        raise ScenarioError(
            f"base = {shorten(repr(sf.base))}: cannot read it ({exc.strerror})"
        ) from None
    return source, read_toml(raw, f"base = {shorten(repr(sf.base))}")


def _plan(sf: SweepFile, base: dict[str, Any]) -> SweepPlan:
    """The grid axes and Monte Carlo draws of the sweep, checked against the base."""
    axes = tuple(_axis(i, a, base) for i, a in enumerate(sf.axis))
    mc = sf.monte_carlo
    draws = () if mc is None else tuple(_draw(i, d, base) for i, d in enumerate(mc.draw))
    if mc is not None and mc.samples < 1:
        raise ScenarioError(f"monte_carlo.samples = {mc.samples} must be ≥ 1")
    if mc is not None and mc.seed < 0:
        raise ScenarioError(f"monte_carlo.seed = {mc.seed} must be ≥ 0")
    try:
        return SweepPlan(axes, draws, 0 if mc is None else mc.samples, 0 if mc is None else mc.seed)
    except ParameterError as exc:
        raise ScenarioError(str(exc)) from None


def _keep(sf: SweepFile, request: RunRequest) -> Keep:
    """What each point keeps; stability only for a model with a stationary motion, series only
    of columns the base scenario's methods write."""
    model = request.model
    stability = sf.keep.stability
    if stability and model.stationary is None:
        raise ScenarioError(
            f"keep.stability = true: the model {model.name} declares no stationary motion "
            "(only rotating_field does)"
        )
    slow = {c.name for m in request.methods for c in model.columns(request.params, m)}
    for name in sf.keep.series:
        if name not in slow:
            raise ScenarioError(
                f"keep.series: {shorten(repr(name), 60)} is not a variable of {model.name} "
                "(allowed: " + ", ".join(sorted(slow)) + ")"
            )
    return Keep(
        final=sf.keep.final,
        differences=sf.keep.differences,
        limits=sf.keep.limits,
        stability=model.stationary is not None if stability is None else stability,
        verify=sf.keep.verify,
        series=tuple(dict.fromkeys(sf.keep.series)),
    )


def load_sweep(
    path: str | Path, *, allow_modules: Iterable[str] = (), consent: Consent | None = None
) -> Sweep:
    """Read and validate a sweep file (TOML); ``consent`` as in :func:`parse_sweep`."""
    path = Path(path)
    data = read_file(path, "sweep file")
    return parse_sweep(data, path, allow_modules=allow_modules, consent=consent)


class SweepStore:
    """The output directory of a sweep: manifest, finished chunks, the Dataset.

    Opening a directory that holds another sweep (a different hash) is refused, so results of
    two sweeps never mix.
    """

    def __init__(self, out_dir: str | Path, sweep: Sweep) -> None:
        self.dir = Path(out_dir)
        self.sweep = sweep
        self.parts = self.dir / "parts"
        manifest = self.dir / "sweep.json"
        if manifest.exists():
            try:
                old = json.loads(manifest.read_text(encoding="utf-8"))
            except (OSError, ValueError) as exc:
                raise ScenarioError(f"{manifest}: unreadable manifest ({exc})") from None
            if old.get("digest") != sweep.digest:
                raise ScenarioError(
                    f"-o {self.dir}: holds another sweep (hash {old.get('digest')}, this one "
                    f"{sweep.digest}); choose another directory or remove it"
                )
        self.parts.mkdir(parents=True, exist_ok=True)
        doc = {
            "tumble_version": __version__,
            "sweep_file": sweep.path,
            "digest": sweep.digest,
            "model": sweep.model,
            "points": sweep.plan.size,
            "dims": dict(zip(sweep.plan.dims, sweep.plan.shape, strict=True)),
            "chunk": sweep.chunk,
            "chunks": sweep.chunks,
        }
        atomic_write(manifest, (json.dumps(doc, indent=2) + "\n").encode())

    def _part(self, c: int) -> Path:
        return self.parts / f"{c:06d}.json"

    def finished(self) -> dict[int, list[Record]]:
        """Chunk → its records, for every chunk whose part on disk is whole and of this
        sweep (anything else is computed again)."""
        out: dict[int, list[Record]] = {}
        for p in sorted(self.parts.glob("*.json")):
            if not p.stem.isdigit() or int(p.stem) >= self.sweep.chunks:
                continue
            c = int(p.stem)
            try:
                doc = json.loads(p.read_text(encoding="utf-8"))
            except (OSError, ValueError):
                continue
            if doc.get("digest") == self.sweep.digest and len(doc["records"]) == len(
                self.sweep.chunk_points(c)
            ):
                out[c] = doc["records"]
        return out

    def write_part(self, c: int, records: list[Record]) -> None:
        """Keep the records of chunk ``c`` (atomically: a part is whole or absent)."""
        doc = {"digest": self.sweep.digest, "chunk": c, "records": records}
        atomic_write(self._part(c), json.dumps(doc, allow_nan=True).encode())

    def records(self, finished: dict[int, list[Record]] | None = None) -> dict[int, Record]:
        """Flat point index → record, over the finished chunks."""
        out: dict[int, Record] = {}
        for c, recs in (self.finished() if finished is None else finished).items():
            out.update(zip(self.sweep.chunk_points(c), recs, strict=True))
        return out

    def write_dataset(self, ds: xr.Dataset) -> Path:
        """Write ``sweep.nc`` (NetCDF 3) atomically and return its path."""
        path = self.dir / "sweep.nc"
        atomic_write(path, bytes(ds.to_netcdf(engine="scipy")))
        return path
