"""The parametrically excited inverted pendulum, eqs (3)-(4) of Zhang, Zhen & Li (2019).

Dimensionless form (time ``t = omega * t_phys``, so the pivot frequency is 1 rad per
unit of ``t`` and the excitation period is ``2*pi``)::

    x'' + (delta + eps*cos(t)) * g(x) = 0,

with ``g(x) = sin(x)`` (eq (3), ``truncation=None``) or its Taylor polynomial of odd
degree ``truncation`` (``truncation=3`` gives eq (4), ``g(x) = x - x**3/6``).
Physical parameters map as ``eps = A/L`` and ``delta = -g/(L*omega**2)``; the paper
assumes ``0 < eps < 1`` and ``-1 < delta < 0`` (pendulum above its pivot).

The ``1/4`` tongue has two sides: the lower curve ``1/4 - eps/2 + ...`` carries the
orbits even in ``t`` (``~ cos(t/2)``, ``x'(0) = 0``), the upper curve ``1/4 + eps/2 + ...``
the odd ones (``~ sin(t/2)``, ``x(0) = 0``).  If ``y`` is a lower-side orbit for
``-eps``, then ``x(t) = y(t - pi)`` solves the equation for ``eps`` (``cos(t - pi) =
-cos t``), with ``x(0) = y(-pi) = 0`` and turning point ``x(pi) = y(0)``: the upper
curve for ``eps`` is the lower curve for ``-eps``.  On the upper side ``amplitude``
means that turning point ``x(pi)`` (``x'(pi) = 0``, ``x(0) = 0``).
"""

from __future__ import annotations

import math
import tomllib
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import numpy as np

from gfrf._data import MODELS_DIR
from gfrf._results import Result
from gfrf.errors import ArgumentError, ModelError

__all__ = [
    "BRANCHES",
    "SIDES",
    "PendulumModel",
    "branch_period",
    "check_paper_range",
    "load_model",
    "nonlinearity",
    "parse_branch",
    "parse_side",
    "physical_to_dimensionless",
    "sin_taylor_coefficients",
    "upper_side_times",
]

#: Transition curves treated by the paper: the 2*pi-periodic one through delta=0 and
#: the 4*pi-periodic one through delta=1/4 (the lower one, ``1/4 - eps/2 + ...``).
BRANCHES: tuple[str, ...] = ("0", "1/4")
#: Sides of a transition tongue: ``"lower"`` (the paper's curves above) or ``"upper"``
#: (the ``1/4`` tongue's upper boundary ``1/4 + eps/2 + ...``, orbits with ``x(0) = 0``).
SIDES: tuple[str, ...] = ("lower", "upper")

DEFAULT_MODEL = MODELS_DIR / "parametric_pendulum.toml"


def parse_branch(branch: str | float) -> str:
    """Normalise a branch label (``"0"``, ``"1/4"``, ``0.25`` ...) to ``"0"`` or ``"1/4"``.

    Parameters
    ----------
    branch : str or float
        The label.

    Returns
    -------
    str
        ``"0"`` or ``"1/4"``.

    Raises
    ------
    ArgumentError
        If the label names neither transition curve.
    """
    text = str(branch).strip()
    if text in ("0", "0.0"):
        return "0"
    if text in ("1/4", "0.25", ".25"):
        return "1/4"
    raise ArgumentError(f"unknown branch {branch!r}: expected '0' or '1/4'")


def parse_side(side: str, branch: str) -> str:
    """Check ``side`` (``"lower"`` or ``"upper"``) for ``branch``.

    Parameters
    ----------
    side : str
        ``"lower"`` or ``"upper"``.
    branch : str
        The branch label.

    Returns
    -------
    str
        ``side``.

    Raises
    ------
    ArgumentError
        If ``side`` is unknown, or ``"upper"`` is asked for branch ``"0"`` (the paper
        has one curve there).
    """
    if side not in SIDES:
        raise ArgumentError(f"unknown side {side!r}: expected 'lower' or 'upper'")
    if side == "upper" and parse_branch(branch) != "1/4":
        raise ArgumentError("side 'upper' exists only for branch '1/4' (the paper has a "
                            "single curve through delta = 0)")
    return side


