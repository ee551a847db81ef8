"""Named layouts of the float arrays compiled code reads: one declaration per layout, from which
the offsets, the packing, the unpacking and the readers follow.

Compiled code takes its parameters as one float array (a kind's parameters, a torque program),
because one compiled integrator serves every right-hand side. What each slot means is declared
once, here or where the physics is, as a :class:`Layout` of :class:`Field` objects (name,
number of components, unit, valid range). The layout gives

* :attr:`Layout.at`: the fields' offsets as a named tuple, which numba freezes into compiled
  code as constants: a kernel reads ``prog[v + GRAVITY.at.n]``, never ``prog[v + 3]``;
* :meth:`Layout.pack`: the floats of named values, each checked against its field (shape,
  finite, range), in the declared order;
* :meth:`Layout.unpack`: the named values of a packed payload (for Python readers: the heyoka
  peer, the engines that pick a mode from a term's values).

The compiled readers :func:`vec3`, :func:`mat3` and :func:`mat_vec` read a field of three or
nine components from its offset; a field of one is ``x[v + L.at.name]``.
"""

from __future__ import annotations

import math
from collections import namedtuple
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError
from tumble.kernels.jit import INLINE, jit

__all__ = ["Field", "Layout", "Mat3", "Vec3", "mat3", "mat_vec", "vec3"]

Vec3 = tuple[float, float, float]
Mat3 = tuple[float, float, float, float, float, float, float, float, float]

_SHAPES = {1: (), 3: (3,), 9: (3, 3)}


@dataclass(frozen=True)
class Field:
    """One named slot group of a layout.

    Attributes
    ----------
    name : str
        The name compiled code reads it by (a Python identifier).
    size : int
        Number of floats: 1 (a scalar), 3 (a vector), 9 (a 3×3 matrix by rows), or any other
        count for a block read by its own code (an orbit's elements, a nested layout).
    unit : str
        Unit of every component, as the docs print it ("1" for a pure number).
    doc : str
        What it is, in a few words.
    low, high : float
        Closed range every component must lie in (checked by :meth:`Layout.pack`).
    """

    name: str
    size: int = 1
    unit: str = "1"
    doc: str = ""
    low: float = -math.inf
    high: float = math.inf


@dataclass(frozen=True)
class Layout:
    """An ordered set of :class:`Field` objects, optionally followed by a variable-length tail.

    Parameters
    ----------
    name : str
        What the layout lays out (for messages).
    fields : tuple of Field
        The fixed part, in order.
    tail : str, optional
        Name of a variable-length tail after the fixed part (a user function's parameters, a
        field model's coefficients); its length is stored by whoever packs it.
    """

    name: str
    fields: tuple[Field, ...]
    tail: str | None = None
    at: Any = field(init=False, repr=False, compare=False)
    size: int = field(init=False)

    def __post_init__(self) -> None:
        names = [f.name for f in self.fields]
        if len(set(names)) != len(names):
            raise ValueError(f"layout {self.name!r} declares a field twice: {names}")
        offsets, k = [], 0
        for f in self.fields:
            offsets.append(k)
            k += f.size
        kind = namedtuple(f"{self.name.title().replace(' ', '')}Offsets", names)  # type: ignore[misc]
        object.__setattr__(self, "at", kind(*offsets))
        object.__setattr__(self, "size", k)

    def pack(self, values: Mapping[str, Any], tail: ArrayLike = ()) -> tuple[float, ...]:
        """The floats of ``values`` (one per field, by name) in the declared order, then
        ``tail``; ParameterError naming the field for a missing, misshapen, non-finite or
        out-of-range value."""
        unknown = set(values) - {f.name for f in self.fields}
        if unknown:
            raise ParameterError(f"{self.name}: unknown field(s) {sorted(unknown)}")
        flat: list[float] = []
        for f in self.fields:
            if f.name not in values:
                raise ParameterError(f"{self.name}.{f.name} is missing")
            flat += _checked(self.name, f, values[f.name])
        rest = np.asarray(tail, dtype=float).ravel()
        if rest.size and self.tail is None:
            raise ParameterError(f"{self.name} has no variable-length tail")
        return (*flat, *(float(x) for x in rest))

    def unpack(self, payload: Sequence[float] | FloatArray) -> dict[str, Any]:
        """The named values of a packed payload: floats, (3,) and (3, 3) arrays, (n,) blocks;
        the tail (if declared) under its name."""
        data = np.asarray(payload, dtype=float)
        out: dict[str, Any] = {}
        for f, k in zip(self.fields, self.at, strict=True):
            block = data[k : k + f.size]
            out[f.name] = float(block[0]) if f.size == 1 else block.reshape(_SHAPES.get(f.size, -1))
        if self.tail is not None:
            out[self.tail] = data[self.size :]
        return out


def _checked(layout: str, f: Field, value: Any) -> list[float]:
    x = np.asarray(value, dtype=float)
    if x.size != f.size or (f.size in _SHAPES and x.shape not in ((f.size,), _SHAPES[f.size])):
        raise ParameterError(
            f"{layout}.{f.name} must have {f.size} component(s), got shape {x.shape}"
        )
    if not np.all(np.isfinite(x)):
        raise ParameterError(f"{layout}.{f.name} must be finite, got {x.ravel().tolist()}")
    if np.any(x < f.low) or np.any(x > f.high):
        raise ParameterError(
            f"{layout}.{f.name} = {x.ravel().tolist()} is outside [{f.low:g}, {f.high:g}] "
            f"[{f.unit}]"
        )
    return [float(v) for v in x.ravel()]


@jit(INLINE)
def vec3(x: FloatArray, i: int) -> Vec3:
    """The vector field stored at x[i : i + 3]."""
    return x[i], x[i + 1], x[i + 2]


@jit(INLINE)
def mat3(x: FloatArray, i: int) -> Mat3:
    """The 3×3 matrix field stored by rows at x[i : i + 9]."""
    return x[i], x[i + 1], x[i + 2], x[i + 3], x[i + 4], x[i + 5], x[i + 6], x[i + 7], x[i + 8]


@jit(INLINE)
def mat_vec(x: FloatArray, i: int, v1: float, v2: float, v3: float) -> Vec3:
    """M v for the 3×3 matrix field M stored by rows at x[i : i + 9]."""
    return (
        x[i] * v1 + x[i + 1] * v2 + x[i + 2] * v3,
        x[i + 3] * v1 + x[i + 4] * v2 + x[i + 5] * v3,
        x[i + 6] * v1 + x[i + 7] * v2 + x[i + 8] * v3,
    )
