"""The families of parameter sets along which ``tumble verify`` varies ε: which parameters
scale with ε, and with what power of ε/ε₀ (the scenario key ``[run] verify_scaling``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TypeVar

from tumble.errors import ParameterError

__all__ = ["DEFAULT_FAMILY", "family_params", "scaling_family"]

P = TypeVar("P")  # a model's Params


DEFAULT_FAMILY: Mapping[str, float] = {"eps": 1.0}
"""How ``tumble verify`` scales a model's parameters with ε unless the model or the scenario
says otherwise: ε alone, every other parameter fixed."""


def scaling_family(p: object, exponents: Mapping[str, float] | None = None) -> dict[str, float]:
    """The family of parameter sets along which ``tumble verify`` varies ε, as exponents:
    along it each named parameter x scales as x·(ε/ε₀)^exponent.

    ``exponents`` is the scenario's ``[run] verify_scaling``; None gives the model's default
    (``Params.family()`` where it defines one, e.g. the orbital rate n ∝ √ε of a gravity
    gradient, else ε alone). Names other than ``eps`` must be among ``Params.SCALABLE``.
    """
    if exponents is None:
        default = getattr(p, "family", None)
        return dict(default() if callable(default) else DEFAULT_FAMILY)
    allowed = ("eps", *getattr(p, "SCALABLE", ()))
    out = {"eps": 1.0}
    for name, power in exponents.items():
        if name not in allowed:
            raise ParameterError(
                f"run.verify_scaling: {name!r} is not a parameter that can scale with ε "
                f"(allowed: {', '.join(allowed)})"
            )
        if not isinstance(power, int | float) or not -4.0 <= float(power) <= 4.0:
            raise ParameterError(
                f"run.verify_scaling.{name} = {power!r} is outside the allowed range [-4, 4] "
                "(the exponent of ε/ε₀)"
            )
        out[name] = float(power)
    return out


def family_params(p: P, ratio: float, exponents: Mapping[str, float]) -> P:
    """The parameter set at ε₀·ratio along the family ``exponents`` (:func:`scaling_family`):
    ``eps`` scaled by ratio^exponents["eps"], and the model's own scalable parameters through
    ``Params.along(ratio, others)``."""
    q = p.with_eps(float(p.eps) * ratio ** exponents.get("eps", 1.0))  # type: ignore[attr-defined]
    others = {k: v for k, v in exponents.items() if k != "eps" and v != 0.0}
    if others:
        q = q.along(ratio, others)
    return q  # type: ignore[no-any-return]
