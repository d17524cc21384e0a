"""Verdict vs simulation, and the linear closed loop vs the nonlinear one.

:func:`validate` computes the verdict of :func:`gfrf.stability.criteria.verdict` (Theorem 1,
or Theorem 2 for a model file with a ``[controller]``) and simulates the polynomial
model (the object the verdict speaks about) with inputs whose size r lies below and
above the verdict's radius r*: a cosine at the peak of |H1|, two tones near it, and
a bounded random input with a fixed seed (in closed loop the input is the reference).
Each trial records whether the response stayed bounded (no blow-up before t_end)
and max |y|.  A trial with r < r* that blew up contradicts the verdict "the series
converges for every r < r*" and is listed in :attr:`ValidationResult.contradictions`.

What the amplitude r is
-----------------------
The paper's r bounds the size of the input spectrum: with
r = (1/2 pi) int |U(jw)| dw (for a periodic input, the sum of the moduli of its
Fourier coefficients over positive and negative frequencies) every series term obeys
|y_n(t)| <= ||H_n|| r^n, so the series converges for r < r*.  Trials use this
conservative mapping, never the peak of u alone:

* ``u = A cos(w t)``: two phasors A/2 e^(+-jwt), so r = A and the n-th term is at
  most ||H_n|| A^n;
* two tones ``A_1 cos(w_1 t) + A_2 cos(w_2 t)``: r = A_1 + A_2 (here A_1 = A_2 = r/2);
* the bounded random input of :func:`random_input`: a periodic piecewise-linear signal
  (16 random knots half a resonance period apart) whose size r = (1/N) sum_m |V_m|
  (V the DFT of its N knot values) is exact, and max |u| <= r.

The series describes the steady state; the simulations start from rest, so each run
also holds the start-up transient, over a finite horizon.

Trials are at 0.5 r* and 2 r* and, for Theorem 1, at the finite-term estimate r_est
of the true radius (from lower norm bounds, an estimate), 2 r_est and 10 r_est.
Theorem 2's estimate comes from the plant's norms alone and is no loop radius: it is not used.
A model with a controller is also simulated from initial angles of 5, 10 and 15
degrees (zero reference), with the polynomial and, where the file has one, the
physical equation; the verdict speaks about the response to the input from rest, so
these trials are neither below nor above r* (``below_radius`` None).  When r* = 0
(both cart-poles: the controller a s^2 + b s + c is improper, Theorem 2 fails) the
verdict gives no radius: there are no input trials at multiples of r*, the
initial-angle runs are still made, and a note says so.

:func:`linear_vs_nonlinear` compares the nonlinear closed loop from an initial angle
with the linear closed loop of :mod:`gfrf.stability.loops` simulated by python-control
(``control.initial_response`` on a realisation with states (y, y')): the difference
is of the order of the neglected cubic terms, i.e. relative error ~ angle^2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import control
import numpy as np

from gfrf._results import Result
from gfrf.errors import ArgumentError
from gfrf.kernels.recursion import kernel
from gfrf.model.modelfile import ModelFile
from gfrf.model.signals import InputSignal, parse_input
from gfrf.sim.integrate import OdeSystem, SimulationResult
from gfrf.sim.simulation import simulate
from gfrf.sim.system import build_system
from gfrf.stability.criteria import verdict as compute_verdict
from gfrf.stability.verdicts import Verdict

#: Multiples of the radius estimate r_est tried for Theorem 1 (r_est and beyond).
ESTIMATE_FACTORS = (1.0, 2.0, 10.0)

__all__ = ["ESTIMATE_FACTORS", "Trial", "ValidationResult", "validate", "resonance",
           "resonance_label", "random_input", "spectrum_size", "linear_vs_nonlinear"]


@dataclass(frozen=True, kw_only=True, repr=False)
class Trial(Result):
    """One simulation of :func:`validate` (amplitudes in input units, times in s).

    Attributes
    ----------
    kind : str
        ``cosine at resonance``, ``two tones``, ``bounded random`` or
        ``initial angle X deg`` (closed loop, zero reference).
    label : str
        Where the amplitude comes from, e.g. ``0.5 r*``, ``2 r_est``.
    amplitude : float
        Input size r (spectrum size, see the module docstring); 0 for initial angles.
    input_peak : float
        max |u| (reference in closed loop) over the horizon, <= ``amplitude``.
    below_radius : bool or None
        r < r* (None for initial-angle runs, about which the verdict says nothing).
    bounded : bool
        The run reached t_end without blowing up.
    peak : float
        max |y| over the run.
    blowup_time : float or None
    closed_loop : bool
    equation : str
        ``polynomial`` or ``physical``.
    """

    kind: str
    label: str
    amplitude: float
    input_peak: float
    below_radius: bool | None
    bounded: bool
    peak: float
    blowup_time: float | None
    closed_loop: bool
    equation: str = "polynomial"


@dataclass(frozen=True, kw_only=True, repr=False)
class ValidationResult(Result):
    """The verdict of one model and its trials; ``to_dict`` feeds reports and the CLI
    (it adds the ``contradictions`` after the trials).

    Attributes
    ----------
    model : str
    verdict : str
        ``stable``, ``inconclusive`` or ``unstable`` at the verdict's amplitude.
    theorem : int
    radius : float
        r* of the verdict (0: no radius).
    radius_certified : bool
    radius_estimate : float or None
        Finite-term estimate of the true radius (Theorem 1 only).
    resonance : float
        Peak of |H1| (rad/s), the frequency of the cosine trials.
    t_end : float
        Horizon of every run (s).
    trials : list of Trial
    notes : list of str
    """

    model: str
    verdict: str
    theorem: int
    radius: float
    radius_certified: bool
    radius_estimate: float | None
    resonance: float
    t_end: float
    trials: list[Trial] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    _order = ("model", "verdict", "theorem", "radius", "radius_certified", "radius_estimate",
              "resonance", "t_end", "trials", "contradictions")

    @property
    def contradictions(self) -> list[Trial]:
        """Trials with r < r* that did not stay bounded (a bug in the verdict or the code)."""
        return [t for t in self.trials if t.below_radius and not t.bounded]

    def _computed(self) -> dict[str, Any]:
        """The trials below r* that did not stay bounded."""
        return {"contradictions": self.contradictions}


def resonance(model: Any) -> float:
    """Angular frequency (rad/s) of the peak of |H1|: the witness of ||H1||.

    The witness of :func:`gfrf.bounds.norms.h1_norm` (exact rational algebra, the
    stationary point enclosed in ball arithmetic) wherever |H1| peaks at a finite
    nonzero frequency, so "resonance" is the resonance, not a point of a grid.  Where it
    has no such peak (maximal at 0 or as w -> inf, or unbounded) the argmax of |H1| on a
    4001-point log grid 1e-2..1e2 rad/s, a grid value, is the drive frequency instead.

    Parameters
    ----------
    model : Model
        The plant model.

    Returns
    -------
    float
        The drive frequency in rad/s.
    """
    return _resonance(model)[0]


def resonance_label(model: Any) -> str:
    """What :func:`resonance` returns for ``model``, in words (for report text).

    Parameters
    ----------
    model : Model
        The plant model.

    Returns
    -------
    str
        The frequency in rad/s and how it was found.
    """
    w, exact = _resonance(model)
    if exact:
        return f"{w:.7g} rad/s, the exact peak of |H1| (the witness of ||H1||)"
    return (f"{w:.7g} rad/s, the argmax of |H1| on a 4001-point log grid 1e-2..1e2 rad/s "
            "(|H1| has no peak at a finite nonzero frequency)")


def _resonance(model: Any) -> tuple[float, bool]:
    from gfrf.bounds.norms import h1_norm

    bound = h1_norm(model)
    w = float(bound.argmax[0]) if bound.argmax else math.nan
    if math.isfinite(bound.upper) and math.isfinite(w) and w > 0:
        return w, True
    grid = np.geomspace(1e-2, 1e2, 4001)
    return float(grid[np.argmax(np.abs(kernel(model, 1)(grid)))]), False


def spectrum_size(values: np.ndarray) -> float:
    """Size r of the periodic piecewise-linear signal through equally spaced ``values``.

    The Fourier coefficients of the signal are c_k = V_(k mod N) sinc^2(k/N) / N
    (V = DFT of the N knot values, sinc^2 the spectrum of the hat function), and
    sinc^2 sums to one over the aliases k + jN, so sum_k |c_k| = sum_m |V_m| / N.

    Parameters
    ----------
    values : numpy.ndarray
        The N >= 1 knot values of one period.

    Returns
    -------
    float
        ``sum_m |V_m| / N``.
    """
    v = np.asarray(values, dtype=float)
    return float(np.sum(np.abs(np.fft.fft(v))) / v.size)


def random_input(size: float, seed: int = 0, hold: float = 0.5,
                 knots: int = 16) -> InputSignal:
    """Bounded random input of spectrum size ``size`` (see :func:`spectrum_size`).

    ``knots`` uniform random values, ``hold`` s apart, linearly joined and repeated
    with period ``knots * hold``, scaled so that the spectrum size is exactly
    ``size``; hence max |u| <= size.  The same seed gives the same signal.  Its kinks,
    the multiples of ``hold``, are its breakpoints (:meth:`InputSignal.breakpoints`).

    Parameters
    ----------
    size : float
        The spectrum size r, > 0.
    seed : int, optional
        Seed of :func:`numpy.random.default_rng`.
    hold : float, optional
        Spacing of the knots in s, > 0.
    knots : int, optional
        Knots per period, >= 2.

    Returns
    -------
    InputSignal
        The periodic signal.
    """
    if not (size > 0 and hold > 0 and knots >= 2):
        raise ArgumentError("size and hold must be positive and knots >= 2")
    rng = np.random.default_rng(seed)
    values = rng.uniform(-1.0, 1.0, knots)
    values *= size / spectrum_size(values)
    times = np.arange(knots) * hold

    def f(t: Any) -> np.ndarray:
        return np.interp(t, times, values, period=knots * hold)

    return InputSignal(text=f"random(r={size:g}, seed={seed})", expr=None, max_derivative=0,
                       tones=None, _funcs=(f,),
                       _breaks=lambda t_end: np.arange(1, int(t_end / hold) + 1) * hold)


def _amplitudes(v: Verdict, scale: float | None,
                factors: tuple[float, ...]) -> list[tuple[str, float]]:
    """(label, r) of the input trials: multiples of r* (or ``scale``) and of r_est."""
    base = v.radius if scale is None else scale
    name = "r*" if scale is None else f"x {scale:.4g}"
    out = [(f"{f:g} {name}", f * base) for f in factors if base > 0 and math.isfinite(base)]
    if scale is None and v.theorem == 1 and v.radius_estimate:
        out += [(f"{f:g} r_est", f * v.radius_estimate) for f in ESTIMATE_FACTORS]
    return out


def _inputs(r: float, w_r: float, t_end: float, seed: int, need: int
            ) -> dict[str, InputSignal]:
    """The trial inputs; ``need`` derivatives of each (a loop whose improper controller
    reads r', r'': the piecewise-linear random input has none, and is left out)."""
    out = {"cosine at resonance": parse_input(f"{r!r}*cos({w_r!r}*t)", max_derivative=need),
           "two tones": parse_input(f"{r / 2!r}*cos({w_r!r}*t) + "
                                    f"{r / 2!r}*cos({0.9 * w_r!r}*t)", max_derivative=need)}
    if need == 0:
        out["bounded random"] = random_input(r, seed, min(math.pi / w_r, t_end / 16))
    return out


def validate(mf: ModelFile, scale: float | None = None, *,
             factors: tuple[float, ...] = (0.5, 2.0), verdict: Verdict | None = None,
             order: int = 5, t_end: float = 100.0,
             angles_deg: tuple[float, ...] = (5.0, 10.0, 15.0), seed: int = 0,
             blowup: float = 1e3, method: str = "rk45") -> ValidationResult:
    """Verdict of ``mf`` and simulations below and above its radius r*.

    Parameters
    ----------
    mf : ModelFile
        A GFRF model file (not ``kind = "parametric"``).
    scale : float, optional
        Amplitude the ``factors`` multiply; default r* of the verdict (then the
        estimate times :data:`ESTIMATE_FACTORS` is tried too).  Trials are always
        judged against r*.
    factors : tuple of float
        Multiples of the scale to try.
    verdict : Verdict, optional
        A verdict already computed for ``mf``; default
        ``gfrf.stability.criteria.verdict(mf, order)``.
    order : int
        Norm order of the verdict when it is computed here.
    t_end : float
        Horizon in seconds.
    angles_deg : tuple of float
        Initial angles (degrees) of the closed-loop runs (models with a controller).
    seed : int
        Seed of the bounded random input.
    blowup : float
        |y| counted as unbounded.
    method : str
        Integrator of :func:`gfrf.sim.simulation.simulate` (``"fast"``: numba RK4).

    Returns
    -------
    ValidationResult
    """
    if scale is not None and not (math.isfinite(scale) and scale > 0):
        raise ArgumentError(f"scale must be positive and finite, got {scale!r}")
    v = compute_verdict(mf, order) if verdict is None else verdict
    closed = mf.controller is not None
    system = build_system(mf, closed_loop=closed, equation="polynomial")
    w_r = resonance(mf.plant)
    result = ValidationResult(model=mf.name,
                              verdict=v.verdict,
                              theorem=v.theorem,
                              radius=v.radius,
                              radius_certified=v.radius_certified,
                              radius_estimate=v.radius_estimate if v.theorem == 1 else None,
                              resonance=w_r,
                              t_end=t_end)
    if not v.radius > 0:
        result.notes.append(f"Theorem {v.theorem} gives no radius (r* = {v.radius:g}): no "
                            "input amplitude is certified, so no simulation can contradict "
                            "the verdict" + ("; the closed loop is still simulated from "
                                             "initial angles" if closed else ""))
    if v.theorem == 2 and v.radius_estimate:
        result.notes.append(f"the radius estimate {v.radius_estimate:.4g} is the plant's "
                            "(open-loop norms), not a radius of the loop: not tried")
    grid = np.linspace(0.0, t_end, 20001)
    need = system.n_inputs - 1 if not system.discrete else 0
    if need and _amplitudes(v, scale, factors):
        result.notes.append(f"the loop u = C(r - y) reads r and its derivatives up to order "
                            f"{need}: the piecewise-linear bounded random reference is not run")
    for label, r in _amplitudes(v, scale, factors):
        for kind, signal in _inputs(r, w_r, t_end, seed, need).items():
            res = _run(system, signal, t_end, None, blowup, method)
            result.trials.append(Trial(kind=kind,
                                       label=label,
                                       amplitude=r,
                                       input_peak=float(np.max(np.abs(signal(grid)))),
                                       below_radius=r < v.radius,
                                       bounded=res.bounded,
                                       peak=res.peak,
                                       blowup_time=res.blowup_time,
                                       closed_loop=closed))
    if closed:
        equations = ["polynomial"] + (["physical"] if mf.plant.physical is not None else [])
        for eq in equations:
            sys_eq = system if eq == "polynomial" else build_system(mf, closed_loop=True,
                                                                    equation=eq)
            for angle in angles_deg:
                res = _run(sys_eq, None, t_end, [math.radians(angle), 0.0], blowup, method)
                result.trials.append(Trial(kind=f"initial angle {angle:g} deg",
                                           label="",
                                           amplitude=0.0,
                                           input_peak=0.0,
                                           below_radius=None,
                                           bounded=res.bounded,
                                           peak=res.peak,
                                           blowup_time=res.blowup_time,
                                           closed_loop=True,
                                           equation=eq))
    return result


def _run(system: OdeSystem, signal: InputSignal | None, t_end: float,
         initial: list[float] | None, blowup: float, method: str) -> SimulationResult:
    return simulate(system, signal, t_end=t_end, initial=initial, method=method, rtol=1e-7,
                    atol=1e-10, blowup=blowup)


def linear_vs_nonlinear(mf: ModelFile, angle_deg: float, t_end: float = 5.0,
                        equation: str = "polynomial") -> dict[str, float]:
    """Max difference between the nonlinear and the linear closed loop from an angle.

    The linear loop is :func:`gfrf.stability.loops.closed_loop`'s characteristic polynomial,
    realised with states (y, y') and simulated by ``control.initial_response``.

    Parameters
    ----------
    mf : ModelFile
        A model file with a controller whose loop has a second-order characteristic
        polynomial.
    angle_deg : float
        The initial angle in degrees (zero initial velocity).
    t_end : float, optional
        The horizon in s.
    equation : str, optional
        Which equation of the model file is simulated (``"polynomial"`` or ``"physical"``).

    Returns
    -------
    dict
        ``{"angle_deg", "max_abs_error", "relative_error"}`` (radians; relative to the
        initial angle).
    """
    from gfrf.stability.loops import closed_loop

    loop = closed_loop(mf)
    chi = np.asarray(loop.characteristic, dtype=float)
    if chi.size != 3:
        raise ArgumentError("linear_vs_nonlinear needs a second-order closed loop")
    a1, a0 = chi[1] / chi[0], chi[2] / chi[0]
    sys = control.ss([[0.0, 1.0], [-a0, -a1]], [[0.0], [0.0]], [[1.0, 0.0]], [[0.0]])
    theta0 = math.radians(angle_deg)
    t = np.linspace(0.0, t_end, 1001)
    linear = control.initial_response(sys, T=t, X0=[theta0, 0.0]).outputs
    res = simulate(mf, None, t_end=t_end, closed_loop=True, equation=equation,
                   initial=[theta0, 0.0], t_eval=t, method="dop853", rtol=1e-11, atol=1e-14)
    err = float(np.max(np.abs(res.y - np.ravel(linear))))
    return {"angle_deg": angle_deg, "max_abs_error": err, "relative_error": err / theta0}
