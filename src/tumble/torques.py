"""Torques as small composable objects.

A torque is called as ``torque(t, q, omega)`` and returns the moment in **body axes**:

* ``t`` — time [the problem's time unit];
* ``q`` — attitude quaternion, scalar first, body → inertial (see :mod:`tumble.rotations`);
* ``omega`` — body angular velocity, shape (3,) [rad per time unit].

Every built-in torque also accepts batches (``t``, ``q`` of shape (..., 4), ``omega``
(..., 3), broadcast against each other) and returns moments of shape (..., 3): the averaging
engine evaluates all quadrature nodes at once. A torque of the body rate alone
(:attr:`Torque.rate_only`) also accepts ``q = None``.

Torques add (``t1 + t2``) and scale by numbers (``eps * t``), so the moment (1.2) of
Medvedev (1987) is ``eps * (ConstantBodyTorque(a) + LinearDrag(b) + QuadraticDrag(s))``.

The physics of the built-in torques is written once, compiled, in the registered terms of
:mod:`tumble.kernels.terms` (one module each): a built-in torque, or a sum or multiple of them,
flattens into a *program* (:attr:`Torque.program`) that the same compiled code evaluates whether
the integrator or Python calls it. The classes here validate the parameters and pack them by the
terms' declared layouts.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import (
    ParameterError,
    TumbleError,
    UserCodeError,
    check_range,
    shorten,
    state_text,
)
from tumble.kernels import terms as registry
from tumble.kernels.terms import CompiledTerm

__all__ = [
    "CallableTorque",
    "CompiledTerm",
    "CompiledTorque",
    "ConstantBodyTorque",
    "ConstantInertialTorque",
    "EddyCurrentTorque",
    "GravityGradientTorque",
    "InternalDissipation",
    "LinearDrag",
    "QuadraticDrag",
    "ScaledTorque",
    "Torque",
    "TorqueSum",
    "UserTorque",
    "ZeroTorque",
    "inertial_moments_on_grid",
    "split_compiled",
]


_FINITE = {(3,): "3 finite numbers", (3, 3): "a 3×3 matrix of finite numbers"}
"""What a parameter of each shape must be, as its error says."""


def _finite(name: str, value: ArrayLike, shape: tuple[int, ...]) -> FloatArray:
    """A torque's parameter as a read-only float array.

    Parameters
    ----------
    name : str
        The parameter's name, for the error.
    value : array_like
        Its value [the parameter's unit].
    shape : (3,) or (3, 3)
        The shape it must have, a body vector or a matrix in body axes.

    Returns
    -------
    FloatArray
        ``value`` as floats, not writeable; ParameterError if it has another shape or a
        non-finite entry.
    """
    a = np.array(value, dtype=float)
    if a.shape != shape or not np.all(np.isfinite(a)):
        raise ParameterError(f"{name} must be {_FINITE[shape]}, got {value!r}")
    a.setflags(write=False)
    return a


def _vector(name: str, value: ArrayLike) -> FloatArray:
    return _finite(name, value, (3,))


def _matrix(name: str, value: ArrayLike) -> FloatArray:
    return _finite(name, value, (3, 3))


class Torque:
    """Base class: a moment in body axes as a function of (t, q, ω).

    A built-in torque declares its terms (:meth:`compiled_terms`) and is evaluated by the
    compiled terms of :mod:`tumble.kernels.terms`. A subclass written in Python overrides
    ``__call__``; it is then not compiled (unless it also overrides :meth:`compiled_terms`),
    and the integrators and the averaging engines call it from Python.
    """

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if "__call__" in cls.__dict__ and "compiled_terms" not in cls.__dict__:
            cls.compiled_terms = Torque.compiled_terms  # type: ignore[method-assign]

    def __getstate__(self) -> dict[str, Any]:
        # The program is rebuilt where the torque is unpickled: a user term's holds the
        # address of a callback of this process (:mod:`tumble.kernels.user`).
        state = dict(self.__dict__)
        state.pop("program", None)
        state.pop("rate_only", None)
        return state

    def __call__(self, t: ArrayLike, q: ArrayLike | None, omega: ArrayLike) -> FloatArray:
        program = self.program
        if program is None:
            raise NotImplementedError(f"{type(self).__name__} defines no moment")
        return _evaluate(program, self.rate_only, t, q, omega)

    def compiled_terms(self) -> tuple[CompiledTerm, ...] | None:
        """The terms of this torque as the compiled code evaluates them; None when it cannot
        be compiled (a Python function), and the scipy integrator is used instead."""
        return None

    @cached_property
    def program(self) -> FloatArray | None:
        """The torque as the flat program the compiled code evaluates, or None if one of its
        terms is a Python function.

        Layout: ``[number of terms, (code, factor, size, payload...)...]``, with the codes and
        payloads of :mod:`tumble.kernels.terms`.
        """
        terms = self.compiled_terms()
        if terms is None:
            return None
        return registry.flatten(terms)

    @cached_property
    def rate_only(self) -> bool:
        """Whether the moment is known to depend on the body rate alone (compiled terms that
        read neither the attitude nor the time)."""
        terms = self.compiled_terms()
        return terms is not None and all(registry.term_of(code).rate_only for code, _, _ in terms)

    @cached_property
    def compiled_apart(self) -> bool:
        """Whether a compiled term runs only on the right-hand side of every term
        (``KIND_ORBITING_BODY``): a term along an orbit or one that calls out (a user's numba
        function)."""
        return any(
            registry.term_of(code).compiled_apart for code, _, _ in self.compiled_terms() or ()
        )

    @cached_property
    def along_orbit(self) -> bool:
        """Whether a compiled term is evaluated along an orbit (Kepler's equation, the
        geomagnetic field): such a program runs on the orbiting body's right-hand side."""
        return any(registry.term_of(code).along_orbit for code, _, _ in self.compiled_terms() or ())

    def __add__(self, other: Torque) -> Torque:
        if not isinstance(other, Torque):
            return NotImplemented
        left = self.terms if isinstance(self, TorqueSum) else (self,)
        right = other.terms if isinstance(other, TorqueSum) else (other,)
        return TorqueSum(left + right)

    def __mul__(self, factor: float) -> Torque:
        return ScaledTorque(float(factor), self)

    __rmul__ = __mul__


_IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])


