"""The scenario keys of a model, declared beside its physics.

A model states which tables and keys a scenario file of it has (:class:`Section`,
:class:`Key`: kind, allowed values, unit, default, documentation) and how the validated values
become its ``Params`` and ``State`` (:attr:`Variant.build`). The loader in :mod:`tumble.io`
is generic: it validates any model's file against these declarations, with one-line errors
that name the key and its allowed values, and the key reference of the documentation is
generated from them. Plain dataclasses only: the models import no validation library.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Generic, Literal, Protocol, TypeVar

from tumble._typing import FloatArray, Json

__all__ = [
    "REQUIRED",
    "Built",
    "GivenInputs",
    "Inputs",
    "Key",
    "KeyKind",
    "Scaling",
    "ScenarioSchema",
    "Section",
    "Variant",
    "required",
    "si_column",
    "si_columns",
]

P = TypeVar("P")
S = TypeVar("S")


class _Required:
    """The default of a key that must be given."""

    def __repr__(self) -> str:
        return "REQUIRED"


REQUIRED = _Required()
"""The default of a key that must be given."""

KeyKind = Literal[
    "number", "integer", "boolean", "text", "vector3", "vector4", "matrix3", "numbers", "table",
    "any",
]  # fmt: skip
"""What a key holds: a float, an int, true/false, one of ``choices`` (text), 3 or 4 numbers,
3 rows of 3 numbers, a list of numbers, a table of anything, or anything at all (the model's
build function checks it)."""


@dataclass(frozen=True, slots=True)
class Key:
    """One key of a scenario table.

    Attributes
    ----------
    name : str
        The key as written in the file.
    kind : KeyKind
        What it holds.
    expected : str
        Its allowed values in words ("a number in (0, 2]"), shown in errors and the reference.
    units : str
        Its unit ("" when it has none); the reference and the outputs' attributes read it.
    default : object
        The value when the key is absent; :data:`REQUIRED` when it must be given, None when it
        is optional with no value.
    choices : tuple of str
        For ``kind = "text"``: the values allowed.
    angle : bool
        Also accepted as ``<name>_deg``, in degrees (converted to radians).
    doc : str
        What it is, for the reference.
    """

    name: str
    kind: KeyKind
    expected: str
    units: str = ""
    default: Json | _Required = REQUIRED
    choices: tuple[str, ...] = ()
    angle: bool = False
    doc: str = ""


@dataclass(frozen=True, slots=True)
class Section:
    """A table of a scenario file (``[parameters]``, ``[initial]``, …) and its keys."""

    name: str
    keys: tuple[Key, ...]
    required: bool = True
    doc: str = ""


class Inputs(Protocol):
    """The validated values of a scenario, handed to a model's build function.

    The values are TOML data already checked against their :class:`Key` (a number is a
    float, a ``vector3`` a list of 3 floats, …), so they are typed ``Any`` here: this is the
    boundary where untyped file data becomes a model's typed ``Params``."""

    def __getitem__(self, section: str) -> Mapping[str, Any] | None:
        """The values of ``section`` by key (defaults filled in), None if it is absent."""
        ...

    def validate(self, section: Section, raw: Mapping[str, Any], where: str) -> dict[str, Any]:
        """A table checked against ``section`` (errors name it ``where``), e.g. one entry of
        a list of tables."""
        ...

    def import_function(self, reference: str, where: str) -> Callable[..., Any]:
        """The function named ``"file:function"`` in the Python file beside the scenario, not
        yet loaded: it runs nothing until the whole scenario is valid (a build function must
        not call it; :attr:`Built.user_checks`; :mod:`tumble.io.user_code`)."""
        ...

    def path(self, name: str, where: str) -> Path:
        """The file ``name`` (relative to the scenario's folder, or absolute), which must exist:
        a data file the scenario reads (a mesh); ``where`` names the key in the error."""
        ...

    def run_end(self) -> float:
        """The last time the run asks for, in the units of its ``[run]`` table."""
        ...


@dataclass(frozen=True)
class GivenInputs:
    """:class:`Inputs` of tables that tumble writes itself, for its own checks of published
    cases (:mod:`tumble.analysis.claims.observations`): each section's keys with their defaults
    where a table leaves them out, an angle in radians under its name (``theta``) or in degrees
    (``theta_deg``), no file beside a scenario and no user code. A key a section does not
    declare, or a required key left out, raises ValueError: the tables are tumble's, so that
    is tumble's error.

    An absent optional section is its defaults when every key has one (``[torques]``), else
    None (``[surface]``), as a scenario file's is.
    """

    tables: Mapping[str, Mapping[str, Any]]
    sections: tuple[Section, ...]

    def __getitem__(self, section: str) -> Mapping[str, Any] | None:
        declared = next((s for s in self.sections if s.name == section), None)
        if declared is None:
            return None
        given = self.tables.get(section)
        if given is None and (
            declared.required or any(k.default is REQUIRED for k in declared.keys)
        ):
            if declared.required:
                raise ValueError(f"[{section}] is required")
            return None
        return self.validate(declared, given or {}, section)

    def validate(self, section: Section, raw: Mapping[str, Any], where: str) -> dict[str, Any]:
        names = {k.name for k in section.keys} | {f"{k.name}_deg" for k in section.keys if k.angle}
        unknown = sorted(set(raw) - names)
        if unknown:
            raise ValueError(f"{where}: keys {unknown} are not declared")
        out = {}
        for k in section.keys:
            degrees = raw.get(f"{k.name}_deg") if k.angle else None
            if degrees is not None:  # an angle in degrees, as a scenario file may give it
                if k.name in raw:
                    raise ValueError(f"{where}: give {k.name} or {k.name}_deg, not both")
                out[k.name] = math.radians(float(degrees))
                continue
            if k.name not in raw and k.default is REQUIRED:
                raise ValueError(f"{where}.{k.name} is required")
            out[k.name] = raw.get(k.name, k.default)
        return out

    def import_function(self, reference: str, where: str) -> Callable[..., Any]:
        raise ValueError(f"{where}: tumble's own tables call no user code")

    def path(self, name: str, where: str) -> Path:
        raise ValueError(f"{where}: tumble's own tables read no file")

    def run_end(self) -> float:
        raise ValueError("tumble's own tables have no [run]")


