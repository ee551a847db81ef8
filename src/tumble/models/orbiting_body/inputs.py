"""The orbiting body's inputs, in SI units: the body (inertia tensor, magnetic tensor or a
conducting shape), the orbit, the geomagnetic field, the torques and the initial state, and
their conversion to the normalised variables of the torqued body (:mod:`tumble.models.
torqued_body`), apart from its numerics (:mod:`tumble.models.orbiting_body`).

Normalisation, done here and nowhere else: time t = T0 τ with T0 = 1/|ω(0)| [s], moments of
inertia over I0 = the largest principal moment [kg·m²], moments over I0/T0²; the torque is then
the physical one (ε = 1), small because the orbit's torques are small against I ω².
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from typing import Any, cast

import numpy as np

from tumble._typing import FloatArray
from tumble.bodies import RigidBody
from tumble.errors import ParameterError, ScenarioError, check_range
from tumble.kernels import terms
from tumble.models.base import Column, Declaration
from tumble.models.schema import Built, Inputs, Key, KeyKind, ScenarioSchema, Section, Variant
from tumble.models.torqued_body import inputs as tb
from tumble.rotations import matrix_to_quat, quat_to_matrix
from tumble.space import (
    EARTH_ROTATION,
    Dipole,
    Igrf,
    Orbit,
    OrbitEddyTorque,
    OrbitGravityTorque,
    flat_plate,
    greenwich_sidereal_angle,
    solid_sphere,
    sun_synchronous_inclination,
    thin_cylindrical_shell,
    thin_spherical_shell,
)
from tumble.space.aerodynamics import Accommodation, air_table
from tumble.space.facets import Facets, Optics, box, box_wing, cylinder, from_mesh
from tumble.space.orbit import EARTH_RADIUS
from tumble.space.sun import julian_date
from tumble.torques import (
    CompiledTorque,
    ConstantBodyTorque,
    InternalDissipation,
    Torque,
    TorqueSum,
)

__all__ = ["DAY", "DECLARED", "SHAPES", "Params", "Scaling", "State", "principal_axes"]

SHAPES = ("thin_spherical_shell", "solid_sphere", "thin_cylindrical_shell", "flat_plate")
"""The conducting shapes whose magnetic tensor tumble computes (:mod:`tumble.space.conductors`)."""

DAY = 86400.0  # [s]

# Bounds of the physical inputs: each far beyond any body or orbit tumble is meant for, and
# near enough that every product the model forms (I ω², M B² ω T0/I0, the moments over I0/T0²,
# a³ of the orbit) stays finite in double precision. The scenario keys' allowed values state
# them, so that the reference shows them too.
MASS = 1e9
"""Largest mass [kg]."""
INERTIA = (1e-10, 1e12)
"""Range of the principal moments [kg·m²]: from a gram-sized fragment to far beyond a space
station (~1e8)."""
MAGNETIC_TENSOR = 1e12
"""Largest magnitude of an entry of the magnetic tensor [S·m⁴] (Envisat's shell: ~1e6)."""
CONDUCTIVITY = 1e9
"""Largest conductivity [S/m] (copper: 6e7)."""
SIZE = 1e3
"""Largest radius, length or width of a conductor [m]."""
THICKNESS = 1.0
"""Largest wall thickness of a conductor [m]."""
ORBIT_SIZE = 1e6
"""Largest altitude or semi-major axis [km] (the Moon's orbit: 3.8e5 km)."""
GAUSS = 1e6
"""Largest magnitude of a Gauss coefficient [nT] (the Earth's g10: −3e4)."""
RESIDUAL_MOMENT = 1e3
"""Largest magnitude of a component of the residual moment [N·m]."""
RATE = (1e-9, 1e4)
"""Range of the initial rate |ω| [rad/s]: a turn in two centuries to ~1e5 rpm."""
SPIN_PERIOD = (2.0 * math.pi / RATE[1], 2.0 * math.pi / RATE[0])
"""Range of the spin period [s], that of :data:`RATE`."""


def principal_axes(inertia: Any, name: str = "body.inertia") -> tuple[FloatArray, FloatArray]:
    """Principal moments (ascending) [kg·m²] and the rotation R whose columns are the principal
    axes in the given body axes (det R = +1): J = R diag(I) Rᵀ.

    Raises
    ------
    ParameterError
        For a tensor that is not symmetric, not positive definite, whose moments break the
        triangle inequality, or whose entries or moments leave :data:`INERTIA`.
    """
    try:
        J = np.array(inertia, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(
            f"{name} must be 3 principal moments or a 3×3 tensor [kg m²]"
        ) from None
    if J.shape == (3,):
        J = np.diag(J)
    if J.shape != (3, 3) or not np.all(np.isfinite(J)):
        raise ParameterError(f"{name} must be 3 principal moments or a 3×3 tensor [kg m²]")
    low, high = INERTIA
    if np.max(np.abs(J)) > high:
        raise ParameterError(f"{name}: an entry of magnitude {np.max(np.abs(J)):g} is outside "
                             f"the allowed range [-{high:g}, {high:g}] [kg m²]")  # fmt: skip
    if not np.allclose(J, J.T, rtol=1e-12, atol=1e-12 * np.max(np.abs(J))):
        raise ParameterError(f"{name} must be symmetric (J = Jᵀ)")
    moments, R = np.linalg.eigh(J)
    if moments[0] <= 0.0:
        raise ParameterError(
            f"{name} is not positive definite (principal moments "
            f"{', '.join(f'{m:.6g}' for m in moments)} kg m²; allowed: all > 0)"
        )
    if moments[0] < low:
        raise ParameterError(f"{name}: the smallest principal moment {moments[0]:.6g} kg m² is "
                             f"outside the allowed range [{low:g}, {high:g}]")  # fmt: skip
    RigidBody(*moments.tolist())  # the triangle inequality
    if np.linalg.det(R) < 0.0:
        R[:, 2] = -R[:, 2]
    return moments, R


@dataclass(frozen=True)
class Scaling(tb.Scaling):
    """The torqued body's normalisation (t = T0 τ, inertia over I0, ε = 1) with the outputs of
    an orbiting body in SI: the rate 2T/L [rad/s] and the spin period [s]."""

    def si(self, name: str) -> tuple[float, str, str] | None:
        if name == "rate":
            return 1.0 / self.T0, "rad/s", "rate_rad_s"
        if name == "period":
            return self.T0, "s", "period_s"
        return super().si(name)


@dataclass(frozen=True)
class Params(tb.Params):
    """The torqued body's parameters (principal axes, normalised units) with what an orbiting
    body adds for its outputs: the orbit, the field, the principal axes R in the user's body
    axes (columns), the scales and the epoch."""

    orbit: Orbit | None = None
    magnetic_field: Dipole | Igrf | None = None
    axes: FloatArray = field(default_factory=lambda: np.eye(3))
    T0: float = 1.0  # [s]
    I0: float = 1.0  # [kg m²]
    epoch: str = ""


State = tb.State


# ---------------------------------------------------------------------------------------------
# Scenario keys.

_BODY = Section(
    "body",
    (
        Key("mass", "number", "a mass in (0, 1e9]", "kg", None, doc="for the record only"),
        Key(
            "inertia",
            "any",
            "3 principal moments or a 3×3 symmetric positive-definite tensor, principal "
            "moments in [1e-10, 1e12] and entries at most 1e12 in magnitude",
            "kg m^2",
            doc="in the body axes every other body vector is given in",
        ),
        Key(
            "magnetic_tensor",
            "matrix3",
            "a 3×3 matrix, entries at most 1e12 in magnitude (or give [conductor])",
            "S m^4",
            None,
            doc="eddy-current tensor M: induced dipole M x, x = −dB/dt in the body",
        ),
    ),
    doc="the body, SI units",
)
_CONDUCTOR = Section(
    "conductor",
    (
        Key("shape", "text", " or ".join(f'"{s}"' for s in SHAPES), choices=SHAPES),
        Key("conductivity", "number", "a conductivity in (0, 1e9]", "S/m"),
        Key("radius", "number", "a radius in (0, 1e3] (sphere, shell, cylinder)", "m", None),
        Key("thickness", "number", "a wall thickness in (0, 1] (shells, plate)", "m", None),
        Key("length", "number", "a length in (0, 1e3] (cylinder; plate side)", "m", None),
        Key("width", "number", "a width in (0, 1e3] (plate side)", "m", None),
        Key(
            "axis",
            "vector3",
            "a nonzero body vector",
            "",
            [0.0, 0.0, 1.0],
            doc="the cylinder's axis or the plate's normal, in body axes",
        ),
    ),
    required=False,
    doc="the magnetic tensor from a conducting shape (instead of body.magnetic_tensor)",
)
_ORBIT = Section(
    "orbit",
    (
        Key("altitude", "number", "a circular orbit's altitude in (0, 1e6]", "km", None),
        Key("semi_major_axis", "number", "a semi-major axis in (6378.137, 1e6]", "km", None),
        Key("eccentricity", "number", "a number in [0, 1)", "", None, doc="default 0"),
        Key("inclination", "number", "in [0, π]", "rad", None, angle=True),
        Key(
            "sun_synchronous",
            "boolean",
            "true or false",
            default=False,
            doc="the inclination of a sun-synchronous orbit (instead of inclination)",
        ),
        Key(
            "raan",
            "number",
            "right ascension of the ascending node",
            "rad",
            None,
            angle=True,
            doc="default 0",
        ),
        Key("argp", "number", "argument of perigee", "rad", None, angle=True, doc="default 0"),
        Key(
            "mean_anomaly",
            "number",
            "mean anomaly at the epoch (circular: argument of latitude)",
            "rad",
            None,
            angle=True,
            doc="default 0",
        ),
        Key(
            "tle",
            "any",
            "two lines of a two-line element set",
            default=None,
            doc="the orbit and its epoch from a TLE (SGP4's mean elements; needs sgp4)",
        ),
        Key(
            "j2",
            "boolean",
            "true or false",
            default=True,
            doc="secular drift of node, perigee and mean anomaly under J2",
        ),
        Key(
            "epoch",
            "text",
            'an ISO 8601 UTC time, e.g. "2025-01-01T00:00:00Z"',
            default=None,
            doc="t = 0: the field's epoch and Earth angle (default: the TLE's, or "
            "2025-01-01T00:00:00Z)",
        ),
    ),
    doc="the orbit: circular by altitude or Keplerian elements at the epoch",
)
_FIELD = Section(
    "field",
    (
        Key(
            "model",
            "text",
            '"dipole", "igrf" or "none"',
            default="dipole",
            choices=("dipole", "igrf", "none"),
            doc="igrf: the whole IGRF to `degree` (needs the space extra's ppigrf)",
        ),
        Key(
            "g10",
            "number",
            "Gauss coefficient in [-1e6, 1e6]",
            "nT",
            None,
            doc="default: IGRF-13 at epoch",
        ),
        Key("g11", "number", "Gauss coefficient in [-1e6, 1e6]", "nT", None),
        Key("h11", "number", "Gauss coefficient in [-1e6, 1e6]", "nT", None),
        Key("degree", "integer", "an integer in [1, 13]", "", None, doc="IGRF only; default 13"),
        Key(
            "rotating",
            "boolean",
            "true or false",
            default=True,
            doc="the field turns with the Earth",
        ),
    ),
    required=False,
    doc="the geomagnetic field (default: the IGRF-13 tilted dipole at the epoch)",
)
SURFACE_SHAPES = ("box", "box_wing", "cylinder", "mesh", "facets")
"""The shapes of a ``[surface]``: a cuboid, a bus with a solar array, a closed cylinder (a rocket
body), a mesh file, or facets listed one by one."""
AREA = 1e6
"""Largest facet or solar-array area [m²]."""


def _optics_keys(prefix: str, what: str) -> tuple[Key, ...]:
    """The optical keys of a surface, ``prefix`` before each name (:class:`tumble.space.
    facets.Optics`)."""
    return (
        Key(
            f"{prefix}specular",
            "number",
            "a fraction in [0, 1]",
            "",
            0.0,
            doc=f"{what}: the fraction of light reflected specularly",
        ),
        Key(
            f"{prefix}diffuse",
            "number",
            "a fraction in [0, 1], with specular at most 1",
            "",
            0.0,
            doc=f"{what}: the fraction reflected diffusely (the rest is absorbed)",
        ),
        Key(
            f"{prefix}emissivity",
            "number",
            "in (0, 1]",
            "",
            1.0,
            doc=f"{what}: the emissivity of the outer face",
        ),
    )


_SURFACE = Section(
    "surface",
    (
        Key("shape", "text", " or ".join(f'"{s}"' for s in SURFACE_SHAPES), choices=SURFACE_SHAPES),
        Key(
            "size",
            "vector3",
            "3 edges in (0, 1e3] along the body axes",
            "m",
            None,
            doc="box; box_wing: the bus",
        ),
        Key("radius", "number", "a radius in (0, 1e3]", "m", None, doc="cylinder"),
        Key(
            "length", "number", "a length in (0, 1e3] along body axis x", "m", None, doc="cylinder"
        ),
        Key(
            "sides",
            "integer",
            "an integer in [3, 4096]",
            "",
            64,
            doc="cylinder: the flat strips around it",
        ),
        Key(
            "mesh",
            "text",
            "a mesh file trimesh reads (STL, OBJ, PLY, …), beside the scenario",
            default=None,
            doc="mesh: in metres, body axes; needs the space extra's trimesh",
        ),
        Key(
            "facet",
            "any",
            "a list of tables [[surface.facet]] (area, normal, centre, optics)",
            default=None,
            doc="facets: one table per facet",
        ),
        *_optics_keys("", "the shape (box_wing: the bus)"),
        Key(
            "back_emissivity",
            "number",
            "in [0, 1]",
            "",
            0.0,
            doc="the inner face's emissivity (0: a closed body's surface)",
        ),
        Key(
            "array_area",
            "number",
            "an area in (0, 1e6]",
            "m^2",
            None,
            doc="box_wing: the solar array (a thin panel)",
        ),
        Key(
            "array_normal",
            "vector3",
            "a nonzero body vector",
            "",
            [0.0, 0.0, 1.0],
            doc="box_wing: the array's front face",
        ),
        Key(
            "array_centre", "vector3", "a body point", "m", None, doc="box_wing: the array's centre"
        ),
        *_optics_keys("array_", "box_wing: the array's front"),
        Key(
            "array_back_emissivity",
            "number",
            "in [0, 1]",
            "",
            None,
            doc="box_wing: the array's back (default its front's)",
        ),
        Key(
            "accommodation_normal",
            "number",
            "a fraction in [0, 1]",
            "",
            1.0,
            doc="the air: the share of the normal momentum accommodated (0 specular, 1 diffuse)",
        ),
        Key(
            "accommodation_tangential",
            "number",
            "a fraction in [0, 1]",
            "",
            1.0,
            doc="the air: the share of the tangential momentum accommodated",
        ),
        Key(
            "wall_speed_ratio",
            "number",
            "a number in [0, 1)",
            "",
            0.05,
            doc="the air: the re-emitted molecules' mean speed over the flow's",
        ),
        Key(
            "averaged_illumination",
            "text",
            '"exact" or "expanded"',
            default="exact",
            choices=("exact", "expanded"),
            doc="the averaged equations' sunlit share of each facet: exact (the lit arcs) or "
            "its Fourier series to second order (Benson and Scheeres 2021; faster, approximate)",
        ),
        Key(
            "centre_of_mass",
            "vector3",
            "a point in the shape's coordinates",
            "m",
            [0.0, 0.0, 0.0],
            doc="the facets are taken about it",
        ),
    ),
    required=False,
    doc="the body's outer surface as flat facets, for sunlight (one facet shading another is "
    "ignored)",
)
_FACET = Section(
    "facet",
    (
        Key("area", "number", "an area in (0, 1e6]", "m^2"),
        Key("normal", "vector3", "a nonzero body vector (outward)", ""),
        Key("centre", "vector3", "a body point", "m"),
        *_optics_keys("", "the facet"),
        Key("back_emissivity", "number", "in [0, 1]", "", 0.0),
    ),
    doc='one facet of [surface] with shape = "facets"',
)


_TORQUES = Section(
    "torques",
    (
        Key("eddy_current", "boolean", "true or false", default=True),
        Key("gravity_gradient", "boolean", "true or false", default=True),
        Key(
            "residual_moment",
            "vector3",
            "3 numbers in [-1e3, 1e3] (body axes)",
            "N m",
            [0.0, 0.0, 0.0],
        ),
        Key(
            "dissipation_days",
            "number",
            "a time constant ≥ 0 (0: none)",
            "days",
            0.0,
            doc="internal energy dissipation: the energy above major-axis rotation decays "
            "with this time constant",
        ),
        *(
            Key(k.name, cast(KeyKind, k.kind), k.meaning, k.unit, k.default, doc=k.doc)
            for k in terms.orbit_key_specs()
        ),
    ),
    required=False,
    doc="which torques act (default: eddy current and gravity gradient)",
)
_INITIAL = Section(
    "initial",
    (
        Key("omega", "vector3", "body angular velocity, |ω| in [1e-9, 1e4] rad/s", "rad/s", None),
        Key(
            "omega_deg_s",
            "vector3",
            "body angular velocity, |ω| in [1e-9, 1e4] rad/s",
            "deg/s",
            None,
        ),
        Key("omega_rpm", "vector3", "body angular velocity, |ω| in [1e-9, 1e4] rad/s", "rpm", None),
        Key("spin_period", "number", "a period in [2π·1e-4, 2π·1e9] (with spin_axis)", "s", None),
        Key("spin_axis", "vector3", "a nonzero body vector (with spin_period)", "", None),
        Key(
            "quaternion",
            "vector4",
            "attitude quaternion [q0, q1, q2, q3], body → inertial",
            default=None,
        ),
        Key("psi", "number", "3-1-3 Euler angle ψ", "rad", None, angle=True),
        Key("theta", "number", "3-1-3 Euler angle ϑ", "rad", None, angle=True),
        Key("phi", "number", "3-1-3 Euler angle φ", "rad", None, angle=True),
    ),
    doc="at the epoch: the body rate (one of omega, omega_deg_s, omega_rpm, spin_period with "
    "spin_axis) and the attitude (default identity: body axes on the inertial ones)",
)


def _epoch(text: str) -> datetime:
    try:
        when = datetime.fromisoformat(text.replace("Z", "+00:00"))
        return when.replace(tzinfo=UTC) if when.tzinfo is None else when.astimezone(UTC)
    except (ValueError, OverflowError):  # OverflowError: an offset past year 1 or 9999
        raise ScenarioError(
            f"orbit.epoch = {text!r} is not an ISO 8601 time from year 1 to 9999 (e.g. "
            '"2025-01-01T00:00:00Z")'
        ) from None


DEFAULT_EPOCH = "2025-01-01T00:00:00Z"


def _orbit(o: Mapping[str, Any]) -> tuple[Orbit, datetime]:
    """The orbit and the epoch of the [orbit] table."""
    if o["tle"] is not None:
        return _from_tle(o)
    given = [k for k in ("altitude", "semi_major_axis") if o[k] is not None]
    if len(given) != 1:
        raise ScenarioError("orbit: give altitude [km] (circular), semi_major_axis [km], or tle")
    if o["inclination"] is not None and o["sun_synchronous"]:
        raise ScenarioError("orbit: give inclination or sun_synchronous = true, not both")
    e = 0.0 if o["eccentricity"] is None else o["eccentricity"]
    check_range("orbit.eccentricity", e, low=0.0, high=1.0, low_open=False)
    if given == ["altitude"]:
        check_range("orbit.altitude [km]", o["altitude"], low=0.0, high=ORBIT_SIZE, high_open=False)
        a = EARTH_RADIUS + 1e3 * o["altitude"]
        if e != 0.0:
            raise ScenarioError("orbit: altitude gives a circular orbit; with eccentricity give "
                                "semi_major_axis")  # fmt: skip
    else:
        check_range(
            "orbit.semi_major_axis [km]",
            o["semi_major_axis"],
            low=EARTH_RADIUS / 1e3,
            high=ORBIT_SIZE,
            high_open=False,
        )
        a = 1e3 * o["semi_major_axis"]
    if o["sun_synchronous"]:
        if e != 0.0:
            raise ScenarioError("orbit.sun_synchronous: only for a circular orbit (altitude)")
        inclination = sun_synchronous_inclination((a - EARTH_RADIUS) / 1e3)
    else:
        inclination = 0.0 if o["inclination"] is None else o["inclination"]
    raan, argp, mean = (0.0 if o[k] is None else o[k] for k in ("raan", "argp", "mean_anomaly"))
    epoch = _epoch(DEFAULT_EPOCH if o["epoch"] is None else o["epoch"])
    return Orbit(a, e, inclination, raan, argp, mean, o["j2"]), epoch


def _from_tle(o: Mapping[str, Any]) -> tuple[Orbit, datetime]:
    """The orbit and epoch of ``orbit.tle``, alone: its elements and epoch are the TLE's."""
    others = [k for k in ("altitude", "semi_major_axis", "eccentricity", "inclination", "raan",
                          "argp", "mean_anomaly", "epoch") if o[k] is not None]  # fmt: skip
    if others or o["sun_synchronous"]:
        extra = ", ".join(others or ["sun_synchronous"])
        raise ScenarioError(f"orbit.tle gives the elements and the epoch: drop {extra}")
    lines = o["tle"]
    if not (isinstance(lines, list) and len(lines) == 2 and all(isinstance(x, str) for x in lines)):
        raise ScenarioError("orbit.tle must be a list of the two lines of the element set")
    return Orbit.from_tle(lines[0], lines[1], o["j2"])


def _field(f: Mapping[str, Any] | None, epoch: datetime) -> Dipole | Igrf | None:
    if f is not None and f["model"] == "none":
        return None
    if f is not None and f["model"] == "igrf":
        given = [k for k in ("g10", "g11", "h11") if f[k] is not None]
        if given:
            raise ScenarioError(f'field.{given[0]} is for model = "dipole"; the IGRF has its own')
        degree = 13 if f["degree"] is None else f["degree"]
        if not (isinstance(degree, int) and 1 <= degree <= 13):
            raise ScenarioError(f"field.degree must be an integer in 1–13, got {degree!r}")
        try:
            return Igrf.at(epoch, degree, f["rotating"])
        except ImportError:
            raise ScenarioError(
                'field.model = "igrf" needs the package ppigrf: pip install "tumble[space]"'
            ) from None
    if f is not None:
        for k in ("g10", "g11", "h11"):
            if f[k] is not None:
                check_range(f"field.{k} [nT]", f[k], low=-GAUSS, high=GAUSS, low_open=False,
                            high_open=False)  # fmt: skip
    if f is not None and f["degree"] is not None:
        raise ScenarioError('field.degree is for model = "igrf"; the dipole is degree 1')
    rotating = f is None or f["rotating"]
    rotation = EARTH_ROTATION if rotating else 0.0
    if f is not None and all(f[k] is not None for k in ("g10", "g11", "h11")):
        # The user's coefficients: no table read, any epoch (it sets the Earth's angle only).
        return Dipole(f["g10"], f["g11"], f["h11"], greenwich_sidereal_angle(epoch), rotation)
    reference = Dipole.igrf(epoch)  # refuses an epoch outside the table
    if f is None:
        return reference
    values = {k: reference.__dict__[k] if f[k] is None else f[k] for k in ("g10", "g11", "h11")}
    return Dipole(**values, theta0=reference.theta0, rotation=rotation)


def _direction(field: str, value: Any) -> FloatArray:
    """A body vector of the scenario that gives a direction, checked nonzero (the callers
    normalise it where they use it).

    Parameters
    ----------
    field : str
        The scenario key, for the error (``conductor.axis``).
    value : array_like, shape (3,)
        The vector [any unit; only its direction counts].

    Returns
    -------
    ndarray, shape (3,)
        ``value`` as floats [as given].

    Raises
    ------
    ParameterError
        If ``value`` is the zero vector.
    """
    axis = np.array(value, dtype=float)
    if not np.any(axis):
        raise ParameterError(f"{field} = [0, 0, 0] is not a direction")
    return axis


def _magnetic_tensor(body: Mapping[str, Any], c: Mapping[str, Any] | None) -> FloatArray | None:
    given = body["magnetic_tensor"]
    if given is not None and c is not None:
        raise ScenarioError("body.magnetic_tensor and [conductor]: give one of them")
    if given is not None:
        M = np.array(given, dtype=float)
        if np.max(np.abs(M)) > MAGNETIC_TENSOR:
            raise ParameterError(
                f"body.magnetic_tensor: an entry of magnitude {np.max(np.abs(M)):g} is outside "
                f"the allowed range [-{MAGNETIC_TENSOR:g}, {MAGNETIC_TENSOR:g}] [S m⁴]"
            )
        if not np.allclose(M, M.T, rtol=1e-9, atol=1e-12 * max(np.max(np.abs(M)), 1e-300)):
            raise ParameterError("body.magnetic_tensor must be symmetric (M = Mᵀ)")
        if np.min(np.linalg.eigvalsh(M)) < -1e-12 * np.max(np.abs(M)):
            raise ParameterError("body.magnetic_tensor must be positive semi-definite (a "
                                 "conductor dissipates)")  # fmt: skip
        return M
    if c is None:
        return None
    shape = c["shape"]
    need = {
        "thin_spherical_shell": ("radius", "thickness"),
        "solid_sphere": ("radius",),
        "thin_cylindrical_shell": ("radius", "length", "thickness"),
        "flat_plate": ("length", "width", "thickness"),
    }[shape]
    missing = [k for k in need if c[k] is None]
    if missing:
        raise ScenarioError(f"conductor: a {shape} needs {', '.join(need)} (missing "
                            f"{', '.join(missing)})")  # fmt: skip
    check_range("conductor.conductivity [S/m]", c["conductivity"], low=0.0, high=CONDUCTIVITY,
                high_open=False)  # fmt: skip
    for k in need:
        high = THICKNESS if k == "thickness" else SIZE
        check_range(f"conductor.{k} [m]", c[k], low=0.0, high=high, high_open=False)
    sigma = c["conductivity"]
    if shape == "thin_spherical_shell":
        own = thin_spherical_shell(sigma, c["radius"], c["thickness"])
    elif shape == "solid_sphere":
        own = solid_sphere(sigma, c["radius"])
    elif shape == "thin_cylindrical_shell":
        own = thin_cylindrical_shell(sigma, c["radius"], c["length"], c["thickness"])
    else:
        own = flat_plate(sigma, c["length"], c["width"], c["thickness"])
    axis = _direction("conductor.axis", c["axis"])
    a = axis / np.linalg.norm(axis)
    # Every shape's tensor is diag(M⊥, M⊥, M∥) about its axis: M⊥ (1 − a aᵀ) + M∥ a aᵀ.
    return own[0, 0] * (np.eye(3) - np.outer(a, a)) + own[2, 2] * np.outer(a, a)


def _omega(ini: Mapping[str, Any]) -> FloatArray:
    """The initial body rate [rad/s] from whichever form the scenario gives."""
    forms = [k for k in ("omega", "omega_deg_s", "omega_rpm", "spin_period") if ini[k] is not None]
    if len(forms) != 1:
        raise ScenarioError("initial: give one of omega [rad/s], omega_deg_s, omega_rpm, or "
                            "spin_period [s] with spin_axis")  # fmt: skip
    if (ini["spin_axis"] is not None) != (forms == ["spin_period"]):
        raise ScenarioError("initial: spin_axis goes with spin_period, and only with it")
    if forms == ["spin_period"]:
        check_range("initial.spin_period [s]", ini["spin_period"], low=SPIN_PERIOD[0],
                    high=SPIN_PERIOD[1], low_open=False, high_open=False)  # fmt: skip
        axis = _direction("initial.spin_axis", ini["spin_axis"])
        return 2.0 * math.pi / ini["spin_period"] * axis / np.linalg.norm(axis)
    factor = {"omega": 1.0, "omega_deg_s": math.pi / 180.0, "omega_rpm": math.pi / 30.0}
    w = np.array(ini[forms[0]], dtype=float) * factor[forms[0]]
    if not np.any(w):
        raise ScenarioError(f"initial.{forms[0]} = [0, 0, 0]: the body must rotate (|ω| > 0 "
                            "sets the time scale)")  # fmt: skip
    rate = float(np.linalg.norm(w))
    if not RATE[0] <= rate <= RATE[1]:
        raise ParameterError(f"initial.{forms[0]}: |ω| = {rate:.6g} rad/s is outside the allowed "
                             f"range [{RATE[0]:g}, {RATE[1]:g}] rad/s")  # fmt: skip
    return w


def _attitude(ini: Mapping[str, Any]) -> FloatArray:
    """The initial attitude, normalised (:func:`torqued_body.initial_attitude`)."""
    q = np.asarray(tb.initial_attitude(ini), dtype=float)
    if not np.any(q):
        raise ParameterError("initial.quaternion = [0, 0, 0, 0] is not a rotation")
    return q / np.linalg.norm(q)


def _positive(name: str, value: Any, high: float) -> float:
    """A required positive length or area of the surface, at most ``high``."""
    if value is None:
        raise ScenarioError(f"surface.{name} is missing (the shape needs it)")
    check_range(f"surface.{name}", value, low=0.0, high=high, high_open=False)
    return float(value)


def _optics(values: Mapping[str, Any], prefix: str, where: str, back: float) -> Optics:
    """The :class:`Optics` of a surface's ``prefix``-ed keys, errors naming ``where``."""
    try:
        return Optics(
            values[f"{prefix}specular"],
            values[f"{prefix}diffuse"],
            values[f"{prefix}emissivity"],
            back,
        )
    except ParameterError as exc:
        raise ParameterError(f"{where}.{prefix}{exc}") from None


def _surface(inputs: Inputs) -> tuple[FloatArray | None, FloatArray | None]:
    """The facets of ``[surface]`` about the centre of mass, the user's body axes, as sunlight
    and the air read them (:meth:`tumble.space.facets.Facets.table`,
    :func:`tumble.space.aerodynamics.air_table`); None, None without the table."""
    s = inputs["surface"]
    if s is None:
        return None, None
    shape = s["shape"]
    optics = _optics(s, "", "surface", s["back_emissivity"])
    if shape == "box":
        facets = box(_checked_size(s["size"]), optics)
    elif shape == "box_wing":
        front = _optics(s, "array_", "surface", 0.0)
        rear = (
            front.emissivity if s["array_back_emissivity"] is None else s["array_back_emissivity"]
        )
        if s["array_centre"] is None:
            raise ScenarioError("surface.array_centre is missing (the shape needs it)")
        facets = box_wing(
            _checked_size(s["size"]), optics, _positive("array_area", s["array_area"], AREA),
            _direction("surface.array_normal", s["array_normal"]), s["array_centre"],
            Optics(front.specular, front.diffuse, front.emissivity, 0.0),
            Optics(front.specular, front.diffuse, rear, 0.0),
        )  # fmt: skip
    elif shape == "cylinder":
        sides = s["sides"]
        if not 3 <= sides <= 4096:
            raise ParameterError(f"surface.sides = {sides} is outside the allowed range [3, 4096]")
        facets = cylinder(
            _positive("radius", s["radius"], SIZE),
            _positive("length", s["length"], SIZE),
            optics,
            sides,
        )
    elif shape == "mesh":
        if s["mesh"] is None:
            raise ScenarioError("surface.mesh is missing: the mesh file, beside the scenario")
        facets = from_mesh(inputs.path(s["mesh"], "surface.mesh"), optics)
    else:
        listed = s["facet"]
        if not isinstance(listed, list) or not listed:
            raise ScenarioError('surface: shape = "facets" needs a list [[surface.facet]]')
        rows = []
        for i, raw in enumerate(listed):
            where = f"surface.facet[{i}]"
            if not isinstance(raw, Mapping):
                raise ScenarioError(f"{where} must be a table (area, normal, centre, optics)")
            f = inputs.validate(_FACET, raw, where)
            check_range(f"{where}.area [m²]", f["area"], low=0.0, high=AREA, high_open=False)
            normal = _direction(f"{where}.normal", f["normal"])
            rows.append(
                Facets.of(
                    f["area"],
                    normal / np.linalg.norm(normal),
                    f["centre"],
                    _optics(f, "", where, f["back_emissivity"]),
                )
            )
        facets = rows[0]
        for more in rows[1:]:
            facets = facets + more
    about = facets.shifted(-np.asarray(s["centre_of_mass"], dtype=float))
    for key in ("accommodation_normal", "accommodation_tangential"):
        check_range(f"surface.{key}", s[key], low=0.0, high=1.0, low_open=False, high_open=False)
    check_range("surface.wall_speed_ratio", s["wall_speed_ratio"], low=0.0, high=1.0,
                low_open=False)  # fmt: skip
    air = Accommodation(
        s["accommodation_normal"], s["accommodation_tangential"], s["wall_speed_ratio"]
    )
    return about.table(), air_table(about, air)


def _checked_size(size: Any) -> FloatArray:
    if size is None:
        raise ScenarioError("surface.size is missing (the shape needs it)")
    a = np.asarray(size, dtype=float)
    if np.any(a <= 0.0) or np.any(a > SIZE):
        raise ParameterError(f"surface.size = {a.tolist()} [m]: each edge must be in (0, {SIZE:g}]")
    return a


def _build(inputs: Inputs) -> Built[Params, State]:
    body, orbit_keys, ini = inputs["body"], inputs["orbit"], inputs["initial"]
    torques = inputs["torques"] or {key.name: key.default for key in _TORQUES.keys}
    assert body is not None and orbit_keys is not None and ini is not None  # required
    if body["mass"] is not None:
        check_range("body.mass [kg]", body["mass"], low=0.0, high=MASS, high_open=False)
    moments, R = principal_axes(body["inertia"])
    orbit, epoch = _orbit(orbit_keys)
    field_model = _field(inputs["field"], epoch)
    M = _magnetic_tensor(body, inputs["conductor"])
    w = _omega(ini)
    T0, I0 = 1.0 / float(np.linalg.norm(w)), float(moments[-1])
    full: list[Torque] = []
    mean: list[Torque] = []
    labels: list[str] = []
    if torques["eddy_current"]:
        if M is None:
            raise ScenarioError("torques.eddy_current: give body.magnetic_tensor or [conductor] "
                                "(or eddy_current = false)")  # fmt: skip
        if field_model is None:
            raise ScenarioError('torques.eddy_current needs a field: [field] model = "none"')
        eddy = OrbitEddyTorque(orbit, field_model, R.T @ M @ R * (T0 / I0), T0)
        full.append(eddy)
        mean.append(eddy.averaged())
        labels.append("eddy current")
    if torques["gravity_gradient"]:
        gg = OrbitGravityTorque(orbit, moments / I0, T0)
        full.append(gg)
        mean.append(gg.averaged())
        labels.append("gravity gradient")
    residual = np.asarray(torques["residual_moment"], dtype=float)
    if np.max(np.abs(residual)) > RESIDUAL_MOMENT:
        raise ParameterError(
            f"torques.residual_moment = {residual.tolist()} [N m]: each component must be within "
            f"±{RESIDUAL_MOMENT:g}"
        )
    if np.any(residual):
        moment = ConstantBodyTorque(R.T @ residual * T0**2 / I0)
        full.append(moment)
        mean.append(moment)
        labels.append("residual moment")
    check_range("torques.dissipation_days", torques["dissipation_days"], low=0.0, low_open=False)
    if torques["dissipation_days"] > 0.0:
        damper = InternalDissipation(moments / I0, torques["dissipation_days"] * DAY / T0)
        full.append(damper)
        mean.append(damper)
        labels.append("internal dissipation")
    light, air = _surface(inputs)
    context = terms.OrbitContext(
        orbit.payload(T0),
        None if field_model is None else field_model.payload(T0),
        R,
        T0,
        I0,
        julian_date(epoch),
        light,
        "exact" if inputs["surface"] is None else inputs["surface"]["averaged_illumination"],
        air,
        EARTH_ROTATION * T0,
    )
    for key in terms.ORBIT_KEYS:
        built = key.build(torques[key.name], context)
        if built is not None:
            label, with_orbit, averaged = built
            full.append(CompiledTorque(tuple(with_orbit), label))
            mean.append(CompiledTorque(tuple(averaged), label))
            labels.append(label)
    if not full:
        raise ScenarioError("torques: every torque is off (nothing drives the evolution)")
    q_user = _attitude(ini)
    q = matrix_to_quat(quat_to_matrix(q_user) @ R)  # principal axes → inertial
    p = Params(
        moments / I0,
        1.0,
        full[0] if len(full) == 1 else TorqueSum(tuple(full)),
        orbit.period / T0,
        " + ".join(labels),
        mean[0] if len(mean) == 1 else TorqueSum(tuple(mean)),
        orbit=orbit,
        magnetic_field=field_model,
        axes=R,
        T0=T0,
        I0=I0,
        epoch=epoch.isoformat(),
    )
    return Built(p, State(R.T @ w * T0, q), Scaling(T0, I0))


SCENARIO: ScenarioSchema[Params, State] = ScenarioSchema(
    variants=(
        Variant(
            (_BODY, _CONDUCTOR, _SURFACE, _ORBIT, _FIELD, _TORQUES, _INITIAL),
            _build,
            physical=True,
            doc="tumble normalises t = T0 τ with T0 = 1/|ω(0)| inside",
        ),
    )
)

DECLARED: Declaration[Params, State] = Declaration(
    name="orbiting_body",
    time=Column("t", "time t", "t"),
    methods=("full", "averaged"),
    check=tb.DECLARED.check,
    scenario=SCENARIO,
    orders=(1,),
    engine=True,
    hybrid=True,  # through the gravity gradient's capture (tumble.models.orbiting_body.capture)
)
"""What a scenario of the model may ask for."""