def upper_side_times(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Times at which to evaluate the ``-eps`` lower orbit ``y`` for ``x(t) = y(t - pi)``.

    A lower-side orbit is even in time, so ``y(t - pi) = y(|t - pi|)``.

    Parameters
    ----------
    t : numpy.ndarray
        Times (dimensionless t of eq (3)).

    Returns
    -------
    (s, index)
        Sorted unique ``s = |t - pi|`` and the index with ``x(t) = y(s)[index]``.
    """
    return np.unique(np.abs(np.asarray(t, dtype=float) - math.pi), return_inverse=True)


def branch_period(branch: str) -> float:
    """Period in ``t`` of the orbits on ``branch``: ``2*pi`` for "0", ``4*pi`` for "1/4".

    Parameters
    ----------
    branch : str
        The branch label.

    Returns
    -------
    float
        The period.
    """
    return 2 * math.pi if parse_branch(branch) == "0" else 4 * math.pi


def physical_to_dimensionless(L: float, A: float, omega: float, g: float) -> tuple[float, float]:
    """Return ``(eps, delta) = (A/L, -g/(L*omega**2))`` (eq (3)); omega in rad/s.

    Parameters
    ----------
    L : float
        Pendulum length in m, > 0.
    A : float
        Amplitude of the pivot's vertical motion in m.
    omega : float
        Angular frequency of the pivot's motion in rad/s, > 0.
    g : float
        Gravitational acceleration in m/s^2.
    """
    if L <= 0 or omega <= 0:
        raise ArgumentError(f"need L > 0 and omega > 0, got L={L}, omega={omega}")
    return A / L, -g / (L * omega**2)


def check_paper_range(eps: float, delta: float | None = None) -> None:
    """Warn (``UserWarning``) when ``eps`` or ``delta`` leave the paper's ranges.

    Parameters
    ----------
    eps : float
        The dimensionless forcing amplitude.
    delta : float, optional
        The dimensionless stiffness; None: not checked.
    """
    if not 0 < eps < 1:
        warnings.warn(f"eps={eps} is outside the paper's range 0 < eps < 1", UserWarning,
                      stacklevel=2)
    if delta is not None and not -1 < delta < 0:
        warnings.warn(f"delta={delta} is outside the paper's range -1 < delta < 0 "
                      "(inverted pendulum)", UserWarning, stacklevel=2)


def sin_taylor_coefficients(truncation: int) -> dict[int, Fraction]:
    """Exact odd Taylor coefficients ``{k: c_k}`` of ``sin(x)`` up to degree ``truncation``.

    Parameters
    ----------
    truncation : int
        The degree, odd and >= 1.

    Returns
    -------
    dict of int to Fraction
        ``{k: c_k}`` for odd k <= ``truncation``.
    """
    if truncation < 1 or truncation % 2 == 0:
        raise ArgumentError(f"truncation must be an odd positive degree, got {truncation}")
    return {k: Fraction((-1) ** (k // 2), math.factorial(k)) for k in range(1, truncation + 1, 2)}


def nonlinearity(truncation: int | None) -> tuple[Callable[[np.ndarray], np.ndarray],
                                                   Callable[[np.ndarray], np.ndarray]]:
    """Return ``(g, g')`` for ``sin`` (``truncation=None``) or its Taylor polynomial.

    Parameters
    ----------
    truncation : int or None
        Odd Taylor degree; None: ``sin`` itself.

    Returns
    -------
    tuple of callable
        g and its derivative, on numpy arrays.
    """
    if truncation is None:
        return np.sin, np.cos
    coeffs = sin_taylor_coefficients(truncation)
    if truncation == 3:  # eq (4): the common case, written out for speed
        return (lambda x: x - x**3 / 6.0), (lambda x: 1.0 - 0.5 * x**2)
    cf = [(k, float(c)) for k, c in coeffs.items()]

    def g(x: np.ndarray) -> np.ndarray:
        return sum(c * x**k for k, c in cf)

    def dg(x: np.ndarray) -> np.ndarray:
        return sum(k * c * x ** (k - 1) for k, c in cf)

    return g, dg


@dataclass(frozen=True, kw_only=True, repr=False)
class PendulumModel(Result):
    """A parametric-pendulum model file (``kind = "parametric"``).

    Attributes
    ----------
    name, source, equation : str
        Descriptive fields of the file.
    truncation : int or None
        Odd Taylor degree of ``sin`` (None: untruncated eq (3)).
    L, A, omega, g : float
        Physical parameters (m, m, rad/s, m/s^2).
    eps, delta : float
        Dimensionless parameters ``A/L`` and ``-g/(L*omega**2)``.
    """

    name: str
    source: str
    equation: str
    truncation: int | None
    L: float
    A: float
    omega: float
    g: float
    eps: float
    delta: float


def load_model(path: str | Path = DEFAULT_MODEL) -> PendulumModel:
    """Read a ``kind = "parametric"`` TOML model file with :mod:`tomllib`.

    Parameters
    ----------
    path : str or Path, optional
        The model file; default the bundled parametric pendulum.

    Returns
    -------
    PendulumModel
        The model.

    Raises
    ------
    ModelError
        If the file is not a parametric model or lacks a physical parameter.
    """
    with open(path, "rb") as fh:
        data = tomllib.load(fh)
    if data.get("kind") != "parametric":
        raise ModelError(f"{path}: not a parametric model (kind = {data.get('kind')!r})")
    params = data.get("parameters", {})
    missing = [k for k in ("L", "A", "omega", "g") if k not in params]
    if missing:
        raise ModelError(f"{path}: [parameters] lacks {', '.join(missing)}")
    trunc = data.get("truncation")
    eps, delta = physical_to_dimensionless(params["L"], params["A"], params["omega"], params["g"])
    return PendulumModel(name=str(data.get("name", Path(path).stem)),
                         source=str(data.get("source", "")),
                         equation=str(data.get("equation", "")),
                         truncation=None if trunc is None else int(trunc),
                         L=float(params["L"]), A=float(params["A"]),
                         omega=float(params["omega"]), g=float(params["g"]),
                         eps=eps, delta=delta)