def _evaluate(
    program: FloatArray, rate_only: bool, t: ArrayLike, q: ArrayLike | None, omega: ArrayLike
) -> FloatArray:
    """Body moments of a program at (t, q, ω), broadcast over their leading axes."""
    w = np.asarray(omega, dtype=float)
    tt = np.asarray(t, dtype=float)
    if q is None:
        if not rate_only:
            raise ParameterError("q is None, but the torque depends on the attitude")
        quat = _IDENTITY
    else:
        quat = np.asarray(q, dtype=float)
    if w.shape[-1:] != (3,) or quat.shape[-1:] != (4,):
        raise ParameterError(
            f"omega must have shape (..., 3) and q (..., 4), got {w.shape} and {quat.shape}"
        )
    shape = np.broadcast_shapes(tt.shape, quat.shape[:-1], w.shape[:-1])
    args = []
    for x, tail in ((tt, ()), (quat, (4,)), (w, (3,))):
        if x.shape[: x.ndim - len(tail)] not in ((), shape):  # a partial broadcast
            x = np.broadcast_to(x, (*shape, *tail))
        args.append(np.ascontiguousarray(x.reshape(-1, *tail)))
    from tumble.kernels.torque import moments  # compiled: loaded on first evaluation

    return np.asarray(moments(program, *args)).reshape(*shape, 3)


