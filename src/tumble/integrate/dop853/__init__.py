"""The compiled DOP853 integrator, for any compiled right-hand side (:mod:`tumble.kernels`).

The Dormand–Prince 8(5,3) method with its 7th-order continuous extension (Hairer, Nørsett &
Wanner, *Solving ODEs I*, §II.5–II.6), with the error norm, step-size controller and starting
step of scipy's ``DOP853``: the two take the same steps, and scipy's solver with the models'
Python right-hand sides is the reference the compiled path is tested against.

The pieces, each compiled: :mod:`~.tableau` (the coefficients), :mod:`~.steps` (the stages,
the error norm, the step-size control), :mod:`~.dense` (the interpolant), :mod:`~.events`
(zeros of an event function), :mod:`~.core` (the loop, which advances in chunks of steps), and
:mod:`~.driver` (the Python side: :func:`solve`, the resumable :class:`Integration`, and
batches over threads with the GIL released).
"""

from tumble.integrate.dop853 import driver
from tumble.integrate.dop853.core import STOPPED
from tumble.integrate.dop853.driver import *  # noqa: F403  (the names of the driver's __all__)

__all__ = ["STOPPED"]
__all__ += driver.__all__  # the core's stop status, and the driver's names