def required(inputs: Inputs, *names: str) -> tuple[Mapping[str, Any], ...]:
    """The values of the required tables ``names`` of a scenario, in that order.

    The loader has checked that every required table is present (an absent one is an input
    error reported there), so a None here is a bug of the model's schema, not of the file.
    """
    found = tuple(inputs[name] for name in names)
    assert all(values is not None for values in found), f"required sections {names}"
    return found  # type: ignore[return-value]


class Scaling(Protocol):
    """Physical units of a scenario: times in seconds to the model's time and back, each
    output column's factor and SI unit, and a summary."""

    def tau_from_time(self, t_s: FloatArray) -> FloatArray: ...

    def time_from_tau(self, tau: FloatArray) -> FloatArray: ...

    def si(self, name: str) -> tuple[float, str, str] | None:
        """(factor, SI unit, SI column name) of the output column ``name``: its SI value is
        factor × the normalised one; None for a column that is the same in both (an angle,
        k², a quaternion)."""
        ...

    def summary(self) -> Mapping[str, Json]: ...


@dataclass(frozen=True)
class Built(Generic[P, S]):
    """What a build function makes of a scenario's values.

    ``scaling`` converts the ``[run]`` times of a physical-units scenario; ``methods`` are the
    default methods when the file names none (None: all the model has). ``user_checks`` call
    the user's functions (a torque at the initial state): the loader runs them only once the
    whole scenario is valid and the user has been told which files run
    (:func:`tumble.io.scenario.load_user_code`); a build function itself never calls them.
    """

    params: P
    initial: S
    scaling: Scaling | None = None
    methods: tuple[str, ...] | None = None
    user_checks: tuple[Callable[[], None], ...] = ()


@dataclass(frozen=True)
class Variant(Generic[P, S]):
    """One way to write a scenario of the model: its tables besides ``model`` and ``run``, and
    how their values become the model's inputs.

    A variant with ``physical = True`` is chosen when the file has a ``[physical]`` table (or
    when the model has no other); its ``[run]`` times are in seconds (``t_end_s``, ``t_s``) or
    days (``t_end_days``, ``t_days``).
    """

    sections: tuple[Section, ...]
    build: Callable[[Inputs], Built[P, S]]
    physical: bool = False
    samples: int = 401  # default number of samples in [run]
    doc: str = ""


@dataclass(frozen=True)
class ScenarioSchema(Generic[P, S]):
    """Every way to write a scenario of the model, and its own ``[run]`` keys beyond the
    common ones (times, samples, methods, tolerances, verify, integrator, averaging)."""

    variants: tuple[Variant[P, S], ...]
    run: tuple[Key, ...] = ()

    @property
    def physical_only(self) -> bool:
        """Whether every scenario of the model is in physical units."""
        return all(v.physical for v in self.variants)

    def variant(self, physical: bool) -> Variant[P, S] | None:
        """The variant for a file with (or without) a ``[physical]`` table."""
        return next((v for v in self.variants if v.physical == physical), None)


def si_column(scaling: Scaling, name: str, units: str = "") -> tuple[tuple[str, float, str], ...]:
    """The SI columns of the output column ``name`` whose unit is ``units``: (SI name, factor
    from the normalised value, SI unit) of each.

    A column :meth:`Scaling.si` converts is written under its SI name; an angle (unit
    ``rad``) under ``<name>_rad`` [rad] and ``<name>_deg`` [deg]; any other (k², q, a
    direction) under its own name, unchanged.
    """
    conv = scaling.si(name)
    if conv is not None:
        factor, unit, si_name = conv
        return ((si_name, factor, unit),)
    if units == "rad":
        return ((f"{name}_rad", 1.0, "rad"), (f"{name}_deg", 180.0 / math.pi, "deg"))
    return ((name, 1.0, units),)


def si_columns(
    scaling: Scaling,
    cols: Mapping[str, FloatArray],
    tau: FloatArray,
    units: Mapping[str, str] | None = None,
) -> dict[str, FloatArray]:
    """A run's columns in SI (:func:`si_column`): the time ``t_s`` [s] and ``t_days`` [d],
    then each column under its SI name or names; ``units`` are the columns' units (an angle's
    is ``rad``)."""
    t_s = scaling.time_from_tau(tau)
    out = {"t_s": t_s, "t_days": t_s / 86400.0}
    for name, values in cols.items():
        for si_name, factor, _unit in si_column(scaling, name, (units or {}).get(name, "")):
            out[si_name] = values if factor == 1.0 else factor * values
    return out
