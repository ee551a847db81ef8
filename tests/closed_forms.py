"""A check the closed-form averages share: the compiled triaxial engine's closed form
(``KIND_TRIAXIAL_CLOSED``) against the same average by quadrature (``KIND_TRIAXIAL_PHASE_MEANS``,
the same parameters), at states across both regimes of the Euler–Poinsot motion."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from tumble.averaging import triaxial_kernel
from tumble.kernels import KIND_TRIAXIAL_CLOSED, KIND_TRIAXIAL_PHASE_MEANS
from tumble.kernels.rhs import evaluate


def closed_and_quadrature(
    torque: object, inertia: np.ndarray, period: float | None, rng: np.random.Generator
) -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """(state, closed-form rates, quadrature rates) at 20 random states [L_ξ, r] and two next
    to the pure rotations, the node turned by a random time; the kernel must choose the closed
    form."""
    kernel = triaxial_kernel(torque, inertia, period, rtol=1e-13)
    assert kernel is not None and kernel.kind == KIND_TRIAXIAL_CLOSED  # the closed form chosen
    I1, I2, I3 = sorted(inertia)
    for r in np.concatenate([rng.uniform(1.0 / I3, 1.0 / I1, 20), [1.0001 / I3, 0.9999 / I1]]):
        if abs(r * I2 - 1.0) < 1e-6:  # the separatrix band: the rates are refused there
            continue
        y = np.array([*rng.normal(size=3), r])
        t = rng.uniform(0.0, 10.0)  # the node has turned
        closed = evaluate(KIND_TRIAXIAL_CLOSED, t, y, kernel.params)
        yield y, closed, evaluate(KIND_TRIAXIAL_PHASE_MEANS, t, y, kernel.params)
