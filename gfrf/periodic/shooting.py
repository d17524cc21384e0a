"""Nonlinear ground truth: periodic orbits of eq (4) (or (3)) by Newton shooting.

Eq ``x'' + (delta + eps cos t) g(x) = 0`` with odd ``g`` is invariant under
``t -> -t`` and under ``(t, x) -> (2*pi - t, -x)``.  An orbit starting at
``x(0) = amplitude``, ``x'(0) = 0`` is therefore even in ``t``, and

* it is 2*pi-periodic (branch ``"0"``) when ``x'(pi) = 0`` (then it is also even
  about ``t = pi``);
* it is 4*pi-periodic with ``x(t + 2*pi) = -x(t)`` (branch ``"1/4"``) when
  ``x(pi) = 0``.

Shooting therefore solves one scalar equation at ``t = pi`` (the symmetry-reduced
monodromy map) by Newton's method, with the derivative from the variational
equations.  The unknown is ``delta`` (transition value for a given amplitude) or
the amplitude (orbit at a given ``delta``).  Its Floquet multipliers and the
periodicity defect are those of the full-period map (computed when first asked for).

Transition values (:func:`transition_delta`, :func:`exact_transition_curve`) come from
the Fourier collocation of :mod:`~gfrf.periodic.spectral` (spectrally accurate, about
ten times cheaper than shooting Newton); each is then checked by one independent
integration of the initial value problem to ``t = pi`` (the shooting residual), and
shooting Newton takes over from the collocation value if that residual is above the
tolerance.  Integrations use scipy's Fortran DOP853 (``scipy.integrate.ode``) at
``rtol = 1e-12``.  Time ``t`` is dimensionless (excitation angular frequency 1).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import ode, solve_ivp
from scipy.optimize import brentq

from gfrf._results import Result
from gfrf.errors import ArgumentError, ConvergenceError
from gfrf.periodic.equation import branch_period, nonlinearity, parse_branch
from gfrf.periodic.floquet import mathieu_transition
from gfrf.periodic.spectral import FourierOrbit, fourier_transition

__all__ = [
    "PeriodicOrbit",
    "exact_transition_curve",
    "orbit_at_delta",
    "orbit_on_transition",
    "transition_delta",
    "transition_zero_eps",
]

_RTOL = 1e-12


@dataclass(frozen=True, kw_only=True, repr=False)
class PeriodicOrbit(Result):
    """A converged periodic orbit with ``x(0) = amplitude``, ``x'(0) = 0``.

    ``to_dict`` adds the period, the full-period residual, the Floquet multipliers and
    the method; ``series`` is left out as such and given as the method and its number of
    Fourier ``modes``.

    Attributes
    ----------
    eps, delta, amplitude : float
        Parameters and initial displacement of the orbit.
    branch : str
        ``"0"`` (period ``2*pi``) or ``"1/4"`` (period ``4*pi``).
    truncation : int or None
        Taylor degree of ``sin`` (3: eq (4); None: eq (3)).
    shooting_residual : float
        ``|x'(pi)|`` or ``|x(pi)|`` divided by the amplitude, from an integration of the
        initial value problem at ``delta``.
    iterations : int
        Newton iterations used (collocation or shooting).
    series : FourierOrbit or None
        The Fourier-collocation orbit ``delta`` comes from (None: shooting Newton).
    """

    eps: float
    delta: float
    amplitude: float
    branch: str
    truncation: int | None
    shooting_residual: float
    iterations: int
    series: FourierOrbit | None = None

    _exclude = ("series",)
    _order = ("eps", "delta", "amplitude", "branch", "truncation", "period",
              "shooting_residual", "period_residual", "multipliers", "iterations", "method",
              "modes")

    @property
    def period(self) -> float:
        """Period in ``t``."""
        return branch_period(self.branch)

    @functools.cached_property
    def _full_period(self) -> tuple[float, np.ndarray]:
        return _full_period_check(self.eps, self.delta, self.amplitude, self.branch,
                                  self.truncation)

    @property
    def period_residual(self) -> float:
        """``|state(T) - state(0)|`` over the full period ``T`` (absolute, integrated)."""
        return self._full_period[0]

    @property
    def multipliers(self) -> np.ndarray:
        """Floquet multipliers of the linearisation about the orbit over one period ``T``."""
        return self._full_period[1]

    def evaluate(self, t: np.ndarray) -> np.ndarray:
        """Return ``x(t)`` at the (sorted, non-negative) times ``t``.

        Parameters
        ----------
        t : numpy.ndarray
            Dimensionless times, sorted and >= 0.

        Returns
        -------
        numpy.ndarray
            x(t).
        """
        if self.series is not None:
            return self.series.evaluate(t)
        t = np.asarray(t, dtype=float)
        g, _ = nonlinearity(self.truncation)
        eps, delta = self.eps, self.delta

        def rhs(s: float, y: np.ndarray) -> np.ndarray:
            return np.array([y[1], -(delta + eps * math.cos(s)) * g(y[0])])

        sol = solve_ivp(rhs, (0.0, float(t.max())), [self.amplitude, 0.0], method="DOP853",
                        rtol=_RTOL, atol=_RTOL * 1e-2 * self.amplitude, t_eval=t)
        return sol.y[0]

    def _computed(self) -> dict[str, object]:
        """The period, the full-period check, the method and its modes."""
        return {"period": self.period, "period_residual": self.period_residual,
                "multipliers": [complex(m) for m in self.multipliers],
                "method": "shooting" if self.series is None else "fourier collocation",
                "modes": None if self.series is None else self.series.modes}


def _integrate(rhs: Callable[[float, np.ndarray], list[float]], y0: list[float],
               t_end: float, amp: float) -> np.ndarray:
    """State at ``t_end`` by scipy's Fortran DOP853 (``rtol`` 1e-12); NaN if it fails."""
    solver = ode(rhs).set_integrator("dop853", rtol=_RTOL, atol=_RTOL * 1e-2 * amp,
                                     nsteps=100_000)
    solver.set_initial_value(y0, 0.0)
    y = solver.integrate(t_end)
    return y if solver.successful() else np.full(len(y0), np.nan)


