"""Frequency response curves: ``gfrf.frc`` against the frequency sweep a user would simulate.

The hardening Duffing oscillator ``y'' + 0.1 y' + y + 0.3 y^3 = 0.3 cos(w t)`` over
w in [0.5, 3] rad/s.  gfrf: one pseudo-arclength continuation with H = 9 harmonics
(about 400 points, stability of every point by Hill's method, folds located, backbone),
CPU time (``time.process_time``) best of :data:`REPEAT`.  Baseline: what a user writes
without gfrf, a stepped sweep of long simulations up and then down the same range
(``solve_ivp`` DOP853 at rtol 1e-6 on the ODE typed by hand; each frequency starts
from the last state and runs :data:`SETTLE` periods; a jump is a change of the
first-harmonic amplitude by more than 15 % between steps) in steps of 1 % of w (2 % in
quick mode), refined from the last state before each jump in steps of 0.1 % of 2.5 x as
many periods (the orbit lingers near a fold), so that its jump frequencies are good to
a few tenths of a percent.  Reference
jump frequencies: the saddle-node orbits by shooting (periodicity and a monodromy
multiplier at +1, ``scipy.optimize.fsolve`` on DOP853 at rtol 1e-12), which shares no
code with gfrf's harmonic balance.
"""

from __future__ import annotations

import math
import os
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve

from gfrf.bench import BenchSection, load_note
from gfrf.harmonic.curve import frc
from gfrf.model.equation import parse_model

__all__ = ["run"]

EQUATION = "D(y,2) + 0.1*D(y) + y + 0.3*y**3 = u"
FORCING = 0.3
RANGE = (0.5, 3.0)
#: Arclength step that gives about 400 points on this curve.
STEP = 0.0072
REPEAT = 3
#: Periods simulated at each frequency of the baseline sweep.
SETTLE = 40


def _rhs(omega: float):
    def f(t: float, z: np.ndarray) -> list[float]:
        return [z[1], FORCING * math.cos(omega * t) - 0.1 * z[1] - z[0] - 0.3 * z[0] ** 3]
    return f


def _amplitude(sol, omega: float, start: float) -> float:
    t = start + 2 * math.pi / omega * np.arange(64) / 64
    return float(abs(np.exp(-1j * omega * t) @ sol.sol(t)[0]) * 2 / 64)


def _settle(w: float, state: list[float], periods: int) -> tuple[float, list[float]]:
    """|first harmonic| after ``periods`` periods at w from ``state``, and the end state."""
    period = 2 * math.pi / w
    sol = solve_ivp(_rhs(w), (0.0, periods * period), state, method="DOP853", rtol=1e-6,
                    atol=1e-9, dense_output=True)
    return _amplitude(sol, w, (periods - 1) * period), list(sol.y[:, -1])


def _jumped(amp: float, previous: float) -> bool:
    return abs(amp - previous) > 0.15 * max(amp, previous)


def _sweep(omegas: np.ndarray) -> float | None:
    """The first jump frequency of a stepped sweep through ``omegas``: coarse steps of
    :data:`SETTLE` periods, then, from the last state before the jump, 0.1 % steps of
    2.5 x as many periods (slow passage near the fold)."""
    previous, state = _settle(float(omegas[0]), [0.0, 0.0], 4 * SETTLE)
    last = float(omegas[0])
    for w in omegas[1:]:
        amp, new_state = _settle(float(w), state, SETTLE)
        if _jumped(amp, previous):
            break
        previous, state, last = amp, new_state, float(w)
    else:
        return None
    ratio = 1.001 if omegas[-1] > omegas[0] else 1 / 1.001
    w = last
    for _ in range(40):
        w *= ratio
        amp, state = _settle(w, state, int(2.5 * SETTLE))
        if _jumped(amp, previous):
            return w
        previous = amp
    return None


def _baseline(relative_step: float) -> tuple[float, list[float]]:
    """CPU seconds and jump frequencies (up-sweep's, then down-sweep's) of the sweeps."""
    count = int(math.log(RANGE[1] / RANGE[0]) / relative_step) + 1
    up = RANGE[0] * (RANGE[1] / RANGE[0]) ** np.linspace(0, 1, count)
    start = time.process_time()
    jumps = [j for j in (_sweep(up), _sweep(up[::-1])) if j is not None]
    return time.process_time() - start, jumps


