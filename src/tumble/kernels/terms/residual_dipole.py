"""The torque of a permanent (residual) magnetic dipole in the geomagnetic field, M = m × B.

Every spacecraft carries a residual magnetic moment m (currents in its harness and equipment,
magnetised materials), fixed in the body; in the field B of the Earth it feels the moment
m × B (e.g. Wertz (ed.), *Spacecraft Attitude Determination and Control*, §17.2), which
attitude tools for debris model as the object's intrinsic magnetic moment. Two terms:

* ``residual_dipole``: m × Aᵀ B(t) along the orbit, B the tilted dipole or the harmonic field
  (the IGRF) at the body's place (:mod:`tumble.kernels.space`): the full equations;
* ``residual_dipole_mean``: the same averaged over the orbit and the Earth's rotation at a
  fixed attitude, m × Aᵀ ⟨B⟩, with the mean field ⟨B⟩ turning about ξ3 with the node: what
  the averaged equations average over the Euler–Poinsot motion. That average has a closed form:
  with the attitude A = F Rz(χ) G (F's third column L̂, G's third row the body direction ℓ of
  L), A(m × Aᵀ b) = F [Rz(χ) G m]× Fᵀ b, whose mean over the precession angle χ is
  (ℓ·m) L̂ × b, and over the polhode ⟨ℓ·m⟩ = ⟨ℓ_a⟩ m_a (a the encircled axis: the other
  components of ℓ average to zero); ⟨ω·M⟩ = ⟨b·A(ω × m)⟩ keeps only ⟨ℓ·(ω × m)⟩ b·L̂, whose
  polhode mean is zero (ℓ × I⁻¹ℓ is odd in the Jacobi functions), so the term does no work on
  average.

The orbiting body's scenario switches it on with ``[torques] residual_dipole = [mx, my, mz]``
[A·m²], in the body axes of the scenario.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.errors import IntegrationError, ParameterError
from tumble.kernels.frames import node_turned, node_turned_body, scaled_cross, to_body
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3, vec3
from tumble.kernels.lframe import Context, Parts, column_dot, sorted_vector
from tumble.kernels.space import (
    DIPOLE,
    HARMONIC,
    ORBIT,
    dipole_field,
    field_samples,
    harmonic_field,
    orbit_at,
)
from tumble.kernels.terms.base import NODE_RATE, ORBIT_FIELD, OrbitContext, OrbitKey, Term

_DIPOLE = Field("dipole", 3, "A·m²", "the body's magnetic moment m, body axes")
LAYOUT = Layout(
    "residual_dipole",
    (
        ORBIT_FIELD,
        _DIPOLE,
        Field("harmonic", 1, "1", "0: the field is a tilted dipole; 1: a harmonic field", 0.0, 1.0),
    ),
    tail="field",  # kernels.space.DIPOLE or kernels.space.HARMONIC
)
MEAN_LAYOUT = Layout(
    "residual_dipole_mean",
    (
        _DIPOLE,
        Field("field", 3, "T", "⟨B⟩ over the orbit and the Earth's turn, inertial, at t = 0"),
        NODE_RATE,
    ),
)
_AT, _MEAN = LAYOUT.at, MEAN_LAYOUT.at
_FIELD = LAYOUT.size  # the field's payload follows the fixed part
_D, _H = DIPOLE.at, HARMONIC.at


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """f m × Aᵀ B(t), B at the body's place on the orbit."""
    # The body placed once for either field, not by field_at / harmonic_field_at in each
    # branch: that compiles to other roundings (results an ulp apart).
    r, vel = orbit_at(prog, v + _AT.orbit, t)
    vf = v + _FIELD
    if prog[v + _AT.harmonic] == 0.0:
        angle = prog[vf + _D.theta0] + prog[vf + _D.earth_rate] * t
        b, _ = dipole_field(prog, vf, angle, r, vel)
    else:
        angle = prog[vf + _H.theta0] + prog[vf + _H.earth_rate] * t
        b, _ = harmonic_field(prog, vf, angle, r, vel)
    b1, b2, b3 = to_body(a, b[0], b[1], b[2])
    return scaled_cross(f, vec3(prog, v + _AT.dipole), b1, b2, b3)


@jit(INLINE)
def mean_moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """f m × Aᵀ ⟨B⟩, ⟨B⟩(t) its value at t = 0 turned about ξ3 by Ω̇ t."""
    b1, b2, b3 = node_turned_body(a, prog, v + _MEAN.field, v + _MEAN.node_rate, t)
    return scaled_cross(f, vec3(prog, v + _MEAN.dipole), b1, b2, b3)


@jit(INLINE)
def closed(p: FloatArray, v: int, t: float, ctx: Context) -> Parts:
    """⟨ℓ·m⟩ L̂ × ⟨B⟩ across L, nothing along L nor in the power (module notes)."""
    first, a, F = ctx[6], ctx[7], ctx[8]
    m1, m2, m3 = vec3(p, v + _MEAN.dipole)
    c = sorted_vector(p, m1, m2, m3)[a] * first
    x1, x2, x3 = node_turned(p, v + _MEAN.field, v + _MEAN.node_rate, t)
    return -c * column_dot(F, 1, x1, x2, x3), c * column_dot(F, 0, x1, x2, x3), 0.0, 0.0


