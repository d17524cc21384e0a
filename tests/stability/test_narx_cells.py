"""Exact integer-corner enclosures of polynomials on grid boxes: they agree with the
term-by-term rational enclosure (python-flint fmpq, one box at a time) and contain every
sampled value of the polynomial."""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from gfrf.stability.narx_box import _enclosure_exact, _frac
from gfrf.stability.narx_cells import enclose

# 0.6 x^3 - 1/7 x y + 2.5 y^2 z - 3 z^4 + 1/3 in the variables (x, y, z)
POLY = {(3, 0, 0): Fraction(3, 5), (1, 1, 0): Fraction(-1, 7), (0, 2, 1): Fraction(5, 2),
        (0, 0, 4): Fraction(-3), (0, 0, 0): Fraction(1, 3)}
SCALES = [Fraction(3, 10), Fraction(7, 64), Fraction(5, 3)]


def _boxes(rows: int, seed: int, top: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    a = rng.integers(-top, top, size=(rows, 3))
    return a, a + rng.integers(0, 4, size=(rows, 3))


def test_integer_enclosure_equals_the_rational_one_box_by_box() -> None:
    for top in (20, 10**6):  # int64 products, then Python integers
        a, b = _boxes(40, 1, top)
        lo, hi, den = enclose([POLY], a, b, SCALES)[0]
        for r in range(len(a)):
            box_lo = [int(a[r, i]) * SCALES[i] for i in range(3)]
            box_hi = [int(b[r, i]) * SCALES[i] for i in range(3)]
            (ref_lo, ref_hi), = _enclosure_exact([POLY], box_lo, box_hi, [1, 1, 1])
            assert Fraction(lo[r], den) == _frac(ref_lo)
            assert Fraction(hi[r], den) == _frac(ref_hi)


def test_sampled_values_lie_inside_the_enclosure() -> None:
    a, b = _boxes(200, 2, 30)
    lo, hi, den = enclose([POLY], a, b, SCALES)[0]
    rng = np.random.default_rng(3)
    s = np.array([float(x) for x in SCALES])
    for _ in range(20):
        x = (a + rng.uniform(size=a.shape) * (b - a)) * s
        val = sum(float(c) * np.prod(x ** np.array(k), axis=1) for k, c in POLY.items())
        tol = 1e-9 * (1 + np.abs(val))
        assert np.all(val >= np.array([float(Fraction(v, den)) for v in lo]) - tol)
        assert np.all(val <= np.array([float(Fraction(v, den)) for v in hi]) + tol)
