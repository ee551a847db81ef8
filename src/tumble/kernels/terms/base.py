"""What a torque term declares, and the compiled dispatch generated from the declarations.

A term is one module of :mod:`tumble.kernels.terms` that builds one :class:`Term`: its name,
its parameters as a :class:`~tumble.kernels.layout.Layout`, what the moment reads, its
compiled moment and the averages it offers. The registry (:mod:`tumble.kernels.terms`) numbers
the terms and generates from them:

* the codes and the program's packing (:func:`tumble.kernels.terms.compiled_term`);
* the compiled dispatch on a term's code (:func:`chain`) for the moment, the moment averaged
  over the term's forcing phase, the closed-form Euler–Poinsot average and the spinner's
  average over the spin angle; a term without an average is NaN there, so that the engine
  that asked fails loudly (and chooses another mode from the declarations beforehand);
* the Python readers (:meth:`Term.values`).

The compiled signatures, for a payload starting at ``prog[v]`` and the term's factor f:

* ``moment(f, prog, v, t, w1, w2, w3, a) -> (M1, M2, M3)``: the body moment at time t, body
  rate ω and body → inertial matrix a (:data:`~tumble.kernels.layout.Mat3`);
* ``phase_mean``: the same signature, the moment averaged over the term's own forcing phase
  (:mod:`tumble.kernels.triaxial`);
* ``closed(p, v, t, ctx) -> (T⊥1, T⊥2, T∥, power)``: the Euler–Poinsot average in the L-frame
  (:mod:`tumble.kernels.triaxial_closed`, where ``ctx`` is formed), without the factor;
* ``spinner(p, v, a, c) -> (⟨X⟩, ⟨M3⟩)``: the means over the spin angle φ of a moment of the
  body rate w = (a sin φ, a cos φ, c) (:mod:`tumble.kernels.spinner`), without the factor.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from tumble._typing import FloatArray
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout
from tumble.kernels.space import ORBIT
from tumble.kernels.terms import KeySpec

__all__ = [
    "MAGNETIC_TENSOR",
    "NODE_RATE",
    "ORBIT_FIELD",
    "READS",
    "OrbitContext",
    "OrbitKey",
    "Term",
    "chain",
    "principal_moments",
]

READS: frozenset[str] = frozenset({"rate", "attitude", "time", "orbit", "field"})
"""What a moment may depend on: the body rate, the attitude, the time, a position along an
orbit (Kepler's equation), the geomagnetic field there."""


# Parameters several terms declare alike: one declaration each.
ORBIT_FIELD = Field("orbit", ORBIT.size, doc="the orbit (kernels.space.ORBIT)")
"""A term's orbit, the body's place along it (:data:`tumble.kernels.space.ORBIT`)."""
MAGNETIC_TENSOR = Field("tensor", 9, "A·m²/(T/s)", "magnetic tensor M, body axes, by rows")
"""A conductor's magnetic tensor M: its induced dipole is M x for the field's rate x seen in
the body."""
NODE_RATE = Field("node_rate", 1, "rad/time", "rate of the node Ω̇")
"""The rate at which an orbit-averaged input turns about ξ3 with the orbit's node."""


def principal_moments(unit: str) -> Field:
    """The parameter ``inertia``: the principal moments I1, I2, I3, each at least 0.

    Parameters
    ----------
    unit : str
        Their unit, as the docs print it (e.g. "kg·m²").

    Returns
    -------
    Field
    """
    return Field("inertia", 3, unit, "principal moments I1, I2, I3", 0.0)


@dataclass(frozen=True)
class Term:
    """A torque term's declaration.

    Attributes
    ----------
    name : str
        Its name (a Python identifier), unique in the registry.
    doc : str
        One line: the moment, with its source.
    layout : Layout
        Its parameters (the payload after the program's header).
    reads : frozenset of str
        What the moment depends on (:data:`READS`).
    moment : compiled function
        The body moment (module notes).
    phase_mean, closed, spinner : compiled function or None
        The averages it offers (module notes); None: the engines average it by quadrature.
    forcing_rate : callable or None
        From the unpacked values, the rate [rad/time] of the term's forcing phase (its explicit
        periodic time dependence), or None for none.
    closed_if : callable or None
        From the unpacked values, whether the closed form holds for them (e.g. symmetric
        tensors); None: always, when ``closed`` is given.
    calls_out : bool
        Whether its moment calls code the compiler cannot see (a user's callback): such a term
        is compiled apart from the common right-hand side, as a term along an orbit is, since
        one opaque call in the stage loops keeps LLVM from holding the parameters in registers
        for every other term (measured: the resisting medium's full run 18 % faster without
        the user term in its dispatch).
    quadrature_only : bool
        Whether its average needs the general product rule on every phase (an arbitrary
        function of the time and the attitude, such as a user's), rather than its value at the
        time t or its ``phase_mean`` (a slowly varying term, or one with a forcing phase).
    precession_degree : int
        The degree of its inertial moment and power as trigonometric polynomials of the
        precession angle χ about L: the phase-means kind integrates χ on four nodes, exact to
        degree 3; a term of higher degree without its closed form is averaged by the product
        rule, χ refined (:func:`tumble.averaging.triaxial_kernel`).
    peer : callable or None
        The independent transcription for the heyoka comparison:
        ``peer(values, f, t, w, frame, hy) -> [M1, M2, M3]`` on heyoka expressions (``w`` the
        body rate, ``frame`` the attitude with ``to_body`` and ``to_inertial`` maps of
        3-lists, ``hy`` the heyoka module), or None where no Taylor form exists; a term
        without it is refused by the peer.
    """

    name: str
    doc: str
    layout: Layout
    reads: frozenset[str]
    moment: Callable[..., Any]
    phase_mean: Callable[..., Any] | None = None
    closed: Callable[..., Any] | None = None
    spinner: Callable[..., Any] | None = None
    forcing_rate: Callable[[dict[str, Any]], float] | None = None
    closed_if: Callable[[dict[str, Any]], bool] | None = None
    calls_out: bool = False
    quadrature_only: bool = False
    precession_degree: int = 3
    peer: Callable[..., Any] | None = None

    def __post_init__(self) -> None:
        if not self.name.isidentifier():
            raise ValueError(f"term name {self.name!r} is not an identifier")
        unknown = set(self.reads) - READS
        if unknown:
            raise ValueError(f"term {self.name!r} reads {sorted(unknown)}: not in {sorted(READS)}")

    @property
    def rate_only(self) -> bool:
        """Whether the moment reads nothing but the body rate."""
        return self.reads <= {"rate"}

    @property
    def along_orbit(self) -> bool:
        """Whether the moment is evaluated along an orbit (the orbiting body's kind only)."""
        return "orbit" in self.reads

    @property
    def compiled_apart(self) -> bool:
        """Whether only the right-hand side of every term (``KIND_ORBITING_BODY``) evaluates it:
        a term along an orbit, or one that calls out."""
        return self.along_orbit or self.calls_out

    def values(self, payload: Sequence[float] | FloatArray) -> dict[str, Any]:
        """The named parameters of a packed payload."""
        return self.layout.unpack(payload)

    def has_closed_form(self, payload: Sequence[float] | FloatArray) -> bool:
        """Whether :attr:`closed` gives this term's average for these parameters."""
        if self.closed is None:
            return False
        return self.closed_if is None or self.closed_if(self.values(payload))


@dataclass(frozen=True)
class OrbitContext:
    """What a term switched on from the orbiting body's scenario is built from: the model's
    normalised units and the orbit and field as the compiled code reads them.

    Attributes
    ----------
    orbit : ndarray
        The orbit's payload (:data:`tumble.kernels.space.ORBIT`), rates per unit of model time.
    field : ndarray or None
        The field's payload (a dipole, :data:`~tumble.kernels.space.DIPOLE`, or a harmonic
        field, :data:`~tumble.kernels.space.HARMONIC`), rates per unit of model time; None
        without a field.
    axes : ndarray, shape (3, 3)
        R: the principal axes (columns) in the user's body axes; a user vector v is R.T @ v in
        the principal axes the model integrates in.
    T0 : float
        The model's unit of time [s].
    I0 : float
        The model's unit of inertia [kg·m²]; a moment in N·m is M T0²/I0 in model units.
    jd : float
        The Julian date of t = 0 (the epoch).
    facets : ndarray or None
        The body's surface, one row per facet
        (:data:`tumble.kernels.terms.solar_radiation.FACET`), the user's body axes from the
        centre of mass [m, m²]; None without a ``[surface]``.
    illumination : str
        How the averaged equations light the facets: "exact" or "expanded"
        (:mod:`tumble.kernels.terms.solar_radiation`).
    air : ndarray or None
        The same facets with the air's areas (:func:`tumble.space.aerodynamics.air_table`);
        None without a ``[surface]``.
    earth_rate : float
        The Earth's rotation rate [rad per unit of model time]: the atmosphere's.
    """

    orbit: FloatArray
    field: FloatArray | None
    axes: FloatArray
    T0: float
    I0: float
    jd: float = 2451545.0
    facets: FloatArray | None = None
    illumination: str = "exact"
    air: FloatArray | None = None
    earth_rate: float = 0.0


@dataclass(frozen=True)
class OrbitKey(KeySpec):
    """A key of the orbiting body's ``[torques]`` section that switches on a registered term:
    what the scenario schema reads of it (:class:`~tumble.kernels.terms.KeySpec`: name, value
    type, meaning, unit, the default that leaves the term off, doc line), and its builder.

    Attributes
    ----------
    build : callable
        ``build(value, context)`` → ``(label, full, averaged)`` or None (the term is off):
        the compiled terms (:data:`tumble.kernels.terms.CompiledTerm` lists) of the full
        equations and of the orbit-averaged ones, in the model's units.
    """

    build: Callable[[Any, OrbitContext], Any] = lambda value, context: None


def _nan3(*args: Any) -> tuple[float, float, float]:
    return math.nan, math.nan, math.nan


def _nan2(*args: Any) -> tuple[float, float]:
    return math.nan, math.nan


def _nan4(*args: Any) -> tuple[float, float, float, float]:
    return math.nan, math.nan, math.nan, math.nan


NAN = {2: jit(INLINE)(_nan2), 3: jit(INLINE)(_nan3), 4: jit(INLINE)(_nan4)}
"""Compiled fallbacks returning NaN tuples of 2, 3 and 4: the value of a code a dispatch does not
know (the caller fails loudly instead of ignoring the term)."""


def chain(
    name: str, entries: Sequence[tuple[int, Callable[..., Any]]], fallback: Callable[..., Any]
) -> Callable[..., Any]:
    """A compiled ``name(code, *args)`` calling the function of ``code`` among ``entries``
    (code, compiled function), or ``fallback`` for any other code.

    One function holding the whole ``if`` chain, written from the registry as if by hand: a
    chain of nested functions, one a term, cost a compile each, and LLVM optimised every
    term again at every level (about 2 s of a cold start for ten terms). The generated source
    is compiled under this file's name (numba caches a function by its file), and the
    functions it calls are its closure's cells, by which numba's cache tells two chains
    apart.
    """
    cells = [f"f{k}" for k in range(len(entries))]
    lines = [f"def make({', '.join([*cells, 'fallback'])}):"]
    lines.append(f"    def {name}(which, *args):")
    for (code, _), cell in zip(entries, cells, strict=True):
        lines.append(f"        if which == {int(code)}:")
        lines.append(f"            return {cell}(*args)")
    lines += ["        return fallback(*args)", f"    return {name}"]
    namespace: dict[str, Any] = {}
    exec(compile("\n".join(lines), __file__, "exec"), namespace)
    made = namespace["make"](*(f for _, f in entries), fallback)
    return jit(INLINE)(made)  # type: ignore[no-any-return]
