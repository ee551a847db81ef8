"""Stability of stationary motions, for any model that declares one.

The linearization is taken from the model's own full right-hand side by complex-step
differentiation (exact to round-off, no step-size trade-off), in the local coordinates the
model's :class:`~tumble.models.base.StationaryMotion` defines. The characteristic polynomial
follows from the Jacobian by sums of principal minors; its roots decide the classification
(docs/theory/rotating-field.md §16):

* ``"unstable"`` if max Re λ > :data:`CRITICAL_TOL`;
* ``"critical"`` if |max Re λ| ≤ :data:`CRITICAL_TOL` (or a structural zero root);
* ``"asymptotically stable"`` otherwise.

A real part closer to zero than its own rounding uncertainty (a root that the rounding of the
coefficients can move across the imaginary axis, e.g. a nearly double root) is counted as
critical too: the verdict never rests on rounding.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import xarray as xr

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError, TumbleError
from tumble.models import AnyModel
from tumble.models.base import StationaryMotion

__all__ = [
    "CLASSES",
    "CRITICAL_TOL",
    "Classification",
    "StabilityReport",
    "analyze",
    "characteristic_polynomial",
    "classify",
    "jacobian",
    "linearize",
    "match_roots",
    "polynomial_roots",
    "root_uncertainty",
    "stability_grid",
]

CRITICAL_TOL = 1e-10
"""|max Re λ| at or below this is a critical case (docs/theory/rotating-field.md §16)."""

Classification = Literal["asymptotically stable", "critical", "unstable"]
CLASSES: tuple[Classification, ...] = ("asymptotically stable", "critical", "unstable")
"""Classification labels; their index is the code used in stability maps."""

FAMILY_SAMPLES = 24
"""Members of a stationary family (parameter in [0, 2π)) scanned by :func:`analyze`."""

_COMPLEX_STEP = 1e-30  # any step ≪ √(machine ε)·|x|: the complex step has no cancellation

_COEFF_ULPS = 8.0
"""Relative error of the coefficients, in units of the machine ε: a closed form such as (2.5)
rounds a handful of times per coefficient."""


def jacobian(f: Callable[[Any], Any], x0: ArrayLike) -> FloatArray:
    """Jacobian of ``f`` at ``x0`` by complex-step differentiation.

    ``∂f/∂x_j = Im f(x0 + i h e_j) / h`` is exact to round-off for real-analytic ``f`` written
    with ordinary arithmetic (no ``abs``, no branch on values, no float conversion).

    Parameters
    ----------
    f : callable
        ``f(x) -> array``, accepting complex arrays.
    x0 : sequence of float
        Point [units of x].

    Returns
    -------
    ndarray, shape (len(f(x0)), len(x0))
    """
    base = np.asarray(x0, dtype=float)
    cols = []
    for j in range(base.size):
        x = base.astype(complex)
        x[j] += 1j * _COMPLEX_STEP
        cols.append(np.imag(np.asarray(f(x))) / _COMPLEX_STEP)
    return np.column_stack(cols)


def linearize(motion: StationaryMotion, p: Any) -> tuple[FloatArray, FloatArray]:
    """Jacobian of a stationary motion in its local coordinates, e.g. (2.3)/(2.4).

    Parameters
    ----------
    motion : StationaryMotion
        The stationary motion and its chart (from ``model.stationary(p)``).
    p : model Params

    Returns
    -------
    (J, J_keep)
        The Jacobian in every local coordinate, and its block on ``motion.keep``.

    Raises
    ------
    ParameterError
        If the state is not stationary, or a dropped coordinate feeds back into the kept ones.
    """
    y0 = np.asarray(motion.state, dtype=float)
    rate = np.asarray(motion.tangent(y0, motion.rhs(0.0, y0, p)), dtype=float)
    scale = max(1.0, float(np.max(np.abs(y0))))
    if np.max(np.abs(rate)) > 1e-12 * scale:  # round-off of one right-hand-side evaluation
        raise ParameterError(
            f"{motion.name} is not stationary: its local rates are {rate.tolist()}"
        )

    def local(x: Any) -> Any:
        y = motion.embed(x)
        return motion.tangent(y, motion.rhs(0.0, y, p))

    J = jacobian(local, np.zeros(len(motion.coordinates)))
    keep = list(motion.keep)
    dropped = [i for i in range(J.shape[0]) if i not in keep]
    if dropped and np.max(np.abs(J[np.ix_(keep, dropped)])) > 0.0:
        raise ParameterError(
            f"{motion.name}: the coordinates {[motion.coordinates[i] for i in dropped]} feed "
            "back into the others and cannot be left out of the stability analysis"
        )
    return J, J[np.ix_(keep, keep)]


def characteristic_polynomial(J: FloatArray, leading: float = 1.0) -> FloatArray:
    """Coefficients of ``leading · det(λE − J)``, highest power first.

    The coefficient of λ^(n−k) is (−1)^k times the sum of the k×k principal minors of J,
    each from an LU factorization, summed with ``math.fsum``: no eigenvalues are involved.
    A coefficient is accurate to a few ulp of the magnitudes of its terms; a coefficient that
    is small because its terms cancel (or because an entry of J is itself a rounded small
    difference, such as I3 − I2 or 1 − cos²β) is accurate to that absolute level only. Meant
    for the small systems of stability problems (n ≤ 12).

    Parameters
    ----------
    J : ndarray, shape (n, n)
    leading : float
        Normalization of the highest coefficient (e.g. I1 I2 I3 for (2.5)).

    Returns
    -------
    ndarray, shape (n + 1,)
    """
    n = J.shape[0]
    if n > 12:
        return leading * np.real(np.poly(J))
    coeffs = [1.0]
    for k in range(1, n + 1):
        total = math.fsum(
            float(np.linalg.det(J[np.ix_(idx, idx)])) for idx in itertools.combinations(range(n), k)
        )
        coeffs.append((-1) ** k * total)
    return leading * np.array(coeffs)


def polynomial_roots(coeffs: ArrayLike) -> np.ndarray:
    """Roots of a real polynomial (highest power first), polished by Newton's method.

    Exact zero trailing coefficients give exact zero roots (structural zeros stay zero).

    Parameters
    ----------
    coeffs : sequence of float

    Returns
    -------
    ndarray of complex, sorted by decreasing real part
    """
    c = np.asarray(coeffs, dtype=float)
    roots = np.roots(c).astype(complex)
    dc = np.polyder(c)
    for i, r in enumerate(roots):
        if r == 0.0:
            continue
        best, best_res = r, abs(np.polyval(c, r))
        for _ in range(4):
            d = np.polyval(dc, best)
            if d == 0.0:
                break
            cand = best - np.polyval(c, best) / d
            res = abs(np.polyval(c, cand))
            if not res < best_res:
                break
            best, best_res = cand, res
        roots[i] = best
    return roots[np.argsort(-roots.real, kind="stable")]


def root_uncertainty(coeffs: ArrayLike, roots: ArrayLike) -> FloatArray:
    """First-order bound on how far rounding of the coefficients can move each root.

    ``|δλ| ≈ u_c · Σ|a_k| |λ|^(n−k) / |P′(λ)|`` with u_c = :data:`_COEFF_ULPS` machine ε: large
    for nearly multiple roots (e.g. ±i and ±iω0 of (2.6) for a thin plate at small ε), where the
    computed real part is not reliable to :data:`CRITICAL_TOL`. Exact zero roots split off by
    exactly zero trailing coefficients (structural zeros) have no uncertainty.

    Parameters
    ----------
    coeffs : sequence of float
        Polynomial, highest power first.
    roots : sequence of complex
        Its roots.

    Returns
    -------
    ndarray
        One bound per root [units of λ]; ``inf`` where P′(λ) vanishes.
    """
    c = np.asarray(coeffs, dtype=float)
    r = np.asarray(roots, dtype=complex)
    zeros = len(c) - 1 - int(np.flatnonzero(c)[-1]) if np.any(c) else len(c) - 1
    size = np.polyval(np.abs(c), np.abs(r))
    slope = np.abs(np.polyval(np.polyder(c), r))
    bound = np.full(r.shape, np.inf)
    np.divide(_COEFF_ULPS * np.finfo(float).eps * size, slope, out=bound, where=slope > 0.0)
    if zeros:
        bound = np.where(r == 0.0, 0.0, bound)
    return np.asarray(bound, dtype=float)


def classify(
    roots: ArrayLike,
    tol: float = CRITICAL_TOL,
    uncertainty: ArrayLike | None = None,
) -> Classification:
    """``"unstable"``, ``"critical"`` or ``"asymptotically stable"`` from the roots.

    Parameters
    ----------
    roots : sequence of complex
    tol : float
        Band of max Re λ counted as zero [1/time].
    uncertainty : sequence of float, optional
        Rounding bound of each root (:func:`root_uncertainty`): a root counts as unstable or
        stable only if its real part clears ``tol`` by more than its own bound; otherwise the
        verdict is at best critical.
    """
    re = np.real(np.asarray(roots, dtype=complex))
    band = tol + (0.0 if uncertainty is None else np.asarray(uncertainty, dtype=float))
    if np.any(re > band):
        return "unstable"
    if np.any(re >= -band):
        return "critical"
    return "asymptotically stable"


def match_roots(roots: ArrayLike, approx: ArrayLike) -> np.ndarray:
    """Order ``approx`` so that its i-th entry is the one nearest to ``roots[i]``.

    Pairs exact roots with approximate ones (e.g. (2.6)) by minimizing the total distance.

    Parameters
    ----------
    roots, approx : sequence of complex
        Equally many roots.

    Returns
    -------
    ndarray of int
        Index into ``approx`` for each exact root.
    """
    from scipy.optimize import linear_sum_assignment

    r = np.asarray(roots, dtype=complex)
    a = np.asarray(approx, dtype=complex)
    if r.shape != a.shape:
        raise ParameterError(f"cannot pair {r.size} roots with {a.size} approximations")
    _, cols = linear_sum_assignment(np.abs(r[:, None] - a[None, :]))
    return np.asarray(cols, dtype=int)


@dataclass(frozen=True)
class StabilityReport:
    """Linear stability of a stationary motion.

    Attributes
    ----------
    motion : str
        Which stationary motion.
    coefficients : ndarray
        Characteristic polynomial, highest power first (the closed form where the model has
        one, e.g. a0 … a5 of (2.5); else from the Jacobian).
    coefficients_jacobian : ndarray
        The same from the automatic Jacobian.
    roots : ndarray of complex
        Exact roots of ``coefficients``, sorted by decreasing real part.
    approx_roots : ndarray of complex or None
        The paper's approximate roots (e.g. (2.6)), reported even where invalid.
    approx_note : str
        Why the approximation may be invalid here ("" if it is expected to hold).
    classification : str
        One of :data:`CLASSES`.
    max_real : float
        Leading real part max Re λ [1/time].
    jacobian : ndarray
        The kept block of the Jacobian.
    notes : list of str
        Structural zero roots and other remarks.
    family_max_real : (float, float) or None
        Range of max Re λ over the one-parameter family the motion belongs to (e.g. the free
        phase of a co-rotation), sampled at :data:`FAMILY_SAMPLES` members; None if isolated.
    uncertainty : ndarray or None
        Rounding bound of each root (:func:`root_uncertainty`) [1/time].
    """

    motion: str
    coefficients: FloatArray
    coefficients_jacobian: FloatArray
    roots: np.ndarray
    approx_roots: np.ndarray | None
    approx_note: str
    classification: Classification
    max_real: float
    jacobian: FloatArray
    notes: list[str] = field(default_factory=list)
    family_max_real: tuple[float, float] | None = None
    uncertainty: FloatArray | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``coefficients`` [a0…], ``roots`` and ``approx_roots`` as [re, im]."""

        def pairs(z: np.ndarray | None) -> list[list[float]] | None:
            return None if z is None else [[float(r.real), float(r.imag)] for r in z]

        return {
            "motion": self.motion,
            "coefficients": [float(c) for c in self.coefficients],
            "coefficients_jacobian": [float(c) for c in self.coefficients_jacobian],
            "roots": pairs(self.roots),
            "approx_roots": pairs(self.approx_roots),
            "approx_note": self.approx_note,
            "classification": self.classification,
            "max_real_part": self.max_real,
            "family_max_real_part": None
            if self.family_max_real is None
            else list(self.family_max_real),
            "root_uncertainty": None
            if self.uncertainty is None
            else [float(u) for u in self.uncertainty],
            "notes": list(self.notes),
        }