def split_compiled(torque: Torque) -> tuple[Torque, Torque | None]:
    """``torque`` as (compiled part, Python part or None), their sum equal to it: the terms of
    sums and multiples that have a program, and the others."""
    if isinstance(torque, ScaledTorque) and type(torque) is ScaledTorque:
        compiled, python = split_compiled(torque.torque)
        return torque.factor * compiled, None if python is None else torque.factor * python
    if isinstance(torque, TorqueSum) and type(torque) is TorqueSum:
        parts = [split_compiled(term) for term in torque.terms]
        compiled_terms = tuple(c for c, _ in parts)
        python_terms = tuple(p for _, p in parts if p is not None)
        return TorqueSum(compiled_terms), TorqueSum(python_terms) if python_terms else None
    if torque.program is not None:
        return torque, None
    return ZeroTorque(), torque


def inertial_moments_on_grid(
    torque: Torque, t: ArrayLike, A: FloatArray, omega: FloatArray
) -> FloatArray:
    """Inertial components A M of a compiled torque's moment for every attitude at every
    time: A (n, 3, 3) body → inertial, ω (n, 3) body rates, t (m,) → shape (n, m, 3)."""
    program = torque.program
    if program is None:
        raise ParameterError(f"{type(torque).__name__} is not compiled")
    from tumble.kernels.torque import inertial_moments  # compiled

    times = np.ascontiguousarray(np.ravel(np.asarray(t, dtype=float)))
    return np.asarray(
        inertial_moments(
            program, times, np.ascontiguousarray(A, dtype=float),
            np.ascontiguousarray(omega, dtype=float),
        )
    )  # fmt: skip


@dataclass(frozen=True, eq=False)
class ZeroTorque(Torque):
    """No external moment (the free body)."""

    def compiled_terms(self) -> tuple[CompiledTerm, ...]:
        return ()


@dataclass(frozen=True, eq=False)
class CompiledTorque(Torque):
    """A sum of registered terms given as they are packed (:func:`tumble.kernels.terms.
    compiled_term`): the torque of a term that has no class of its own, such as one a module
    of :mod:`tumble.kernels.terms` switches on from a scenario.

    Parameters
    ----------
    terms : tuple of (code, factor, payload)
        The terms.
    label : str
        What the torque is, for messages.
    """

    terms: tuple[CompiledTerm, ...]
    label: str = "compiled torque"

    def compiled_terms(self) -> tuple[CompiledTerm, ...]:
        return tuple(self.terms)


@dataclass(frozen=True, eq=False)
class _OneTerm(Torque):
    """A built-in torque that is one compiled term of :mod:`tumble.kernels.terms` (kind
    ``TERM``) with one parameter, the dataclass's only field, of shape ``SHAPE``: checked finite
    and made read-only on construction."""

    TERM: ClassVar[str]
    SHAPE: ClassVar[tuple[int, ...]]

    def __post_init__(self) -> None:
        (f,) = fields(self)
        object.__setattr__(self, f.name, _finite(f.name, getattr(self, f.name), self.SHAPE))

    def compiled_terms(self) -> tuple[CompiledTerm, ...]:
        (f,) = fields(self)
        return (registry.compiled_term(self.TERM, {f.name: getattr(self, f.name)}),)


@dataclass(frozen=True, eq=False)
class ConstantBodyTorque(_OneTerm):
    """A moment constant in body axes, M = (A1, A2, A3); the first term of (1.2) of Medvedev (1987).

    Parameters
    ----------
    moment : array_like, shape (3,)
        Body components [moment unit].
    """

    TERM = "body_constant"
    SHAPE = (3,)

    moment: FloatArray


@dataclass(frozen=True, eq=False)
class LinearDrag(_OneTerm):
    """Linear drag of a resisting medium, M = −B ω; the second term of (1.2) of Medvedev (1987).

    Parameters
    ----------
    B : array_like, shape (3, 3)
        Damping matrix in body axes [moment·time/rad]; any sign, off-diagonal entries allowed.
    """

    TERM = "linear_drag"
    SHAPE = (3, 3)

    B: FloatArray


