"""The first-order generator of the near-identity transformation, numerically, on a torus grid.

For slow variables x driven by fast phases φ turning at the frequencies ν (a vector),

    dx/dt = ε f(x, φ),    dφ/dt = ν(x),

the near-identity transformation x = x̄ + ε w₁(x̄, φ) removes the oscillating part of f at first
order when w₁ is the zero-mean solution of

    ν · ∂w₁/∂φ = f(x̄, φ) − ⟨f⟩(x̄)

(J. A. Sanders, F. Verhulst and J. Murdock, *Averaging Methods in Nonlinear Dynamical
Systems*, 2nd ed., Springer 2007: ch. 2 for one angle, ch. 7 for several). The mean variables x̄
then obey the averaged equations dx̄/dt = ε⟨f⟩ + O(ε²), and w₁ maps them to the osculating
ones and back: x = x̄ + ε w₁(x̄, φ), x̄ = x − ε w₁(x, φ) + O(ε²).

On a uniform grid of the torus (the averaging engine's quadrature grid), f has the discrete
Fourier coefficients f̂_k, and

    w₁(φ) = Σ_{k ≠ 0} f̂_k / (i k·ν) · e^{i k·φ},

exact for a trigonometric polynomial the grid resolves and spectrally accurate for a smooth f.
A harmonic with k·ν = 0 and f̂_k ≠ 0 is a resonance: there is no bounded w₁, and the
averaging of the non-resonant case does not hold. A small k·ν (a *small divisor*) makes w₁,
hence the O(ε) correction, large. Both are reported (:class:`SmallDivisorError`), never
divided by. The Nyquist harmonic of an even grid (k_j = −n_j/2) is not resolved: its
coefficient is the grid's aliasing, and it is dropped.
"""

from __future__ import annotations

import functools

import numpy as np

from tumble._typing import ArrayLike, BoolArray, FloatArray
from tumble.averaging.quadrature import AveragingError
from tumble.errors import ParameterError

__all__ = ["DIVISOR_RTOL", "RESONANT_FLOOR", "SmallDivisorError", "zero_mean_antiderivative"]

DIVISOR_RTOL = 1e-6
"""A harmonic k is a small divisor when |k·ν| ≤ DIVISOR_RTOL·|k|·max|ν_j| while its coefficient
is at least RESONANT_FLOOR of the largest: its term of w₁ would be ≥ 1e6 times the size of the
oscillation it removes."""

RESONANT_FLOOR = 1e-6
"""A harmonic below this fraction of the largest is no resonance the averaged equations must
respect: the resonance table gives it no band (its width goes as the square root of its size),
and at a small divisor its term is dropped rather than reported. Its term at the edge of the
small divisors, |f̂_k|/(DIVISOR_RTOL·|k|·max|ν|), is then at most the size of the generator's
largest terms, |f̂|/ν, and far below it for the high harmonics that meet such resonances near a
separatrix (a rotating field's run of order 2 met k = (22, −2, −2), of coefficient 3.5e-15,
at k·ν = −7.6e-6)."""


class SmallDivisorError(AveragingError):
    """A harmonic of the fast right-hand side at (or near) a resonance k·ν = 0."""


@functools.lru_cache(maxsize=64)
def _harmonics(shape: tuple[int, ...]) -> tuple[tuple[FloatArray, ...], FloatArray, BoolArray]:
    """The integer harmonics k of the grid along each axis (ij indexing), |k|, and where an
    even axis is at its Nyquist harmonic: built once per grid, read-only."""
    waves = tuple(np.meshgrid(*(np.fft.fftfreq(n) * n for n in shape), indexing="ij"))
    k_size = np.sqrt(sum(w * w for w in waves))
    nyquist = np.zeros(shape, dtype=bool)
    for axis, n in enumerate(shape):
        if n % 2 == 0:
            nyquist |= waves[axis] == -n // 2
    for a in (*waves, k_size, nyquist):
        a.flags.writeable = False
    return waves, np.asarray(k_size, dtype=float), nyquist


