"""The models tumble ships and the papers they implement, without their numerics.

Each model module takes its name, description and paper from here, and ``tumble models`` lists
them from here without loading a model (numba, scipy): the command answers at once.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["CATALOGUE", "Entry", "Paper"]


@dataclass(frozen=True, slots=True)
class Paper:
    """The paper a model implements."""

    author: str
    year: int
    title: str  # in English

    def __str__(self) -> str:
        return f"{self.author} ({self.year}), {self.title}"


@dataclass(frozen=True)
class Entry:
    """One shipped model: the name a scenario's ``model`` key uses, one line, its paper."""

    name: str
    description: str
    paper: Paper | None


CATALOGUE: dict[str, Entry] = {
    e.name: e
    for e in (
        Entry(
            "resisting_medium",
            "fast-spinning symmetric gyroscope, constant body-fixed moment + linear and "
            "quadratic drag of a resisting medium",
            Paper(
                "A. V. Medvedev",
                1987,
                "Motion of a fast-spinning gyroscope under a constant moment in a resisting medium",
            ),
        ),
        Entry(
            "rotating_field",
            "triaxial conducting body in a rotating magnetic field (eddy-current torque)",
            Paper(
                "Yu. G. Martynenko",
                1979,
                "On the stability of stationary rotations of a rigid body in a magnetic field",
            ),
        ),
        Entry(
            "nonlinear_moment",
            "symmetric body under M0 = A(a·sinθ + b·sin2θ): exact motion, Volosov averaging",
            Paper(
                "V. M. Serov",
                1991,
                "Rotational motion of a dynamically symmetric rigid body under the action of a "
                "nonlinear moment",
            ),
        ),
        Entry(
            "torqued_body",
            "triaxial rigid body under any small torque, averaged by the general engine",
            None,  # the triaxial averaging of the rotating-field paper, for any torque
        ),
        Entry(
            "orbiting_body",
            "satellite or debris in Earth orbit: eddy currents in the geomagnetic field and the "
            "gravity gradient, SI units, over days to years",
            None,  # the rotating-field paper's eddy torque, with an orbit and a real field
        ),
    )
}
"""Every shipped model, in the order ``tumble models`` lists them."""
