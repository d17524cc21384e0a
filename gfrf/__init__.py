"""gfrf: stability of polynomial nonlinear systems from their generalized frequency response functions.

Angular frequency is in rad/s everywhere.  The public API is re-exported here.
"""

from gfrf.errors import (
    ArgumentError,
    ConvergenceError,
    GfrfError,
    InstabilityError,
    ModelError,
)

__all__ = [
    "ArgumentError",
    "ConvergenceError",
    "GfrfError",
    "InstabilityError",
    "ModelError",
]

__version__ = "0.1.0"
