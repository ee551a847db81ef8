"""The data an orbit is built from: its turning points, charts, poles and Jacobi phases, and
the limits of the representation."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal, NamedTuple

import numpy as np

from tumble._typing import FloatArray
from tumble.errors import ParameterError
from tumble.unperturbed.symmetric_body.carlson import _lam_integral, _rj_complete, _s_integral

if TYPE_CHECKING:
    from tumble.unperturbed.symmetric_body.orbit import NutationOrbit

_EPS = float(np.finfo(float).eps)
_POLE_TOUCH = 1e-280  # 1 ∓ u at a turning point below this: the axis passes through ±e_z

Kind = Literal["elliptic", "steady", "free"]


# NamedTuples, not frozen dataclasses: as immutable, and several are built per orbit.


class _Point(NamedTuple):
    """A turning point: u, 1 − u and 1 + u, each to full relative accuracy."""

    u: float
    om: float  # 1 − u
    op: float  # 1 + u
    d: float  # u − u0 (the δ coordinate)

    def minus(self, rho: float) -> float:
        """u − ρ, exact in the last digits for ρ = ±1."""
        if rho == 1.0:
            return -self.om
        if rho == -1.0:
            return self.op
        return self.u - rho


class _Chart(NamedTuple):
    """u = (A (1 − σ) + B ν σ)/((1 − σ) + ν σ); Jacobi argument βt + τ0 + offset."""

    A: _Point
    B: _Point
    nu: float
    offset: float  # 0 (main chart) or K (case 1, anchored at the other turning point)


class _Pole(NamedTuple):
    """∫0^t dt/(u − ρ) = sec·t + (cper/β)·[kS (S − S0) − (Λ − Λ0)] (Λ only in case 2).

    S0 = S(γ0) and Λ0 = Λ(γ0) belong to the phase at t = 0 and are needed only by ψ(t), φ(t):
    they are computed on first use (:attr:`NutationOrbit._pole_starts`, :func:`_pole_start`).
    """

    sec: float
    cper: float
    kS: float
    p: float  # fourth Carlson argument coefficient: 1 + w
    Sc: float  # S(π/2) = R_J(0, 1 − k², 1, p)/3
    lam: float  # case 2 only
    chart: _Chart  # case 1: whose Jacobi argument

    def mean(self, K: float) -> float:
        return self.sec + self.cper * self.kS * self.Sc / K


@dataclass(frozen=True)
class _Jac:
    """Jacobi functions of βt + τ0 + offset, reduced (§5): v = 2jK + v_r, |v_r| ≤ K."""

    sn: FloatArray  # sn v_r (with sign)
    cn: FloatArray  # cn v_r ≥ 0
    dn: FloatArray
    j: FloatArray


def _make_pole(orbit: NutationOrbit, rho: float) -> _Pole:
    """Coefficients of ∫dt/(u − ρ) (module notes; (1.13) with corrections S7–S9 in case 2)."""
    mc, m = orbit.mc, orbit.k2
    p1, p2 = orbit._p1, orbit._p2
    if orbit.root_case == 1:
        # Anchor at the turning point farther from ρ: no cancellation between the parts.
        above = rho > orbit.u1 or rho == 1.0
        ch = orbit._main if above else orbit._other
        assert ch is not None
        dA, dB = ch.A.minus(rho), ch.B.minus(rho)
        if dA == 0.0:
            raise ParameterError(f"rho = {rho:g} is a turning point: ⟨1/(u − ρ)⟩ diverges")
        r = ch.nu * dB / dA
        if not r > 0.0:
            raise ParameterError(f"rho = {rho:g} is a turning point: ⟨1/(u − ρ)⟩ diverges")
        Sc = _rj_complete(mc, r) / 3.0
        return _Pole(
            sec=1.0 / dA,
            cper=ch.nu * (ch.A.d - ch.B.d) / (dA * dA),
            kS=1.0,
            p=r,
            Sc=Sc,
            lam=0.0,
            chart=ch,
        )
    ch = orbit._main
    xi = ch.nu
    e1, e2 = p1.minus(rho), p2.minus(rho)
    if e1 == 0.0 or e2 == 0.0:
        raise ParameterError(f"rho = {rho:g} is a turning point: ⟨1/(u − ρ)⟩ diverges")
    r = xi * e2 / e1
    what = (r - 1.0) ** 2 / (4.0 * r)  # ŵ of §5 (case 2), ≥ 0
    p = (r + 1.0) ** 2 / (4.0 * r)  # 1 + ŵ
    Sc = _rj_complete(mc, p) / 3.0
    lam = math.sqrt(m + what)
    return _Pole(
        sec=(e1 + e2) / (2.0 * e1 * e2),
        cper=(p1.d - p2.d) / (2.0 * e1 * e2),
        kS=(r - 1.0) * (r + 1.0) / (4.0 * r),
        p=p,
        Sc=Sc,
        lam=lam,
        chart=ch,
    )


def _pole_start(orbit: NutationOrbit, pole: _Pole, jac0: _Jac) -> tuple[float, float]:
    """(S0, Λ0) of ``pole`` at t = 0, by the same path as at any t (ψ(0) = ψ0 exactly)."""
    if orbit.root_case == 1:
        j0 = jac0 if pole.chart.offset == 0.0 else orbit._shifted(jac0)
        return float(_s_integral(j0.sn, j0.cn, j0.dn, j0.j, pole.p, pole.Sc)), 0.0
    sign = 1.0 - 2.0 * float(np.mod(jac0.j, 2.0))
    S0 = float(_s_integral(jac0.sn, jac0.cn, jac0.dn, jac0.j, pole.p, pole.Sc))
    L0 = float(_lam_integral(np.asarray(sign * jac0.sn), jac0.dn, pole.lam))
    return S0, L0
