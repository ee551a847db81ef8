"""Torques as small composable objects.

A torque is called as ``torque(t, q, omega)`` and returns the moment in **body axes**:

* ``t`` — time [the problem's time unit];
* ``q`` — attitude quaternion, scalar first, body → inertial (see :mod:`tumble.rotations`);
* ``omega`` — body angular velocity, shape (3,) [rad per time unit].

Torques add (``t1 + t2``) and scale by numbers (``eps * t``), so the moment (1.2) of the
resisting-medium paper is ``eps * (ConstantBodyTorque(a) + LinearDrag(b) + QuadraticDrag(s))``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError

__all__ = [
    "CallableTorque",
    "ConstantBodyTorque",
    "LinearDrag",
    "QuadraticDrag",
    "ScaledTorque",
    "Torque",
    "TorqueSum",
    "ZeroTorque",
]


def _vector(name: str, value: ArrayLike) -> FloatArray:
    v = np.array(value, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ParameterError(f"{name} must be 3 finite numbers, got {value!r}")
    v.setflags(write=False)
    return v


def _matrix(name: str, value: ArrayLike) -> FloatArray:
    m = np.array(value, dtype=float)
    if m.shape != (3, 3) or not np.all(np.isfinite(m)):
        raise ParameterError(f"{name} must be a 3×3 matrix of finite numbers, got {value!r}")
    m.setflags(write=False)
    return m


class Torque:
    """Base class: a moment in body axes as a function of (t, q, ω)."""

    def __call__(self, t: float, q: FloatArray, omega: FloatArray) -> FloatArray:
        raise NotImplementedError

    def __add__(self, other: Torque) -> Torque:
        if not isinstance(other, Torque):
            return NotImplemented
        left = self.terms if isinstance(self, TorqueSum) else (self,)
        right = other.terms if isinstance(other, TorqueSum) else (other,)
        return TorqueSum(left + right)

    def __mul__(self, factor: float) -> Torque:
        return ScaledTorque(float(factor), self)

    __rmul__ = __mul__


@dataclass(frozen=True, eq=False)
class ZeroTorque(Torque):
    """No external moment (the free body)."""

    def __call__(self, t: float, q: FloatArray, omega: FloatArray) -> FloatArray:
        return np.zeros(3)


@dataclass(frozen=True, eq=False)
class ConstantBodyTorque(Torque):
    """A moment constant in body axes, M = (A1, A2, A3); the first term of (1.2) in seed 000.

    Parameters
    ----------
    moment : array_like, shape (3,)
        Body components [moment unit].
    """

    moment: FloatArray

    def __post_init__(self) -> None:
        object.__setattr__(self, "moment", _vector("moment", self.moment))

    def __call__(self, t: float, q: FloatArray, omega: FloatArray) -> FloatArray:
        return np.array(self.moment)


@dataclass(frozen=True, eq=False)
class LinearDrag(Torque):
    """Linear drag of a resisting medium, M = −B ω; the second term of (1.2) in seed 000.

    Parameters
    ----------
    B : array_like, shape (3, 3)
        Damping matrix in body axes [moment·time/rad]; any sign, off-diagonal entries allowed.
    """

    B: FloatArray

    def __post_init__(self) -> None:
        object.__setattr__(self, "B", _matrix("B", self.B))

    def __call__(self, t: float, q: FloatArray, omega: FloatArray) -> FloatArray:
        return -(self.B @ omega)


@dataclass(frozen=True, eq=False)
class QuadraticDrag(Torque):
    """Quadratic drag, M = −S (ω ∘ |ω|) component-wise; the third term of (1.2) in seed 000.

    Parameters
    ----------
    S : array_like, shape (3, 3)
        Quadratic damping matrix in body axes [moment·time²/rad²].
    """

    S: FloatArray

    def __post_init__(self) -> None:
        object.__setattr__(self, "S", _matrix("S", self.S))

    def __call__(self, t: float, q: FloatArray, omega: FloatArray) -> FloatArray:
        return -(self.S @ (omega * np.abs(omega)))


@dataclass(frozen=True, eq=False)
class TorqueSum(Torque):
    """Sum of torques."""

    terms: tuple[Torque, ...] = field(default=())

    def __call__(self, t: float, q: FloatArray, omega: FloatArray) -> FloatArray:
        total = np.zeros(3)
        for term in self.terms:
            total += term(t, q, omega)
        return total


@dataclass(frozen=True, eq=False)
class ScaledTorque(Torque):
    """A torque multiplied by a constant (e.g. the small parameter ε)."""

    factor: float
    torque: Torque

    def __call__(self, t: float, q: FloatArray, omega: FloatArray) -> FloatArray:
        return self.factor * self.torque(t, q, omega)


@dataclass(frozen=True, eq=False)
class CallableTorque(Torque):
    """A user function ``f(t, q, omega) -> body moment`` wrapped as a :class:`Torque`."""

    function: Callable[[float, FloatArray, FloatArray], ArrayLike]

    def __call__(self, t: float, q: FloatArray, omega: FloatArray) -> FloatArray:
        return np.asarray(self.function(t, q, omega), dtype=float)
