"""Every method against the ground truth: transition values, orbits, errors, timings.

Conventions: ``amplitude`` is ``x(0)`` of the orbit with ``x'(0) = 0``; each method's
own amplitude parameter is converted explicitly (perturbation branch ``1/4``:
``a = x(0)/eps``; homotopy: ``c = x(0)``; energy: ``a(0) = x(0)``; averaging:
``B = x(0)``).  On the upper side of the ``1/4`` tongue (``side="upper"``: energy (49),
averaging case 3, exact) ``amplitude`` is the turning point ``x(pi)`` of the orbit with
``x(0) = 0``, and the exact curve and orbit are the lower ones for ``-eps`` shifted by
``pi`` (:mod:`~gfrf.periodic.equation`); perturbation and homotopy give only the lower
side (as in the paper).  ``equation=3`` (untruncated ``sin x``) is supported where the
derivation allows it: averaging with Bessel-function averages, perturbation on the
``1/4`` branch with the Taylor series of ``sin`` to degree ``order + 1`` (``x = eps u``, so
``x**k`` enters at ``eps**(k-1)``: exact to the order computed), perturbation on branch
``0`` and homotopy with degree :data:`SIN_DEGREE` (remainder below ``4e-10`` for
``|x| <= 1.5``), exact with ``sin`` itself; the energy method is tied to eq (4)
(:mod:`~gfrf.periodic.energy`).  Errors are ``|delta_method - delta_exact|`` and the maximum of
``|x_method(t) - x_exact(t)|`` over one period (401 samples), where the exact orbit
is the orbit of eq (4) (of eq (3) with ``equation=3``) with the same ``x(0)`` (Fourier
collocation checked by shooting, :func:`~gfrf.periodic.shooting.transition_delta`) or
the same ``delta`` (Newton shooting on ``x(0)``).
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from gfrf._results import Result
from gfrf.errors import ArgumentError, ConvergenceError
from gfrf.periodic.averaging import averaging_solution, averaging_transition
from gfrf.periodic.energy import energy_solution, energy_transition
from gfrf.periodic.equation import branch_period, parse_branch, parse_side, upper_side_times
from gfrf.periodic.homotopy import ham_optimal
from gfrf.periodic.perturbation import PerturbationSeries, perturbation_series
from gfrf.periodic.shooting import PeriodicOrbit, orbit_at_delta, transition_delta

__all__ = [
    "DEFAULT_ORDER",
    "METHODS",
    "PeriodicComparison",
    "TransitionResult",
    "compare_periodic",
    "error_table",
    "method_orbit",
    "method_transition",
    "transition_curve",
]

METHODS: tuple[str, ...] = ("perturbation", "homotopy", "energy", "averaging", "exact")
#: Orders used when none is given (the paper stops at 2; 4 shows the convergence).
DEFAULT_ORDER: dict[str, int] = {"perturbation": 4, "homotopy": 4}
_N_SAMPLES = 401
#: Taylor degree of ``sin`` standing for eq (3) in perturbation (branch 0) and homotopy.
SIN_DEGREE = 13


def _check_method(method: str) -> str:
    if method not in METHODS:
        raise ArgumentError(f"unknown method {method!r}: expected one of {', '.join(METHODS)}")
    return method


@functools.lru_cache(maxsize=32)
def _series(branch: str, order: int, truncation: int = 3) -> PerturbationSeries:
    return perturbation_series(branch, order, truncation=truncation)


def _truncation(method: str, branch: str, order: int | None, equation: int) -> int | None:
    """Taylor degree of ``sin`` used by ``method`` for ``equation`` (None: ``sin`` itself)."""
    if equation == 4:
        return 3
    if equation != 3:
        raise ArgumentError(f"unknown equation {equation!r}: expected 4 or 3")
    if method == "energy":
        raise ArgumentError("energy: the method is derived for eq (4) only (quartic "
                            "potential in (39)); use --equation 4")
    if method == "perturbation" and branch == "1/4":
        return max(3, (order or 1) + 1) | 1  # smallest odd degree >= order + 1
    return None if method in ("exact", "averaging") else SIN_DEGREE


def _order(method: str, order: int | None) -> int | None:
    if method not in DEFAULT_ORDER:
        return None
    k = DEFAULT_ORDER[method] if order is None else order
    if k < 0 or (method == "perturbation" and k < 1):
        raise ArgumentError(f"order {k} is too low for {method}")
    return k


def _check_eps(method: str, eps: float, branch: str) -> None:
    if eps <= 0 and method == "perturbation" and branch == "1/4":
        raise ArgumentError("the 1/4-branch perturbation series scales x = eps*u: need eps > 0")


def _check_side(method: str, branch: str, side: str) -> str:
    if parse_side(side, branch) == "upper" and method in ("perturbation", "homotopy"):
        raise ArgumentError(f"{method}: only the lower 1/4 curve is derived (the paper's "
                            "(15)/(32)); side 'upper' is available for energy, averaging "
                            "and exact")
    return side


@dataclass(frozen=True, kw_only=True, repr=False)
class TransitionResult(Result):
    """``delta`` on a transition curve from one method.

    Attributes
    ----------
    method, branch : str
    eps, amplitude : float
    order : int or None
    delta : float
        NaN when the method has no curve there (energy beyond its root).
    seconds : float
        Wall time of this computation.
    side : str
        ``"lower"`` or ``"upper"`` side of the ``1/4`` tongue.
    equation : int
        4 (truncated) or 3 (``sin x``).
    """

    method: str
    eps: float
    amplitude: float
    branch: str
    order: int | None
    delta: float
    seconds: float
    side: str = "lower"
    equation: int = 4


def _sign(side: str) -> float:
    """Sign of ``eps`` in the lower-side problem equivalent to ``side``."""
    return 1.0 if side == "lower" else -1.0


def _delta(method: str, eps: float, amplitude: float, branch: str, order: int | None,
           side: str = "lower", equation: int = 4) -> float:
    tr = _truncation(method, branch, order, equation)
    if method == "perturbation":
        return _series(branch, order, tr).delta(eps, amplitude)
    if method == "homotopy":
        return ham_optimal(eps, amplitude, branch, order, tr).delta
    if method == "energy":
        return float(energy_transition(eps, amplitude, branch, side=side))
    if method == "averaging":
        return float(averaging_transition(eps, amplitude, branch, side, equation))
    return transition_delta(_sign(side) * eps, amplitude, branch, tr).delta


def method_transition(method: str, eps: float, amplitude: float, branch: str = "0",
                      order: int | None = None, side: str = "lower",
                      equation: int = 4) -> TransitionResult:
    """``delta`` on ``branch`` (and ``side``) for ``amplitude`` by ``method`` (timed).

    ``equation`` is 4 (truncated) or 3 (``sin x``; not for the energy method).

    Parameters
    ----------
    method : str
        One of :data:`METHODS`.
    eps : float
        The dimensionless forcing amplitude.
    amplitude : float
        x(0) of the orbit, > 0.
    branch : str, optional
        ``"0"`` or ``"1/4"``.
    order : int, optional
        The method's order (perturbation, homotopy); None: its default.
    side : str, optional
        ``"lower"`` or ``"upper"`` (branch 1/4 only).
    equation : int, optional
        4 or 3.

    Returns
    -------
    TransitionResult
        delta, the settings and the wall time of the call.
    """
    _check_method(method)
    b = parse_branch(branch)
    _check_side(method, b, side)
    k = _order(method, order)
    _check_eps(method, eps, b)
    if amplitude <= 0:
        raise ArgumentError(f"amplitude must be positive, got {amplitude}")
    t0 = time.perf_counter()
    d = _delta(method, eps, amplitude=amplitude, branch=b, order=k, side=side, equation=equation)
    return TransitionResult(method=method,
                            eps=eps,
                            amplitude=amplitude,
                            branch=b,
                            order=k,
                            delta=d,
                            seconds=time.perf_counter() - t0,
                            side=side,
                            equation=equation)


def transition_curve(method: str, eps: np.ndarray, amplitude: float, branch: str = "0",
                     order: int | None = None, side: str = "lower") -> np.ndarray:
    """``delta`` of ``method`` at every ``eps`` (NaN where the method has no value).

    Parameters
    ----------
    method : str
        One of :data:`METHODS`.
    eps : numpy.ndarray
        The values of eps.
    amplitude : float
        x(0) of the orbits.
    branch : str, optional
        ``"0"`` or ``"1/4"``.
    order : int, optional
        The method's order (perturbation, homotopy); None: its default.
    side : str, optional
        ``"lower"`` or ``"upper"`` (branch 1/4 only).

    Returns
    -------
    numpy.ndarray
        delta at each eps.
    """
    _check_method(method)
    b = parse_branch(branch)
    _check_side(method, b, side)
    k = _order(method, order)
    eps = np.asarray(eps, dtype=float)
    if method == "energy":
        return np.asarray(energy_transition(eps, amplitude, b, side=side), dtype=float)
    if method == "averaging":
        return np.asarray(averaging_transition(eps, amplitude, b, side), dtype=float)
    if method == "exact":
        from gfrf.periodic.shooting import exact_transition_curve
        return exact_transition_curve(_sign(side) * eps, amplitude, b)
    out = np.empty(len(eps))
    for i, e in enumerate(eps):
        out[i] = np.nan if (e <= 0 and method == "perturbation" and b == "1/4") \
            else _delta(method, float(e), amplitude, b, k)
    return out


def method_orbit(method: str, eps: float, amplitude: float, branch: str, t: np.ndarray,
                 order: int | None = None, delta: float | None = None, side: str = "lower",
                 equation: int = 4) -> tuple[float, np.ndarray]:
    """``(delta, x(t))`` of ``method``'s periodic orbit with ``x(0) = amplitude``.

    ``delta`` defaults to the method's own transition value; only the energy method
    uses a different one (it integrates (50) at that ``delta``).  On the upper side
    ``amplitude`` is ``x(pi)``.

    Parameters
    ----------
    method : str
        One of :data:`METHODS`.
    eps : float
        The dimensionless forcing amplitude.
    amplitude : float
        x(0) of the orbit (x(pi) on the upper side).
    branch : str
        ``"0"`` or ``"1/4"``.
    t : numpy.ndarray
        Dimensionless times.
    order : int, optional
        The method's order (perturbation, homotopy); None: its default.
    delta : float, optional
        delta of the energy method's orbit; None: its transition value.
    side : str, optional
        ``"lower"`` or ``"upper"`` (branch 1/4 only).
    equation : int, optional
        4 (truncated) or 3 (``sin x``).
    """
    _check_method(method)
    b = parse_branch(branch)
    _check_side(method, b, side)
    k = _order(method, order)
    _check_eps(method, eps, b)
    tr = _truncation(method, b, k, equation)
    if method == "perturbation":
        s = _series(b, k, tr)
        return s.delta(eps, amplitude), s.solution(eps, amplitude, t)
    if method == "homotopy":
        r = ham_optimal(eps, amplitude, b, k, tr)
        return r.delta, r.solution(t)
    if method == "energy":
        d = float(energy_transition(eps, amplitude, b, side=side)) if delta is None else delta
        return d, energy_solution(eps, amplitude, t, d, b, side)
    if method == "averaging":
        return (float(averaging_transition(eps, amplitude, b, side, equation)),
                averaging_solution(eps, amplitude, t, b, side))
    orbit = transition_delta(_sign(side) * eps, amplitude, b, tr)
    return orbit.delta, _evaluate(orbit, t, side)


def _evaluate(orbit: PeriodicOrbit, t: np.ndarray, side: str) -> np.ndarray:
    """``x(t)`` of the shooting orbit, shifted by ``pi`` on the upper side."""
    if side == "lower":
        return orbit.evaluate(t)
    s_times, index = upper_side_times(t)
    return orbit.evaluate(s_times)[index]


@dataclass(frozen=True, kw_only=True, repr=False)
class PeriodicComparison(Result):
    """Error of one method's periodic orbit against the shooting orbit.

    Attributes
    ----------
    method, branch : str
    eps : float
    order : int or None
    amplitude_method, amplitude_exact : float
        ``x(0)`` of the two orbits (equal unless ``delta`` was prescribed).
    delta_method, delta_exact : float
    delta_error : float
        ``|delta_method - delta_exact|``.
    max_error : float
        ``max_t |x_method - x_exact|`` over one period; NaN if the method has no orbit.
    seconds : float
        Wall time of the method alone.
    side : str
        ``"lower"`` or ``"upper"`` side of the ``1/4`` tongue.
    equation : int
        4 (truncated) or 3 (``sin x``): both orbits solve/approximate this equation.
    """

    method: str
    branch: str
    eps: float
    order: int | None
    amplitude_method: float
    amplitude_exact: float
    delta_method: float
    delta_exact: float
    delta_error: float
    max_error: float
    seconds: float
    side: str = "lower"
    equation: int = 4


def _method_amplitude(method: str, eps: float, delta: float, branch: str, order: int | None,
                      guess: float, side: str = "lower", equation: int = 4) -> float:
    """Amplitude at which ``method``'s transition curve passes through ``delta``."""
    def f(a: float) -> float:
        return _delta(method, eps, amplitude=a, branch=branch, order=order, side=side,
                      equation=equation) - delta

    grid = np.unique(np.clip(guess * np.array([0.25, 0.5, 0.8, 1.0, 1.25, 1.6, 2.0, 3.0]),
                             1e-6, 3.0))
    vals = [f(float(a)) for a in grid]
    brackets = [(grid[i], grid[i + 1]) for i in range(len(grid) - 1)
                if np.isfinite(vals[i]) and np.isfinite(vals[i + 1])
                and vals[i] * vals[i + 1] <= 0]
    if not brackets:
        raise ConvergenceError(f"{method}: its {branch} transition curve does not reach "
                               f"delta={delta} for amplitudes near {guess:g} (eps={eps})")
    lo, hi = min(brackets, key=lambda ab: abs(0.5 * (ab[0] + ab[1]) - guess))
    return float(brentq(f, lo, hi, xtol=1e-12))