def analyze(
    model: AnyModel, p: Any, *, tol: float = CRITICAL_TOL, family: bool = True
) -> StabilityReport:
    """Linear stability of the model's stationary motion at parameters ``p``.

    Parameters
    ----------
    model : Model
        A model with ``stationary`` (e.g. ``rotating_field.MODEL``).
    p : model Params
    tol : float
        Band of max Re λ counted as zero [1/time].
    family : bool
        Also scan the family the motion belongs to (:data:`FAMILY_SAMPLES` more
        linearizations); False analyses the model's own member only.

    Returns
    -------
    StabilityReport
    """
    if model.stationary is None:
        raise ParameterError(f"model {model.name} declares no stationary motion to analyse")
    motion = model.stationary(p)
    _, J = linearize(motion, p)
    from_jacobian = characteristic_polynomial(J, motion.leading)
    coeffs = from_jacobian if motion.coefficients is None else np.asarray(motion.coefficients)
    roots = polynomial_roots(coeffs)
    uncertainty = root_uncertainty(coeffs, roots)
    notes = []
    max_real = float(np.max(roots.real))
    label = classify(roots, tol, uncertainty)
    if label != classify(roots, tol):
        worst = float(np.max(uncertainty[np.abs(roots.real) <= tol + uncertainty]))
        notes.append(
            f"a real part is within its rounding uncertainty (±{worst:.2g}) of zero (a nearly "
            "multiple root): the verdict cannot be sharper than critical"
        )
    if motion.structural_zero:
        notes.append(
            "the constant coefficient is exactly zero: a structural zero root (a continuum of "
            "stationary motions), so the motion is at best critical"
        )
        if label == "asymptotically stable":  # rounding cannot make it stable
            label = "critical"
    family_range = None
    if family and motion.family is not None:
        leads, labels = [], set()
        for phase in np.linspace(0.0, 2.0 * np.pi, FAMILY_SAMPLES, endpoint=False):
            member = motion.family(float(phase))
            _, Jm = linearize(member, p)
            cm = characteristic_polynomial(Jm, member.leading)
            r = polynomial_roots(cm)
            leads.append(float(np.max(r.real)))
            labels.add(classify(r, tol, root_uncertainty(cm, r)))
        family_range = (min(leads), max(leads))
        if family_range[1] - family_range[0] > tol:
            notes.append(
                f"the stationary motion belongs to a family ({motion.name}) whose members have "
                f"max Re λ from {family_range[0]:.6g} to {family_range[1]:.6g}; the reported "
                "roots are those of the member analysed"
                + ("" if len(labels) == 1 else f"; classifications differ: {sorted(labels)}")
            )
    approx = None if motion.approx_roots is None else np.asarray(motion.approx_roots)
    return StabilityReport(
        motion.name,
        coeffs,
        from_jacobian,
        roots,
        approx,
        motion.approx_note,
        label,
        max_real,
        J,
        notes,
        family_range,
        uncertainty,
    )


