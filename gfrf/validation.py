"""Verdict vs simulation, and the linear closed loop vs the nonlinear one.

:func:`validate` simulates the polynomial model (the object the verdict speaks about)
with inputs of peak amplitude below and above a radius r* (a sinusoid at the H1
peak, a two-tone input, a bounded random input with a fixed seed; in closed loop the
input is the reference) and, for a model with a controller, the closed loop from
initial angles of 5, 10 and 15 degrees.  Each trial records whether the response
stayed bounded (no blow-up before t_end).  A verdict "stable below r*" contradicted
by a bounded-input trial below r* is listed in :attr:`ValidationResult.contradictions`.

:func:`linear_vs_nonlinear` compares the nonlinear closed loop from an initial angle
with the linear closed loop of :mod:`gfrf.loops` simulated by python-control
(``control.initial_response`` on a realisation with states (y, y')): the difference
is of the order of the neglected cubic terms, i.e. relative error ~ angle^2.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any

import control
import numpy as np

from gfrf.errors import ArgumentError
from gfrf.kernels import kernel
from gfrf.modelfile import ModelFile
from gfrf.signals import InputSignal
from gfrf.simulate import build_system, simulate

__all__ = ["Trial", "ValidationResult", "validate", "resonance", "random_input",
           "linear_vs_nonlinear"]


@dataclass(frozen=True)
class Trial:
    """One simulation of :func:`validate` (amplitude in input units, times in s)."""

    kind: str
    amplitude: float
    below_radius: bool
    bounded: bool
    peak: float
    blowup_time: float | None
    closed_loop: bool


@dataclass
class ValidationResult:
    """All trials of one model; ``to_dict`` feeds reports."""

    model: str
    radius: float
    resonance: float
    trials: list[Trial] = field(default_factory=list)

    @property
    def contradictions(self) -> list[Trial]:
        """Trials below r* that did not stay bounded (a bug in the verdict or the code)."""
        return [t for t in self.trials if t.below_radius and not t.bounded]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description."""
        return {"model": self.model, "radius": self.radius, "resonance": self.resonance,
                "trials": [asdict(t) for t in self.trials],
                "contradictions": [asdict(t) for t in self.contradictions]}


def resonance(model: Any) -> float:
    """Angular frequency (rad/s) of the peak of |H1| on a 1e-2..1e2 rad/s grid."""
    w = np.geomspace(1e-2, 1e2, 4001)
    return float(w[np.argmax(np.abs(kernel(model, 1)(w)))])


def random_input(amplitude: float, t_end: float, seed: int = 0, hold: float = 0.5) -> InputSignal:
    """Bounded random input: uniform values in [-A, A] every ``hold`` s, linearly joined."""
    rng = np.random.default_rng(seed)
    knots = np.arange(0.0, t_end + 2 * hold, hold)
    values = rng.uniform(-amplitude, amplitude, knots.size)

    def f(t: Any) -> np.ndarray:
        return np.interp(t, knots, values)

    return InputSignal(f"random(A={amplitude:g}, seed={seed})", None, 0, None, (f,))


def validate(mf: ModelFile, radius: float, *, factors: tuple[float, ...] = (0.5, 2.0),
             t_end: float = 100.0, angles_deg: tuple[float, ...] = (5.0, 10.0, 15.0),
             seed: int = 0, blowup: float = 1e3) -> ValidationResult:
    """Simulate inputs at ``factor * radius`` and the closed loop from initial angles.

    Parameters
    ----------
    mf : ModelFile
    radius : float
        The verdict's input radius r* (peak input amplitude).
    factors : tuple of float
        Multiples of r* to try (below 1: "below radius").
    t_end : float
        Horizon in seconds.
    angles_deg : tuple of float
        Initial angles (degrees) of the closed-loop runs (models with a controller).
    blowup : float
        |y| counted as unbounded.
    """
    if not (math.isfinite(radius) and radius > 0):
        raise ArgumentError(f"radius must be positive and finite, got {radius!r}")
    closed = mf.controller is not None
    system = build_system(mf, closed_loop=closed, equation="polynomial")
    w_r = resonance(mf.plant)
    result = ValidationResult(mf.name, radius, w_r)
    for factor in factors:
        a = factor * radius
        inputs = {"sine at resonance": f"{a!r}*sin({w_r!r}*t)",
                  "two tones": f"{a / 2!r}*sin({w_r!r}*t) + {a / 2!r}*sin({2.3 * w_r!r}*t)",
                  "bounded random": random_input(a, t_end, seed)}
        for kind, signal in inputs.items():
            res = simulate(system, signal, t_end=t_end, rtol=1e-7, atol=1e-10,
                           blowup=blowup)
            result.trials.append(Trial(kind, a, factor < 1, res.bounded, res.peak,
                                       res.blowup_time, closed))
    if closed:
        for angle in angles_deg:
            res = simulate(system, None, t_end=t_end, initial=[math.radians(angle), 0.0],
                           rtol=1e-7, atol=1e-10, blowup=blowup)
            result.trials.append(Trial(f"initial angle {angle:g} deg", 0.0, True,
                                       res.bounded, res.peak, res.blowup_time, True))
    return result


def linear_vs_nonlinear(mf: ModelFile, angle_deg: float, t_end: float = 5.0,
                        equation: str = "polynomial") -> dict[str, float]:
    """Max difference between the nonlinear and the linear closed loop from an angle.

    The linear loop is :func:`gfrf.loops.closed_loop`'s characteristic polynomial,
    realised with states (y, y') and simulated by ``control.initial_response``.

    Returns
    -------
    dict
        ``{"angle_deg", "max_abs_error", "relative_error"}`` (radians; relative to the
        initial angle).
    """
    from gfrf.loops import closed_loop

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
