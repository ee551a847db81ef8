"""Analysis: running and comparing methods, error studies."""

from tumble.analysis.compare import (
    ErrorStudy,
    angle_difference,
    averaging_error_study,
    fitted_order,
    max_differences,
)
from tumble.analysis.run import RunRequest, RunResult, run, to_dataset
from tumble.analysis.verify import VerifyResult, verify

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
