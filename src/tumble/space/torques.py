"""The torques on a body in Earth orbit, as built-in (compiled) torques: the eddy current in the
geomagnetic field and the gravity gradient along a Keplerian orbit, and their averages over the
orbit and the Earth's rotation.

All four evaluate in compiled code (:mod:`tumble.kernels.terms`, :mod:`tumble.kernels.space`)
in the units of their payloads: ``time_unit`` [s] is the model's unit of time, so that a model
in normalised time T0 gets the orbit's rates times T0 (its moment then in units of
kg·m²/time_unit², with the tensors and moments of inertia as given).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np

from tumble._typing import FloatArray
from tumble.errors import ParameterError, check_range
from tumble.kernels import terms as registry
from tumble.space.geomagnetic import Dipole, Igrf
from tumble.space.moments import field_moments, gravity_factor
from tumble.space.orbit import Orbit
from tumble.torques import CompiledTerm, Torque

__all__ = [
    "FieldMomentsTorque",
    "GravityMomentsTorque",
    "OrbitEddyTorque",
    "OrbitGravityTorque",
]


def _tensor(name: str, value: object) -> FloatArray:
    m = np.array(value, dtype=float)
    if m.shape != (3, 3) or not np.all(np.isfinite(m)):
        raise ParameterError(f"{name} must be a 3×3 matrix of finite numbers, got {value!r}")
    m.setflags(write=False)
    return m


def _moments(name: str, value: object) -> FloatArray:
    v = np.array(value, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)) or np.any(v <= 0.0):
        raise ParameterError(f"{name} must be 3 positive numbers, got {value!r}")
    v.setflags(write=False)
    return v


@functools.lru_cache(maxsize=64)
def _field_moments(orbit: Orbit, field: Dipole | Igrf) -> tuple[FloatArray, FloatArray]:
    """:func:`field_moments` at the epoch, once per orbit and field: the points of a sweep
    that vary only the body share them."""
    S, D = field_moments(orbit, field)
    S.setflags(write=False)
    D.setflags(write=False)
    return S, D


@dataclass(frozen=True, eq=False)
class OrbitEddyTorque(Torque):
    """The eddy-current moment (M x) × B on a conductor of magnetic tensor M moving along
    ``orbit`` in the geomagnetic ``field``, x = ω × B − Aᵀ dB/dt (body axes): minus the rate of
    change of the field seen in the body (:mod:`tumble.space.conductors`).

    Parameters
    ----------
    orbit : Orbit
    field : Dipole or Igrf
    tensor : array_like, shape (3, 3)
        Magnetic tensor in body axes [S·m⁴ times whatever scales the model's moment].
    time_unit : float
        The model's unit of time [s].
    """

    orbit: Orbit
    field: Dipole | Igrf
    tensor: FloatArray
    time_unit: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "tensor", _tensor("magnetic tensor", self.tensor))
        check_range("time_unit", self.time_unit, low=0.0)

    def compiled_terms(self) -> tuple[CompiledTerm, ...]:
        orbit, field = self.orbit.payload(self.time_unit), self.field.payload(self.time_unit)
        if isinstance(self.field, Igrf):
            values = {"orbit": orbit, "tensor": self.tensor}
            return (registry.compiled_term("orbit_eddy_harmonic", values, tail=field),)
        values = {"orbit": orbit, "field": field, "tensor": self.tensor}
        return (registry.compiled_term("orbit_eddy", values),)

    def averaged(self) -> FieldMomentsTorque:
        """The same moment averaged over the orbit and the Earth's rotation."""
        S, D = _field_moments(self.orbit, self.field)
        node_rate = self.orbit.secular_rates()[0]
        return FieldMomentsTorque(self.tensor, S, D * self.time_unit, node_rate * self.time_unit)


@dataclass(frozen=True, eq=False)
class OrbitGravityTorque(Torque):
    """The gravity-gradient moment 3μ/r³ r̂ × (I r̂) along ``orbit`` (body axes principal).

    Parameters
    ----------
    orbit : Orbit
    inertia : array_like, shape (3,)
        Principal moments (I1, I2, I3) [kg·m², or as the model scales them].
    time_unit : float
        The model's unit of time [s].
    """

    orbit: Orbit
    inertia: FloatArray
    time_unit: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "inertia", _moments("inertia", self.inertia))
        check_range("time_unit", self.time_unit, low=0.0)

    def compiled_terms(self) -> tuple[CompiledTerm, ...]:
        values = {"orbit": self.orbit.payload(self.time_unit), "inertia": self.inertia}
        return (registry.compiled_term("orbit_gravity", values),)

    def averaged(self) -> GravityMomentsTorque:
        """The same moment averaged over the orbit."""
        return GravityMomentsTorque(
            self.inertia,
            gravity_factor(self.orbit) * self.time_unit**2,
            self.orbit.normal(),
            self.orbit.secular_rates()[0] * self.time_unit,
        )


