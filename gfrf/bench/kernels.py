"""Speed of the GFRF generator: symbolic H1..H7 and numeric H3 on 10^6 points.

Model: the cart-pole of eq (12) (every term type: cubic, theta*theta'^2,
theta^2*theta'', theta^2*u).  Symbolic: a fresh generator builds the recursion steps
(placeholder form) and the fully inlined rational functions of H1..H7.  Numeric: H3
at 10^6 random frequency triples in [-20, 20] rad/s, by gfrf's numpy path and its
numba ufunc (compile time excluded, reported), against the baseline a user would
really write: ``sympy.lambdify((s1, s2, s3), H3, "numpy", cse=True)`` of the same
explicit rational function, called at s = j*omega (its set-up time reported
separately).  All on the same points, least CPU time of three, in one run.  Error: max relative
deviation from harmonic probing (:mod:`gfrf.kernels.probing`, an independent algorithm) on
2000 of the points.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import sympy as sp

from gfrf._data import MODELS_DIR
from gfrf.bench import BenchSection, load_note
from gfrf.kernels.probing import probe_kernel
from gfrf.kernels.recursion import GFRFGenerator, kernel
from gfrf.model.modelfile import load_model

__all__ = ["run"]


def best_of(call: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    """Least CPU time in s of ``repeat`` calls (the machine is shared: wall time is not
    this process's work) and the last call's result."""
    best, out = math.inf, None
    for _ in range(repeat):
        start = time.process_time()
        out = call()
        best = min(best, time.process_time() - start)
    return best, out


def _rate(points: int, seconds: float) -> str:
    return f"{points / seconds:.3g}"


def run(quick: bool) -> BenchSection:
    """Time symbolic generation and numeric evaluation; return the report section.

    Parameters
    ----------
    quick : bool
        Orders up to 5 on 10^5 points (200 checked) instead of 7 on 10^6 (2,000).

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``.
    """
    load = os.getloadavg()
    model = load_model(MODELS_DIR / "cartpole.toml").plant
    top = 5 if quick else 7
    fresh = GFRFGenerator(model)
    start = time.process_time()
    for n in range(1, top + 1):
        fresh.recursive(n, True)
    t_recursive = time.process_time() - start
    start = time.process_time()
    for n in range(1, top + 1):
        fresh.explicit(n, True)
    t_explicit = time.process_time() - start + t_recursive

    rng = np.random.default_rng(0)
    points = 10**5 if quick else 10**6
    repeat = 3
    w = rng.uniform(-20.0, 20.0, (3, points))
    s_points = 1j * w
    check = 200 if quick else 2000
    reference = np.array([probe_kernel(model, list(w[:, i])) for i in range(check)])

    def error(values: np.ndarray) -> float:
        return float(np.max(np.abs(values[:check] - reference) / np.abs(reference)))

    h3 = kernel(model, 3)
    start = time.process_time()
    h3(*w[:, :10])  # plan and lambdify once, outside the timing
    t_plan = time.process_time() - start
    t_numpy, numpy_values = best_of(lambda: h3(*w), repeat)

    explicit, s = h3.expr, h3.variables
    start = time.process_time()
    baseline = sp.lambdify(s, explicit, "numpy", cse=True)
    t_lambdify_setup = time.process_time() - start
    t_lambdify, lambdify_values = best_of(lambda: baseline(*s_points), repeat)

    rows = [[f"symbolic H1..H{top}, recursive form", "placeholder recursion",
             f"{t_recursive:.3f} s", "exact", "target < 5 s"],
            [f"symbolic H1..H{top}, explicit rational functions", "inlined",
             f"{t_explicit:.3f} s", "exact", "target < 5 s"],
            [f"H3 numeric, {points} points", "baseline: sympy.lambdify(..., 'numpy', cse=True)",
             f"{_rate(points, t_lambdify)} pts/s", f"{error(lambdify_values):.1e}",
             f"set-up (lambdify with cse) {t_lambdify_setup:.3f} s"],
            [f"H3 numeric, {points} points", "gfrf numpy (vectorised)",
             f"{_rate(points, t_numpy)} pts/s", f"{error(numpy_values):.1e}",
             f"{t_lambdify / t_numpy:.2g}x the lambdify rate; set-up (plan) {t_plan:.3f} s"]]
    notes = []
    try:
        start = time.process_time()
        ufunc = h3.compiled()
        ufunc(*w[:, :2])
        t_compile = time.process_time() - start
        t_fast, fast_values = best_of(lambda: ufunc(*w), repeat)
        rows.append([f"H3 numeric, {points} points", "gfrf numba ufunc (one core)",
                     f"{_rate(points, t_fast)} pts/s", f"{error(fast_values):.1e}",
                     f"{t_lambdify / t_fast:.2g}x the lambdify rate; target >= 1e7 pts/s"])
        notes.append(f"numba compile or cache load of H3 (excluded above): {t_compile:.2f} s; "
                     f"it pays for itself against lambdify after about "
                     f"{_break_even(t_compile, t_fast, t_lambdify, points)} points.")
    except ImportError:
        notes.append("numba not installed: the compiled path was skipped.")

    sample = 10 if quick else 50
    start = time.process_time()
    naive = np.array([complex(explicit.subs({s[k]: sp.I * float(w[k, i]) for k in range(3)})
                              .evalf()) for i in range(sample)])
    t_naive = (time.process_time() - start) / sample
    naive_error = float(np.max(np.abs(naive - reference[:sample]) / np.abs(reference[:sample])))
    notes.append(f"Not a fair baseline, for scale only: sympy subs/evalf point by point runs "
                 f"at {1 / t_naive:.3g} pts/s (error {naive_error:.1e}, {sample} points).")
    notes.append(load_note(load))
    return BenchSection(
        title="GFRF generation and evaluation (cart-pole eq (12))",
        intro=" ".join(__doc__.split("\n\n", 1)[1].split()),
        columns=["what", "method", "time or rate", "max rel. error", "note"],
        rows=rows, notes=notes)


def _break_even(t_compile: float, t_fast: float, t_lambdify: float, points: int) -> str:
    """Points after which compile + compiled evaluation beats lambdify evaluation."""
    saving = (t_lambdify - t_fast) / points
    return f"{t_compile / saving:.2g}" if saving > 0 else "never (the ufunc is not faster)"