def _shooting_fold(omega: float, y0: float, v0: float) -> float:
    """The fold frequency by shooting: the orbit is periodic and its monodromy matrix
    has the multiplier +1 (det(M - I) = 0)."""
    def equations(v: np.ndarray) -> list[float]:
        y, dy, w = v

        def rhs(t: float, z: np.ndarray) -> np.ndarray:
            jac = np.array([[0.0, 1.0], [-(1 + 0.9 * z[0] ** 2), -0.1]])
            return np.concatenate([_rhs(w)(t, z[:2]), (jac @ z[2:].reshape(2, 2)).ravel()])

        end = solve_ivp(rhs, (0, 2 * math.pi / w), [y, dy, 1, 0, 0, 1], method="DOP853",
                        rtol=1e-12, atol=1e-13).y[:, -1]
        return [end[0] - y, end[1] - dy,
                float(np.linalg.det(end[2:].reshape(2, 2) - np.eye(2)))]

    # started 0.2 % off in omega and 1 % off in the state: the root is found, not copied
    root, info, ok, message = fsolve(equations, [1.01 * y0, v0, 1.002 * omega], xtol=1e-12,
                                     full_output=True)
    if ok != 1 and max(abs(v) for v in info["fvec"]) > 1e-9:
        raise RuntimeError(f"shooting fold did not converge: {message}")
    return float(root[2])


def run(quick: bool) -> BenchSection:
    """Time the continuation and the baseline sweeps; errors against shooting folds.

    Parameters
    ----------
    quick : bool
        Baseline sweeps in coarse steps of 2 % of the frequency instead of 1 %.

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``: CPU time and jump-frequency error of the
        continuation and of the stepped-sweep baseline.
    """
    load = os.getloadavg()
    model = parse_model(EQUATION)
    best, curve = math.inf, None
    for _ in range(REPEAT):
        start = time.process_time()
        curve = frc(model, FORCING, RANGE, harmonics=9, step=STEP)
        best = min(best, time.process_time() - start)
    assert curve is not None
    reference = []
    for fold in curve.folds:
        c = fold.coefficients
        k = np.arange(1, curve.harmonics + 1)
        reference.append(_shooting_fold(fold.omega, float(c[0] + c[1::2].sum()),
                                        float(fold.omega * (k * c[2::2]).sum())))
    ours = [f.omega for f in curve.folds]
    coarse = 0.02 if quick else 0.01
    t_base, jumps = _baseline(coarse)

    def error(found: list[float]) -> str:
        if len(found) != len(reference):
            return f"found {len(found)} jumps, expected {len(reference)}"
        return f"{max(abs(a - b) / b for a, b in zip(found, reference, strict=True)):.1e}"

    setting = f"w in [{RANGE[0]}, {RANGE[1]}] rad/s, A = {FORCING}"
    rows: list[list[object]] = [
        ["frequency response curve", f"gfrf.frc, H = 9, {len(curve.points)} points "
         "(continuation, Hill stability, folds, backbone)", setting, f"{best:.3f}",
         error(ours), ", ".join(f"{w:.6f}" for w in ours)],
        ["frequency response curve", f"stepped DOP853 sweeps up and down, "
         f"{coarse:.0%} steps of {SETTLE} periods, then 0.1 % steps of "
         f"{int(2.5 * SETTLE)} periods past the jump", setting, f"{t_base:.2f}",
         error(jumps), ", ".join(f"{w:.4f}" for w in jumps)]]
    notes = [f"Reference jump frequencies (shooting, multiplier +1): "
             f"{', '.join(f'{w:.8f}' for w in reference)} rad/s.",
             f"The baseline sweeps take {t_base / best:.3g}x the CPU time of gfrf.frc; "
             f"their jump frequencies are off by {error(jumps)} (relative), gfrf's folds by "
             f"{error(ours)}.",
             "CPU seconds (time.process_time); gfrf best of "
             f"{REPEAT}, the baseline once.", load_note(load)]
    return BenchSection(
        title="Frequency response curves: harmonic balance against simulated sweeps",
        intro=__doc__.split("\n\n", 1)[1].replace("\n", " ").strip(),
        columns=["task", "method", "setting", "CPU s", "jump error (relative)",
                 "jump frequencies (rad/s)"],
        rows=rows, notes=notes)
