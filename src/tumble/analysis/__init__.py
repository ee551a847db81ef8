"""Analysis: running and comparing methods, error studies.

Names load their module on first use, so that the plan of a sweep
(:mod:`tumble.analysis.plan`) comes without the integrators.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tumble._lazy import lazy_exports

# Public name → the module that defines it.
_EXPORTS: dict[str, str] = {
    "ErrorStudy": "tumble.analysis.compare",
    "angle_difference": "tumble.analysis.compare",
    "averaging_error_study": "tumble.analysis.compare",
    "fitted_order": "tumble.analysis.compare",
    "max_differences": "tumble.analysis.compare",
    "RunRequest": "tumble.analysis.run",
    "RunResult": "tumble.analysis.run",
    "run": "tumble.analysis.run",
    "to_dataset": "tumble.analysis.run",
    "VerifyResult": "tumble.analysis.verify",
    "verify": "tumble.analysis.verify",
}

__all__ = [
    "ErrorStudy",
    "RunRequest",
    "RunResult",
    "VerifyResult",
    "angle_difference",
    "averaging_error_study",
    "fitted_order",
    "max_differences",
    "run",
    "to_dataset",
    "verify",
]

if TYPE_CHECKING:
    from tumble.analysis.compare import (
        ErrorStudy,
        angle_difference,
        averaging_error_study,
        fitted_order,
        max_differences,
    )
    from tumble.analysis.run import RunRequest, RunResult, run, to_dataset
    from tumble.analysis.verify import VerifyResult, verify

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