@dataclass(frozen=True, eq=False)
class FieldMomentsTorque(Torque):
    """The eddy-current moment averaged over the orbit and the Earth's rotation: (M x) × B with
    the products B Bᵀ and Ḃ Bᵀ replaced by their means S and D, turned about ξ3 by Ω̇ t
    (:mod:`tumble.space.moments`).

    Parameters
    ----------
    tensor : array_like, shape (3, 3)
        Magnetic tensor in body axes.
    S, D : array_like, shape (3, 3)
        ⟨B Bᵀ⟩ and ⟨Ḃ Bᵀ⟩ in inertial axes at t = 0 (D per unit of the model's time).
    node_rate : float
        Ω̇ [rad per unit of time].
    """

    tensor: FloatArray
    S: FloatArray
    D: FloatArray
    node_rate: float = 0.0

    def __post_init__(self) -> None:
        for name in ("tensor", "S", "D"):
            object.__setattr__(self, name, _tensor(name, getattr(self, name)))
        check_range("node_rate", self.node_rate)

    def compiled_terms(self) -> tuple[CompiledTerm, ...]:
        # The mean of Ḃ Bᵀ over a period is antisymmetric (its symmetric part is the mean of
        # d(B Bᵀ)/dt/2, zero): [δ]× with δ from its antisymmetric part.
        D = self.D
        delta = 0.5 * np.array([D[2, 1] - D[1, 2], D[0, 2] - D[2, 0], D[1, 0] - D[0, 1]])
        values = {"tensor": self.tensor, "S": self.S, "delta": delta, "node_rate": self.node_rate}
        return (registry.compiled_term("field_moments", values),)


@dataclass(frozen=True, eq=False)
class GravityMomentsTorque(Torque):
    r"""The gravity gradient averaged over the orbit, −c ĥ × (I ĥ), with the orbit normal ĥ
    turned about ξ3 by Ω̇ t.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments.
    c : float
        :math:`3\mu/(2a^3(1 - e^2)^{3/2})` [per unit of time squared].
    normal : array_like, shape (3,)
        Orbit normal at t = 0 (normalised here).
    node_rate : float
        Ω̇ [rad per unit of time].
    """

    inertia: FloatArray
    c: float
    normal: FloatArray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    node_rate: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "inertia", _moments("inertia", self.inertia))
        check_range("c", self.c, low=0.0, low_open=False)
        h = np.array(self.normal, dtype=float)
        if h.shape != (3,) or not np.all(np.isfinite(h)) or not np.any(h):
            raise ParameterError(f"normal must be a nonzero 3-vector, got {self.normal!r}")
        h = h / np.linalg.norm(h)
        h.setflags(write=False)
        object.__setattr__(self, "normal", h)
        check_range("node_rate", self.node_rate)

    def compiled_terms(self) -> tuple[CompiledTerm, ...]:
        values = {"inertia": self.inertia, "c": self.c, "normal": self.normal}
        return (registry.compiled_term("gravity_moments", {**values, "node_rate": self.node_rate}),)
