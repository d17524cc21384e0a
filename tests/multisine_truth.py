"""Known systems driven by multisines, for the tests of the nonparametric estimates.

Two truths: a NARX model with a cross term (simulated by its own recursion, written
here) and a hardening oscillator (scipy ``solve_ivp`` DOP853 with the multisine
evaluated as its sum of cosines at every time the integrator asks for).  The expected
level of the stochastic nonlinear distortion is computed from the model's H3 by summing
over the non-degenerate triples of excited lines, enumerated here independently of
``gfrf.identify.multisine``.
"""

from __future__ import annotations

import itertools
import math
from collections import Counter

import numpy as np
from scipy.integrate import solve_ivp

from gfrf.identify.measured import Periodic, periodic
from gfrf.identify.multisine import Multisine
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import Model, parse_model

NARX = ("y[k] = 0.6*y[k-1] - 0.2*y[k-2] + 0.5*u[k-1] + 0.3*u[k-2] "
        "+ 0.15*y[k-1]*u[k-1] - 0.1*u[k-1]**2 - 0.05*y[k-1]**3")
OSCILLATOR = "D(y,2) + 0.4*D(y) + y + 0.3*y**2 + 0.5*y**3 = u"


def narx_model(sample_time: float) -> Model:
    return parse_model(NARX, sample_time=sample_time)


def oscillator_model() -> Model:
    return parse_model(OSCILLATOR)


def _narx_run(u: np.ndarray) -> np.ndarray:
    y = np.zeros(u.size)
    for k in range(2, u.size):
        y1 = y[k - 1]
        y[k] = (0.6 * y1 - 0.2 * y[k - 2] + 0.5 * u[k - 1] + 0.3 * u[k - 2]
                + 0.15 * y1 * u[k - 1] - 0.1 * u[k - 1] ** 2 - 0.05 * y1 ** 3)
    return y


def _oscillator_run(design: Multisine, warmup: int) -> np.ndarray:
    """y at the samples of every realisation (rows), after ``warmup`` periods from rest."""
    n, t_s = design.period, design.sample_time
    spectrum = np.fft.rfft(design.u[:, :n], axis=1) / n
    lines = np.array(design.lines)
    amp = 2 * np.abs(spectrum[:, lines])
    phase = np.angle(spectrum[:, lines])
    w = lines * 2 * math.pi / (n * t_s)
    r = design.u.shape[0]

    def rhs(t: float, z: np.ndarray) -> np.ndarray:
        y, v = z[:r], z[r:]
        u = np.sum(amp * np.cos(w * t + phase), axis=1)
        return np.concatenate([v, u - 0.4 * v - y - 0.3 * y ** 2 - 0.5 * y ** 3])

    samples = design.u.shape[1]
    t_eval = (warmup * n + np.arange(samples)) * t_s
    sol = solve_ivp(rhs, (0.0, t_eval[-1]), np.zeros(2 * r), method="DOP853", rtol=1e-10,
                    atol=1e-12, t_eval=t_eval)
    assert sol.success
    return sol.y[:r]


def measure(design: Multisine, system: str, noise: float = 0.0, seed: int = 0,
            skip: int = 1, offset: float = 0.0) -> tuple[Periodic, np.ndarray]:
    """The periods of ``design`` through ``system`` ("narx" or "oscillator"), with white
    Gaussian output noise of ``noise`` times the output's standard deviation and an
    output offset; returns the periods and the noise standard deviation used."""
    rows = design.u.shape[0]
    if system == "narx":
        y = np.stack([_narx_run(u) for u in design.u])
    else:
        y = _oscillator_run(design, warmup=2)
    sigma = noise * float(np.std(y))
    y = y + offset + sigma * np.random.default_rng(seed).standard_normal(y.shape)
    samples = design.u.shape[1]
    t = np.tile(np.arange(samples) * design.sample_time, rows)
    starts = np.arange(rows) * samples
    return periodic(t, design.u.ravel(), y.ravel(), starts, design.period, skip), \
        np.full(1, sigma)


def distortion_variance(model: Model, design: Multisine) -> np.ndarray:
    """Variance, over random phases, of the third-order stochastic distortion of one
    realisation's FRF on each excited line: the sum over the non-degenerate triples of
    signed excited lines reaching it of |c H3 X X X|^2 / |X|^2 (flat |X| = A)."""
    lines = list(design.lines)
    n, w0 = design.period, 2 * math.pi / (design.period * design.sample_time)
    a = design.rms / math.sqrt(2 * len(lines))
    signed = lines + [-k for k in lines]
    triples = [c for c in itertools.combinations_with_replacement(signed, 3)
               if not any(-x in c for x in c) and sum(c) in lines and sum(c) < n / 2]
    f = np.array(triples, dtype=float) * w0
    h3 = kernel(model, 3)(f[:, 0], f[:, 1], f[:, 2])
    counts = np.array([6 // math.prod(math.factorial(m) for m in Counter(c).values())
                       for c in triples])
    power = np.abs(counts * h3 * a ** 3) ** 2 / a ** 2
    out = np.zeros(len(lines))
    for c, p in zip(triples, power, strict=True):
        out[lines.index(sum(c))] += p
    return out