def _half_period(eps: float, delta: float, amp: float, truncation: int | None
                 ) -> np.ndarray:
    """State ``(x, x', dx/ddelta, dx'/ddelta, dx/damp, dx'/damp)`` at ``t = pi``."""
    g, dg = nonlinearity(truncation)

    def rhs(t: float, y: np.ndarray) -> list[float]:
        k = delta + eps * math.cos(t)
        gx = g(y[0])
        kd = k * dg(y[0])
        return [y[1], -k * gx, y[3], -gx - kd * y[2], y[5], -kd * y[4]]

    return _integrate(rhs, [amp, 0.0, 0.0, 0.0, 1.0, 0.0], math.pi, amp)


def _full_period_check(eps: float, delta: float, amp: float, branch: str,
                       truncation: int | None) -> tuple[float, np.ndarray]:
    """Periodicity residual and Floquet multipliers over the full period."""
    g, dg = nonlinearity(truncation)

    def rhs(t: float, y: np.ndarray) -> list[float]:
        k = delta + eps * math.cos(t)
        kd = k * dg(y[0])
        return [y[1], -k * g(y[0]), y[3], -kd * y[2], y[5], -kd * y[4]]

    y = _integrate(rhs, [amp, 0.0, 1.0, 0.0, 0.0, 1.0], branch_period(branch), amp)
    residual = float(math.hypot(y[0] - amp, y[1]))
    mono = np.array([[y[2], y[4]], [y[3], y[5]]])
    if not np.all(np.isfinite(mono)):
        return residual, np.full(2, np.nan + 0j)
    return residual, np.linalg.eigvals(mono)