def stability_grid(
    model: AnyModel,
    make_params: Callable[[float, float], Any],
    x: tuple[str, ArrayLike, dict[str, str]],
    y: tuple[str, ArrayLike, dict[str, str]],
    *,
    attrs: dict[str, Any] | None = None,
    tol: float = CRITICAL_TOL,
    family: bool = False,
    progress: Callable[[int, int], None] | None = None,
) -> xr.Dataset:
    """Classification and leading Re λ over a 2-D parameter grid.

    Parameters
    ----------
    model : Model
    make_params : callable
        ``(x, y) -> Params``; a :class:`~tumble.errors.TumbleError` marks a point outside the
        model's domain (e.g. inertia breaking the triangle inequality).
    x, y : (name, values, attrs)
        The grid axes, with ``units`` and ``long_name`` in ``attrs``.
    attrs : dict, optional
        Dataset attributes (the fixed parameters).
    tol : float
        Band of max Re λ counted as zero.
    family : bool
        Scan the family of every point too (see :func:`analyze`); off by default, since it
        multiplies the cost by :data:`FAMILY_SAMPLES` + 1: the map is of the model's own member.
    progress : callable, optional
        ``progress(done, total)`` after each grid point (e.g. to drive a progress bar).

    Returns
    -------
    xarray.Dataset
        ``classification`` (code: index in :data:`CLASSES`, −1 outside the domain) and
        ``max_real`` (NaN outside the domain) on dims (y, x).
    """
    xs, ys = np.asarray(x[1], dtype=float), np.asarray(y[1], dtype=float)
    code = np.full((ys.size, xs.size), -1, dtype=int)
    lead = np.full((ys.size, xs.size), np.nan)
    total = code.size
    for k, ((i, yv), (j, xv)) in enumerate(itertools.product(enumerate(ys), enumerate(xs))):
        try:
            p = make_params(float(xv), float(yv))
        except TumbleError:
            p = None  # outside the domain: recorded as code −1
        if p is not None:
            rep = analyze(model, p, tol=tol, family=family)
            code[i, j] = CLASSES.index(rep.classification)
            lead[i, j] = rep.max_real
        if progress is not None:
            progress(k + 1, total)
    ds = xr.Dataset(
        {
            "classification": (
                (y[0], x[0]),
                code,
                {
                    "long_name": "classification",
                    "units": "1",
                    "flag_values": "-1 0 1 2",
                    "flag_meanings": "outside_domain "
                    + " ".join(c.replace(" ", "_") for c in CLASSES),
                },
            ),
            "max_real": (
                (y[0], x[0]),
                lead,
                {"long_name": "leading real part max Re λ", "units": "1/τ"},
            ),
        },
        coords={x[0]: (x[0], xs, x[2]), y[0]: (y[0], ys, y[2])},
    )
    ds.attrs.update(model=model.name, critical_tol=tol, family_scanned=int(family), **(attrs or {}))
    return ds
