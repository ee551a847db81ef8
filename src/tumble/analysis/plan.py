"""The points of a sweep, without running them: grid axes, Monte Carlo draws, what each
point keeps, and the plan that numbers the points.

Plain numpy, so that a sweep file is validated (:mod:`tumble.io.sweep`) before the
integrators, xarray or Dask load; running the points is :mod:`tumble.analysis.sweep`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from tumble._typing import FloatArray
from tumble.errors import ParameterError

__all__ = [
    "MAX_POINTS",
    "PENDING",
    "STATUS",
    "Axis",
    "Distribution",
    "Draw",
    "Keep",
    "Record",
    "Spacing",
    "SweepPlan",
]

MAX_POINTS = 10_000_000
"""Most points a sweep may have (grid × Monte Carlo samples): their records are held in
memory and written to one Dataset."""

STATUS = ("ok", "failed")
"""Meanings of the ``status`` codes 0 and 1; −1 marks a point not yet computed."""

PENDING = -1

Spacing = Literal["values", "linspace", "logspace"]
Distribution = Literal["uniform", "normal", "log_uniform"]


@dataclass(frozen=True)
class Axis:
    """One grid axis: a scenario key and its values.

    Attributes
    ----------
    name : str
        Dimension name in the Dataset.
    key : str
        The scenario key it sets (``parameters.b[2][2]``).
    values : ndarray
        Its values, in the order of the dimension [the key's unit].
    units, long_name : str
        For the coordinate's ``attrs``.
    scale : {"linear", "log"}
        How the values are spaced (``log`` for ``logspace``), for the figures.
    """

    name: str
    key: str
    values: FloatArray
    units: str = ""
    long_name: str = ""
    scale: str = "linear"

    @classmethod
    def spaced(
        cls,
        name: str,
        key: str,
        spacing: Spacing,
        given: Sequence[float],
        units: str = "",
        long_name: str = "",
    ) -> Axis:
        """An axis from a list of values, or ``[start, stop, num]`` spaced evenly
        (``linspace``) or geometrically (``logspace``: the end points, not their exponents).

        Raises
        ------
        ParameterError
            Naming the axis when the entry is not one of those.
        """
        where = f"axis {name!r} ({key}): {spacing}"
        if spacing == "values":
            values = np.asarray(given, dtype=float)
            if values.ndim != 1 or values.size == 0 or not np.all(np.isfinite(values)):
                raise ParameterError(f"{where} must be a non-empty list of finite numbers")
        else:
            if len(given) != 3:
                raise ParameterError(f"{where} = {list(given)!r}: expected [start, stop, num]")
            start, stop, num = (float(v) for v in given)
            if not (math.isfinite(start) and math.isfinite(stop)):
                raise ParameterError(f"{where}: start and stop must be finite numbers")
            if not (math.isfinite(num) and num == int(num) and 1 <= num <= MAX_POINTS):
                raise ParameterError(f"{where}: num = {num:g} must be an integer in [1, 1e7]")
            if spacing == "logspace":
                if start <= 0.0 or stop <= 0.0:
                    raise ParameterError(
                        f"{where} = [{start:g}, {stop:g}, {int(num)}]: the end points must be "
                        "> 0 (they are values, spaced geometrically)"
                    )
                values = np.geomspace(start, stop, int(num))
            else:
                values = np.linspace(start, stop, int(num))
        return cls(
            name, key, values, units, long_name or key, "log" if spacing == "logspace" else "linear"
        )


@dataclass(frozen=True)
class Draw:
    """One Monte Carlo variable: a scenario key and its distribution.

    Attributes
    ----------
    name, key, units, long_name : str
        As for :class:`Axis`.
    distribution : {"uniform", "normal", "log_uniform"}
        ``uniform`` on [low, high]; ``normal`` with (mean, standard deviation); ``log_uniform``
        uniform in log on [low, high] (both > 0).
    a, b : float
        The two parameters, in that order.
    """

    name: str
    key: str
    distribution: Distribution
    a: float
    b: float
    units: str = ""
    long_name: str = ""

    def __post_init__(self) -> None:
        where = f"draw {self.name!r} ({self.key}): {self.distribution} = [{self.a:g}, {self.b:g}]"
        if not (math.isfinite(self.a) and math.isfinite(self.b)):
            raise ParameterError(f"{where}: both numbers must be finite")
        if self.distribution == "normal":
            if self.b < 0.0:
                raise ParameterError(f"{where}: the standard deviation must be ≥ 0")
        elif not self.a < self.b:
            raise ParameterError(f"{where}: needs low < high")
        if self.distribution == "log_uniform" and self.a <= 0.0:
            raise ParameterError(f"{where}: needs 0 < low")

    def sample(self, rng: np.random.Generator, n: int) -> FloatArray:
        """``n`` draws from ``rng``."""
        if self.distribution == "uniform":
            return rng.uniform(self.a, self.b, n)
        if self.distribution == "normal":
            return rng.normal(self.a, self.b, n)
        return np.exp(rng.uniform(math.log(self.a), math.log(self.b), n))


@dataclass(frozen=True)
class Keep:
    """What is kept of every run (the sweep file's ``[keep]``).

    Attributes
    ----------
    final : bool
        The final value of every slow variable, per method.
    differences : bool
        The largest |difference| of every variable between each two methods.
    limits : bool
        The model's predicted limits as time → ∞ (numbers and statements).
    stability : bool
        Classification and leading Re λ of the model's stationary motion.
    verify : bool
        The figures of ``tumble verify`` (status, order and error at ε per slow variable);
        costs six more integrations per point.
    series : tuple of str
        Slow variables kept at every sample time of each method (in SI for a physical
        scenario, against its time in seconds): a Monte Carlo's percentile bands.
    """

    final: bool = True
    differences: bool = True
    limits: bool = True
    stability: bool = False
    verify: bool = False
    series: tuple[str, ...] = ()


@dataclass(frozen=True)
class SweepPlan:
    """The points of a sweep: grid axes × Monte Carlo samples, in C order.

    Attributes
    ----------
    axes : tuple of Axis
        Grid axes, one dimension each.
    draws : tuple of Draw
        Monte Carlo variables; with ``samples`` > 0 they add a last dimension ``sample``,
        the same draws at every grid point (common random numbers).
    samples : int
        Monte Carlo sample count (0: none).
    seed : int
        Seed of the draws (numpy's PCG64).
    """

    axes: tuple[Axis, ...]
    draws: tuple[Draw, ...] = ()
    samples: int = 0
    seed: int = 0
    drawn: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if self.samples < 0 or (self.draws and self.samples == 0):
            raise ParameterError(
                f"monte_carlo.samples = {self.samples} must be ≥ 1 when draws are given"
            )
        if not self.axes and self.samples == 0:
            raise ParameterError("sweep: give at least one axis or Monte Carlo draws")
        names = [a.name for a in self.axes] + [d.name for d in self.draws]
        keys = [a.key for a in self.axes] + [d.key for d in self.draws]
        for seen, what in ((names, "name"), (keys, "key")):
            dup = sorted({x for x in seen if seen.count(x) > 1})
            if dup:
                raise ParameterError(f"sweep: the {what} {dup[0]!r} is swept twice")
        if "sample" in names:
            raise ParameterError("sweep: 'sample' is the Monte Carlo dimension, not a name")
        size = math.prod(a.values.size for a in self.axes) * max(1, self.samples)
        if size > MAX_POINTS:
            raise ParameterError(
                f"sweep: {size:.3g} points, more than {MAX_POINTS:.0e} (a sweep's records are "
                "held in memory): fewer axis values or Monte Carlo samples"
            )
        rng = np.random.default_rng(self.seed)
        # Each variable's draws in turn, so adding a draw does not change the earlier ones.
        drawn = (
            np.column_stack([d.sample(rng, self.samples) for d in self.draws])
            if (self.draws)
            else np.empty((self.samples, 0))
        )
        object.__setattr__(self, "drawn", drawn)

    @property
    def dims(self) -> tuple[str, ...]:
        """Dataset dimensions: the axes, then ``sample`` for Monte Carlo."""
        return tuple(a.name for a in self.axes) + (("sample",) if self.samples else ())

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(a.values.size for a in self.axes) + ((self.samples,) if self.samples else ())

    @property
    def size(self) -> int:
        return math.prod(self.shape)

    def assignments(self, index: int) -> dict[str, float]:
        """Scenario key → value at flat point ``index`` (C order over :attr:`dims`)."""
        where = np.unravel_index(index, self.shape)
        out = {a.key: float(a.values[i]) for a, i in zip(self.axes, where, strict=False)}
        if self.samples:
            row = self.drawn[where[-1]]
            out.update({d.key: float(v) for d, v in zip(self.draws, row, strict=True)})
        return out


# What each point keeps: plain values, so a record is JSON and crosses processes cheaply.
Record = dict[str, Any]