def _newton(eps: float, delta: float, amp: float, branch: str, truncation: int | None,
            unknown: str, tol: float, maxiter: int) -> PeriodicOrbit:
    """Newton iteration on ``delta`` or ``amp`` for the symmetric shooting condition."""
    b = parse_branch(branch)
    guess = amp
    idx = 1 if b == "0" else 0  # x'(pi) = 0 or x(pi) = 0
    g_of = nonlinearity(truncation)[0]
    res = math.inf
    for it in range(1, maxiter + 1):
        y = _half_period(eps, delta, amp, truncation)
        f = y[idx]
        res = abs(f) / amp
        if not math.isfinite(res):
            break
        if res <= tol:
            if unknown == "amp" and abs(g_of(amp)) < 1e-6 * amp:
                raise ConvergenceError(
                    f"shooting converged to the equilibrium x = {amp:.6g} (g(x) = 0), not to "
                    f"a {b}-branch orbit at eps={eps}, delta={delta:.6g}; try another amplitude")
            return PeriodicOrbit(eps=float(eps),
                                 delta=float(delta),
                                 amplitude=float(amp),
                                 branch=b,
                                 truncation=truncation,
                                 shooting_residual=res,
                                 iterations=it)
        if unknown == "delta":
            delta -= f / y[2 + idx]
        else:  # damped: the amplitude moves by at most half of itself per step
            step = f / y[4 + idx]
            amp -= math.copysign(min(abs(step), 0.5 * amp), step)
            if not 0 < amp < math.pi:
                res = math.inf
                break
    raise ConvergenceError(
        f"shooting for a {b}-branch orbit (eps={eps}, delta={delta:.6g}, x(0) guess "
        f"{guess:.6g}) did not converge: relative residual {res:.3g} after {maxiter} Newton "
        f"steps (tolerance {tol:g}, last x(0) = {amp:.3g}); no periodic orbit found near "
        f"this guess")


def orbit_on_transition(eps: float, amplitude: float, branch: str = "0",
                        truncation: int | None = 3, delta_guess: float | None = None,
                        tol: float = 1e-10, maxiter: int = 30) -> PeriodicOrbit:
    """Periodic orbit with ``x(0) = amplitude`` and the ``delta`` that makes it exist.

    Parameters
    ----------
    eps : float
        Excitation amplitude.
    amplitude : float
        ``x(0) > 0`` (``x'(0) = 0``).
    branch : {"0", "1/4"}
        Which transition curve.
    truncation : int or None
        3 for eq (4), None for eq (3).
    delta_guess : float, optional
        Newton start; default the linear (Mathieu) value.
    tol : float
        Tolerance on the shooting residual relative to the amplitude.
    maxiter : int
        Newton iteration limit.

    Raises
    ------
    ConvergenceError
        If Newton does not converge (message gives the residual reached).
    """
    if amplitude <= 0:
        raise ArgumentError(f"amplitude must be positive, got {amplitude}")
    if delta_guess is None:
        delta_guess = float(mathieu_transition(eps, branch))
    return _newton(eps, delta_guess, amp=amplitude, branch=branch, truncation=truncation,
                   unknown="delta", tol=tol, maxiter=maxiter)


def _checked(series: FourierOrbit, tol: float) -> PeriodicOrbit:
    """The collocation orbit, checked by integration; shooting Newton if the check fails."""
    eps, delta, amp, b = series.eps, series.delta, series.amplitude, series.branch
    y = _half_period(eps, delta, amp, series.truncation)
    res = abs(y[1 if b == "0" else 0]) / amp
    if res <= tol:
        return PeriodicOrbit(eps=eps,
                             delta=delta,
                             amplitude=amp,
                             branch=b,
                             truncation=series.truncation,
                             shooting_residual=res,
                             iterations=series.iterations,
                             series=series)
    return _newton(eps, delta, amp=amp, branch=b, truncation=series.truncation, unknown="delta",
                   tol=tol, maxiter=30)


def transition_delta(eps: float, amplitude: float, branch: str = "0",
                     truncation: int | None = 3, step: float = 0.1,
                     tol: float = 1e-10) -> PeriodicOrbit:
    """Exact nonlinear transition orbit with ``x(0) = amplitude`` and its ``delta``.

    Fourier collocation (:func:`~gfrf.periodic.spectral.fourier_transition`, continued
    from the linear orbit in the amplitude by steps of at most ``step``), checked by
    integrating the initial value problem to ``t = pi``: if the relative shooting residual
    exceeds ``tol``, shooting Newton refines ``delta`` to ``tol``.

    Parameters
    ----------
    eps : float
        The dimensionless forcing amplitude.
    amplitude : float
        x(0) of the orbit, > 0.
    branch : str, optional
        ``"0"`` or ``"1/4"``.
    truncation : int or None, optional
        Odd Taylor degree of ``sin``; None: ``sin`` itself.
    step : float, optional
        Largest amplitude step of the continuation.
    tol : float, optional
        Relative tolerance of the shooting residual.

    Returns
    -------
    PeriodicOrbit
        The orbit, with its ``delta``.

    Raises
    ------
    ArgumentError
        Non-positive amplitude.
    ConvergenceError
        If neither collocation nor shooting converges (the message says how far).
    """
    if amplitude <= 0:
        raise ArgumentError(f"amplitude must be positive, got {amplitude}")
    return _checked(fourier_transition(eps, amplitude, branch, truncation, step=step), tol)