@functools.lru_cache(maxsize=256)
def _exact(eps: float, amplitude: float, branch: str, delta: float | None,
           side: str = "lower", equation: int = 4) -> tuple[PeriodicOrbit, np.ndarray]:
    """Shooting orbit and its samples (cached: tables reuse it for every method)."""
    e = _sign(side) * eps
    tr = 3 if equation == 4 else None
    if delta is None:
        orbit = transition_delta(e, amplitude, branch, tr)
    else:
        orbit = orbit_at_delta(e, delta, amplitude, branch, tr)
    return orbit, _evaluate(orbit, np.linspace(0.0, branch_period(branch), _N_SAMPLES), side)


def compare_periodic(method: str, eps: float, amplitude: float, branch: str = "1/4",
                     order: int | None = None, delta: float | None = None,
                     side: str = "lower", equation: int = 4) -> PeriodicComparison:
    """Compare ``method``'s orbit with the exact one.

    Parameters
    ----------
    method : str
        One of :data:`METHODS`.
    eps, amplitude : float
        Excitation and ``x(0)``; with ``delta`` given, ``amplitude`` only guesses
        the exact orbit's ``x(0)``.
    branch : {"0", "1/4"}
    order : int, optional
        Perturbation/homotopy order.
    delta : float, optional
        Compare the orbits at this ``delta`` (each at its own amplitude) instead of at
        equal ``x(0)``.
    side : {"lower", "upper"}
        Side of the ``1/4`` tongue; on the upper side ``amplitude`` is ``x(pi)``.
    equation : {4, 3}
        Truncated eq (4) or ``sin x`` eq (3) (method and exact orbit alike).

    Raises
    ------
    ConvergenceError
        If no exact orbit (or no method orbit) exists near the guess.
    """
    _check_method(method)
    b = parse_branch(branch)
    _check_side(method, b, side)
    k = _order(method, order)
    _check_eps(method, eps, b)
    _truncation(method, b, k, equation)
    exact, x_exact = _exact(eps, amplitude, b, delta, side, equation)
    t = np.linspace(0.0, branch_period(b), _N_SAMPLES)
    t0 = time.perf_counter()
    a_m = amplitude if delta is None else exact.amplitude
    if delta is not None and method != "exact":
        a_m = _method_amplitude(method, eps, delta=delta, branch=b, order=k, guess=exact.amplitude,
                                side=side, equation=equation)
    try:
        d_m, x_m = method_orbit(method, eps, a_m, b, t, k, side=side, equation=equation)
    except ArgumentError:
        if method != "energy":
            raise
        d_m, x_m = math.nan, np.full_like(t, np.nan)
    secs = time.perf_counter() - t0
    err = float(np.max(np.abs(x_m - x_exact))) if np.all(np.isfinite(x_m)) else math.nan
    return PeriodicComparison(method=method,
                              branch=b,
                              eps=eps,
                              order=k,
                              amplitude_method=a_m,
                              amplitude_exact=exact.amplitude,
                              delta_method=d_m,
                              delta_exact=exact.delta,
                              delta_error=abs(d_m - exact.delta),
                              max_error=err,
                              seconds=secs,
                              side=side,
                              equation=equation)


def error_table(methods: tuple[str, ...], eps_values: tuple[float, ...],
                amplitudes: tuple[float, ...], branch: str = "1/4",
                orders: dict[str, int] | None = None,
                side: str = "lower") -> list[PeriodicComparison]:
    """Compare every method at every ``(eps, amplitude)`` (equal ``x(0)``).

    Parameters
    ----------
    methods : tuple of str
        Methods of :data:`METHODS`.
    eps_values : tuple of float
        The values of eps.
    amplitudes : tuple of float
        The values of x(0).
    branch : str, optional
        ``"0"`` or ``"1/4"``.
    orders : dict of str to int, optional
        Order per method; a method not in it gets its default.
    side : str, optional
        ``"lower"`` or ``"upper"`` (branch 1/4 only).

    Returns
    -------
    list of PeriodicComparison
        One per (eps, amplitude, method), in that nesting order.
    """
    rows = []
    for e in eps_values:
        for a in amplitudes:
            for m in methods:
                rows.append(compare_periodic(m, e, a, branch, (orders or {}).get(m), side=side))
    return rows