def mean_peer(
    values: dict[str, Any], f: float, t: Any, w: list[Any], frame: Any, hy: Any
) -> list[Any]:
    m, x, rate = values["dipole"], values["field"], values["node_rate"]
    c, s = hy.cos(rate * t), hy.sin(rate * t)
    b = frame.to_body([c * float(x[0]) - s * float(x[1]), s * float(x[0]) + c * float(x[1]),
                       float(x[2])])  # fmt: skip
    m1, m2, m3 = (float(k) for k in m)
    return [f * (m2 * b[2] - m3 * b[1]), f * (m3 * b[0] - m1 * b[2]), f * (m1 * b[1] - m2 * b[0])]


_FIRST_NODES = 32  # mean anomalies of the first grid, doubled until ⟨B⟩ settles
_MAX_NODES = 2**16
_EARTH_NODES = 8  # Earth angles at least; 2N + 2 for a field of degree N


def mean_field(orbit: FloatArray, field: FloatArray, rtol: float = 1e-12) -> FloatArray:
    """⟨B⟩ [T, inertial axes] over the mean anomaly and the Earth's rotation angle, with the
    node and perigee of t = 0: the trapezoidal rule on both periodic phases, the anomaly's grid
    doubled until the mean changes by at most ``rtol`` of the mean |B|."""
    dipole = field.size == DIPOLE.size
    theta0 = field[_D.theta0] if dipole else field[_H.theta0]
    rate = field[_D.earth_rate] if dipole else field[_H.earth_rate]
    if rate != 0.0:  # the Earth's turn: a phase of its own, averaged
        degree = 1 if dipole else int(field[_H.degree])
        nodes = max(_EARTH_NODES, 2 * degree + 2)
        angles = 2.0 * math.pi * np.arange(nodes) / nodes
    else:  # a field fixed in inertial space: at its angle
        angles = np.array([theta0])

    def sums(n: int, offset: float) -> tuple[FloatArray, float]:
        means = 2.0 * math.pi * (np.arange(n) + offset) / n
        b = field_samples(orbit, field, means, angles, 0.0)[..., :3].reshape(-1, 3)
        return b.sum(axis=0), float(np.linalg.norm(b, axis=1).sum())

    n = _FIRST_NODES
    total, size = sums(n, 0.0)
    mean, scale = total / (n * angles.size), size / (n * angles.size)
    while n < _MAX_NODES:
        more, _ = sums(n, 0.5)
        new = 0.5 * mean + more / (2 * n * angles.size)
        change = float(np.max(np.abs(new - mean)))
        mean, n = new, 2 * n
        if change <= rtol * scale:
            return mean
    raise IntegrationError(
        f"residual dipole: the mean field did not converge in {_MAX_NODES} mean anomalies "
        f"(e = {orbit[ORBIT.at.e]:g})"
    )


def build(value: Any, context: OrbitContext) -> tuple[str, list[Any], list[Any]] | None:
    """The terms of ``[torques] residual_dipole = m`` [A·m², the scenario's body axes]: m × B
    [N·m] in the model's units (times T0²/I0), m in the principal axes."""
    from tumble.kernels.terms import compiled_term  # the registry, loaded by now

    m = np.asarray(value, dtype=float)
    if not np.any(m):
        return None
    if not np.all(np.isfinite(m)) or np.max(np.abs(m)) > 1e9:
        raise ParameterError(
            f"torques.residual_dipole = {m.tolist()} [A m²]: each component must be finite and "
            "within ±1e9"
        )
    if context.field is None:
        raise ParameterError('torques.residual_dipole needs a field: [field] model = "none"')
    dipole = context.axes.T @ m * context.T0**2 / context.I0
    harmonic = float(context.field.size != DIPOLE.size)
    full = compiled_term(
        "residual_dipole",
        {"orbit": context.orbit, "dipole": dipole, "harmonic": harmonic},
        tail=context.field,
    )
    values = {
        "dipole": dipole,
        "field": mean_field(context.orbit, context.field),
        "node_rate": context.orbit[ORBIT.at.raan_rate],
    }
    return "residual dipole", [full], [compiled_term("residual_dipole_mean", values)]


TERMS = (
    Term(
        name="residual_dipole",
        doc="a permanent magnetic dipole along an orbit, M = m × B",
        layout=LAYOUT,
        reads=frozenset({"attitude", "time", "orbit", "field"}),
        moment=moment,
    ),
    Term(
        name="residual_dipole_mean",
        doc="a permanent magnetic dipole in the orbit-averaged field, M = m × ⟨B⟩",
        layout=MEAN_LAYOUT,
        reads=frozenset({"attitude", "time"}),
        moment=mean_moment,
        closed=closed,
        peer=mean_peer,
    ),
)

ORBIT_KEYS = (
    OrbitKey(
        name="residual_dipole",
        kind="vector3",
        meaning="3 numbers (body axes)",
        unit="A m²",
        default=[0.0, 0.0, 0.0],
        doc="a permanent magnetic dipole m: the moment m × B in the geomagnetic field",
        build=build,
    ),
)
