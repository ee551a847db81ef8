"""Errors and warnings of tumble, and the range checks that raise them.

Two kinds of trouble get two responses (docs/reference/errors.md): input that cannot describe a
valid run raises a :class:`TumbleError` subclass with a one-line message naming the field, the
value and the allowed range; a valid run that enters a region where a method loses accuracy
emits a :class:`TumbleWarning` and is never refused.
"""

from __future__ import annotations

import math
import os
import sys
import warnings
from collections.abc import Sequence
from types import FrameType
from typing import Any

__all__ = [
    "IntegrationError",
    "ParameterError",
    "ScenarioError",
    "TumbleError",
    "TumbleWarning",
    "UserCodeError",
    "UserCodeTimeout",
    "check_finite",
    "check_range",
    "shorten",
    "state_text",
    "warn",
]

MAX_ECHO = 80
"""Longest piece of the user's input an error message repeats."""


def shorten(text: object, limit: int = MAX_ECHO) -> str:
    """``str(text)`` cut to ``limit`` characters: an error message never echoes a huge input."""
    out = str(text)
    return out if len(out) <= limit else out[: limit - 3] + "..."


class TumbleError(Exception):
    """Base class of every error tumble raises on purpose; ``exit_code`` is the CLI's.

    ``partial`` is what the run computed before the error stopped it, where it keeps any (a
    full run's :class:`~tumble.integrate.Trajectory` up to the last step it took); the runner
    writes it, marked as ending early, and sets ``written``.
    """

    exit_code = 2
    partial: Any = None
    dense: Any = None
    """On scipy's path: the dense output of the run up to the last step it took before the
    error (from which :func:`tumble.integrate.simulate` makes ``partial``)."""
    written: str | None = None
    """The output directory that holds what the run computed before the error, if any."""


class ParameterError(TumbleError, ValueError):
    """A parameter or initial value outside its allowed range."""


class ScenarioError(TumbleError):
    """A scenario file that cannot be read or does not follow the scenario contract."""


class UserCodeError(ScenarioError):
    """A user's function (a torque the scenario names) that failed: it raised, returned a
    moment that is not 3 finite numbers, or does not compile for the call tumble makes. A
    fault of the user's input, as a parameter out of range is (exit 2)."""


class UserCodeTimeout(UserCodeError):
    """A user's function that did not return within ``run.user_code_timeout``. Raised in the
    main thread either by a watcher thread (which can only give a class, so the message is
    set on the class first) or by the compiled driver that waited for it."""

    message = "a user's function did not return"

    def __init__(self, *args: object) -> None:
        super().__init__(*(args or (type(self).message,)))

    @staticmethod
    def said(names: Sequence[str], seconds: float) -> str:
        """The message: the functions ``names`` did not return within ``seconds``."""
        named = ", ".join(names) or "the user's torque"
        return (f"{named} did not return within {seconds:g} s (run.user_code_timeout): "
                "the run is stopped")  # fmt: skip


class OutputError(TumbleError):
    """The output directory cannot take the results (not a directory, not writable)."""


class IntegrationError(TumbleError, RuntimeError):
    """An integration that failed, or a solution that left the real numbers (blow-up)."""

    exit_code = 3


class TumbleWarning(UserWarning):
    """A valid run entered a region where a method is known to lose accuracy."""


def warn(message: str) -> None:
    """Emit ``message`` as a :class:`TumbleWarning` attributed to the first caller outside
    tumble (a user's script or notebook cell), not to the line of tumble that noticed it: the
    place Python prints beside a warning is then the user's own call."""
    package = os.path.dirname(os.path.abspath(__file__))
    level = 2  # stacklevel 2: warn's caller
    frame: FrameType | None = sys._getframe(1)
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(package):
        frame, level = frame.f_back, level + 1
    warnings.warn(message, TumbleWarning, stacklevel=level)


def _fmt(x: float) -> str:
    return "inf" if x == math.inf else "-inf" if x == -math.inf else f"{x:g}"


def state_text(t: Any, q: Any, omega: Any) -> str:
    """``t = …, q = […], omega = […]``: where a user's function was called, for a message
    (``q`` None: a torque of the rate alone)."""
    fmt = ", ".join
    attitude = "" if q is None else f", q = [{fmt(f'{float(x):.6g}' for x in q)}]"
    rate = fmt(f"{float(x):.6g}" for x in omega)
    return f"t = {float(t):.9g}{attitude}, omega = [{rate}]"


def check_finite(field: str, value: float) -> None:
    """Raise :class:`ParameterError` unless ``value`` is a finite real number."""
    if not math.isfinite(value):
        raise ParameterError(f"{field} = {value!r} must be a finite number")


def check_range(
    field: str,
    value: float,
    *,
    low: float = -math.inf,
    high: float = math.inf,
    low_open: bool = True,
    high_open: bool = True,
) -> None:
    """Raise :class:`ParameterError` unless ``low < value < high`` (or ≤ where closed).

    Parameters
    ----------
    field : str
        Dotted name of the field, as a scenario file spells it (``parameters.eps``).
    value : float
        The value to check.
    low, high : float
        Bounds of the allowed interval.
    low_open, high_open : bool
        Whether each bound is excluded.
    """
    check_finite(field, value)
    ok_low = value > low if low_open else value >= low
    ok_high = value < high if high_open else value <= high
    if not (ok_low and ok_high):
        left = "(" if low_open else "["
        right = ")" if high_open else "]"
        allowed = f"{left}{_fmt(low)}, {_fmt(high)}{right}"
        raise ParameterError(f"{field} = {value:g} is outside the allowed range {allowed}")