def zero_mean_antiderivative(
    values: ArrayLike, frequencies: ArrayLike, *, divisor_rtol: float = DIVISOR_RTOL
) -> FloatArray:
    """w with ν·∂w/∂φ = values − ⟨values⟩ and ⟨w⟩ = 0 on a uniform torus grid (module notes).

    Parameters
    ----------
    values : array_like, shape (..., n_1, ..., n_d)
        f at the nodes φ_j = 2π i_j / n_j of the last d axes (one per fast phase), any
        leading axes (the components of f) [rate unit].
    frequencies : array_like, shape (d,)
        The phases' rates ν_j [rad per time unit].
    divisor_rtol : float
        Relative size of k·ν below which a harmonic present in f is a small divisor [1].

    Returns
    -------
    ndarray, same shape as ``values``
        w₁ at the same nodes [rate unit × time unit].

    Raises
    ------
    SmallDivisorError
        A harmonic k of f (at least :data:`RESONANT_FLOOR` of the largest) with
        |k·ν| ≤ divisor_rtol·|k|·max|ν|; the message
        names k, k·ν and the size of the coefficient.
    ParameterError
        Not finite, or a frequency vector that does not match the grid's dimension.
    """
    f = np.asarray(values, dtype=float)
    nu = np.asarray(frequencies, dtype=float).reshape(-1)
    d = nu.size
    if d == 0 or f.ndim < d:
        raise ParameterError(
            f"frequencies: {d} phases for values of {f.ndim} axes (need 1 ≤ phases ≤ axes)"
        )
    if not (np.all(np.isfinite(f)) and np.all(np.isfinite(nu))):
        raise ParameterError("values and frequencies must be finite")
    if d == 1 and nu[0] != 0.0:  # one phase turning: no divisor k·ν = kν can be small
        n = f.shape[-1]
        half = np.fft.rfft(f, axis=-1)  # k = 0 … ⌊n/2⌋, the real transform's half
        divisor = 1j * nu[0] * np.arange(half.shape[-1])
        divisor[0] = 1.0
        w = half / divisor
        w[..., 0] = 0.0
        if n % 2 == 0:
            w[..., -1] = 0.0  # the Nyquist harmonic, as below
        return np.asarray(np.fft.irfft(w, n=n, axis=-1), dtype=float)
    axes = tuple(range(f.ndim - d, f.ndim))
    shape = f.shape[-d:]
    coef = np.fft.fftn(f, axes=axes)
    waves, k_size, nyquist = _harmonics(shape)
    k_dot_nu = sum(w * v for w, v in zip(waves, nu, strict=True))
    size = np.abs(coef).reshape(-1, *shape).max(axis=0)  # over the leading components
    present = size > RESONANT_FLOOR * max(float(size.max()), 1e-300)
    zero = k_size == 0.0
    near = ~zero & ~nyquist
    near &= np.abs(k_dot_nu) <= divisor_rtol * k_size * float(np.max(np.abs(nu)))
    small = near & present
    if np.any(small):
        at = tuple(int(i[0]) for i in np.nonzero(small))
        k = tuple(int(w[at]) for w in waves)
        raise SmallDivisorError(
            f"the harmonic k = {k} of the fast right-hand side has k·ν = {k_dot_nu[at]:.3g} "
            f"(ν = {nu.tolist()}) and a coefficient {size[at] / size.size:.3g}: at or near "
            "a resonance, where the first-order generator is unbounded (averaging of the "
            "non-resonant case does not hold)"
        )
    divisor = 1j * k_dot_nu
    keep = ~zero & ~nyquist & ~near  # a near-resonant harmonic kept is round-off only: 0
    divisor[~keep] = 1.0  # those coefficients are set to 0 below
    w = coef / divisor
    w[..., ~keep] = 0.0
    return np.asarray(np.fft.ifftn(w, axes=axes).real, dtype=float)
