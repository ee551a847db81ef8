"""The registry of torque terms: every term the compiled code evaluates, one module each.

A term module declares its :class:`~tumble.kernels.terms.base.Term` objects in ``TERMS`` (their
parameters, what they read, their compiled moments and averages) and, if a scenario may switch
them on, its ``ORBIT_KEYS``; registering it is one line in :data:`tumble.kernels.terms.NAMES`. From
the registry follow the codes, the program's packing (:func:`compiled_term`, :func:`flatten`)
and the compiled dispatch every kernel uses (:data:`moment_of` and the others below).

A *program* is the flat float array of a sum of terms,
``[number of terms, (code, factor, size, payload...)...]``: each term's header
(:data:`HEADER`) gives its code, the factor that multiplies its moment and its payload's length,
so that a walk over a program needs nothing of the terms it does not evaluate.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from importlib import import_module
from types import ModuleType
from typing import Any

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout
from tumble.kernels.terms import NAMES, CompiledTerm
from tumble.kernels.terms.base import NAN, OrbitContext, OrbitKey, Term, chain

__all__ = [
    "BY_CODE",
    "CODES",
    "HEADER",
    "HEAD_SIZE",
    "MODULES",
    "ORBIT_KEYS",
    "TERMS",
    "CompiledTerm",
    "OrbitContext",
    "OrbitKey",
    "Term",
    "closed_of",
    "code",
    "compiled_term",
    "engine_moment_of",
    "flatten",
    "moment_of",
    "next_term",
    "orbit_moment_of",
    "phase_mean_of",
    "spinner_of",
    "term_of",
    "walk",
]

MODULES: tuple[ModuleType, ...] = tuple(
    import_module(f"tumble.kernels.terms.{name}") for name in NAMES
)
"""The registered term modules (:data:`tumble.kernels.terms.NAMES`), each declaring ``TERMS``
(and optionally ``ORBIT_KEYS``)."""

TERMS: tuple[Term, ...] = tuple(term for module in MODULES for term in module.TERMS)
"""The registered terms. A term's code is its place here plus one."""
ORBIT_KEYS: tuple[OrbitKey, ...] = tuple(
    key for module in MODULES for key in getattr(module, "ORBIT_KEYS", ())
)
"""The keys of the orbiting body's ``[torques]`` section that registered modules declare."""

CODES: dict[str, int] = {term.name: k + 1 for k, term in enumerate(TERMS)}
BY_CODE: dict[int, Term] = {k + 1: term for k, term in enumerate(TERMS)}
if len(CODES) != len(TERMS):
    raise ValueError("two registered terms share a name")

HEADER = Layout(
    "program term",
    (
        Field("code", 1, "1", "the term's code (its place in TERMS, from 1)", 1.0),
        Field("factor", 1, "1", "multiplies the term's moment"),
        Field("size", 1, "1", "length of the payload that follows", 0.0),
    ),
)
"""The header of every term in a program."""
_HEAD = HEADER.at
HEAD_SIZE = HEADER.size
"""Length of a term's header in a program (an int compiled code can read)."""


def code(name: str) -> int:
    """The code of the registered term ``name``."""
    try:
        return CODES[name]
    except KeyError:
        raise ParameterError(f"no torque term {name!r}; registered: {sorted(CODES)}") from None


def term_of(which: int) -> Term:
    """The registered term of code ``which``."""
    try:
        return BY_CODE[which]
    except KeyError:
        raise ParameterError(f"torque program: unknown term code {which}") from None


def compiled_term(
    name: str, values: Mapping[str, Any], *, factor: float = 1.0, tail: ArrayLike = ()
) -> CompiledTerm:
    """One term of a program: the registered term ``name`` with its parameters ``values`` (by
    field name, checked against its layout) and its variable-length ``tail``."""
    which = code(name)
    return which, float(factor), BY_CODE[which].layout.pack(values, tail)


def flatten(terms: Iterable[CompiledTerm]) -> FloatArray:
    """The program of ``terms`` (module notes), read-only."""
    terms = tuple(terms)
    flat: list[float] = [float(len(terms))]
    for which, factor, payload in terms:
        flat += [float(which), float(factor), float(len(payload)), *(float(v) for v in payload)]
    program = np.array(flat)
    program.setflags(write=False)
    return program


def walk(program: FloatArray, start: int = 0) -> list[tuple[Term, float, FloatArray]]:
    """(term, factor, payload) of every term of ``program[start:]``, from Python."""
    out = []
    i = start + 1
    for _ in range(int(program[start])):
        size = int(program[i + _HEAD.size])
        payload = np.asarray(program[i + HEADER.size : i + HEADER.size + size])
        out.append(
            (term_of(int(program[i + _HEAD.code])), float(program[i + _HEAD.factor]), payload)
        )
        i += HEADER.size + size
    return out


@jit(INLINE)
def next_term(prog: FloatArray, i: int) -> int:
    """Index of the term after the one whose header starts at ``prog[i]``."""
    return i + HEAD_SIZE + int(prog[i + _HEAD.size])


def _entries(kind: str, among: Iterable[Term]) -> list[tuple[int, Any]]:
    return [(CODES[t.name], getattr(t, kind)) for t in among if getattr(t, kind) is not None]


_FIXED = [t for t in TERMS if not t.along_orbit]

moment_of = chain(
    "moment_of", _entries("moment", [t for t in TERMS if not t.compiled_apart]), NAN[3]
)
"""``moment_of(code, f, prog, v, t, w1, w2, w3, a)``: the body moment of a term of the common
right-hand side (NaN for a term compiled apart, along an orbit or calling out: only the kind of
every term, ``KIND_ORBITING_BODY``, compiles those)."""
engine_moment_of = chain("engine_moment_of", _entries("moment", _FIXED), NAN[3])
"""The same for every term not along an orbit, a user's callback included: what the averaging
engines' general quadrature evaluates."""
orbit_moment_of = chain("orbit_moment_of", _entries("moment", TERMS), NAN[3])
"""The same for every term."""
phase_mean_of = chain(
    "phase_mean_of", [(CODES[t.name], t.phase_mean or t.moment) for t in _FIXED], NAN[3]
)
"""``phase_mean_of(code, ...)``: the moment averaged over the term's forcing phase, or as it is
at the time t for a term without one."""
closed_of = chain("closed_of", _entries("closed", TERMS), NAN[4])
"""``closed_of(code, p, v, t, ctx)``: a term's closed-form Euler–Poinsot average."""
spinner_of = chain("spinner_of", _entries("spinner", TERMS), NAN[2])
"""``spinner_of(code, p, v, a, c)``: a term's means over the spin angle."""
