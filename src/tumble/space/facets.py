"""A body's surface as flat facets, each with its optical properties: what sunlight and the
air act on.

A facet is a flat piece of the surface: its area, outward unit normal and centre (body axes,
from the centre of mass), and how it answers light: the fractions of the incident light it
reflects specularly (ρs) and diffusely (ρd, Lambertian), the rest absorbed
(α = 1 − ρs − ρd), and the emissivities of its front and back. The absorbed light is
re-emitted at once as heat (no thermal lag), from the front and the back in proportion to
their emissivities: a facet of a closed body's surface emits from its front only
(``back_emissivity`` 0), a thin panel — a solar array — from both faces at one temperature.
Each facet sees the Sun when its normal faces it; one facet shading another (a solar array
over the bus) is ignored, and said so in the theory page.

Builders: :func:`box` (a cuboid, six facets), :func:`plate` (a thin panel, two facets),
:func:`box_wing` (a bus with a solar array), :func:`from_mesh` (any closed triangle mesh:
a ``trimesh.Trimesh``, or a file trimesh reads, STL, OBJ, PLY, …), :func:`cylinder` (a
rocket body: a mesh of ``sides`` flat strips and two caps).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError

__all__ = ["Facets", "Optics", "box", "box_wing", "cylinder", "from_mesh", "plate"]


@dataclass(frozen=True)
class Optics:
    """How a surface answers light (fractions of the incident light, and emissivities).

    Attributes
    ----------
    specular, diffuse : float
        The fractions reflected specularly and diffusely (Lambertian); the rest,
        1 − specular − diffuse, is absorbed [1].
    emissivity : float
        The front face's emissivity [1], in (0, 1].
    back_emissivity : float
        The back face's [1], in [0, 1]: 0 for a facet of a closed body's surface (its heat
        leaves through the front), the other face's for a thin panel.
    """

    specular: float = 0.0
    diffuse: float = 0.0
    emissivity: float = 1.0
    back_emissivity: float = 0.0

    def __post_init__(self) -> None:
        for name in ("specular", "diffuse", "back_emissivity"):
            value = getattr(self, name)
            if not 0.0 <= value <= 1.0:
                raise ParameterError(f"{name} = {value:g} must be in [0, 1]")
        if not 0.0 < self.emissivity <= 1.0:
            raise ParameterError(f"emissivity = {self.emissivity:g} must be in (0, 1]")
        if self.specular + self.diffuse > 1.0:
            raise ParameterError(
                f"specular + diffuse = {self.specular + self.diffuse:g} must be at most 1 "
                "(the rest of the light is absorbed)"
            )


@dataclass(frozen=True)
class Facets:
    """Flat facets of a body's surface, body axes, from its centre of mass.

    Attributes
    ----------
    area : ndarray, shape (n,)
        Areas [m²].
    normal : ndarray, shape (n, 3)
        Outward unit normals [1].
    centre : ndarray, shape (n, 3)
        Centres (the centroid of each facet) [m].
    specular, diffuse, emissivity, back_emissivity : ndarray, shape (n,)
        Each facet's :class:`Optics` [1].
    """

    area: FloatArray
    normal: FloatArray
    centre: FloatArray
    specular: FloatArray
    diffuse: FloatArray
    emissivity: FloatArray
    back_emissivity: FloatArray

    def __post_init__(self) -> None:
        n = self.area.shape[0] if self.area.ndim == 1 else -1
        shapes = {
            "area": (n,),
            "normal": (n, 3),
            "centre": (n, 3),
            "specular": (n,),
            "diffuse": (n,),
            "emissivity": (n,),
            "back_emissivity": (n,),
        }
        for name, shape in shapes.items():
            value = getattr(self, name)
            if n < 1 or value.shape != shape:
                raise ParameterError(f"facets: {name} must have shape {shape}, not {value.shape}")
            if not np.all(np.isfinite(value)):
                raise ParameterError(f"facets: {name} must be finite numbers")
        if np.any(self.area <= 0.0):
            raise ParameterError("facets: every area must be positive [m²]")
        if np.any(np.abs(np.linalg.norm(self.normal, axis=1) - 1.0) > 1e-9):
            raise ParameterError("facets: every normal must be a unit vector")
        Optics(0.0, 0.0)  # the optical ranges, checked facet by facet below
        for i in range(n):
            Optics(
                float(self.specular[i]),
                float(self.diffuse[i]),
                float(self.emissivity[i]),
                float(self.back_emissivity[i]),
            )

    @property
    def absorbed(self) -> FloatArray:
        """α = 1 − ρs − ρd [1]."""
        return 1.0 - self.specular - self.diffuse

    @property
    def thermal(self) -> FloatArray:
        """The share of the absorbed light re-emitted as a push along −n:
        (ε_front − ε_back)/(ε_front + ε_back) [1]."""
        return (self.emissivity - self.back_emissivity) / (self.emissivity + self.back_emissivity)

    def __len__(self) -> int:
        return int(self.area.shape[0])

    def table(self) -> FloatArray:
        """One row per facet, as the compiled solar term reads it
        (:data:`tumble.kernels.terms.solar_radiation.FACET`): the normal n, the centre r [m],
        the areas ks = A (1 − ρs), kp = 2 A ρs, kd = ⅔ A (ρd + α κ) [m²] of the force
        −P ĉ [ks s + (kp ĉ + kd) n] on a facet lit at ĉ = n·s > 0, and the arm r × n [m]."""
        return np.column_stack([
            self.normal,
            self.centre,
            self.area * (1.0 - self.specular),
            2.0 * self.area * self.specular,
            (2.0 / 3.0) * self.area * (self.diffuse + self.absorbed * self.thermal),
            np.cross(self.centre, self.normal),
        ])  # fmt: skip

    @staticmethod
    def of(
        area: ArrayLike, normal: ArrayLike, centre: ArrayLike, optics: Optics | list[Optics]
    ) -> Facets:
        """Facets from their geometry and one :class:`Optics` for all or one each."""
        a = np.atleast_1d(np.asarray(area, dtype=float))
        each = optics if isinstance(optics, list) else [optics] * a.size
        if len(each) != a.size:
            raise ParameterError(f"facets: {len(each)} optics for {a.size} facets")
        return Facets(
            a,
            np.atleast_2d(np.asarray(normal, dtype=float)),
            np.atleast_2d(np.asarray(centre, dtype=float)),
            np.array([o.specular for o in each]),
            np.array([o.diffuse for o in each]),
            np.array([o.emissivity for o in each]),
            np.array([o.back_emissivity for o in each]),
        )

    def shifted(self, offset: ArrayLike) -> Facets:
        """The same facets with every centre moved by ``offset`` [m] (a new centre of mass)."""
        return Facets(
            self.area,
            self.normal,
            self.centre + np.asarray(offset, dtype=float),
            self.specular,
            self.diffuse,
            self.emissivity,
            self.back_emissivity,
        )

    def __add__(self, other: Facets) -> Facets:
        return Facets(
            *(
                np.concatenate([getattr(self, f), getattr(other, f)])
                for f in (
                    "area",
                    "normal",
                    "centre",
                    "specular",
                    "diffuse",
                    "emissivity",
                    "back_emissivity",
                )
            )
        )


def box(size: ArrayLike, optics: Optics, centre: ArrayLike = (0.0, 0.0, 0.0)) -> Facets:
    """The six faces of a cuboid of edges ``size`` = (a, b, c) [m] along the body axes,
    centred at ``centre`` [m]."""
    a = np.asarray(size, dtype=float)
    if a.shape != (3,) or np.any(a <= 0.0):
        raise ParameterError(f"box size = {a.tolist()} must be three positive lengths [m]")
    normals, areas, centres = [], [], []
    for axis in range(3):
        others = [k for k in range(3) if k != axis]
        for sign in (1.0, -1.0):
            n = np.zeros(3)
            n[axis] = sign
            normals.append(n)
            areas.append(a[others[0]] * a[others[1]])
            centres.append(n * a[axis] / 2.0)
    return Facets.of(areas, normals, np.array(centres) + np.asarray(centre, dtype=float), optics)


def plate(
    area: float, normal: ArrayLike, centre: ArrayLike, front: Optics, back: Optics | None = None
) -> Facets:
    """A thin flat panel of ``area`` [m²]: two facets, the front along ``normal`` and the back
    against it, at one temperature (each re-emits through both faces by their emissivities).
    ``back`` defaults to ``front``'s optics."""
    n = np.asarray(normal, dtype=float)
    size = float(np.linalg.norm(n))
    if size == 0.0 or not np.isfinite(size):
        raise ParameterError("plate normal must be a nonzero vector")
    n = n / size
    rear = back if back is not None else front
    faces = [
        Optics(front.specular, front.diffuse, front.emissivity, rear.emissivity),
        Optics(rear.specular, rear.diffuse, rear.emissivity, front.emissivity),
    ]
    c = np.asarray(centre, dtype=float)
    return Facets.of([area, area], [n, -n], [c, c], faces)


