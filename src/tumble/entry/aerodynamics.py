"""Segmental-conical entry capsule: geometry, mass properties and modified-Newtonian
aerodynamics at any total angle of attack, and the fit of its pitching moment to the
two-term moment M0(θ) = A(a sinθ + b sin2θ), eq. (1.5) of the nonlinear-moment paper.

Body axes: x along the symmetry axis from the heat-shield apex towards the back [m], r the
distance from the axis. The total angle of attack α ∈ [0, π] is the angle between the
vehicle's velocity and the forward axis (-x): α = 0 flies heat shield first, α = π back first.
This α is the paper's θ (§1: e_z the velocity direction, θ the total angle of attack).

Pressure: modified Newtonian theory (Lees 1955), Cp = Cp_max sin²δ on the surface that faces
the flow and Cp = 0 in its shadow, δ the local inclination of the surface to the free stream.
For a convex body (which :class:`Capsule` enforces) the local test is exact visibility, so the
afterbody and the back cap load up at large α. Cp_max is the pitot-pressure coefficient
behind a normal shock (Rayleigh pitot formula, γ = 1.4): Cp_max → 1.8394 as M → ∞. On
each ring of the axisymmetric surface the azimuthal integral of Cp over the windward arc is
done in closed form (``_ring_integrals``), the meridional one by composite Gauss–Legendre
quadrature.

Signs: CA is the force along +x (rearward) over q S, CN the force along the transverse
component of the relative wind over q S, Cm the moment about the centre of mass over q S D,
positive when it tends to **increase** α. A statically stable capsule has Cm < 0 for small
α > 0, and Cm = M0/(q S D) with M0 the paper's moment along the line of nodes, so
a = q S D c1 / A and b = q S D c2 / A (per unit A, [1/s²]).

References
----------
L. Lees, "Hypersonic flow", Proc. 5th International Aeronautical Conference, Los Angeles,
IAS (1955), pp. 241–276 (modified Newtonian theory).
J. D. Anderson, *Hypersonic and High-Temperature Gas Dynamics*, ch. 3 (Newtonian theory;
sphere and disk limits).
Ames Research Staff, *Equations, Tables, and Charts for Compressible Flow*, NACA Report 1135
(1953) (normal shock, Rayleigh pitot formula).
V. M. Serov (1991); docs/theory/nonlinear-moment.md §1, §9, §10.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import brentq

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError, check_range

__all__ = [
    "CP_MAX_HYPERSONIC",
    "SOYUZ_CLASS",
    "AeroCoefficients",
    "Capsule",
    "MomentFit",
    "Trim",
    "coefficients",
    "cp_max",
    "fit_moment",
    "restoring_coefficients",
    "trim_angles",
]

_GAMMA = 1.4  # perfect-gas ratio of specific heats of the pitot formula

# Gauss–Legendre nodes per panel of the meridional quadrature.
_GL_ORDER = 4
_GL_X, _GL_W = np.polynomial.legendre.leggauss(_GL_ORDER)


def cp_max(mach: float = math.inf, gamma: float = _GAMMA) -> float:
    """Stagnation-pressure coefficient behind a normal shock (Rayleigh pitot formula).

    Cp_max = (p02/p∞ - 1) / (γ M²/2) with

        p02/p∞ = [(γ+1)² M² / (4γM² - 2(γ-1))]^(γ/(γ-1)) · (1 - γ + 2γM²)/(γ+1),

    and its limit M → ∞: [(γ+1)²/(4γ)]^(γ/(γ-1)) · 4/(γ+1) (1.8394 for γ = 1.4).

    Parameters
    ----------
    mach : float
        Free-stream Mach number [1], in [1, inf] (Newtonian theory is a hypersonic one; at
        M = 1 the formula meets the isentropic value).
    gamma : float
        Ratio of specific heats [1], in (1, 5/3].

    Returns
    -------
    float
        Cp_max [1].

    References
    ----------
    NACA Report 1135 (1953), Rayleigh supersonic pitot formula; Lees (1955) for its use as
    the Newtonian Cp_max.
    """
    check_range("gamma", gamma, low=1.0, high=5.0 / 3.0, high_open=False)
    e = gamma / (gamma - 1.0)
    if mach == math.inf:
        return ((gamma + 1.0) ** 2 / (4.0 * gamma)) ** e * 4.0 / (gamma + 1.0)
    check_range("mach", mach, low=1.0, low_open=False)
    m2 = mach * mach
    ratio = ((gamma + 1.0) ** 2 * m2 / (4.0 * gamma * m2 - 2.0 * (gamma - 1.0))) ** e * (
        (1.0 - gamma + 2.0 * gamma * m2) / (gamma + 1.0)
    )
    return (ratio - 1.0) / (0.5 * gamma * m2)


CP_MAX_HYPERSONIC: float = cp_max(math.inf)
"""Cp_max in the limit M → ∞ for γ = 1.4 [1] (≈ 1.8394)."""


@dataclass(frozen=True, slots=True)
class Capsule:
    """Axisymmetric segmental-conical entry capsule with its mass properties.

    Profile, from front to back along the axis x (origin at the heat-shield apex):

    1. heat shield: spherical segment of radius ``Rn`` from the apex to the rim of diameter
       ``D`` at x_rim = Rn - sqrt(Rn² - D²/4);
    2. afterbody: cone narrowing at half-angle ``theta_c`` over the axial length ``Lc``, to
       the back radius r_back = D/2 - Lc tan θc at x_back = x_rim + Lc;
    3. back cap: a flat disk (``Rb = inf``) or a convex spherical cap of radius ``Rb`` over the
       back radius.

    The body must be convex (Rb ≥ r_back / cos θc) so that the Newtonian shadow test is exact.

    Parameters
    ----------
    D : float
        Maximum diameter [m]; also the reference length.
    Rn : float
        Heat-shield (nose) sphere radius [m], ≥ D/2 (D/2: a hemisphere).
    theta_c : float
        Afterbody cone half-angle [rad], in [0, π/2); the cone narrows towards the back.
    Lc : float
        Axial length of the conical afterbody [m], ≥ 0, with r_back ≥ 0.
    Rb : float
        Radius of the spherical back cap [m]; ``inf`` for a flat back.
    m : float
        Mass [kg].
    A : float
        Equatorial (transverse) moment of inertia about the centre of mass [kg m²].
    C : float
        Axial moment of inertia [kg m²], with C ≤ 2A (true of any mass distribution).
    x_cg : float
        Centre of mass on the axis, measured from the heat-shield apex [m], inside the body.

    References
    ----------
    V. M. Serov (1991); docs/theory/nonlinear-moment.md §1 (A equatorial, C axial), §10
    (segmental-conical capsule).
    """

    D: float
    Rn: float
    theta_c: float
    Lc: float
    Rb: float
    m: float
    A: float
    C: float
    x_cg: float

    def __post_init__(self) -> None:
        check_range("capsule.D", self.D, low=0.0)
        check_range("capsule.Rn", self.Rn, low=self.D / 2.0, low_open=False)
        check_range("capsule.theta_c", self.theta_c, low=0.0, high=math.pi / 2, low_open=False)
        # The cone may close to a point, not beyond.
        lc_max = self.D / 2.0 / math.tan(self.theta_c) if self.theta_c > 0.0 else math.inf
        check_range("capsule.Lc", self.Lc, low=0.0, high=lc_max, low_open=False, high_open=False)
        if self.Rb != math.inf:
            # Convexity: the back cap meets the cone at an outward corner.
            check_range(
                "capsule.Rb",
                self.Rb,
                low=max(self.r_back / math.cos(self.theta_c), 0.0),
                low_open=self.r_back == 0.0,
                high_open=False,
            )
        check_range("capsule.m", self.m, low=0.0)
        check_range("capsule.A", self.A, low=0.0)
        check_range("capsule.C", self.C, low=0.0, high=2.0 * self.A, high_open=False)
        check_range("capsule.x_cg", self.x_cg, low=0.0, high=self.length)

    @property
    def S(self) -> float:
        """Reference area πD²/4 [m²]."""
        return math.pi * self.D**2 / 4.0

    @property
    def x_rim(self) -> float:
        """Axial station of the heat-shield rim (maximum diameter) [m]."""
        return self.Rn - math.sqrt(self.Rn**2 - self.D**2 / 4.0)

    @property
    def r_back(self) -> float:
        """Radius of the back end of the cone [m]."""
        return max(self.D / 2.0 - self.Lc * math.tan(self.theta_c), 0.0)

    @property
    def x_back(self) -> float:
        """Axial station of the back end of the cone [m]."""
        return self.x_rim + self.Lc

    @property
    def length(self) -> float:
        """Overall length from the heat-shield apex to the back [m]."""
        if self.Rb == math.inf:
            return self.x_back
        return self.x_back + self.Rb - math.sqrt(self.Rb**2 - self.r_back**2)

    @classmethod
    def from_mass_distribution(
        cls,
        *,
        D: float,
        Rn: float,
        theta_c: float,
        Lc: float,
        Rb: float,
        m: float,
        shield_fraction: float,
        wall_fraction: float,
    ) -> Capsule:
        """Capsule whose x_cg, A, C follow from a simple three-part mass distribution.

        The mass ``m`` is split into a thin heat-shield shell of uniform areal density on the
        spherical segment (``shield_fraction``), a thin wall of uniform areal density on the
        cone and back cap (``wall_fraction``), and the rest spread uniformly through the
        enclosed volume (equipment, crew, structure). Thin-shell ring and solid-disk inertias
        are integrated along the axis by Gauss–Legendre quadrature.

        Parameters
        ----------
        D, Rn, theta_c, Lc, Rb : float
            Geometry as in :class:`Capsule` [m], [rad].
        m : float
            Mass [kg].
        shield_fraction, wall_fraction : float
            Mass fractions of the heat-shield shell and of the afterbody wall [1], each in
            [0, 1) with sum ≤ 1 (the rest fills the volume).

        Returns
        -------
        Capsule
            With x_cg [m], A, C [kg m²] of that distribution.

        References
        ----------
        Rigid-body inertia of thin rings (m r², m r²/2 + m x²) and disks (m r²/2,
        m r²/4 + m x²) about the axis and a transverse axis.
        """
        check_range("shield_fraction", shield_fraction, low=0.0, high=1.0, low_open=False)
        check_range("wall_fraction", wall_fraction, low=0.0, high=1.0, low_open=False)
        check_range(
            "shield_fraction + wall_fraction",
            shield_fraction + wall_fraction,
            high=1.0,
            high_open=False,
        )
        check_range("capsule.m", m, low=0.0)
        # Geometry checks with placeholder mass properties that pass every range check; the
        # result is this capsule with the mass properties of the distribution.
        geo = cls(D=D, Rn=Rn, theta_c=theta_c, Lc=Lc, Rb=Rb, m=m, A=1.0, C=1.0, x_cg=1e-9)
        surf = _surface(geo, 64)
        vol = _volume(geo, 64)
        parts = _mass_elements(surf, vol, m, shield_fraction, wall_fraction)
        mass = sum(p[0].sum() for p in parts)
        x_cg = sum((p[0] * p[1]).sum() for p in parts) / mass
        a_inertia = sum((p[0] * (p[2] + (p[1] - x_cg) ** 2)).sum() for p in parts)
        c_inertia = sum((p[0] * p[3]).sum() for p in parts)
        return replace(geo, A=float(a_inertia), C=float(c_inertia), x_cg=float(x_cg))


def _mass_elements(
    surf: _Nodes, vol: _Volume, m: float, shield_fraction: float, wall_fraction: float
) -> list[tuple[FloatArray, FloatArray, FloatArray, FloatArray]]:
    """The mass elements of a capsule: thin rings of the heat shield and of the afterbody
    wall, and disks of the filled volume, as (dm, x, own transverse inertia per unit mass,
    own axial inertia per unit mass)."""
    parts = []
    for frac, mask in ((shield_fraction, surf.seg == 0), (wall_fraction, surf.seg > 0)):
        da = 2.0 * math.pi * surf.r[mask] * surf.w[mask]
        if frac == 0.0 or da.sum() == 0.0:
            continue
        dm = frac * m * da / da.sum()
        x, r = surf.x[mask], surf.r[mask]
        parts.append((dm, x, r**2 / 2.0, r**2))
    fill = 1.0 - shield_fraction - wall_fraction
    if fill > 0.0:
        dv = math.pi * vol.r2 * vol.w
        parts.append((fill * m * dv / dv.sum(), vol.x, vol.r2 / 4.0, vol.r2 / 2.0))
    return parts


SOYUZ_CLASS = Capsule(
    D=2.2,
    Rn=2.2,
    theta_c=math.radians(7.0),
    Lc=1.4,
    Rb=1.2,
    m=2900.0,
    A=1910.0,
    C=1750.0,
    x_cg=0.92,
)
"""Illustrative Soyuz-descent-module-class capsule (not the real vehicle's data).

Where each number comes from:

* D = 2.2 m, m = 2900 kg: rounded public figures for the Soyuz descent module (≈ 2.2 m
  maximum diameter, ≈ 2.9 t at entry). The real module's CoM is offset from the axis so that
  it flies at a lifting trim; this axisymmetric model leaves that out.
* Rn = 2.2 m (Rn/D = 1), θc = 7°, Lc = 1.4 m, spherical back cap Rb = 1.2 m: assumed, to give
  the "headlight" segmental-conical shape; overall length 2.13 m, back radius 0.93 m, heat
  shield depth 0.295 m, S = 3.80 m².
* x_cg = 0.92 m (0.42 D behind the apex), A = 1910 kg m², C = 1750 kg m² (C/A = 0.92):
  computed (rounded to 3 figures) by :meth:`Capsule.from_mass_distribution` with an assumed
  split of 15 % heat shield, 25 % afterbody wall and 60 % uniformly distributed contents.

Modified-Newtonian results at M → ∞ (checked in tests/entry/test_entry.py): CD(0) = 1.609
(= Cp_max (1 + cos²β)/2 of the spherical segment, sin β = D/(2Rn)); trims at α = 0
(stable, dCm/dα = -0.134), α = 80.3° (unstable, +0.108) and α = 180° (stable but weak,
-0.014: the "backward" trim, a double well). The fit of (1.5) gives c1 = -0.0066,
c2 = -0.0370 (b-dominated, b < 0: a double well), rms residual 0.0140 and largest 0.0222
(24 % and 38 % of max |Cm| = 0.0577).
"""


@dataclass(frozen=True, slots=True)
class _Nodes:
    """Quadrature nodes on the meridian: stations, normals, weights and segment index."""

    x: FloatArray  # axial station [m]
    r: FloatArray  # radius [m]
    nx: FloatArray  # outward normal, axial component [1]
    nr: FloatArray  # outward normal, radial component [1]
    w: FloatArray  # arc-length weight [m]
    seg: FloatArray  # 0 heat shield, 1 cone, 2 back cap


def _gauss(lo: float, hi: float, n_panels: int) -> tuple[FloatArray, FloatArray]:
    """Composite Gauss–Legendre nodes and weights on [lo, hi] with ``n_panels`` panels."""
    edges = np.linspace(lo, hi, n_panels + 1)
    half = 0.5 * np.diff(edges)
    mid = 0.5 * (edges[1:] + edges[:-1])
    t = (mid[:, None] + half[:, None] * _GL_X[None, :]).ravel()
    w = (half[:, None] * _GL_W[None, :]).ravel()
    return t, w


def _surface(c: Capsule, n_panels: int) -> _Nodes:
    """Meridional quadrature of the capsule's surface, ``n_panels`` panels per segment."""
    xs, rs, nxs, nrs, ws, segs = [], [], [], [], [], []
    # Heat shield, parameter: polar angle β from the apex, ds = Rn dβ.
    beta, wb = _gauss(0.0, math.asin(min(c.D / (2.0 * c.Rn), 1.0)), n_panels)
    xs.append(c.Rn * (1.0 - np.cos(beta)))
    rs.append(c.Rn * np.sin(beta))
    nxs.append(-np.cos(beta))
    nrs.append(np.sin(beta))
    ws.append(c.Rn * wb)
    segs.append(np.zeros_like(beta))
    if c.Lc > 0.0:
        # Cone, parameter: axial distance t from the rim, ds = dt / cos θc.
        t, wt = _gauss(0.0, c.Lc, n_panels)
        xs.append(c.x_rim + t)
        rs.append(c.D / 2.0 - t * math.tan(c.theta_c))
        nxs.append(np.full_like(t, math.sin(c.theta_c)))
        nrs.append(np.full_like(t, math.cos(c.theta_c)))
        ws.append(wt / math.cos(c.theta_c))
        segs.append(np.ones_like(t))
    if c.r_back > 0.0:
        if c.Rb == math.inf:
            # Flat back, parameter: radius, ds = dr.
            r, wr = _gauss(0.0, c.r_back, n_panels)
            xs.append(np.full_like(r, c.x_back))
            rs.append(r)
            nxs.append(np.ones_like(r))
            nrs.append(np.zeros_like(r))
            ws.append(wr)
        else:
            # Spherical back cap, parameter: polar angle η from the back pole, ds = Rb dη.
            eta_max = math.asin(min(c.r_back / c.Rb, 1.0))
            eta, wr = _gauss(0.0, eta_max, n_panels)
            x_centre = c.x_back - c.Rb * math.cos(eta_max)
            xs.append(x_centre + c.Rb * np.cos(eta))
            rs.append(c.Rb * np.sin(eta))
            nxs.append(np.cos(eta))
            nrs.append(np.sin(eta))
            ws.append(c.Rb * wr)
        segs.append(np.full_like(ws[-1], 2.0))
    return _Nodes(*(np.concatenate(a) for a in (xs, rs, nxs, nrs, ws, segs)))


@dataclass(frozen=True, slots=True)
class _Volume:
    x: FloatArray  # axial station [m]
    r2: FloatArray  # squared radius of the cross-section [m²]
    w: FloatArray  # axial weight [m]


def _volume(c: Capsule, n_panels: int) -> _Volume:
    """Axial quadrature of the enclosed volume (r² is a polynomial in x on each piece)."""
    xs, r2s, ws = [], [], []
    x, w = _gauss(0.0, c.x_rim, n_panels)
    xs.append(x)
    r2s.append(c.Rn**2 - (c.Rn - x) ** 2)
    ws.append(w)
    if c.Lc > 0.0:
        x, w = _gauss(c.x_rim, c.x_back, n_panels)
        xs.append(x)
        r2s.append((c.D / 2.0 - (x - c.x_rim) * math.tan(c.theta_c)) ** 2)
        ws.append(w)
    if c.Rb != math.inf and c.r_back > 0.0:
        x_centre = c.x_back - math.sqrt(c.Rb**2 - c.r_back**2)
        x, w = _gauss(c.x_back, c.length, n_panels)
        xs.append(x)
        r2s.append(c.Rb**2 - (x - x_centre) ** 2)
        ws.append(w)
    return _Volume(*(np.concatenate(a) for a in (xs, r2s, ws)))


def _ring_integrals(a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Closed-form azimuthal integrals of the Newtonian pressure over one ring.

    With n·u = a - b cos φ (b ≥ 0) on the ring, sin δ = max(0, b cos φ - a) and the windward
    arc is |φ| < φ0, cos φ0 = a/b clipped to [-1, 1] (φ0 = π if b = 0 and a < 0):

        I0 = ∫ sin²δ dφ       = b² (φ0 + s c) - 4 a b s + 2 a² φ0,
        I1 = ∫ sin²δ cos φ dφ = 2 b² (s - s³/3) - 2 a b (φ0 + s c) + 2 a² s,

    with s = sin φ0, c = cos φ0.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(b > 0.0, a / np.where(b > 0.0, b, 1.0), np.where(a < 0.0, -1.0, 1.0))
    phi0 = np.arccos(np.clip(ratio, -1.0, 1.0))
    s, c = np.sin(phi0), np.cos(phi0)
    i0 = b**2 * (phi0 + s * c) - 4.0 * a * b * s + 2.0 * a**2 * phi0
    i1 = 2.0 * b**2 * (s - s**3 / 3.0) - 2.0 * a * b * (phi0 + s * c) + 2.0 * a**2 * s
    return i0, i1


@dataclass(frozen=True, slots=True)
class AeroCoefficients:
    """Body-axis force and moment coefficients at total angles of attack α.

    Attributes
    ----------
    alpha : ndarray
        Total angle of attack [rad].
    CA : ndarray
        Axial-force coefficient, force along +x (rearward) / (q S) [1].
    CN : ndarray
        Normal-force coefficient, force along the transverse relative wind / (q S) [1].
    Cm : ndarray
        Pitching-moment coefficient about the CoM / (q S D) [1], > 0 tends to increase α.

    References
    ----------
    Body-axis coefficients and CD = CA cos α + CN sin α, CL = CN cos α - CA sin α: Anderson,
    *Hypersonic and High-Temperature Gas Dynamics*, ch. 3.
    """

    alpha: FloatArray
    CA: FloatArray
    CN: FloatArray
    Cm: FloatArray

    @property
    def CD(self) -> FloatArray:
        """Drag coefficient CA cos α + CN sin α [1]."""
        return self.CA * np.cos(self.alpha) + self.CN * np.sin(self.alpha)

    @property
    def CL(self) -> FloatArray:
        """Lift coefficient CN cos α - CA sin α [1] (in the plane of α)."""
        return self.CN * np.cos(self.alpha) - self.CA * np.sin(self.alpha)


def _angles(alpha: ArrayLike) -> FloatArray:
    arr = np.asarray(alpha, dtype=float)
    bad = ~np.isfinite(arr) | (arr < 0.0) | (arr > math.pi)
    if np.any(bad):
        i = int(np.flatnonzero(bad.ravel())[0])
        name = "alpha" if arr.ndim == 0 else f"alpha[{i}]"
        raise ParameterError(
            f"{name} = {arr.ravel()[i]:g} rad is outside the allowed range [0, {math.pi:.6g}]"
        )
    return arr


def coefficients(
    capsule: Capsule, alpha: ArrayLike, mach: float = math.inf, *, n_panels: int = 64
) -> AeroCoefficients:
    """Modified-Newtonian CA, CN, Cm of the capsule at total angles of attack α ∈ [0, π].

    The pressure Cp = Cp_max sin²δ (0 in the shadow) is integrated over the whole closed
    surface (heat shield, cone, back cap): azimuth in closed form, meridian by composite
    4-point Gauss–Legendre quadrature with ``n_panels`` panels per segment. The
    meridional integrand has kinks where the shadow boundary enters or leaves a ring, so the
    error falls like n_panels^-3.5 rather than spectrally; the default 64 panels resolve the
    coefficients of :data:`SOYUZ_CLASS` to ≈ 1e-10 (measured in the tests). Cm is the moment
    about the CoM.

    Parameters
    ----------
    capsule : Capsule
        Geometry and centre of mass.
    alpha : array_like
        Total angle of attack [rad], in [0, π].
    mach : float
        Free-stream Mach number [1] in [1, inf]; enters only through Cp_max, so every
        coefficient scales by cp_max(mach)/cp_max(inf).
    n_panels : int
        Quadrature panels per surface segment, ≥ 1.

    Returns
    -------
    AeroCoefficients
        CA, CN, Cm [1] shaped like ``alpha`` (and CD, CL).

    References
    ----------
    Lees (1955); Anderson, *Hypersonic and High-Temperature Gas Dynamics*, ch. 3.
    """
    a = _angles(alpha)
    if n_panels < 1:
        raise ParameterError(f"n_panels = {n_panels} is outside the allowed range [1, inf)")
    cpm = cp_max(mach)
    nodes = _surface(capsule, n_panels)
    al = a.reshape(-1, 1)
    i0, i1 = _ring_integrals(nodes.nx * np.cos(al), nodes.nr * np.sin(al))
    rw = nodes.r * nodes.w
    scale = cpm / capsule.S
    fx = -scale * (i0 * nodes.nx * rw).sum(axis=1)
    fy = -scale * (i1 * nodes.nr * rw).sum(axis=1)
    arm = (nodes.x - capsule.x_cg) * nodes.nr - nodes.r * nodes.nx
    mz = -scale / capsule.D * (i1 * arm * rw).sum(axis=1)
    # The relative wind is u = (cos α, -sin α, 0): CN is along -y, and a moment about +z
    # increases α.
    return AeroCoefficients(
        alpha=a, CA=fx.reshape(a.shape), CN=(-fy).reshape(a.shape), Cm=mz.reshape(a.shape)
    )


@dataclass(frozen=True, slots=True)
class MomentFit:
    """Least-squares fit Cm(α) ≈ c1 sin α + c2 sin 2α over α ∈ [0, π].

    Attributes
    ----------
    c1, c2 : float
        Coefficients of sin α and sin 2α [1]; a = q S D c1 / A, b = q S D c2 / A.
    rms, max_abs : float
        Root-mean-square and largest absolute residual of Cm on the fit grid [1].
    cm_max : float
        Largest |Cm| on the grid [1], to judge the residuals against.
    cd0 : float
        Drag coefficient at α = 0 [1].
    mach : float
        Mach number of the fit [1].

    References
    ----------
    V. M. Serov (1991), eq. (1.5).
    """

    c1: float
    c2: float
    rms: float
    max_abs: float
    cm_max: float
    cd0: float
    mach: float


def fit_moment(capsule: Capsule, mach: float = math.inf, *, n_alpha: int = 181) -> MomentFit:
    """Fit the Newtonian Cm(α) of the capsule by the two-term form (1.5), c1 sinα + c2 sin2α.

    The fit is an ordinary least-squares fit on ``n_alpha`` equally spaced α in [0, π] (both
    end points are zeros of Cm and of the model). How good (1.5) is for :data:`SOYUZ_CLASS`:
    qualitatively right — a stable well at α = 0, an unstable trim in between (fit 95°,
    Newtonian 80°) and a stable backward well at α = π, i.e. b < 0 — but only to ≈ 25 %
    quantitatively: rms residual 24 % and largest residual 38 % of max |Cm| (at α = 90°).
    The Newtonian Cm/sin α is not linear in cos α as (1.5) requires: it is steep near α = 0
    and nearly flat for α > 90°. So the fitted small-α slope c1 + 2c2 = -0.080 is 60 % of
    the Newtonian -0.134 (nutation period near α = 0 too long by ≈ 29 %), and the fitted
    backward well (slope -c1 + 2c2 = -0.067) is ≈ 5 times stiffer than the Newtonian one
    (-0.014).

    Parameters
    ----------
    capsule : Capsule
        The capsule.
    mach : float
        Mach number [1] (Cp_max scaling only).
    n_alpha : int
        Number of fit angles, ≥ 3.

    Returns
    -------
    MomentFit
        c1, c2 [1], the residuals and CD(0).

    References
    ----------
    V. M. Serov (1991), eq. (1.5); docs/theory/nonlinear-moment.md §10 (the paper's claim that
    (1.5) represents the moment of a segmental-conical capsule).
    """
    if n_alpha < 3:
        raise ParameterError(f"n_alpha = {n_alpha} is outside the allowed range [3, inf)")
    alpha = np.linspace(0.0, math.pi, n_alpha)
    co = coefficients(capsule, alpha, mach)
    basis = np.column_stack([np.sin(alpha), np.sin(2.0 * alpha)])
    (c1, c2), *_ = np.linalg.lstsq(basis, co.Cm, rcond=None)
    res = co.Cm - basis @ np.array([c1, c2])
    return MomentFit(
        c1=float(c1),
        c2=float(c2),
        rms=float(np.sqrt(np.mean(res**2))),
        max_abs=float(np.max(np.abs(res))),
        cm_max=float(np.max(np.abs(co.Cm))),
        cd0=float(co.CD[0]),
        mach=mach,
    )


@dataclass(frozen=True, slots=True)
class Trim:
    """A trim point Cm(α) = 0.

    Attributes
    ----------
    alpha : float
        Trim angle [rad].
    slope : float
        dCm/dα there [1/rad].
    stable : bool
        True if dCm/dα < 0 (a small deviation is pushed back).

    References
    ----------
    Static stability of a trim, dCm/dα < 0; docs/theory/nonlinear-moment.md (1.5)–(1.6) (wells of
    W(θ)).
    """

    alpha: float
    slope: float
    stable: bool


def trim_angles(capsule: Capsule, mach: float = math.inf, *, n_alpha: int = 361) -> list[Trim]:
    """All trim angles of the Newtonian Cm(α) in [0, π], with their static stability.

    α = 0 and α = π are always trims (symmetry). Interior ones are bracketed by sign changes
    on ``n_alpha`` equally spaced angles and refined by Brent's method; slopes are central
    differences (one-sided at the ends) with a 1e-5 rad step.

    Parameters
    ----------
    capsule : Capsule
        The capsule.
    mach : float
        Mach number [1] (does not move the trims: Cp_max scales Cm uniformly).
    n_alpha : int
        Number of bracketing angles, ≥ 3.

    Returns
    -------
    list of Trim
        In increasing α.

    References
    ----------
    Static stability of a trim: dCm/dα < 0 (any flight-mechanics text).
    """
    if n_alpha < 3:
        raise ParameterError(f"n_alpha = {n_alpha} is outside the allowed range [3, inf)")

    def cm(al: float) -> float:
        return float(coefficients(capsule, al, mach).Cm)

    step = 1e-5
    alpha = np.linspace(0.0, math.pi, n_alpha)
    values = coefficients(capsule, alpha, mach).Cm
    roots = [0.0]
    for i in range(1, n_alpha - 2):
        if values[i] == 0.0:
            roots.append(float(alpha[i]))
        elif values[i] * values[i + 1] < 0.0:
            roots.append(float(brentq(cm, alpha[i], alpha[i + 1], xtol=1e-13)))
    roots.append(math.pi)
    trims = []
    for r in roots:
        lo, hi = max(r - step, 0.0), min(r + step, math.pi)
        slope = (cm(hi) - cm(lo)) / (hi - lo)
        trims.append(Trim(alpha=r, slope=slope, stable=slope < 0.0))
    return trims


def restoring_coefficients(
    capsule: Capsule, q: ArrayLike, fit: MomentFit | None = None
) -> tuple[FloatArray, FloatArray]:
    """Coefficients a, b of the moment (1.5) per unit A at dynamic pressure q.

    M0(θ)/A = q S D (c1 sin θ + c2 sin 2θ)/A, so a = q S D c1 / A and b = q S D c2 / A.

    Parameters
    ----------
    capsule : Capsule
        The capsule (S, D, A).
    q : array_like
        Dynamic pressure ρV²/2 [Pa], ≥ 0.
    fit : MomentFit, optional
        The moment fit; default ``fit_moment(capsule)`` (M → ∞).

    Returns
    -------
    a, b : ndarray
        [1/s²], shaped like ``q``; a < 0 restores towards θ = 0, b < 0 is a double well.

    References
    ----------
    V. M. Serov (1991), eq. (1.5); docs/theory/nonlinear-moment.md §9 (a = a0 Q, b = b0 Q with Q
    the dynamic-pressure profile).
    """
    qa = np.asarray(q, dtype=float)
    if not np.all(np.isfinite(qa)) or np.any(qa < 0.0):
        i = int(np.flatnonzero(~(np.isfinite(qa) & (qa >= 0.0)).ravel())[0])
        raise ParameterError(f"q = {qa.ravel()[i]:g} Pa is outside the allowed range [0, inf)")
    f = fit if fit is not None else fit_moment(capsule)
    k = qa * capsule.S * capsule.D / capsule.A
    return k * f.c1, k * f.c2