@dataclass(frozen=True, eq=False)
class QuadraticDrag(_OneTerm):
    """Quadratic drag, ``M = −S (ω ∘ |ω|)`` component-wise; the third term of (1.2) of
    Medvedev (1987).

    Parameters
    ----------
    S : array_like, shape (3, 3)
        Quadratic damping matrix in body axes [moment·time²/rad²].
    """

    TERM = "quadratic_drag"
    SHAPE = (3, 3)

    S: FloatArray


@dataclass(frozen=True, eq=False)
class TorqueSum(Torque):
    """Sum of torques."""

    terms: tuple[Torque, ...] = field(default=())

    def __call__(self, t: ArrayLike, q: ArrayLike | None, omega: ArrayLike) -> FloatArray:
        if self.program is not None:
            return super().__call__(t, q, omega)
        total = np.zeros(np.shape(omega))
        for term in self.terms:
            total = total + term(t, q, omega)
        return total

    def compiled_terms(self) -> tuple[CompiledTerm, ...] | None:
        parts = [term.compiled_terms() for term in self.terms]
        if any(part is None for part in parts):
            return None
        return tuple(t for part in parts if part is not None for t in part)


@dataclass(frozen=True, eq=False)
class ScaledTorque(Torque):
    """A torque multiplied by a constant (e.g. the small parameter ε)."""

    factor: float
    torque: Torque

    def __call__(self, t: ArrayLike, q: ArrayLike | None, omega: ArrayLike) -> FloatArray:
        if self.program is not None:
            return super().__call__(t, q, omega)
        return self.factor * self.torque(t, q, omega)

    def compiled_terms(self) -> tuple[CompiledTerm, ...] | None:
        inner = self.torque.compiled_terms()
        if inner is None:
            return None
        return tuple((code, self.factor * factor, payload) for code, factor, payload in inner)


@dataclass(frozen=True, eq=False)
class CallableTorque(Torque):
    """A user function ``f(t, q, omega) -> body moment`` wrapped as a :class:`Torque`."""

    function: Callable[[Any, Any, Any], ArrayLike]

    def __call__(self, t: ArrayLike, q: ArrayLike | None, omega: ArrayLike) -> FloatArray:
        return np.asarray(self.function(t, q, omega), dtype=float)


PYTHON_CALLS = [0, 0]
"""Calls of Python user torques: begun, and in progress (the heartbeat and the state that
:mod:`tumble.app.guard` watches)."""


def _where(t: ArrayLike, q: ArrayLike | None, omega: ArrayLike) -> str:
    """Where a user's function was called, for a message: the state, or the size of the grid
    of states the averaging engine passed at once."""
    if np.ndim(omega) > 1:
        return f"one of {int(np.prod(np.shape(omega)[:-1]))} states the averaging engine passed"
    time = float(np.ravel(t)[0])  # (one state: one time)
    return state_text(time, None if q is None else np.ravel(q), np.ravel(omega))