def exact_transition_curve(eps: np.ndarray, amplitude: float, branch: str = "0",
                           truncation: int | None = 3, tol: float = 1e-10) -> np.ndarray:
    """``delta`` on the exact nonlinear transition curve at each ``eps`` (fixed amplitude).

    Continuation in ``eps``: each collocation solve starts from the previous orbit, and
    each value is checked by integration as in :func:`transition_delta`.

    Parameters
    ----------
    eps : numpy.ndarray
        The values of eps, in the order of the continuation.
    amplitude : float
        x(0) of the orbits.
    branch : str, optional
        ``"0"`` or ``"1/4"``.
    truncation : int or None, optional
        Odd Taylor degree of ``sin``; None: ``sin`` itself.
    tol : float, optional
        Relative tolerance of the shooting residual.

    Returns
    -------
    numpy.ndarray
        delta at each eps.
    """
    out = np.empty(len(eps))
    series: FourierOrbit | None = None
    for i, e in enumerate(eps):
        series = fourier_transition(float(e), amplitude, branch, truncation, start=series)
        out[i] = _checked(series, tol).delta
    return out


def orbit_at_delta(eps: float, delta: float, amplitude_guess: float, branch: str = "0",
                   truncation: int | None = 3, tol: float = 1e-10,
                   maxiter: int = 40) -> PeriodicOrbit:
    """Periodic orbit at fixed ``(eps, delta)``, Newton on the amplitude ``x(0)``.

    Parameters
    ----------
    eps, delta : float
        The parameters.
    amplitude_guess : float
        Initial x(0), in (0, pi).
    branch : str, optional
        ``"0"`` or ``"1/4"``.
    truncation : int or None, optional
        Odd Taylor degree of ``sin``; None: ``sin`` itself.
    tol : float, optional
        Tolerance of the shooting residual.
    maxiter : int, optional
        Most Newton iterations.

    Returns
    -------
    PeriodicOrbit
        The orbit.

    Raises
    ------
    ConvergenceError
        If no orbit is found from ``amplitude_guess`` (the residual is in the message).
    """
    if not 0 < amplitude_guess < math.pi:
        raise ArgumentError(f"amplitude guess must be in (0, pi), got {amplitude_guess}")
    return _newton(eps, delta, amp=amplitude_guess, branch=branch, truncation=truncation,
                   unknown="amp", tol=tol, maxiter=maxiter)


def transition_zero_eps(amplitude: float, branch: str = "1/4",
                        bracket: tuple[float, float] = (0.3, 0.7),
                        xtol: float = 1e-12) -> float:
    """``eps`` where the exact nonlinear ``1/4`` curve at ``x(0) = amplitude`` hits ``delta = 0``.

    Brent's method on ``eps`` of :func:`transition_delta` (shooting residual ``1e-10``
    relative, so ``delta`` and the root are accurate to about ``1e-10``).  The linear
    limit (``amplitude -> 0``) is :func:`~gfrf.periodic.floquet.quarter_tongue_zero`.

    Parameters
    ----------
    amplitude : float
        x(0) of the orbits.
    branch : str, optional
        Must be ``"1/4"``.
    bracket : tuple of float, optional
        The interval of eps searched; the sign of delta must change over it.
    xtol : float, optional
        Brent's absolute tolerance on eps.

    Returns
    -------
    float
        The root eps.

    Raises
    ------
    ArgumentError
        Branch ``"0"`` (its curve ``a_0(2 eps)/4 < 0`` for every ``eps > 0``) or no sign
        change of ``delta`` over ``bracket``.
    """
    if parse_branch(branch) != "1/4":
        raise ArgumentError("only the '1/4' curve crosses delta = 0 at eps > 0; the branch-0 "
                            "curve is negative for every eps > 0")

    def delta(e: float) -> float:
        return transition_delta(e, amplitude, "1/4").delta

    lo, hi = bracket
    if not delta(lo) > 0 > delta(hi):
        raise ArgumentError(f"the 1/4 curve at x(0) = {amplitude} does not cross delta = 0 "
                            f"for eps in [{lo}, {hi}]; widen the bracket")
    return float(brentq(delta, lo, hi, xtol=xtol))
