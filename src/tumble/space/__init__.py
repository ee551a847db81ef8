"""A body in Earth orbit: orbits with J2 drift, the geomagnetic field (a dipole or the IGRF), the
magnetic tensors of conducting shapes, the eddy-current and gravity-gradient torques along the
orbit and averaged over it, and sunlight: the Sun's direction, the Earth's shadow, a body's
surface as facets and the force and moment of the light on them.

Numerics in SI units; the orbit and the field are evaluated in compiled code
(:mod:`tumble.kernels.space`). From tumble it imports the torques' base, the kernels and its
errors.
"""

from tumble.space.aerodynamics import (
    Accommodation,
    aerodynamic_force_and_moment,
    air_table,
    air_velocity,
    exponential_density,
)
from tumble.space.conductors import (
    flat_plate,
    solid_sphere,
    thin_cylindrical_shell,
    thin_spherical_shell,
    torsion_constant_rectangle,
)
from tumble.space.facets import Facets, Optics, box, box_wing, cylinder, from_mesh, plate
from tumble.space.geomagnetic import (
    DIPOLE_EPOCHS,
    EARTH_ROTATION,
    IGRF13_DIPOLE,
    REFERENCE_RADIUS,
    Dipole,
    Igrf,
    greenwich_sidereal_angle,
)
from tumble.space.moments import field_moments, gravity_factor
from tumble.space.orbit import (
    EARTH_J2,
    EARTH_MU,
    EARTH_RADIUS,
    Orbit,
    sun_synchronous_inclination,
)
from tumble.space.radiation import expanded_coefficients, pressure, radiation_force_and_moment
from tumble.space.sun import eclipse_fraction, julian_date, shadow, sun_direction
from tumble.space.torques import (
    FieldMomentsTorque,
    GravityMomentsTorque,
    OrbitEddyTorque,
    OrbitGravityTorque,
)

__all__ = [
    "DIPOLE_EPOCHS",
    "EARTH_J2",
    "EARTH_MU",
    "EARTH_RADIUS",
    "EARTH_ROTATION",
    "IGRF13_DIPOLE",
    "REFERENCE_RADIUS",
    "Accommodation",
    "Dipole",
    "Facets",
    "FieldMomentsTorque",
    "GravityMomentsTorque",
    "Igrf",
    "Optics",
    "Orbit",
    "OrbitEddyTorque",
    "OrbitGravityTorque",
    "aerodynamic_force_and_moment",
    "air_table",
    "air_velocity",
    "box",
    "box_wing",
    "cylinder",
    "eclipse_fraction",
    "expanded_coefficients",
    "exponential_density",
    "field_moments",
    "flat_plate",
    "from_mesh",
    "gravity_factor",
    "greenwich_sidereal_angle",
    "julian_date",
    "plate",
    "pressure",
    "radiation_force_and_moment",
    "shadow",
    "solid_sphere",
    "sun_direction",
    "sun_synchronous_inclination",
    "thin_cylindrical_shell",
    "thin_spherical_shell",
    "torsion_constant_rectangle",
]