@dataclass(frozen=True, eq=False)
class UserTorque(Torque):
    """A user function ``f(t, q, omega, params) -> body moment`` with its parameters.

    The form a scenario names as ``torque = "module:function"``: ``params`` is the
    scenario's ``[torque_params]`` table, passed unchanged. A function written with numpy
    broadcasting over leading axes of ``q`` and ``omega`` is evaluated on whole quadrature
    grids by the averaging engine; any other is called one state at a time. A function
    compiled with ``numba.njit`` runs in the compiled integrators and averaging kernels
    instead (:meth:`compiled_terms`), with ``params`` as a float array of the table's values.

    Parameters
    ----------
    function : callable
        ``f(t, q, omega, params)`` → body moment, shape (3,) [moment unit].
    params : mapping
        Passed as the fourth argument.
    name : str
        ``"module:function"``, for messages.
    """

    function: Callable[[float, Any, Any, Any], ArrayLike]
    params: Mapping[str, Any] = field(default_factory=dict)
    name: str = "user torque"

    def __call__(self, t: ArrayLike, q: ArrayLike | None, omega: ArrayLike) -> FloatArray:
        """The moment at (t, q, ω), or at every point of arrays of them; a fault of the user's
        function (it raises, or returns anything but finite moments of 3 components) is a
        :class:`~tumble.errors.UserCodeError` naming the function, the state and the fault."""
        if self.program is not None:  # a numba function: through its compiled callback
            from tumble.kernels.user import raise_fault

            moment = super().__call__(t, q, omega)
            raise_fault()
            return moment
        PYTHON_CALLS[0] += 1  # the heartbeat, and the call in progress (tumble.app.guard)
        PYTHON_CALLS[1] += 1
        try:
            moment = np.asarray(self.function(t, q, omega, self.params), dtype=float)
        except TumbleError:
            raise
        except Exception as exc:
            raise UserCodeError(
                f"{self.name} raised {type(exc).__name__}: {shorten(exc)} at {_where(t, q, omega)}"
            ) from None
        finally:
            PYTHON_CALLS[1] -= 1
        if moment.shape[-1:] != (3,) or (np.ndim(omega) == 1 and moment.shape != (3,)):
            raise UserCodeError(
                f"{self.name}: a torque function must return the 3 body components of the "
                f"moment for each state, got shape {moment.shape} at {_where(t, q, omega)}"
            )
        if not np.all(np.isfinite(moment)):
            raise UserCodeError(f"{self.name} returned a moment that is not finite at "
                                f"{_where(t, q, omega)}")  # fmt: skip
        return moment

    def compiled_terms(self) -> tuple[CompiledTerm, ...] | None:
        """A function compiled with ``numba.njit`` runs in the compiled code through a C
        callback (:mod:`tumble.kernels.user`), with ``params`` as a float array of the
        table's values in their order; any other is Python (None)."""
        from tumble.kernels.user import (  # numba
            compiled_user_torque,
            fault_record,
            is_numba_function,
            probe,
        )

        function = inspect.unwrap(self.function, stop=is_numba_function)  # a lazy import too
        if not is_numba_function(function):
            return None
        values = []
        for key, value in self.params.items():
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ParameterError(
                    f"torque_params.{key} = {value!r}: a numba torque function takes numbers "
                    "only (its params arrive as a float array, in the table's order)"
                )
            values.append(float(value))
        # Calls from Python first, so that a function that does not compile for the call,
        # raises or returns anything but 3 finite numbers fails here with its own error; in
        # the run, a fault goes to the function's record (tumble.kernels.user).
        probe(function, self.name, values)
        head = {
            "address": float(compiled_user_torque(function).address),
            "record": float(fault_record(function, self.name, values)),
            "n": float(len(values)),
        }
        return (registry.compiled_term("user", head, tail=values),)


