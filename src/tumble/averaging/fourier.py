"""Fourier series of functions sampled on a uniform grid of a d-torus.

The grid has n_j nodes φ = 2π i / n_j along phase j (:func:`_nodes`); values on it are
interpolated by their trigonometric series (:func:`torus_values`), differentiated spectrally
(:func:`_phase_derivatives`) and tested for resolution (:func:`resolved`). The Nyquist
harmonic of an even axis is not resolved and is treated as absent throughout. These are the
tools of the second-order averaging of :mod:`tumble.averaging.second_order`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError

__all__ = ["resolved", "torus_values"]


def _nodes(shape: Sequence[int]) -> list[FloatArray]:
    """The phases of a uniform grid, one array per axis shaped to broadcast (ij indexing)."""
    d = len(shape)
    out: list[FloatArray] = []
    for axis, n in enumerate(shape):
        view = [1] * d
        view[axis] = n
        out.append(np.asarray(np.arange(n) * (2.0 * math.pi / n), dtype=float).reshape(view))
    return out


def _waves(shape: Sequence[int]) -> list[FloatArray]:
    """Integer harmonics of each axis, shaped to broadcast over the grid, Nyquist set to 0
    (read-only arrays, built once per grid)."""
    return list(_waves_of(tuple(int(n) for n in shape)))


@functools.lru_cache(maxsize=64)
def _waves_of(shape: tuple[int, ...]) -> tuple[FloatArray, ...]:
    d = len(shape)
    out: list[FloatArray] = []
    for axis, n in enumerate(shape):
        k = np.asarray(np.fft.fftfreq(n) * n, dtype=float)
        if n % 2 == 0:
            k[n // 2] = 0.0  # the Nyquist harmonic is not resolved: treated as absent
        view = [1] * d
        view[axis] = n
        k = k.reshape(view)
        k.flags.writeable = False
        out.append(k)
    return tuple(out)


def torus_values(values: ArrayLike, phases: ArrayLike) -> FloatArray:
    """The trigonometric interpolant of grid values at arbitrary phases.

    Parameters
    ----------
    values : array_like, shape (c, n_1, …, n_d)
        c functions at the nodes φ_j = 2π i_j / n_j.
    phases : array_like, shape (d,) or (n, d)
        Where to evaluate them [rad].

    Returns
    -------
    ndarray, shape (c,) or (n, c)
        The interpolant (the Nyquist harmonic of an even axis dropped).
    """
    f = np.asarray(values, dtype=float)
    at = np.asarray(phases, dtype=float)
    single = at.ndim == 1
    at = np.atleast_2d(at)
    shape = f.shape[1:]
    d = len(shape)
    if at.shape[-1] != d:
        raise ParameterError(f"phases: {at.shape[-1]} phases given for a {d}-torus")
    coef = _coefficients(f)
    out = _series(np.broadcast_to(coef, (at.shape[0], *coef.shape)), at)  # (n, c)
    return out[0] if single else out


def resolved(values: FloatArray, rtol: float) -> list[bool]:
    """Per phase axis: whether the harmonics above a quarter of the grid are below ``rtol``
    of the largest coefficient of ``values`` (shape (c, *grid))."""
    d = values.ndim - 1
    coef = np.abs(np.fft.fftn(values, axes=tuple(range(1, d + 1)))).max(axis=0)
    top = float(coef.max())
    if top == 0.0:
        return [True] * d
    out = []
    for axis, n in enumerate(coef.shape):
        k = np.abs(np.fft.fftfreq(n) * n)
        high = np.moveaxis(coef, axis, 0)[k > n / 4]
        out.append(n < 4 or high.size == 0 or float(high.max()) <= rtol * top)
    return out


def _phase_derivatives(values: FloatArray) -> list[FloatArray]:
    """∂/∂φ_j of grid values (shape (c, *grid)), spectrally, one array per phase."""
    shape = values.shape[1:]
    axes = tuple(range(1, len(shape) + 1))
    coef = np.fft.fftn(values, axes=axes)
    return [np.fft.ifftn(1j * k * coef, axes=axes).real for k in _waves(shape)]


def _coefficients(values: FloatArray) -> FloatArray:
    """Fourier coefficients of grid values (c, *grid) with the Nyquist harmonics removed."""
    shape = values.shape[1:]
    d = len(shape)
    coef = np.fft.fftn(values, axes=tuple(range(1, d + 1))) / math.prod(shape)
    for axis, n in enumerate(shape):
        if n % 2 == 0:
            index = [slice(None)] * (d + 1)
            index[axis + 1] = slice(n // 2, n // 2 + 1)
            coef[tuple(index)] = 0.0
    return np.asarray(coef)


def _padded(coef: FloatArray, shape: tuple[int, ...]) -> FloatArray:
    """Coefficients of a coarser grid placed on a finer one (harmonics by their numbers)."""
    out = np.zeros((coef.shape[0], *shape[1:]), dtype=complex)
    places = [
        (np.fft.fftfreq(n) * n).astype(int) % fine
        for n, fine in zip(coef.shape[1:], shape[1:], strict=True)
    ]
    index = np.ix_(range(coef.shape[0]), *places)
    out[index] = coef
    return out


def _series(coef: FloatArray, phases: FloatArray) -> FloatArray:
    """Σ_k c_k e^{i k·φ} for each row: coef (n, c, *grid), phases (n, d) → (n, c)."""
    shape = coef.shape[2:]
    waves = _waves(shape)
    k = np.stack([np.broadcast_to(w, shape).reshape(-1) for w in waves], -1)  # (N, d)
    turn = np.exp(1j * (phases @ k.T))  # (n, N)
    flat = coef.reshape(coef.shape[0], coef.shape[1], -1)  # (n, c, N)
    return np.asarray(np.real(np.einsum("ncN,nN->nc", flat, turn)), dtype=float)
