"""The unperturbed motion of the symmetric body in closed form: θ(t), θ'(t), ψ(t), φ(t) and the
period averages, (1.9)–(1.13) of Serov (1991)."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from tumble._docstrings import DocSections
from tumble._typing import ArrayLike, FloatArray
from tumble.errors import IntegrationError, ParameterError, check_finite, check_range
from tumble.unperturbed._checks import finite_array, whole_number
from tumble.unperturbed.elliptic import _jacobi
from tumble.unperturbed.symmetric_body import means
from tumble.unperturbed.symmetric_body.carlson import _lam_integral, _s_integral
from tumble.unperturbed.symmetric_body.charts import (
    _EPS,
    _POLE_TOUCH,
    Kind,
    _Chart,
    _Jac,
    _make_pole,
    _Point,
    _Pole,
    _pole_start,
)

_N_START = 32  # first trapezoid level of :meth:`NutationOrbit.average`

_DOC = DocSections(
    constants="""
    mu : float
        C/A [1], in (0, 2].
    a, b : float
        Moment coefficients of (1.5) [1/time²].
    R, G : float
        Reduced angular momenta μr and K·e_z/A [1/time].
    """,
    angles="""
    psi, phi : float
        ψ0, φ0 [rad].
    """,
    t="""
    Parameters
    ----------
    t : array_like
        Times [time].
    """,
)


@dataclass(frozen=True, eq=False)
class NutationOrbit:
    """Unperturbed motion through a given state, Serov (1991), eqs. (1.9)–(1.13).

    Frozen: R, G, a, b and E are constants of this motion. Build it with :meth:`from_state`,
    :meth:`from_turning_point` or :meth:`from_energy`; t = 0 is the construction state.

    Attributes
    ----------
    mu : float
        C/A [1], in (0, 2].
    a, b : float
        Moment coefficients of (1.5) [1/time²].
    R, G : float
        Reduced angular momenta [1/time].
    E : float
        Energy (1.6) [1/time²].
    root_case : int
        1 (u3, u4 real; also b = 0 and a = b = 0) or 2 (complex pair), §3 and §14.
    roots : ndarray, complex, shape (4,)
        (u1, u2, u3, u4) in the cyclic labelling of §3 (u1 → u4 → u3 → u2 going upwards from u1
        through ±∞); case 2: u3 = c + id, u4 = c − id. A root at infinity (b = 0) is
        ``complex(inf)``; for a = b = 0 (f quadratic) u3 = u4 = ``complex(inf)``.
    u1, u2 : float
        cos θmin ≥ cos θmax [1].
    theta_min, theta_max : float
        Turning points [rad].
    k2, mc : float
        Parameter m = k² and 1 − k² [1], each from its own cancellation-free formula.
    beta : float
        β of §4 (corrections S5, S6) [1/time].
    period : float
        Nutation period T = 2K/β (case 1) or 4K/β (case 2) [time]; for a steady precession the
        limit of small oscillations about it.
    kind : {"elliptic", "steady", "free"}
        "steady": u1 = u2 (constant θ; takes precedence), "free": a = b = 0 (harmonic u, §11),
        else "elliptic".
    mean_psidot, mean_phidot : float
        Secular precession and spin rates over one period, §5 "Mean rates" [rad/time].
    psi0, phi0 : float
        ψ(0), φ(0) [rad].

    Notes
    -----
    If G = R (G = −R) exactly, the term (G ∓ R)/(1 ∓ u) of (1.12) is absent. If moreover the
    motion reaches u = 1 (u = −1), the symmetry axis passes through ±e_z: the true ψ and φ then
    jump by π at each passage, while :meth:`psi` and :meth:`phi` return the continuous branch of
    (1.13) (the true attitude after n passages is Rz(ψ + nπ) Rx(θ) Rz(φ + nπ)). The same holds
    when 1 − u1 (1 + u2) is below 1e-280 (the axis passes within ~1e-140 rad of ±e_z), which is
    beyond the range of the Carlson functions: the term is then treated as absent.

    Accuracy: θ, ψ, φ to a few ulps of the phase for any 1 − k² ≥ SEPARATRIX_TOL. In case 2
    the pole terms lose digits like 1/sqrt(1 ∓ u) when θmin → 0 or θmax → π (measured 1e-13 at
    1 + u2 = 1.5e-5); case 1 anchors each pole term at the far turning point and does not.
    """

    mu: float
    a: float
    b: float
    R: float
    G: float
    E: float
    root_case: int
    roots: np.ndarray = field(repr=False)
    u1: float
    u2: float
    theta_min: float
    theta_max: float
    k2: float
    mc: float
    beta: float
    period: float
    kind: Kind
    mean_psidot: float
    mean_phidot: float
    psi0: float = field(repr=False)
    phi0: float = field(repr=False)
    _u0: float = field(repr=False)
    _K: float = field(repr=False)
    _tau0: float = field(repr=False)
    _turning_start: bool = field(repr=False)
    _main: _Chart = field(repr=False)
    _other: _Chart | None = field(repr=False)
    _poles: tuple[tuple[float, float, _Pole], ...] = field(repr=False)  # (wψ, wφ, pole)
    _p1: _Point = field(repr=False)
    _p2: _Point = field(repr=False)

    # ----------------------------------------------------------------------------------
    # Constructors
    # ----------------------------------------------------------------------------------

    @classmethod
    @_DOC
    def from_state(
        cls,
        mu: float,
        a: float,
        b: float,
        R: float,
        G: float,
        theta: float,
        theta_dot: float,
        psi: float = 0.0,
        phi: float = 0.0,
    ) -> NutationOrbit:
        """The motion through (θ, θ', ψ, φ) at t = 0, Serov (1991), eqs. (1.9)–(1.13).

        Parameters
        ----------
        {{constants}}
        theta : float
            Nutation angle θ0 [rad], strictly inside (0, π).
        theta_dot : float
            θ0' [rad/time]; 0 starts at a turning point (side chosen by the sign of f'(u0), §3).
        {{angles}}

        Returns
        -------
        NutationOrbit

        Raises
        ------
        ParameterError
            An input out of range, or a motion at a separatrix (1 − k² < SEPARATRIX_TOL,
            including a start at an unstable equilibrium), or a body at rest with a = b = 0.
        """
        from tumble.unperturbed.symmetric_body import build  # it builds this class

        return build.from_state(mu, a, b, R, G, theta, theta_dot, psi, phi, "theta")

    @classmethod
    @_DOC
    def from_turning_point(
        cls,
        mu: float,
        a: float,
        b: float,
        R: float,
        G: float,
        theta_ext: float,
        psi: float = 0.0,
        phi: float = 0.0,
    ) -> NutationOrbit:
        """The motion with θ(0) = θext and θ'(0) = 0, (1.10) with γ0 ∈ {0, π/(2δ)}.

        θext is θmax if f'(u0) > 0 and θmin if f'(u0) < 0 (§3, last bullet).

        Parameters
        ----------
        {{constants}}
        theta_ext : float
            Turning point θ(0) [rad], strictly inside (0, π).
        {{angles}}

        Returns
        -------
        NutationOrbit

        Raises
        ------
        ParameterError
            As :meth:`from_state`.
        """
        from tumble.unperturbed.symmetric_body import build  # it builds this class

        return build.from_state(mu, a, b, R, G, theta_ext, 0.0, psi, phi, "theta_ext")

    @classmethod
    @_DOC
    def from_energy(
        cls, mu: float, a: float, b: float, R: float, G: float, E: float, u_hint: float
    ) -> NutationOrbit:
        """The motion of energy E on the allowed interval [u2, u1] containing u_hint, (1.7).

        If no allowed interval contains u_hint, the one nearest to it (one well of a double
        well). t = 0 at the turning point u2 (θmax); ψ(0) = φ(0) = 0. An energy equal to a
        minimum of W (within round-off) gives the steady precession there.

        Parameters
        ----------
        {{constants}}
        E : float
            Energy (1.6) [1/time²].
        u_hint : float
            A value of cosθ [1] that selects the interval.

        Returns
        -------
        NutationOrbit

        Raises
        ------
        ParameterError
            No motion with this energy (E below the minimum of W beyond round-off), a
            separatrix, or an input out of range.
        """
        from tumble.unperturbed.symmetric_body import build  # it builds this class

        return build.from_energy(mu, a, b, R, G, E, u_hint)

    # Evaluation
    # ----------------------------------------------------------------------------------

    def _t(self, t: ArrayLike) -> FloatArray:
        return finite_array("t", t)

    def _jac(self, tt: FloatArray) -> _Jac:
        v = self.beta * tt + self._tau0
        m = self.k2
        sn, cn, dn, j = _jacobi(np.asarray(v, dtype=float), m, self.mc, self._K)
        return _Jac(sn, cn, dn, j)

    def _shifted(self, jac: _Jac) -> _Jac:
        """Jacobi functions at v + K from those at v (sn → cd, cn → −k' sd, dn → k' nd)."""
        kc = math.sqrt(self.mc)
        low = jac.sn <= 0.0  # v_r ∈ [−K, 0]: v_r + K ∈ [0, K], same j
        sn = np.where(low, 1.0, -1.0) * jac.cn / jac.dn
        cn = kc * np.abs(jac.sn) / jac.dn
        dn = kc / jac.dn
        j = np.where(low, jac.j, jac.j + 1.0)
        return _Jac(sn, cn, dn, j)

    def _sigma(self, jac: _Jac) -> tuple[FloatArray, FloatArray]:
        """(σ, 1 − σ) of the chart: sin²γ (case 1) or sin²(γ/2) (case 2), no cancellation."""
        if self.root_case == 1:
            return jac.sn * jac.sn, jac.cn * jac.cn
        half_s = jac.sn * jac.sn / (2.0 * (1.0 + jac.cn))  # sin²(γr/2)
        half_c = 0.5 * (1.0 + jac.cn)  # cos²(γr/2)
        odd = np.mod(jac.j, 2.0) == 1.0
        return np.where(odd, half_c, half_s), np.where(odd, half_s, half_c)

    def _mix(self, sig: FloatArray, sigc: FloatArray, xa: float, xb: float) -> FloatArray:
        ch = self._main
        return np.asarray((xa * sigc + xb * ch.nu * sig) / (sigc + ch.nu * sig), dtype=float)

    def cos_theta(self, t: ArrayLike) -> FloatArray:
        """u(t) = cos θ(t), Serov (1991), eqs. (1.9)–(1.10).

        Parameters
        ----------
        t : array_like
            Times [time], any real values (t = 0 is the construction state).

        Returns
        -------
        ndarray
            cos θ [1], shape of ``t``.
        """
        tt = self._t(t)
        if self.kind == "steady":
            return np.full_like(tt, self._u0)
        sig, sigc = self._sigma(self._jac(tt))
        ch = self._main
        d = self._mix(sig, sigc, ch.A.d, ch.B.d)
        return np.asarray(self._u0 + d, dtype=float)

    def _theta_from(
        self, sig: FloatArray, sigc: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """θ, 1 − u and 1 + u, the latter two as weighted means (no cancellation near ±1)."""
        ch = self._main
        om = self._mix(sig, sigc, ch.A.om, ch.B.om)
        op = self._mix(sig, sigc, ch.A.op, ch.B.op)
        return np.asarray(2.0 * np.arctan2(np.sqrt(om), np.sqrt(op)), dtype=float), om, op

    @_DOC
    def theta(self, t: ArrayLike) -> FloatArray:
        """Nutation angle θ(t), Serov (1991), eq. (1.9), accurate also near θ = 0 and π.

        {{t}}

        Returns
        -------
        ndarray
            θ [rad] in [0, π], shape of ``t``.
        """
        tt = self._t(t)
        if self.kind == "steady":
            return np.full_like(tt, self.theta_min)
        sig, sigc = self._sigma(self._jac(tt))
        return self._theta_from(sig, sigc)[0]

    def _theta_dot_from(
        self, jac: _Jac, sig: FloatArray, sigc: FloatArray, om: FloatArray, op: FloatArray
    ) -> FloatArray:
        """θ' = −u'/sinθ with u' from d σ/dt of the chart (no f(u) near the turning points)."""
        ch = self._main
        den = sigc + ch.nu * sig
        if self.root_case == 1:
            dsig = 2.0 * self.beta * jac.sn * jac.cn * jac.dn  # d(sn²)/dt, reduced signs cancel
        else:
            sign = 1.0 - 2.0 * np.mod(jac.j, 2.0)
            dsig = 0.5 * self.beta * sign * jac.sn * jac.dn  # d sin²(γ/2)/dt = β sn dn/2
        udot = (ch.B.d - ch.A.d) * ch.nu * dsig / (den * den)
        sin_th = np.sqrt(om * op)
        safe = np.where(sin_th > 0.0, sin_th, 1.0)
        # Exactly at θ = 0 (θ = π), only possible for G = R (G = −R): the limit
        # θ'² = 2(E ∓ a − b) of f/(1 − u²), with the sign of the motion leaving the pole.
        up = math.sqrt(max(2.0 * (self.E - self.a - self.b), 0.0))
        down = -math.sqrt(max(2.0 * (self.E + self.a - self.b), 0.0))
        limit = np.where(om == 0.0, up, down)
        return np.asarray(np.where(sin_th > 0.0, -udot / safe, limit), dtype=float)

    @_DOC
    def theta_dot(self, t: ArrayLike) -> FloatArray:
        """Nutation rate θ'(t) = −u'/sinθ, from Serov (1991), eqs. (1.9)–(1.10).

        {{t}}

        Returns
        -------
        ndarray
            θ' [rad/time], shape of ``t``.
        """
        return self._theta_pair(self._t(t))[1]

    @functools.cached_property
    def _pole_starts(self) -> tuple[tuple[float, float], ...]:
        """(S0, Λ0) of each pole of :attr:`_poles`: the phase data of t = 0, on first use."""
        if not self._poles or self.kind == "steady":
            return tuple((0.0, 0.0) for _ in self._poles)
        jac0 = self._jac(np.zeros(()))
        return tuple(_pole_start(self, pole, jac0) for _, _, pole in self._poles)

    def _pole_integral(
        self,
        pole: _Pole,
        start: tuple[float, float],
        tt: FloatArray,
        jac: _Jac,
        jac_k: _Jac | None,
    ) -> FloatArray:
        """∫0^t dt'/(u − ρ) for one pole, (1.13) in the anchor-based form of the module notes."""
        if self.kind == "steady":
            return np.asarray(pole.sec * tt, dtype=float)
        S0, L0 = start
        jj = jac if pole.chart.offset == 0.0 or jac_k is None else jac_k
        S = _s_integral(jj.sn, jj.cn, jj.dn, jj.j, pole.p, pole.Sc)
        per = pole.kS * (S - S0)
        if self.root_case == 2:
            sign = 1.0 - 2.0 * np.mod(jj.j, 2.0)
            per = per - (_lam_integral(sign * jj.sn, jj.dn, pole.lam) - L0)
        return np.asarray(pole.sec * tt + pole.cper / self.beta * per, dtype=float)

    def _angles(self, t: ArrayLike) -> tuple[FloatArray, FloatArray]:
        tt = self._t(t)
        psi = np.zeros_like(tt)
        phi = np.zeros_like(tt)
        if self._poles:
            jac = None if self.kind == "steady" else self._jac(tt)
            jac_k = None if jac is None or self._other is None else self._shifted(jac)
            for (w_psi, w_phi, pole), start in zip(self._poles, self._pole_starts, strict=True):
                if jac is None:
                    integral = np.asarray(pole.sec * tt, dtype=float)
                else:
                    integral = self._pole_integral(pole, start, tt, jac, jac_k)
                psi = psi + w_psi * integral
                phi = phi + w_phi * integral
        phi = phi + self.R * (1.0 / self.mu - 1.0) * tt
        return np.asarray(self.psi0 + psi, dtype=float), np.asarray(self.phi0 + phi, dtype=float)

    @_DOC
    def psi(self, t: ArrayLike) -> FloatArray:
        """Precession angle ψ(t), Serov (1991), eqs. (1.11)–(1.13); continuous, ψ(0) = ψ0.

        {{t}}

        Returns
        -------
        ndarray
            ψ [rad] (unwrapped), shape of ``t``.
        """
        return self._angles(t)[0]

    @_DOC
    def phi(self, t: ArrayLike) -> FloatArray:
        """Proper rotation φ(t), Serov (1991), eqs. (1.11)–(1.13); continuous, φ(0) = φ0.

        {{t}}

        Returns
        -------
        ndarray
            φ [rad] (unwrapped), shape of ``t``.
        """
        return self._angles(t)[1]

    def turning_time(self, which: Literal["last", "next"] = "last") -> float:
        """Time of the nearest turning point of θ before (≤ 0) or after (> 0) t = 0, (1.10).

        Turning points are at βt + τ0 ∈ (T β/2)·ℤ. For a steady precession every instant is a
        turning point: "last" gives 0 and "next" T/2.

        Parameters
        ----------
        which : {"last", "next"}
            "last": largest turning time ≤ 0 (0.0 if t = 0 is one); "next": smallest > 0.

        Returns
        -------
        float
            [time].
        """
        if which not in ("last", "next"):
            raise ParameterError(f"which = {which!r} is not one of 'last', 'next'")
        half = 0.5 * self.period
        if self._turning_start or self.kind == "steady":
            return 0.0 if which == "last" else half
        h = self._K if self.root_case == 1 else 2.0 * self._K  # Jacobi argument per half swing
        j = math.floor(self._tau0 / h)
        t_last = (j * h - self._tau0) / self.beta
        if which == "last":
            return min(t_last, 0.0)
        t_next = ((j + 1) * h - self._tau0) / self.beta
        return t_next if t_next > 0.0 else t_next + half

    # ----------------------------------------------------------------------------------
    # Averages (§8)
    # ----------------------------------------------------------------------------------

    def mean_u_power(self, n: int) -> float:
        """Period average ⟨u^n⟩ = ⟨cos^n θ⟩, Serov (1991), eq. (2.5).

        ⟨u⟩ and ⟨u²⟩ in closed form by R_F, R_D, R_J (K, E, Π); higher powers by the recurrence
        k⟨u^{k−1} f⟩ + ½⟨u^k f'⟩ = 0 of §8 while its propagated error bound stays below 1e-13
        of max|u|^n. Near the removable singularities of I2 (case 1 with ν within 2% of 1 − k²
        or 1, e.g. b → 0) and when the recurrence is ill-conditioned (small |b|, outer roots
        far from [u2, u1]) the average is the periodic trapezoid rule in time, converged to
        round-off.

        Parameters
        ----------
        n : int
            Power, n ≥ 0.

        Returns
        -------
        float
            ⟨u^n⟩ [1].
        """
        n = whole_number("n", n, 0)
        return float(means.u_moments(self, n)[n])

    def _pole(self, rho: float) -> _Pole:
        return _make_pole(self, rho)

    def mean_pole(self, rho: float) -> float:
        """Period average ⟨1/(u − ρ)⟩ for a real pole outside [u2, u1], by Carlson integrals.

        Closed form 1/(A_* − ρ) + ν(A_* − B_*)/(A_* − ρ)² ⟨σ/(1 + (r − 1)σ)⟩ (module notes),
        the same reduction as W_ρ, C_ρ of §8 anchored at a turning point.

        Parameters
        ----------
        rho : float
            Pole [1], outside [u2, u1] (ρ = u1 or u2 diverges).

        Returns
        -------
        float
            ⟨1/(u − ρ)⟩ [1].
        """
        check_finite("rho", rho)
        if self.u2 <= rho <= self.u1:
            raise ParameterError(
                f"rho = {rho:g} is inside the motion interval [u2, u1] = "
                f"[{self.u2:g}, {self.u1:g}]; allowed: rho < u2 or rho > u1"
            )
        value = self._pole(float(rho)).mean(self._K)
        if not math.isfinite(value):
            raise ParameterError(
                f"rho = {rho:g} is too close to the motion interval [{self.u2:g}, {self.u1:g}] "
                "for ⟨1/(u − ρ)⟩ in double precision"
            )
        return value

    def mean_inverse(self, sign: int) -> float:
        """Period average ⟨1/(1 + sign·u)⟩, sign = ±1, Serov (1991), eq. (2.5).

        Parameters
        ----------
        sign : int
            +1 for ⟨1/(1 + u)⟩, −1 for ⟨1/(1 − u)⟩.

        Returns
        -------
        float
            [1]; infinite averages (the motion reaches u = ∓1) raise ParameterError.
        """
        if sign not in (1, -1):
            raise ParameterError(f"sign = {sign!r} is not one of +1, −1")
        if sign == 1:
            if self._p2.op <= _POLE_TOUCH:
                raise ParameterError(
                    f"⟨1/(1 + u)⟩ diverges: the motion reaches u = −1 (1 + u2 = {self._p2.op:g}, "
                    f"allowed > {_POLE_TOUCH:g})"
                )
            return self._pole(-1.0).mean(self._K)
        if self._p1.om <= _POLE_TOUCH:
            raise ParameterError(
                f"⟨1/(1 − u)⟩ diverges: the motion reaches u = 1 (1 − u1 = {self._p1.om:g}, "
                f"allowed > {_POLE_TOUCH:g})"
            )
        return -self._pole(1.0).mean(self._K)

    def nodes(self, n: int) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Quadrature nodes over one nutation period, the fallback average of §8.

        The periodic trapezoidal rule in time (uniform in the Jacobi argument βt + τ0, i.e.
        in F(γ)): t_i = iT/n, weights 1/n. It converges geometrically like
        exp(−πn K'/K) (case 1), faster than the rule in γ with weights 1/Δ of §8,
        exp(−2n arcsinh(k'/k)), and without its collapse near the separatrix.

        Parameters
        ----------
        n : int
            Number of nodes, ≥ 1.

        Returns
        -------
        t, theta, theta_dot, w : ndarray, shape (n,)
            Times [time], θ [rad], θ' [rad/time] (both halves of the swing) and weights [1]
            (≥ 0, sum 1).
        """
        n = whole_number("n", n, 1)
        t = self.period * np.arange(n) / n
        th, thd = self._theta_pair(t)
        return t, th, thd, np.full(n, 1.0 / n)

    def _theta_pair(self, t: FloatArray) -> tuple[FloatArray, FloatArray]:
        """(θ [rad], θ' [rad/time]) at checked times t [time], from one set of Jacobi values."""
        if self.kind == "steady":
            return np.full_like(t, self.theta_min), np.zeros_like(t)
        jac = self._jac(t)
        sig, sigc = self._sigma(jac)
        th, om, op = self._theta_from(sig, sigc)
        return th, self._theta_dot_from(jac, sig, sigc, om, op)

    def average(
        self,
        g: Callable[[FloatArray, FloatArray], ArrayLike],
        rtol: float = 1e-12,
        atol: float = 1e-14,
        n_max: int = 1 << 16,
    ) -> float:
        """Period average ⟨g(θ, θ')⟩ = (1/T)∫0^T g dt, Serov (1991), eq. (2.3), adaptively.

        Periodic trapezoid rule of :meth:`nodes`, doubled (reusing nodes) from 32 nodes until
        two successive results agree within max(atol, rtol·|result|).

        Parameters
        ----------
        g : callable
            g(theta [rad], theta_dot [rad/time]) → values, vectorised over arrays.
        rtol, atol : float
            Relative and absolute tolerances [1] and [units of g].
        n_max : int
            Largest number of nodes.

        Returns
        -------
        float
            ⟨g⟩ [units of g].

        Raises
        ------
        IntegrationError
            No convergence with n_max nodes (for instance too near a separatrix), or g not finite.
        """
        check_range("rtol", rtol, low=0.0)
        check_range("atol", atol, low=0.0, low_open=False)
        check_range("n_max", n_max, low=2 * _N_START, low_open=False)
        T = self.period
        n = _N_START
        vals = means.g_values(self, g, T * np.arange(n) / n)
        total, total_abs = float(np.sum(vals)), float(np.sum(np.abs(vals)))
        est = total / n
        while 2 * n <= n_max:
            vals = means.g_values(self, g, T * (np.arange(n) + 0.5) / n)
            total += float(np.sum(vals))
            total_abs += float(np.sum(np.abs(vals)))
            n *= 2
            new = total / n
            # Round-off floor: g itself is evaluated to a few ulps of |g| only.
            floor = 64.0 * _EPS * total_abs / n
            if abs(new - est) <= max(atol, rtol * abs(new), floor):
                return new
            est = new
        raise IntegrationError(
            f"the period average did not converge with n_max = {n_max} nodes on the orbit with "
            f"k² = {self.k2:.6g}, 1 − k² = {self.mc:.3g} (g too sharply peaked, e.g. 1/(1 ∓ cos θ) "
            "for θ passing near 0 or π, or the orbit too near a separatrix)"
        )

    def time_integral(
        self,
        g: Callable[[FloatArray, FloatArray], ArrayLike],
        t0: float,
        t1: float,
        rtol: float = 1e-12,
    ) -> float:
        """∫_{t0}^{t1} g(θ(t), θ'(t)) dt along the orbit, §7 ("corrected" initial state).

        Whole periods contribute T⟨g⟩ (:meth:`average`); the rest is adaptive Gauss–Legendre in
        t (the integrand is analytic in t), panels of at most T/8 bisected until a 20- and a
        40-point rule agree.

        Parameters
        ----------
        g : callable
            g(theta [rad], theta_dot [rad/time]), vectorised.
        t0, t1 : float
            Limits [time].
        rtol : float
            Relative tolerance [1] (relative to ∫|g|).

        Returns
        -------
        float
            [units of g × time].
        """
        check_finite("t0", t0)
        check_finite("t1", t1)
        check_range("rtol", rtol, low=0.0)
        if t1 == t0:
            return 0.0
        if t1 < t0:
            return -self.time_integral(g, t1, t0, rtol)
        T = self.period
        n_per = math.floor((t1 - t0) / T)
        whole = 0.0
        if n_per > 0:
            size = float(np.mean(np.abs(means.g_values(self, g, T * np.arange(64) / 64))))
            whole = n_per * T * self.average(g, rtol=0.1 * rtol, atol=0.1 * rtol * size + 1e-300)
        lo = t0 + n_per * T
        return whole + means.gauss_legendre(self, g, lo, t1, rtol)