@dataclass(frozen=True, eq=False)
class EddyCurrentTorque(Torque):
    """Eddy-current moment on a spherical conductor in a conical rotating field, (1.2)/(1.3).

    ``M_ξ = k_f H_ξ × (H_ξ × Ω_ξ + dH_ξ/dt) = −M0 [(Ω_ξ − ω ξ3)]_⊥H`` (Martynenko (1979),
    eq. (1.2), with the time derivative of the field that its print drops): minus
    ``M0 = k_f H²`` times the component, perpendicular to the field, of the body's angular
    velocity relative to the field. The field direction is
    ``(sin β cos ωt, sin β sin ωt, cos β)`` in inertial axes.

    Parameters
    ----------
    M0 : float
        Torque factor k_f H² ≥ 0 [moment·time/rad]; in the nondimensional form (1.5) this is ε.
    omega : float
        Field rotation rate about ξ3 [rad/time]; 0 is a static field.
    beta : float
        Angle between the field and ξ3 [rad], in [0, π].
    """

    M0: float
    omega: float
    beta: float

    def __post_init__(self) -> None:
        check_range("M0", self.M0, low=0.0, low_open=False)
        check_range("omega", self.omega)
        check_range("beta", self.beta, low=0.0, high=np.pi, low_open=False, high_open=False)

    def field_direction(self, t: ArrayLike) -> FloatArray:
        """Unit field direction in inertial axes at time ``t``, (1.1); shape (..., 3)."""
        wt = self.omega * np.asarray(t, dtype=float)
        sb, cb = np.sin(self.beta), np.cos(self.beta)
        return np.stack([sb * np.cos(wt), sb * np.sin(wt), np.full_like(wt, cb)], -1)

    def inertial(self, t: ArrayLike, omega_inertial: ArrayLike) -> FloatArray:
        """The moment (1.3) in inertial axes for the inertial angular velocity Ω_ξ: the body
        form at the identity attitude (batched like a call)."""
        assert self.program is not None  # built in
        return _evaluate(self.program, False, t, _IDENTITY, omega_inertial)

    def compiled_terms(self) -> tuple[CompiledTerm, ...]:
        values = {"M0": self.M0, "rate": self.omega, "beta": self.beta}
        return (registry.compiled_term("eddy_current", values),)


@dataclass(frozen=True, eq=False)
class ConstantInertialTorque(_OneTerm):
    """A moment fixed in inertial space (e.g. a thruster misaligned with nothing that turns,
    solar pressure on a slowly tumbling body averaged over its shape): M_body = Aᵀ M.

    Accepts batches: ``q`` of shape (..., 4) gives moments of shape (..., 3).

    Parameters
    ----------
    moment : array_like, shape (3,)
        Inertial components [moment unit].
    """

    TERM = "inertial_constant"
    SHAPE = (3,)

    moment: FloatArray


@dataclass(frozen=True, eq=False)
class GravityGradientTorque(Torque):
    """Gravity-gradient moment on a body in a circular orbit: M = 3n² r̂ × (I r̂), body axes.

    r̂ is the unit vector from the attracting centre to the body, in body axes; n the orbital
    mean motion (n² = μ_E/r³). The orbit frame: the orbit lies in the inertial plane normal
    to ĥ = ``normal`` (its angular momentum: the body moves counter-clockwise about ĥ), e1 is
    the direction of the ascending node, where the orbit crosses the inertial equator ξ1ξ2
    northwards, e1 = ξ3 × ĥ normalised (ξ1 for an equatorial orbit, where no node exists), and
    e2 = ĥ × e1; the body is at r̂(t) = cos u e1 + sin u e2, with u = u0 + nt the argument of
    latitude. For ĥ = (sin Ω sin i, −cos Ω sin i, cos i) (inclination i, right ascension of the
    ascending node Ω) e1 = (cos Ω, sin Ω, 0). Accepts batches of states.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments (I1, I2, I3) [inertia unit]; body axes are principal.
    n : float
        Orbital mean motion > 0 [rad/time].
    normal : array_like, shape (3,)
        Orbit normal in inertial axes (normalized here) [1].
    u0 : float
        Argument of latitude at t = 0, from the ascending node [rad].

    References
    ----------
    The standard first-order expansion of the gravity field over the body, e.g. Wertz (ed.),
    *Spacecraft Attitude Determination and Control*, §17.2.
    """

    inertia: FloatArray
    n: float
    normal: FloatArray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    u0: float = 0.0
    basis: FloatArray = field(init=False, repr=False)  # rows e1, e2, normal (unit)

    def __post_init__(self) -> None:
        inertia = _vector("inertia", self.inertia)
        if np.any(inertia <= 0.0):
            raise ParameterError(f"inertia must be positive, got {inertia.tolist()}")
        object.__setattr__(self, "inertia", inertia)
        check_range("n", self.n, low=0.0)
        normal = _vector("normal", self.normal)
        norm = float(np.linalg.norm(normal))
        if norm == 0.0:
            raise ParameterError("normal must be a nonzero vector")
        k = normal / norm
        node = np.cross([0.0, 0.0, 1.0], k)  # towards the ascending node, |node| = sin i
        size = float(np.linalg.norm(node))
        # An equatorial orbit (sin i below 1e-12) has no node: u is then measured from ξ1.
        e1 = node / size if size > 1e-12 else np.array([1.0, 0.0, 0.0])
        e2 = np.cross(k, e1)
        basis = np.array([e1, e2, k])
        basis.setflags(write=False)
        object.__setattr__(self, "normal", _vector("normal", k))
        object.__setattr__(self, "basis", basis)

    @property
    def period(self) -> float:
        """Orbital period 2π/n [time]."""
        return 2.0 * np.pi / self.n

    def radial(self, t: ArrayLike) -> FloatArray:
        """r̂(t) in inertial axes, shape (..., 3)."""
        u = self.n * np.asarray(t, dtype=float) + self.u0
        e1, e2 = self.basis[0], self.basis[1]
        return np.cos(u)[..., None] * e1 + np.sin(u)[..., None] * e2

    def compiled_terms(self) -> tuple[CompiledTerm, ...]:
        values = {"inertia": self.inertia, "n": self.n, "u0": self.u0, "basis": self.basis}
        return (registry.compiled_term("gravity_gradient", values),)


