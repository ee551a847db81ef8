"""Rigid bodies described by their principal moments of inertia."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError, check_range

__all__ = ["TRIANGLE_RTOL", "RigidBody", "proper_sorting"]

TRIANGLE_RTOL = 1e-12
"""Relative slack in the triangle inequality, so that a thin plate I3 = I1 + I2 given in
decimal is accepted (it is a legitimate limiting body)."""


@dataclass(frozen=True, slots=True)
class RigidBody:
    """A rigid body about a fixed point (or its centre of mass), in principal axes.

    Parameters
    ----------
    I1, I2, I3 : float
        Principal moments of inertia [any consistent unit; 1 in normalized problems]. Each
        must be positive and no larger than the sum of the other two (triangle inequality);
        equality is a flat body and is allowed.
    """

    I1: float
    I2: float
    I3: float

    def __post_init__(self) -> None:
        for name in ("I1", "I2", "I3"):
            check_range(f"inertia.{name}", float(getattr(self, name)), low=0.0)
        moments = (self.I1, self.I2, self.I3)
        total = sum(moments)
        for name, value in zip(("I1", "I2", "I3"), moments, strict=True):
            others = total - value
            if value > others * (1.0 + TRIANGLE_RTOL):
                raise ParameterError(
                    f"inertia.{name} = {value:g} breaks the triangle inequality: it must not "
                    f"exceed the sum of the other two moments ({others:g})"
                )

    @classmethod
    def symmetric(cls, I1: float, I3: float) -> RigidBody:
        """A dynamically symmetric body, I1 = I2 equatorial and I3 polar."""
        return cls(I1, I1, I3)

    @property
    def inertia(self) -> FloatArray:
        """Principal moments (I1, I2, I3) as an array."""
        return np.array([self.I1, self.I2, self.I3])

    @property
    def is_symmetric(self) -> bool:
        """True when I1 = I2 (to round-off): the axis x3 is an axis of dynamic symmetry."""
        return bool(np.isclose(self.I1, self.I2, rtol=1e-14, atol=0.0))

    def angular_momentum(self, omega: ArrayLike) -> FloatArray:
        """Body components of the angular momentum, K = I ω [I·rad/time].

        Parameters
        ----------
        omega : array_like, shape (..., 3)
            Body angular velocity [rad/time].
        """
        return np.asarray(omega, dtype=float) * self.inertia

    def kinetic_energy(self, omega: ArrayLike) -> FloatArray:
        """Kinetic energy of rotation, T = ½ ω·Iω [I·rad²/time²].

        Parameters
        ----------
        omega : array_like, shape (..., 3)
            Body angular velocity [rad/time].
        """
        w = np.asarray(omega, dtype=float)
        return 0.5 * np.sum(self.inertia * w * w, axis=-1)


def proper_sorting(inertia: ArrayLike) -> FloatArray:
    """Signed permutation Q (det +1) with Q diag(I) Qᵀ sorted ascending
    (docs/theory/rotating-field.md §8, §16).

    ``v_sorted = Q v_user``; a transposition gets one axis reversed to stay proper.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments in the user's labels [inertia unit].
    """
    order = np.argsort(np.asarray(inertia, dtype=float), kind="stable")
    Q = np.eye(3)[order]
    if np.linalg.det(Q) < 0.0:
        Q[0] *= -1.0  # a transposition: reverse the first sorted axis to keep det = +1
    return Q
