"""The torque terms: every term the compiled code evaluates, one module each, and their registry.

Registering a term is one line: its module's name in :data:`NAMES`. The registry itself
(:mod:`tumble.kernels.terms.registry`: the codes, the packing, the program walk and the
compiled dispatch generated from the modules' declarations) loads numba; this package's own
namespace does not, so that a scenario can be validated before any numerics load: the keys that
term modules add to the orbiting body's scenario are read from their declarations' source
(:func:`orbit_key_specs`, literal values only), and every other name of the registry is
loaded on first access (``terms.compiled_term``, ``from tumble.kernels.terms import TERMS``).
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from functools import cache
from importlib import import_module
from pathlib import Path
from typing import Any

__all__ = ["NAMES", "CompiledTerm", "KeySpec", "orbit_key_specs"]

CompiledTerm = tuple[int, float, tuple[float, ...]]
"""One term of a compiled torque: (code, factor, payload)."""

NAMES: tuple[str, ...] = (
    "body_constant",
    "linear_drag",
    "quadratic_drag",
    "inertial_constant",
    "gravity_gradient",
    "eddy_current",
    "user",
    "orbit_eddy",
    "orbit_gravity",
    "field_moments",
    "gravity_moments",
    "orbit_eddy_harmonic",
    "residual_dipole",
    "solar_radiation",
    "internal_dissipation",
    "aerodynamic",
)
"""The registered term modules of this package. Append, never reorder: a program stores codes
(a term's place in the registry)."""


@dataclass(frozen=True)
class KeySpec:
    """What a scenario schema needs of an :class:`~tumble.kernels.terms.base.OrbitKey`: its
    name, value type (a kind of the scenario schema, e.g. ``"vector3"``), meaning (what a
    valid value is, as the key reference prints it), unit (SI; tumble converts), default (the
    value that leaves the term off) and doc line; its builder stays with the term."""

    name: str
    kind: str
    meaning: str
    unit: str
    default: Any
    doc: str


_SPEC_FIELDS = ("name", "kind", "meaning", "unit", "default", "doc")


@cache
def orbit_key_specs() -> tuple[KeySpec, ...]:
    """The ``ORBIT_KEYS`` of the registered modules, read from their source without importing
    them (each ``OrbitKey(...)`` with its fields as keyword arguments of literal values; a test
    holds these equal to the imported declarations)."""
    specs = []
    for name in NAMES:
        tree = ast.parse((Path(__file__).parent / f"{name}.py").read_text(encoding="utf-8"))
        for node in tree.body:
            if not (
                isinstance(node, ast.Assign)
                and any(isinstance(t, ast.Name) and t.id == "ORBIT_KEYS" for t in node.targets)
            ):
                continue
            for call in getattr(node.value, "elts", ()):
                kwargs = {k.arg: k.value for k in call.keywords if k.arg in _SPEC_FIELDS}
                specs.append(KeySpec(**{k: ast.literal_eval(v) for k, v in kwargs.items()}))
    return tuple(specs)


def __getattr__(name: str) -> Any:
    """Every other name of the registry, loaded (with numba) on first access."""
    if name.startswith("__"):
        raise AttributeError(name)
    registry = import_module(f"{__name__}.registry")
    try:
        return getattr(registry, name)
    except AttributeError:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