@dataclass(frozen=True, eq=False)
class InternalDissipation(Torque):
    """Internal energy dissipation: a viscous damper whose contents turn at the body's mean
    rate about L, ``M = −c (ω − (2T/L²) L)`` in body axes, L² = L·L
    (:mod:`tumble.kernels.terms.internal_dissipation`).

    The size of L is kept and the kinetic energy falls at the rate ``c ω⊥·ω⊥`` (ω⊥ the body
    rate across L) until the body turns about its axis of largest inertia. The coefficient c
    is set by the time constant: near that axis the energy above it decays as e^(−t/τ),
    c = 1 / (τ (Σ 1/Iᵢ − 3/I_max)).

    Parameters
    ----------
    inertia : array_like, shape (3,)
        The body's principal moments (I1, I2, I3), in the body axes of the state; not all
        equal [inertia unit].
    tau : float
        The time constant τ > 0 of the energy near major-axis rotation [time].

    References
    ----------
    The energy-sink view of a quasi-rigid body with a damper (e.g. Hughes, *Spacecraft
    Attitude Dynamics*, 1986, on internal energy dissipation); the coefficient from the mean
    of ω⊥·ω⊥ over the small Euler–Poinsot oscillation about the major axis (derived on the
    theory page).
    """

    inertia: FloatArray
    tau: float
    c: float = field(init=False)

    def __post_init__(self) -> None:
        inertia = _vector("inertia", self.inertia)
        if np.any(inertia <= 0.0):
            raise ParameterError(f"inertia must be positive, got {inertia.tolist()}")
        check_range("tau", self.tau, low=0.0)
        spread = float(np.sum(1.0 / inertia) - 3.0 / np.max(inertia))
        # Equal moments (to 1e-12) have no axis to settle on: every rotation is one.
        if spread <= 1e-12 * float(np.sum(1.0 / inertia)):
            raise ParameterError(
                f"inertia = {inertia.tolist()}: internal dissipation needs a largest moment "
                "above the others (a sphere has no axis to settle on)"
            )
        object.__setattr__(self, "inertia", inertia)
        object.__setattr__(self, "tau", float(self.tau))
        object.__setattr__(self, "c", 1.0 / (float(self.tau) * spread))

    def compiled_terms(self) -> tuple[CompiledTerm, ...]:
        values = {"inertia": self.inertia, "c": self.c}
        return (registry.compiled_term("internal_dissipation", values),)
