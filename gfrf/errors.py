"""Typed exceptions of gfrf.

Every error caused by user input derives from :class:`GfrfError`, so the CLI can
turn it into a one-line message and exit code 2 instead of a traceback.  Each
also subclasses the matching built-in (``ValueError``, ``RuntimeError``) so that
generic ``except ValueError`` code keeps working.
"""

__all__ = [
    "GfrfError",
    "ModelError",
    "ArgumentError",
    "ConvergenceError",
]


class GfrfError(Exception):
    """Base class of every error gfrf raises on purpose."""


class ModelError(GfrfError, ValueError):
    """A model text or model file is invalid (unparsable, non-polynomial, unknown key...)."""


class ArgumentError(GfrfError, ValueError):
    """A numeric or option argument is invalid (negative order, empty frequency list...)."""


class ConvergenceError(GfrfError, RuntimeError):
    """An iterative computation did not reach its tolerance; the message gives the residual."""

