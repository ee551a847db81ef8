"""Scenario files: TOML, validated against the keys each model declares, turned into a
:class:`RunRequest`.

Validation reads each model's :class:`~tumble.models.base.Declaration` only: a scenario is
checked, and an input error reported, before numba, scipy or the model's equations load; the
model itself loads once the scenario is valid.

The loader is generic. A model states its tables and keys in its own module
(:class:`tumble.models.schema.ScenarioSchema`); here they are compiled into pydantic models,
so that every error is one line naming the key, the value and what is allowed. The ``[run]``
table is common to every model: the times (in the model's time variable, or in seconds for a
physical-units variant), samples, methods, tolerances, ``verify``, ``integrator``, and the
averaging choices the model's averaged equations offer.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

import numpy as np
from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    create_model,
    model_validator,
)

from tumble.errors import ParameterError, ScenarioError, check_range, shorten
from tumble.integrate.limits import MAX_STEPS, USER_CODE_TIMEOUT_S, check_times
from tumble.io.text import check_text
from tumble.io.toml import read_file, template
from tumble.io.user_code import UserFunction, user_function
from tumble.models import declaration, get_model, names
from tumble.models.base import AveragingOptions, Declaration, scaling_family
from tumble.models.schema import REQUIRED, Key, Section, Variant

if TYPE_CHECKING:
    from tumble.analysis import RunRequest

__all__ = [
    "Consent",
    "Scenario",
    "key_units",
    "load_scenario",
    "load_user_code",
    "parse_scenario",
    "schema_for",
    "template",
]

MAX_MAGNITUDE = 1e100
"""Largest magnitude of any number in a scenario, and the inverse of the smallest nonzero
one: far beyond any physical input, and far enough from overflow and underflow that the
squares and products of the computations stay representable."""

MAX_ANGLE = 1e4
"""Largest magnitude of an angle [rad]: a few thousand turns. Beyond it the attitude is set by
the last digits of the angle (at 1e308 it is not a number of turns at all)."""


def _sane(x: float) -> float:
    """A finite number of magnitude 0 or in [1/MAX_MAGNITUDE, MAX_MAGNITUDE]."""
    if not math.isfinite(x):
        raise ValueError("must be a finite number")
    if x != 0.0 and not 1.0 / MAX_MAGNITUDE <= abs(x) <= MAX_MAGNITUDE:
        raise ValueError("must be 0 or of magnitude in [1e-100, 1e100]")
    return x


def _angle(x: float) -> float:
    if abs(x) > MAX_ANGLE:
        raise ValueError("an angle must be at most 1e4 rad in magnitude")
    return x


Number = Annotated[float, AfterValidator(_sane)]
Vector3 = Annotated[list[Number], Field(min_length=3, max_length=3, description="3 numbers")]
Vector4 = Annotated[list[Number], Field(min_length=4, max_length=4, description="4 numbers")]
Matrix3 = Annotated[
    list[Vector3], Field(min_length=3, max_length=3, description="3 rows of 3 numbers")
]

_TYPES: dict[str, Any] = {
    "number": Number,
    "integer": int,
    "boolean": bool,
    "vector3": Vector3,
    "vector4": Vector4,
    "matrix3": Matrix3,
    "numbers": list[Number],
    "table": dict[str, Any],
    "any": Any,
}


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)


@dataclass(frozen=True)
class Scenario:
    """A validated scenario: the run it asks for, and its inputs as given.

    A scenario that names user functions holds them not yet loaded until
    :func:`load_user_code` (which :func:`parse_scenario` calls unless told to wait);
    ``user_code`` lists the files (or allowed modules) whose code it runs.
    """

    request: RunRequest
    inputs: dict[str, Any]
    source: str
    user_code: tuple[str, ...] = ()  # the files (or allowed modules) whose code it runs
    user_functions: tuple[str, ...] = ()  # the functions it names, as it names them
    user_code_timeout: float = USER_CODE_TIMEOUT_S  # [s] (run.user_code_timeout)
    pending: _UserCode | None = field(default=None, repr=False, compare=False)


@dataclass
class _UserCode:
    """The user functions of a validated scenario and the checks that call them, run once."""

    functions: list[UserFunction]
    checks: tuple[Callable[[], None], ...]
    loaded: bool = False


# ---------------------------------------------------------------------------------------------
# Declared keys → pydantic models.


def _degrees_to_radians(data: Any, names: tuple[str, ...]) -> Any:
    """Accept ``<angle>_deg`` keys (degrees) for the angles in ``names``."""
    if not isinstance(data, dict):
        return data
    out = dict(data)
    for name in names:
        key = f"{name}_deg"
        if key in out:
            if name in out:
                raise ValueError(f"give either {name} or {key}, not both")
            value = out.pop(key)
            if isinstance(value, int | float) and not isinstance(value, bool):
                value = math.radians(value)
            out[name] = value
    return out


def describe(key: Key) -> str:
    """The key's allowed values, with its unit in brackets: what errors and the reference
    show."""
    return f"{key.expected} [{key.units}]" if key.units else key.expected


def _field(key: Key) -> tuple[Any, Any]:
    """The pydantic (type, Field) of a declared key."""
    kind: Any = (
        Literal[key.choices] if key.kind == "text" and key.choices else _TYPES.get(key.kind, str)
    )
    if key.angle and key.kind == "number":
        kind = Annotated[kind, AfterValidator(_angle)]
    if key.default is REQUIRED:
        return kind, Field(description=describe(key))
    if key.default is None:
        return kind | None, Field(None, description=describe(key))
    if isinstance(key.default, list | dict):
        default = key.default
        return kind, Field(default_factory=lambda: _copy(default), description=describe(key))
    return kind, Field(key.default, description=describe(key))


def _copy(value: Any) -> Any:
    if isinstance(value, list):
        return [_copy(v) for v in value]
    if isinstance(value, dict):
        return {k: _copy(v) for k, v in value.items()}
    return value


def _model(name: str, keys: tuple[Key, ...]) -> type[_Section]:
    """A pydantic model of ``keys``, accepting ``<angle>_deg`` for the angles."""
    angles = tuple(k.name for k in keys if k.angle)
    validators: dict[str, Any] = {}
    if angles:

        def degrees(cls: type, data: Any) -> Any:
            return _degrees_to_radians(data, angles)

        validators["_degrees"] = model_validator(mode="before")(classmethod(degrees))  # type: ignore[arg-type]
    fields: dict[str, Any] = {k.name: _field(k) for k in keys}
    model: type[_Section] = create_model(  # type: ignore[call-overload]
        name, __base__=_Section, __validators__=validators, **fields
    )
    return model


_SECTION_MODELS: dict[int, tuple[Section, type[_Section]]] = {}


def section_model(section: Section) -> type[_Section]:
    """The pydantic model of a declared table, built once per table (the declarations are
    module constants; their defaults may be lists, so they are looked up by identity)."""
    found = _SECTION_MODELS.get(id(section))
    if found is None or found[0] is not section:
        found = (section, _model(f"{section.name or 'top'}_section", section.keys))
        _SECTION_MODELS[id(section)] = found
    return found[1]


_TIMES = {"tau": ("tau_end", "tau"), "t": ("t_end", "t")}
_DAY = 86400.0  # [s]


def run_keys(model: Declaration[Any, Any], variant: Variant[Any, Any]) -> tuple[Key, ...]:
    """The ``[run]`` keys of a model's scenario: common to every model, the averaging choices
    its averaged equations offer, and its own."""
    time = model.time.name
    end, listed = ("t_end_s", "t_s") if variant.physical else _TIMES.get(time, ("t_end", "t"))
    unit = "s" if variant.physical else model.time.units
    allowed = ", ".join(f'"{m}"' for m in model.methods)
    units = "" if unit == "1" else unit
    keys = [
        Key(end, "number", "a time > 0", units, None, doc="end of the run (with samples)"),
        Key(listed, "numbers", "ascending times ≥ 0", units, None, doc="or the sample times"),
    ]
    if variant.physical:
        keys += [
            Key("t_end_days", "number", "a time > 0", "days", None, doc="or the end in days"),
            Key("t_days", "numbers", "ascending times ≥ 0", "days", None,
                doc="or the sample times in days"),
        ]  # fmt: skip
    keys += [
        Key("samples", "integer", "an integer in [2, 1e7]", default=variant.samples,
            doc="equally spaced samples from 0 to the end; samples × output columns at most "
            "3.5e7 (a run's memory: at most about 4 GB, whatever its span)"),
        Key("methods", "any", f"a non-empty list of {allowed}", default=None,
            doc="default: every method the model has"),
        Key("rtol", "number", "a number in [1e-14, 1e-3]", default=1e-10,
            doc="relative tolerance of the integrations"),
        Key("atol", "number", "a number in (0, 1e-3]", default=1e-12,
            doc="absolute tolerance of the integrations"),
        Key("max_steps", "integer", "an integer in [1, 1e12]", default=MAX_STEPS,
            doc="step budget of each integration: it stops with an error when spent, or at "
                "once when its pace needs 100 times what is left (a compiled full run: as many "
                "times as its steps have grown, and a run speeding up with its speed-up "
                "carried on; Python right-hand sides, the averaged equations: at most 1e6)"),
        Key("user_code_timeout", "number", "a time in (0, 1e6]", "s", default=USER_CODE_TIMEOUT_S,
            doc="how long a user's torque function may run without returning: then the run "
                "stops, with one line naming it"),
    ]  # fmt: skip
    if model.numeric:
        doc = "the paper's averaged equations, or the general engine's quadrature"
        keys.append(_choice("averaging", ("closed_form", "numeric"), doc))
    if model.coordinates:
        choices = " or ".join(f'"{c}"' for c in model.coordinates)
        first = model.coordinates[0]
        keys.append(Key("averaged_form", "text", choices, default=first, choices=model.coordinates,
                        doc="the slow coordinates the averaged run integrates"))  # fmt: skip
    if model.corrected_start:
        doc = "start from the given state, or from its first-order mean"
        keys.append(_choice("averaged_init", ("exact", "corrected"), doc))
    if max(model.orders) > 1:
        keys += [
            Key("averaging_order", "integer", "1 or 2", default=1,
                doc="the order of the averaged equations; 2 adds the second-order rates and "
                    "the mean ↔ osculating map"),
            _choice("initial", ("osculating", "mean"),
                    "for averaging_order = 2: the initial state is the physical one "
                    "(converted to the mean one) or the mean one"),
        ]  # fmt: skip
    if model.hybrid:
        keys.append(_choice("averaged_method", ("auto", "plain", "hybrid"),
                            "hybrid: the bands where averaging fails (ϑ = π/2 for the "
                            "resisting medium, the resonances of the phases and the polhode "
                            "separatrix for a triaxial body, the gravity gradient's capture "
                            "for an orbiting body) are crossed on the full equations, "
                            "re-entered through the osculating → mean map; plain: the "
                            "averaged equations throughout (a run of order 2 stops at the "
                            "first band); auto: hybrid at averaging_order = 2, plain at "
                            "1"))  # fmt: skip
    if model.steps:
        doc = ("the averaged equations alone: no asymptotic step across the crossings "
               "theory bridges (ϑ = π/2 of the resisting medium)")  # fmt: skip
        keys.append(Key("averaged_only", "boolean", "true or false", default=False, doc=doc))
    keys += [
        Key("verify", "boolean", "true or false", default=False,
            doc="also measure the averaging error at ε, ε/2, ε/4"),
        Key("verify_scaling", "table", "a table of parameter = exponent in [-4, 4]",
            default=None,
            doc="how verify scales the parameters with ε: each x as x·(ε/ε₀)^exponent "
                "(default: ε alone; for a gravity gradient n ∝ √ε at fixed eps)"),
        _choice("integrator", ("auto", "numba", "scipy"),
                "the compiled DOP853 (auto: unless the parameters hold Python) or scipy's"),
    ]  # fmt: skip
    assert model.scenario is not None
    return (*keys, *model.scenario.run)


def _choice(name: str, choices: tuple[str, ...], doc: str) -> Key:
    """A ``[run]`` text key that takes one of ``choices``, the first its default; its allowed
    values in words as '"a", "b" or "c"'."""
    *rest, last = (f'"{c}"' for c in choices)
    expected = f"{', '.join(rest)} or {last}" if rest else last
    return Key(name, "text", expected, default=choices[0], choices=choices, doc=doc)


def _methods_field(model: Declaration[Any, Any]) -> tuple[Any, Any]:
    allowed = ", ".join(f'"{m}"' for m in model.methods)
    kind = list[Literal[model.methods]]  # type: ignore[name-defined]
    return kind | None, Field(None, description=f"a non-empty list of {allowed}")


@cache
def _compiled(name: str, physical: bool) -> type[BaseModel] | None:
    """The pydantic model a scenario of model ``name`` (with or without ``[physical]``) is
    validated against; None if the model declares no such variant."""
    model = declaration(name)
    if model.scenario is None:
        return None
    variant = model.scenario.variant(physical)
    if variant is None:
        return None
    run = _model(f"{name}_run", tuple(k for k in run_keys(model, variant) if k.name != "methods"))
    run = create_model(  # type: ignore[call-overload]
        f"{name}_run_methods", __base__=run, methods=_methods_field(model)
    )
    fields: dict[str, Any] = {"model": (Literal[name], Field(description=f'"{name}"'))}
    for section in variant.sections:
        compiled = section_model(section)
        if not section.name:  # top-level keys
            fields.update({k.name: _field(k) for k in section.keys})
        elif section.required:
            fields[section.name] = (compiled, Field(description=section.doc or section.name))
        else:
            fields[section.name] = (compiled | None, Field(None, description=section.doc))
    fields["run"] = (run, Field(description="the run"))
    scenario: type[BaseModel] = create_model(  # type: ignore[call-overload]
        f"{name}_{'physical' if physical else 'normalized'}", __base__=_Section, **fields
    )
    return scenario


def schema_for(data: Mapping[str, Any]) -> type[BaseModel] | None:
    """The pydantic schema a scenario dict is validated against (None: unknown model)."""
    name = data.get("model")
    if not isinstance(name, str) or name not in names():
        return None
    return _compiled(name, _physical(name, data))


def _physical(name: str, data: Mapping[str, Any]) -> bool:
    """Whether a scenario of model ``name`` is in physical units: it has a ``[physical]``
    table, or the model has no other kind of scenario."""
    model = declaration(name)
    return "physical" in data or (model.scenario is not None and model.scenario.physical_only)


# ---------------------------------------------------------------------------------------------
# One-line errors.


def _path(loc: tuple[int | str, ...]) -> str:
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        # Skip pydantic's union-member tags ("float", "literal['a']", …), not keys that
        # merely begin like one ("integrator").
        elif str(part) not in ("float", "int") and not str(part).startswith(
            ("function-", "literal[", "list[")
        ):
            out += f".{part}" if out else str(part)
    return out


def _field_hint(schema: type[BaseModel], loc: tuple[int | str, ...]) -> tuple[str, list[str]]:
    """Allowed range of the field at ``loc`` and the keys allowed beside it."""
    cls: Any = schema
    hint, siblings = "", list(schema.model_fields)
    for part in loc:
        if not (isinstance(cls, type) and issubclass(cls, BaseModel)):
            break
        siblings = list(cls.model_fields)  # the keys allowed in the section ``part`` is in
        if not isinstance(part, str) or part not in cls.model_fields:
            break
        info = cls.model_fields[part]
        hint = info.description or hint
        ann = info.annotation
        cls = next(
            (
                a
                for a in getattr(ann, "__args__", ())
                if isinstance(a, type) and issubclass(a, BaseModel)
            ),
            ann,
        )
    return hint, siblings


MAX_SAMPLES = 10_000_000
"""Most samples a run may ask for (the outputs of every method hold them all in memory)."""

MEMORY_BOUND_GB = 4.0
"""The memory a run may need for its samples, as :func:`memory_estimate_gb` estimates it: a
run asking for more samples (× output columns) is refused before it starts. Its steps cost no
memory: full and averaged runs keep their samples, not their steps."""

_BASE_GB = 0.5  # peak of a run with few samples: 0.32 GB (orbiting body), 0.57 GB (full run)
_BYTES_PER_VALUE = 100.0  # per sample and output column: 50-95 B measured (columns, datasets,
# the SI copy, the files' text) at 1e6 samples; 100 keeps the estimate above every measurement


def memory_estimate_gb(samples: int, columns: int) -> float:
    """Peak memory of a run of ``samples`` samples with ``columns`` output columns over all
    its methods [GB]: a fixed part, and each value's copies (the columns, the datasets, the
    SI columns, the text of the files); the span and the steps add nothing."""
    return _BASE_GB + samples * columns * _BYTES_PER_VALUE / 1e9


def _check_memory(request: RunRequest, key: str) -> None:
    """Refuse a run whose samples would need more than :data:`MEMORY_BOUND_GB`."""
    model, p = request.model, request.params
    columns = sum(len(model.columns(p, m)) for m in request.methods)
    samples = int(request.tau.size)
    need = memory_estimate_gb(samples, columns)
    if need > MEMORY_BOUND_GB:
        most = int((MEMORY_BOUND_GB - _BASE_GB) * 1e9 / (columns * _BYTES_PER_VALUE))
        raise ParameterError(
            f"{key} = {samples} would need about {need:.3g} GB ({columns} output columns of "
            f"{', '.join(request.methods)}), over the bound of {MEMORY_BOUND_GB:g} GB: "
            f"allowed at most {most} samples for these methods"
        )


def _one_line(exc: ValidationError, schema: type[BaseModel]) -> str:
    errors = exc.errors(include_url=False)
    # A misspelt key explains the required one it leaves missing: report it first.
    err = next((e for e in errors if e["type"] == "extra_forbidden"), errors[0])
    loc = tuple(err["loc"])
    path = shorten(_path(loc)) or "scenario"
    hint, siblings = _field_hint(schema, loc)
    kind = err["type"]
    if kind == "missing":
        return f"{path}: required key is missing" + (f" (expected {hint})" if hint else "")
    if kind == "extra_forbidden":
        close = difflib.get_close_matches(str(loc[-1]), siblings, n=1, cutoff=0.6)
        guess = f"did you mean {close[0]}? " if close else ""
        return f"{path}: unknown key ({guess}allowed here: {', '.join(siblings)})"
    msg = str(err["msg"]).removeprefix("Value error, ")
    if kind == "literal_error" and hint:  # pydantic's list of the values is the hint's
        msg = "not one of the allowed values"
    elif kind in ("list_type", "tuple_type"):  # a number where a vector or matrix belongs
        msg = "should be a list, e.g. [x, y, z] for a vector"
    shown = shorten(repr(err.get("input")), 60)
    return f"{path} = {shown}: {msg}" + (f" (expected {hint})" if hint else "")


def _validated(schema: type[BaseModel], data: Mapping[str, Any]) -> Any:
    try:
        return schema.model_validate(data)
    except ValidationError as exc:
        raise ScenarioError(_one_line(exc, schema)) from None


# ---------------------------------------------------------------------------------------------
# The run table.


def _times(run: Any, end_key: str, list_key: str, days: bool = False) -> np.ndarray:
    """The run's sample times in the units of ``end_key`` (seconds for a physical scenario,
    which may give them in days instead: ``t_end_days``, ``t_days``)."""
    if days and (run.t_end_days is not None or run.t_days is not None):
        if getattr(run, end_key) is not None or getattr(run, list_key) is not None:
            raise ScenarioError(
                f"run: give the times in seconds ({end_key}, {list_key}) or in days "
                "(t_end_days, t_days), not both"
            )
        return _DAY * _times(run, "t_end_days", "t_days")
    end, listed = getattr(run, end_key), getattr(run, list_key)
    if (end is None) == (listed is None):
        keys = f"{end_key} (with samples) or {list_key}"
        if days:
            keys = f"{end_key} or t_end_days (with samples), or {list_key} or t_days"
        raise ScenarioError(f"run: give exactly one of {keys}")
    if listed is not None:
        return check_times(listed, field=f"run.{list_key}")
    if not (math.isfinite(end) and end > 0.0):
        raise ParameterError(f"run.{end_key} = {end:g} is outside the allowed range (0, inf)")
    if not 2 <= run.samples <= MAX_SAMPLES:
        raise ParameterError(
            f"run.samples = {shorten(str(run.samples))} is outside the allowed range [2, 1e7]"
        )
    return np.linspace(0.0, end, run.samples)


def _tolerances(run: Any) -> tuple[float, float]:
    check_range("run.user_code_timeout", run.user_code_timeout, low=0.0, high=1e6,
                high_open=False)  # fmt: skip
    if not 1e-14 <= run.rtol <= 1e-3:
        raise ParameterError(f"run.rtol = {run.rtol:g} is outside the allowed range [1e-14, 1e-3]")
    if not 0.0 < run.atol <= 1e-3:
        raise ParameterError(f"run.atol = {run.atol:g} is outside the allowed range (0, 1e-3]")
    return run.rtol, run.atol


def _methods(run: Any, allowed: tuple[str, ...], default: tuple[str, ...]) -> tuple[str, ...]:
    methods = tuple(run.methods) if run.methods is not None else default
    if not methods:
        raise ScenarioError(
            "run.methods: give at least one method (allowed: " + ", ".join(allowed) + ")"
        )
    if len(set(methods)) != len(methods):
        raise ScenarioError(f"run.methods = {list(methods)}: each method at most once")
    for m in methods:
        if m not in allowed:
            raise ScenarioError(
                f"run.methods: {m!r} is not a method of this model (allowed: "
                + ", ".join(allowed)
                + ")"
            )
    return methods


# ---------------------------------------------------------------------------------------------
# The values handed to a model's build function.


@dataclass(frozen=True)
class _Inputs:
    """:class:`tumble.models.schema.Inputs` of one validated scenario."""

    values: Mapping[str, Any]
    base: Path
    times: np.ndarray
    allow_modules: frozenset[str] = frozenset()
    functions: list[UserFunction] = field(default_factory=list)

    def __getitem__(self, section: str) -> Mapping[str, Any] | None:
        value = self.values.get(section)
        return value if value is None or isinstance(value, Mapping) else {section: value}

    def validate(self, section: Section, raw: Mapping[str, Any], where: str) -> dict[str, Any]:
        schema = section_model(section)
        try:
            return schema.model_validate(raw).model_dump()
        except ValidationError as exc:
            raise ScenarioError(f"{where}.{_one_line(exc, schema)}") from None

    def import_function(self, reference: str, where: str) -> Callable[..., Any]:
        function = user_function(reference, self.base, where, self.allow_modules)
        self.functions.append(function)
        return function

    def path(self, name: str, where: str) -> Path:
        found = (self.base / Path(name).expanduser()).resolve()
        if not found.is_file():
            raise ScenarioError(f"{where} = {name!r}: no such file (looked for {found})")
        return found

    def run_end(self) -> float:
        return float(self.times[-1])


def _top_level(values: dict[str, Any], variant: Variant[Any, Any]) -> dict[str, Any]:
    """The validated values by section, top-level keys gathered under ``""``."""
    top = next((s for s in variant.sections if not s.name), None)
    if top is not None:
        values[""] = {k.name: values.pop(k.name) for k in top.keys}
    return values


# ---------------------------------------------------------------------------------------------
# The scenario.


Consent = Callable[[tuple[str, ...]], None]
"""Called with the files (or allowed modules) whose code a valid scenario runs, just before
the first of them is loaded: the command line prints ``runs user code from …`` for each (a
caller may also refuse by raising)."""


def parse_scenario(
    data: dict[str, Any],
    source: str = "<scenario>",
    *,
    allow_modules: Iterable[str] = (),
    consent: Consent | None = None,
    load: bool = True,
) -> Scenario:
    """Validate a scenario given as a dict (as read from TOML).

    Nothing of a user's file runs before the whole scenario is valid: a function the scenario
    names (a user torque) is looked for in its file's syntax tree, and the file is loaded
    only once every key has been checked, after ``consent`` has been called with what runs
    (:func:`load_user_code`; :mod:`tumble.io.user_code`). ``Scenario.user_code`` lists it.

    Parameters
    ----------
    data : dict
        The scenario.
    source : str
        Its path: user functions are looked for beside it.
    allow_modules : iterable of str
        Importable modules a scenario may name functions of (``--allow-module``).
    consent : callable, optional
        Called with ``Scenario.user_code`` before any of it is loaded (not called for a
        scenario without user code).
    load : bool
        False: validate only; the user functions stay unloaded and unchecked until
        :func:`load_user_code` (a caller that validates more first: a sweep file).

    Raises
    ------
    ScenarioError, ParameterError
        With a one-line message naming the key and its allowed range; also for a user
        function that fails its checks once loaded (called at the initial state).
    """
    check_text(data)
    if "model" not in data:
        raise ScenarioError(
            "model: required key is missing (allowed: " + ", ".join(names(scenario=True)) + ")"
        )
    name = data["model"]
    if not isinstance(name, str):
        raise ScenarioError(f"model = {name!r}: expected a string")
    model = declaration(name)  # unknown model → one line naming the allowed ones
    physical = _physical(name, data)
    if physical and "parameters" in data:
        raise ScenarioError("give either [parameters] (normalized) or [physical] (SI), not both")
    schema = _compiled(name, physical)
    if model.scenario is None or schema is None:
        raise ScenarioError(
            f"model = {name!r} has no scenario keys"
            + (" in physical units" if physical and model.scenario is not None else "")
        )
    sc = _validated(schema, data)
    variant = model.scenario.variant(physical)
    assert variant is not None  # the schema exists
    values = _top_level(sc.model_dump(), variant)
    end, listed = (
        ("t_end_s", "t_s") if variant.physical else _TIMES.get(model.time.name, ("t_end", "t"))
    )
    times = _times(sc.run, end, listed, days=variant.physical)
    _tolerances(sc.run)  # the run's own keys first: nothing is loaded for a bad one
    if sc.run.methods is not None:
        _methods(sc.run, model.methods, model.methods)
    inputs = _Inputs(values, Path(source).resolve().parent, times, frozenset(allow_modules))
    built = variant.build(inputs)
    request = _request(model, sc.run, built, times)  # loads the model: the scenario is valid
    given = next((k for k in (listed, "t_days") if getattr(sc.run, k, None) is not None), None)
    _check_memory(request, f"run.{given}" if given else "run.samples")
    user_code = tuple(dict.fromkeys(f.origin for f in inputs.functions))
    pending = _UserCode(inputs.functions, built.user_checks) if inputs.functions else None
    functions = tuple(dict.fromkeys(f.reference for f in inputs.functions))
    scenario = Scenario(
        request, sc.model_dump(), source, user_code, user_functions=functions,
        user_code_timeout=float(sc.run.user_code_timeout), pending=pending,
    )  # fmt: skip
    return load_user_code(scenario, consent) if load else scenario


def load_user_code(scenario: Scenario, consent: Consent | None = None) -> Scenario:
    """Load the user functions of a validated scenario and run the checks that call them
    (the torque at the initial state), once; ``consent`` is first called with what runs.

    Parameters
    ----------
    scenario : Scenario
        As :func:`parse_scenario` returned it (with ``load=False``, or already loaded: then
        nothing happens).
    consent : callable, optional
        Called with ``scenario.user_code`` before the first file is loaded.

    Returns
    -------
    Scenario
        ``scenario``, its user functions loaded.

    Raises
    ------
    ScenarioError, ParameterError
        A file that fails to load, a name that is not a function, or a check that fails.
    """
    pending = scenario.pending
    if pending is None or pending.loaded:
        return scenario
    if consent is not None:
        consent(scenario.user_code)
    for function in pending.functions:
        function.load()
    for check in pending.checks:
        check()
    pending.loaded = True
    return scenario


def _hybrid(run: Any) -> bool:
    """Whether the run crosses its bands on the full equations: asked for, or by default at
    order 2 (which would stop at the first band), unless the averaged equations alone are
    asked for."""
    method = getattr(run, "averaged_method", "plain")
    if method == "auto":
        return getattr(run, "averaging_order", 1) == 2 and not getattr(run, "averaged_only", False)
    return bool(method == "hybrid")


def _request(model: Declaration[Any, Any], run: Any, built: Any, times: np.ndarray) -> RunRequest:
    """The run request of a validated scenario and its built parameters (every check first,
    then the model loads)."""
    tau = built.scaling.tau_from_time(times) if built.scaling is not None else times
    methods = _methods(run, model.methods, built.methods or model.methods)
    for m in methods:
        model.check(built.params, m)  # refuse before any work is done
        if model.check_initial is not None:
            model.check_initial(built.params, built.initial, m)
    rtol, atol = _tolerances(run)
    averaging = AveragingOptions(
        # A model whose averaged equations are the general engine's alone runs "numeric".
        averaging=getattr(run, "averaging", "numeric" if model.engine else "closed_form"),
        coordinates=getattr(run, "averaged_form", ""),
        start=getattr(run, "averaged_init", "exact"),
        order=getattr(run, "averaging_order", 1),
        initial=getattr(run, "initial", "osculating"),
        hybrid=_hybrid(run),
        averaged_only=getattr(run, "averaged_only", False),
    )
    family = getattr(run, "verify_scaling", None)
    if family is not None:
        family = scaling_family(built.params, family)  # a name it cannot scale: refused here
    if not 1 <= run.max_steps <= 10**12:
        raise ParameterError(
            f"run.max_steps = {shorten(str(run.max_steps))} is outside the allowed range [1, 1e12]"
        )
    from tumble.analysis import RunRequest

    return RunRequest(get_model(model.name), built.params, built.initial, tau, methods, rtol, atol,
                      built.scaling, run.verify, run.integrator, averaging,
                      run.max_steps, family)  # fmt: skip


def key_units(data: dict[str, Any], path: tuple[str | int, ...]) -> str:
    """The unit of a scenario key, as its description gives it (``"rad"`` for
    ``initial.theta``); ``""`` when it states none, or ``"deg"`` for a ``*_deg`` key.

    Parameters
    ----------
    data : dict
        The scenario (its model and physical-units choice select the schema).
    path : tuple
        The key, split into table names and list indices.
    """
    names = [part for part in path if isinstance(part, str)]
    if names and names[-1].endswith("_deg"):
        return "deg"
    schema = schema_for(data)
    if schema is None:
        return ""
    hint, _ = _field_hint(schema, tuple(names))
    if not hint.endswith("]") or "[" not in hint:
        return ""
    unit = hint[hint.rindex("[") + 1 : -1]
    # "[0, π]" is a range, not a unit.
    return "" if "," in unit else unit


def load_scenario(
    path: str | Path, *, allow_modules: Iterable[str] = (), consent: Consent | None = None
) -> Scenario:
    """Read and validate a TOML scenario file.

    A scenario that names a torque function runs that code: it is loaded from the Python file
    the scenario names, beside it, once the whole scenario is valid (see
    :mod:`tumble.io.user_code`).

    Parameters
    ----------
    path : str or Path
        The scenario file.
    allow_modules : iterable of str
        Importable modules the scenario may name functions of, besides files.
    consent : callable, optional
        Called with the files whose code runs, before the first is loaded
        (:func:`parse_scenario`).
    """
    return parse_scenario(read_file(path), str(path), allow_modules=allow_modules, consent=consent)