def box_wing(
    bus: ArrayLike,
    bus_optics: Optics,
    array_area: float,
    array_normal: ArrayLike,
    array_centre: ArrayLike,
    front: Optics,
    back: Optics | None = None,
) -> Facets:
    """A box-wing satellite: a cuboid bus of edges ``bus`` [m] centred at the origin and a
    thin solar array (:func:`plate`) of ``array_area`` [m²] at ``array_centre`` [m] facing
    ``array_normal``; shift the result to the centre of mass (:meth:`Facets.shifted`)."""
    return box(bus, bus_optics) + plate(array_area, array_normal, array_centre, front, back)


def from_mesh(mesh: Any, optics: Optics) -> Facets:
    """The triangles of a closed mesh as facets: a ``trimesh.Trimesh`` or a file path that
    trimesh reads (STL, OBJ, PLY, …), in metres, body axes, from the centre of mass."""
    import trimesh

    if isinstance(mesh, (str, Path)):
        path = Path(mesh)
        if not path.is_file():
            raise ParameterError(f"facets: no mesh file {path}")
        try:
            mesh = trimesh.load(str(path), force="mesh")
        except Exception as exc:  # trimesh's own errors, one line
            raise ParameterError(
                f"facets: cannot read {path} as a mesh ({type(exc).__name__}: {exc})"
            ) from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise ParameterError("facets: the mesh holds no triangles")
    keep = mesh.area_faces > 0.0
    return Facets.of(
        mesh.area_faces[keep], mesh.face_normals[keep], mesh.triangles_center[keep], optics
    )


def cylinder(radius: float, length: float, optics: Optics, sides: int = 64) -> Facets:
    """A closed cylinder along body axis 1 (a rocket body's long axis), centred at the origin:
    ``sides`` flat strips around it and its two end caps, as a triangle mesh."""
    import trimesh

    if not (radius > 0.0 and length > 0.0) or sides < 3:
        raise ParameterError(
            f"cylinder radius = {radius:g} and length = {length:g} must be positive [m], "
            f"sides = {sides} at least 3"
        )
    mesh = trimesh.creation.cylinder(radius=radius, height=length, sections=sides)
    along_x = trimesh.transformations.rotation_matrix(np.pi / 2.0, [0.0, 1.0, 0.0])
    mesh.apply_transform(along_x)
    return from_mesh(mesh, optics)
