"""Truncation error of the Volterra prediction: measured against simulation, bounded a priori.

The independent check of :func:`gfrf.sim.volterra.predict` is the simulated steady
state: for commensurate tones (w_k = m_k w_0, :func:`base_frequency`) the steady state
is periodic with period 2 pi / w_0, found here by Newton shooting on the period map
(DOP853 at rtol 1e-12, :func:`steady_state`), so no transient has to decay, and its FFT
over exactly one period is exact for the harmonics m w_0.
The truncation error of the order-N prediction falls like A^(N+1), or like A^(N+2)
when H_{N+1} vanishes (odd systems such as the pendulum): :func:`compare` and
:func:`error_vs_amplitude` measure it.

:func:`select_order` picks the smallest N whose truncation bound
``sum_{n>N} sup|H_n| (sum_k A_k)^n`` (upper bounds of :func:`gfrf.bounds.norms.kernel_norm`)
is below a tolerance; since |sum c_i| <= sum_k A_k this bounds the sup-norm error of
the steady state while the series converges.  Like :func:`gfrf.sim.volterra.predict` it
refuses a plant without a steady state (:class:`gfrf.sim.volterra.NoSteadyStateError`)
and an amplitude at or beyond the series radius
(:class:`gfrf.sim.volterra.BeyondRadiusError`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from gfrf._results import Result
from gfrf.errors import ArgumentError, ConvergenceError
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import Model
from gfrf.model.signals import tones_input
from gfrf.sim.integrate import MAX_RHS_EVALUATIONS, OdeSystem, input_values
from gfrf.sim.system import build_system
from gfrf.sim.volterra import (
    BeyondRadiusError,
    Component,
    NoSteadyStateError,
    VolterraPrediction,
    _check_tones,
    _steady_state_problem,
    predict,
    series_radius,
)

__all__ = ["SteadyState", "steady_state", "compare", "error_vs_amplitude",
           "OrderChoice", "select_order", "base_frequency"]


def _truncate(p: VolterraPrediction, order: int) -> VolterraPrediction:
    """The order-``order`` prediction from the per-order terms of a higher-order one."""
    comps = []
    for c in p.components:
        row = {n: v for n, v in c.by_order.items() if n <= order}
        if row:
            comps.append(Component(omega=c.omega, value=sum(row.values()), by_order=row))
    return VolterraPrediction(tones=p.tones, order=order, components=tuple(comps))


def base_frequency(tones: Any, max_denominator: int = 1000) -> float:
    """Largest w0 (rad/s) of which every tone frequency is an integer multiple.

    Parameters
    ----------
    tones : str or sequence of tuple
        ``(A, omega, phi)`` per tone (omega in rad/s, > 0), or input text.
    max_denominator : int, optional
        Largest denominator of a frequency ratio accepted.

    Returns
    -------
    float
        w0 in rad/s.

    Raises
    ------
    ArgumentError
        If the frequencies are not commensurate within ``max_denominator``.
    """
    tones = _check_tones(tones)
    w_ref = tones[0][1]
    ratios = [Fraction(w / w_ref).limit_denominator(max_denominator) for _, w, _ in tones]
    for (_, w, _), r in zip(tones, ratios, strict=True):
        if abs(float(r) * w_ref - w) > 1e-9 * w:
            raise ArgumentError(f"tone frequencies {[t[1] for t in tones]} rad/s are not "
                                f"commensurate: the steady state is not periodic")
    lcm_den = math.lcm(*(r.denominator for r in ratios))
    gcd_num = math.gcd(*(r.numerator * (lcm_den // r.denominator) for r in ratios))
    return w_ref * gcd_num / lcm_den


@dataclass(frozen=True)
class SteadyState:
    """A periodic steady state found by shooting: one period sampled at ``t`` (s)."""

    t: np.ndarray
    y: np.ndarray
    omega0: float
    residual: float
    iterations: int

    def harmonic(self, m: int) -> complex:
        """Phasor Y(m omega0) from the FFT over one period (y = 2 Re(Y e^{j m w0 t})).

        Parameters
        ----------
        m : int
            The harmonic of ``omega0``, 0 <= m <= samples / 2.

        Returns
        -------
        complex
            The phasor Y.
        """
        return complex(np.fft.rfft(self.y)[m] / self.y.size)


def steady_state(system: OdeSystem, tones: Any, *, samples: int = 256,
                 guess: np.ndarray | None = None, tol: float = 1e-12,
                 max_iter: int = 20, max_evaluations: int = MAX_RHS_EVALUATIONS
                 ) -> SteadyState:
    """Periodic steady state of ``system`` under a commensurate multi-tone input.

    Newton's method on z -> Phi(z) - z, Phi the period map (DOP853, rtol 1e-12),
    with a finite-difference Jacobian.  All integrations together may evaluate the
    right-hand side at most ``max_evaluations`` times (default
    :data:`gfrf.sim.integrate.MAX_RHS_EVALUATIONS`; tones 1000 times apart need about that).

    Parameters
    ----------
    system : OdeSystem
        The generated state form of a continuous-time model.
    tones : str or sequence of tuple
        ``(A, omega, phi)`` per tone, commensurate frequencies in rad/s, or input text.
    samples : int, optional
        Samples of the returned period.
    guess : numpy.ndarray, optional
        Initial state of the Newton iteration; default zero.
    tol : float, optional
        Tolerance of the shooting residual, relative to the state's size.
    max_iter : int, optional
        Most Newton iterations.
    max_evaluations : int, optional
        Budget of right-hand-side evaluations of all the integrations together.

    Returns
    -------
    SteadyState
        One period of y, sampled at ``samples`` equally spaced times.

    Raises
    ------
    ConvergenceError
        If the shooting residual does not fall below ``tol`` (times the state size), or
        the work budget is spent first.
    """
    tones = _check_tones(tones)
    w0 = base_frequency(tones)
    period = 2 * math.pi / w0
    signal = tones_input(tones)
    rhs = system.function("rhs")
    count = [0]

    def f(t: float, z: np.ndarray) -> np.ndarray:
        count[0] += 1
        if count[0] > max_evaluations:
            raise ConvergenceError(f"shooting stopped: the period maps of the common period "
                                   f"{period:.6g} s used the work budget max_evaluations = "
                                   f"{max_evaluations} right-hand-side evaluations")
        out = np.empty(system.n_states)
        rhs(z, input_values(signal, 1, np.array([t]))[:, 0], out)
        return out

    def flow(z: np.ndarray, t_eval: np.ndarray | None = None) -> Any:
        return solve_ivp(f, (0.0, period), z, method="DOP853", rtol=1e-12, atol=1e-14,
                         t_eval=t_eval)

    z = np.zeros(system.n_states) if guess is None else np.array(guess, dtype=float)
    scale = 1.0
    for iteration in range(1, max_iter + 1):  # noqa: B007 - reported after the loop
        end = flow(z).y[:, -1]
        g = end - z
        scale = max(1e-300, float(np.max(np.abs(z))), float(np.max(np.abs(end))))
        if np.max(np.abs(g)) <= tol * scale:
            break
        jac = np.empty((z.size, z.size))
        for i in range(z.size):
            dz = np.zeros_like(z)
            dz[i] = 1e-7 * scale
            jac[:, i] = (flow(z + dz).y[:, -1] - z - dz - g) / dz[i]
        z = z - np.linalg.solve(jac, g)
    else:
        raise ConvergenceError(f"shooting did not converge: residual {np.max(np.abs(g)):.3g}")
    t = np.arange(samples) * period / samples
    sol = flow(z, t)
    return SteadyState(t=t, y=sol.y[0], omega0=w0, residual=float(np.max(np.abs(g))),
                       iterations=iteration)


def compare(model: Model, tones: Any, orders: tuple[int, ...] = (1, 3, 5), *,
            samples: int = 256) -> dict[str, Any]:
    """Sup-norm error of each order's prediction against the shot steady state.

    Parameters
    ----------
    model : Model
        A continuous-time plant model.
    tones : str or sequence of tuple
        ``(A, omega, phi)`` per tone, commensurate frequencies in rad/s, or input text.
    orders : tuple of int, optional
        The truncation orders N compared.
    samples : int, optional
        Samples of the period.

    Returns
    -------
    dict
        ``{"errors": {N: max_t |y_sim - y_N|}, "steady_state": SteadyState}``.
    """
    system = build_system(model, equation="polynomial")
    best = predict(model, tones, max(orders))
    guess = np.array([best.waveform(0.0, d) for d in range(system.order)])
    ss = steady_state(system, tones, samples=samples, guess=guess)
    errors = {n: float(np.max(np.abs(ss.y - _truncate(best, n).waveform(ss.t))))
              for n in orders}
    return {"errors": errors, "steady_state": ss}


def error_vs_amplitude(model: Model, omega: float, amplitudes: Any,
                       orders: tuple[int, ...] = (1, 3, 5)) -> dict[str, Any]:
    """Prediction error against amplitude for a sinusoid ``A cos(omega t)`` (rad/s).

    Returns ``{"amplitudes", "errors": {N: [...]}, "slopes": {N: fitted log-log slope}}``.

    Parameters
    ----------
    model : Model
        A continuous-time plant model.
    omega : float
        The angular frequency in rad/s.
    amplitudes : array_like
        The amplitudes A, > 0.
    orders : tuple of int, optional
        The truncation orders N compared.
    """
    amplitudes = np.asarray(amplitudes, dtype=float)
    errors: dict[int, list[float]] = {n: [] for n in orders}
    for a in amplitudes:
        res = compare(model, [(float(a), omega, 0.0)], orders)
        for n in orders:
            errors[n].append(res["errors"][n])
    slopes = {n: float(np.polyfit(np.log(amplitudes), np.log(errors[n]), 1)[0])
              for n in orders}
    return {"omega": omega, "amplitudes": amplitudes.tolist(), "errors": errors,
            "slopes": slopes}


@dataclass(frozen=True, kw_only=True, repr=False)
class OrderChoice(Result):
    """Result of :func:`select_order`: N, its tail bound and the terms sup|H_n| A^n.

    ``certified`` is False whenever the tail beyond ``max_order`` is extrapolated.
    """

    order: int
    bound: float
    amplitude: float
    tolerance: float
    terms: dict[int, float] = field(default_factory=dict)
    certified: bool = False
    note: str = ""


def select_order(model: Model, amplitude: float, tolerance: float,
                 max_order: int = 7) -> OrderChoice:
    """Smallest N with ``sum_{n>N} sup|H_n| A^n < tolerance`` (upper norm bounds).

    Parameters
    ----------
    model : Model
        The system whose kernel norms are bounded.
    amplitude : float
        Peak input amplitude A (for a multi-tone input, the sum of the tone amplitudes).
    tolerance : float
        Allowed sup-norm error of the steady-state output.
    max_order : int
        Highest kernel order whose norm is bounded; the tail beyond it is a geometric
        extrapolation of the last two non-zero terms (then ``certified`` is False).

    Raises
    ------
    NoSteadyStateError
        The linear part has a pole on or beyond the stability boundary.
    BeyondRadiusError
        The amplitude is at or beyond the series radius r* (no truncation bound holds).
    ArgumentError
        Non-positive amplitude or tolerance, or no N <= max_order meets the tolerance.
    """
    from gfrf.bounds.norms import kernel_norm

    if not (amplitude > 0 and tolerance > 0):
        raise ArgumentError("amplitude and tolerance must be positive")
    problem = _steady_state_problem(model)
    if problem is not None:
        raise NoSteadyStateError(problem)
    r_star, inside, _ = series_radius(model)
    if amplitude >= inside:
        raise BeyondRadiusError(f"amplitude {amplitude:.6g} is at or beyond the series radius "
                                f"r* = {r_star:.6g}: no truncation order bounds the error",
                                amplitude, r_star)
    terms = {n: 0.0 if kernel(model, n).is_zero else
             float(kernel_norm(model, n).upper) * amplitude**n for n in range(1, max_order + 1)}
    nonzero = [v for v in terms.values() if v > 0]
    ratio = nonzero[-1] / nonzero[-2] if len(nonzero) >= 2 else 0.0
    beyond = nonzero[-1] * ratio / (1 - ratio) if ratio < 1 else math.inf
    for order in range(1, max_order + 1):
        bound = sum(v for n, v in terms.items() if n > order) + beyond
        if bound < tolerance:
            note = (f"orders <= {max_order} from upper norm bounds, beyond that a geometric "
                    f"extrapolation (ratio {ratio:.3g})")
            return OrderChoice(order=order,
                               bound=bound,
                               amplitude=amplitude,
                               tolerance=tolerance,
                               terms=terms,
                               certified=False,
                               note=note)
    raise ArgumentError(f"no kernel order <= {max_order} meets tolerance {tolerance:g} at "
                        f"amplitude {amplitude:g} (series ratio {ratio:.3g})")
