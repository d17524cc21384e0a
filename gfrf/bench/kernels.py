"""Speed of the GFRF generator: symbolic H1..H7 and numeric H3 on 10^6 points.

Model: the cart-pole of eq (12) (every term type: cubic, theta*theta'^2,
theta^2*theta'', theta^2*u).  Symbolic: a fresh generator builds the recursion steps
(placeholder form) and the fully inlined rational functions of H1..H7.  Numeric: H3
at 10^6 random frequency triples in [-20, 20] rad/s, by the numpy path and the numba
ufunc (compile time excluded, reported), against the naive baseline a user would
write, sympy ``subs``/``evalf`` of the explicit H3 point by point (timed on a sample
and reported as a rate).  Error: max relative deviation from harmonic probing
(:mod:`gfrf.probing`, an independent algorithm) on 2000 of the points.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import sympy as sp

from gfrf.bench import BenchSection
from gfrf.kernels import GFRFGenerator, kernel
from gfrf.modelfile import load_model
from gfrf.probing import probe_kernel

__all__ = ["run"]


def _rate(points: int, seconds: float) -> str:
    return f"{points / seconds:.3g}"


def run(quick: bool) -> BenchSection:
    """Time symbolic generation and numeric evaluation; return the report section."""
    model = load_model(Path(__file__).resolve().parents[2] / "models" / "cartpole.toml").plant
    top = 5 if quick else 7
    fresh = GFRFGenerator(model)
    start = time.perf_counter()
    for n in range(1, top + 1):
        fresh.recursive(n, True)
    t_recursive = time.perf_counter() - start
    start = time.perf_counter()
    for n in range(1, top + 1):
        fresh.explicit(n, True)
    t_explicit = time.perf_counter() - start + t_recursive

    rng = np.random.default_rng(0)
    points = 10**5 if quick else 10**6
    w = rng.uniform(-20.0, 20.0, (3, points))
    check = 200 if quick else 2000
    reference = np.array([probe_kernel(model, list(w[:, i])) for i in range(check)])

    def error(values: np.ndarray) -> float:
        return float(np.max(np.abs(values[:check] - reference) / np.abs(reference)))

    h3 = kernel(model, 3)
    h3(*w[:, :10])  # plan and lambdify once, outside the timing
    start = time.perf_counter()
    numpy_values = h3(*w)
    t_numpy = time.perf_counter() - start
    rows = [[f"symbolic H1..H{top}, recursive form", "placeholder recursion",
             f"{t_recursive:.3f} s", "exact", "target < 5 s"],
            [f"symbolic H1..H{top}, explicit rational functions", "inlined",
             f"{t_explicit:.3f} s", "exact", "target < 5 s"],
            [f"H3 numeric, {points} points", "numpy (vectorised)",
             f"{_rate(points, t_numpy)} pts/s", f"{error(numpy_values):.1e}", ""]]
    notes = []
    try:
        start = time.perf_counter()
        ufunc = h3.compiled()
        ufunc(*w[:, :2])
        t_compile = time.perf_counter() - start
        timings = []
        for _ in range(3):
            start = time.perf_counter()
            fast_values = ufunc(*w)
            timings.append(time.perf_counter() - start)
        t_fast = min(timings)
        rows.append([f"H3 numeric, {points} points", "numba ufunc (one core)",
                     f"{_rate(points, t_fast)} pts/s", f"{error(fast_values):.1e}",
                     "target >= 1e7 pts/s"])
        notes.append(f"numba compile time of H3 (excluded above): {t_compile:.2f} s.")
    except ImportError:
        t_fast = t_numpy
        notes.append("numba not installed: the compiled path was skipped.")

    explicit = h3.expr
    s = h3.variables
    sample = 20 if quick else 100
    start = time.perf_counter()
    naive = np.array([complex(explicit.subs({s[k]: sp.I * float(w[k, i]) for k in range(3)})
                              .evalf()) for i in range(sample)])
    t_naive = (time.perf_counter() - start) / sample
    naive_error = float(np.max(np.abs(naive - reference[:sample]) / np.abs(reference[:sample])))
    rows.append(["H3 numeric", "naive: sympy subs/evalf per point",
                 f"{1 / t_naive:.3g} pts/s", f"{naive_error:.1e}",
                 f"ours is {t_naive * points / t_fast:.3g}x faster"])
    return BenchSection(
        title="GFRF generation and evaluation (cart-pole eq (12))",
        intro=__doc__.split("\n\n", 1)[1].strip(),
        columns=["what", "method", "time or rate", "max rel. error", "note"],
        rows=rows, notes=notes)
