"""Tests of gfrf.bounds.tail: the bound of |H_n| outside the box |w_i| <= W is sound and decays.

References are independent of gfrf.kernels.recursion: harmonic probing
(gfrf.kernels.probing) for the
symmetric kernel, a direct mpmath evaluation of the contiguous-block recursion for the
asymmetric one, and closed forms (tests/mp_reference.py) for one-dimensional sups.  The
compiled kernel only finds the adversarial points quickly; the values asserted against
the bound are recomputed by those references.
"""

from __future__ import annotations

import itertools
import math
from functools import cache

import mpmath as mp
import numpy as np
import pytest
from mp_reference import mp_sup
from scipy.optimize import minimize

from gfrf.bounds.branch_bound import branch_and_bound
from gfrf.bounds.majorant import majorant
from gfrf.bounds.tail import tail_bound
from gfrf.kernels.combinatorics import compositions
from gfrf.kernels.probing import probe_kernel
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import Model, parse_model
from gfrf.model.modelfile import load_model

CARTPOLE = "models/cartpole.toml"
MODELS = {
    "cartpole": CARTPOLE,
    "hanging": "models/hanging_pendulum.toml",
    "duffing": "models/duffing.toml",
    # the cart-pole's non-decaying factor alone: s^2 H1 of relative degree 0
    "y2_ddy": "D(y,2) + 0.2*D(y) + y + 0.3*y**2*D(y,2) = u",
    # an input slot (|u| = 1, no decay) next to two output slots
    "u_y2": "D(y,2) + 0.2*D(y) + y + 0.5*y**2*u = u",
    # H1 of relative degree 1 and two s H1 slots (relative degree 0)
    "reldeg1": "D(y,2) + 0.5*D(y) + 2*y + 0.3*y**3 - 0.2*y*D(y)**2 = D(u) + u",
    # first-order A: 1/A decays like 1/W only; an input slot in a quadratic term
    "first_order": "D(y) + 0.5*y + 0.4*y**2 - 0.2*y*u = u",
    # two non-decaying s^2 H1 slots in one term: H3 has a tail that does not decay
    "two_ddy": "D(y,2) + 0.3*D(y) + y + 0.1*y*D(y,2)**2 + 0.2*y**2 = u",
    # a pure input term: H2 = -0.3 / A(s1 + s2) does not decay when w2 = -w1
    "u_squared": "D(y,2) + 0.2*D(y) + y + 0.3*u**2 + 0.2*y**3 = u",
}


def load(name: str) -> Model:
    text = MODELS[name]
    return load_model(text).plant if text.endswith(".toml") else parse_model(text)


def mp_asymmetric(model: Model, omegas: list[float], digits: int = 30) -> float:
    """|H_n| of the asymmetric kernel by the recursion, in mpmath (contiguous blocks in
    the order of the sorted output factors, input factors on the last coordinates)."""
    with mp.workdps(digits):
        s = [mp.mpc(0, w) for w in omegas]
        a = model.linear_output
        b = model.linear_input

        def poly(c: dict[int, float], x: mp.mpc) -> mp.mpc:
            return mp.fsum(mp.mpf(v) * x ** k for k, v in c.items())

        @cache
        def h(lo: int, hi: int) -> mp.mpc:
            sigma = mp.fsum(s[lo:hi])
            if hi - lo == 1:
                return -poly(b, sigma) / poly(a, sigma)
            total = mp.mpc(0)
            for t in model.nonlinear_terms:
                p, q = len(t.y_orders), len(t.u_orders)
                rest = hi - lo - q
                for sizes in compositions(rest, p) if p or rest == 0 else ():
                    value = mp.mpf(t.coefficient)
                    start = lo
                    for size, ell in zip(sizes, t.y_orders, strict=True):
                        value *= h(start, start + size) * mp.fsum(s[start:start + size]) ** ell
                        start += size
                    for k, order in enumerate(t.u_orders):
                        value *= s[hi - q + k] ** order
                    total += value
            return -total / poly(a, sigma)

        return float(abs(h(0, len(omegas))))


def independent(model: Model, w: np.ndarray, symmetric: bool) -> float:
    """|H_n(w)| by probing (symmetric) or by the mpmath recursion (asymmetric)."""
    if symmetric:
        return abs(probe_kernel(model, [float(x) for x in w]))
    return mp_asymmetric(model, [float(x) for x in w])


def adversarial_points(n: int, width: float, rng: np.random.Generator) -> np.ndarray:
    """Points with some |w_i| >= width, shape (n, N): the families of the module docstring."""
    families = []
    k = 4000
    for scale in (0.5, 2.0, 0.1 * width, width, 10 * width):  # random, one coordinate large
        w = rng.standard_normal((n, k)) * scale
        i = rng.integers(0, n, k)
        beyond = rng.exponential(0.2, k) * (rng.uniform(size=k) < 0.5)
        big = rng.choice([-1.0, 1.0], k) * width * (1 + beyond)
        w[i, np.arange(k)] = big
        # a second large coordinate cancelling the first (block sums stay small)
        j = (i + rng.integers(1, n, k)) % n
        cancel = rng.uniform(size=k) < 0.6
        small = rng.choice([1e-3, 0.3, 2.0], k) * rng.standard_normal(k)
        w[j[cancel], np.arange(k)[cancel]] = -big[cancel] + small[cancel]
        families.append(w)
    if n >= 4:  # w_3 = W, w_4 = -W + small, the others small
        w = rng.uniform(-2, 2, (n, k))
        w[2] = width * (1 + 1e-9)
        w[3] = -width + rng.uniform(-3, 3, k)
        families.append(w)
    w = rng.uniform(-width, width, (n, k))  # just outside the box
    w[rng.integers(0, n, k), np.arange(k)] = width * (1 + 1e-9) * rng.choice([-1.0, 1.0], k)
    families.append(w)
    return np.hstack(families)


def outside(x: np.ndarray, width: float) -> np.ndarray:
    """x scaled up, if needed, so that its largest |coordinate| is at least ``width``."""
    big = float(np.max(np.abs(x)))
    return x if big >= width else x * (width / big * (1 + 1e-12))


def far_sup(model: Model, n: int, width: float, symmetric: bool, seed: int,
            polish: int = 3) -> float:
    """Largest |H_n| found outside the box (dense sampling, then Nelder-Mead polishing of
    the ``polish`` best points), each candidate re-evaluated independently."""
    k = kernel(model, n, symmetric)
    rng = np.random.default_rng(seed)
    w = adversarial_points(n, width, rng)
    values = np.abs(k(*w))
    best = 0.0
    for t in np.argsort(values)[::-1][:polish]:

        def objective(x: np.ndarray) -> float:
            return -abs(complex(k(*outside(x, width))))

        res = minimize(objective, w[:, t], method="Nelder-Mead",
                       options={"maxiter": 1500, "xatol": 1e-10, "fatol": 1e-18})
        for x in (w[:, t], outside(res.x, width)):
            x = outside(x + rng.uniform(-1e-9, 1e-9, n) * (1 + np.abs(x)), width)  # generic
            assert np.max(np.abs(x)) >= width
            ref = independent(model, x, symmetric)
            assert ref == pytest.approx(abs(complex(k(*x))), rel=1e-8)
            best = max(best, ref)
    return best


@pytest.mark.parametrize(("name", "n", "symmetric"), [
    ("cartpole", 3, True), ("cartpole", 5, False), ("hanging", 3, False),
    ("y2_ddy", 3, False), ("u_y2", 3, False), ("reldeg1", 3, False),
    ("first_order", 2, False), ("two_ddy", 3, False), ("u_squared", 2, True),
    ("u_squared", 4, False)])
@pytest.mark.parametrize("width", [3.0, 40.0])
def test_tail_bound_encloses_far_points(name: str, n: int, symmetric: bool,
                                        width: float) -> None:
    """The best sampled far point is polished (the slow order-5 test polishes three)."""
    m = load(name)
    bound = tail_bound(m, n, width)
    found = far_sup(m, n, width, symmetric, seed=n + int(width), polish=1)
    assert 0 < found <= bound * (1 + 1e-12)
    assert bound <= majorant(m).coefficients(n)[n, 0] * (1 + 1e-12)


@pytest.mark.slow
@pytest.mark.parametrize(("name", "n"), [
    ("cartpole", 5), ("hanging", 5), ("duffing", 5), ("y2_ddy", 5), ("u_y2", 5),
    ("reldeg1", 5), ("first_order", 4), ("two_ddy", 4), ("u_squared", 5)])
@pytest.mark.parametrize("symmetric", [True, False])
@pytest.mark.parametrize("width", [3.0, 30.0, 300.0])
def test_tail_bound_encloses_far_points_order_5(name: str, n: int, symmetric: bool,
                                                width: float) -> None:
    m = load(name)
    found = far_sup(m, n, width, symmetric, seed=11 * n + int(width))
    assert found <= tail_bound(m, n, width) * (1 + 1e-12)


def test_asymmetric_reference_is_the_kernel() -> None:
    """The mpmath recursion and probing evaluate the kernels the bound is about."""
    m = load("cartpole")
    rng = np.random.default_rng(1)
    for w in rng.uniform(-20, 20, (4, 5)):
        assert mp_asymmetric(m, list(w)) == pytest.approx(abs(complex(kernel(m, 5, False)(*w))),
                                                          rel=1e-10)
        assert abs(probe_kernel(m, list(w))) == pytest.approx(abs(complex(kernel(m, 5)(*w))),
                                                              rel=1e-10)


def test_two_large_coordinates_in_the_non_decaying_slots() -> None:
    """y D(y,2)^2: w2 = V, w3 = -V + x, w1 = x0 gives |H3| -> 0.1 |H1(x0)| / |A(x0 + x)|
    for the asymmetric kernel (both s^2 H1 factors tend to 1): no decay, and the
    bound must not decay either."""
    m = load("two_ddy")
    peak_h1 = float(mp_sup([1.0], [1.0, 0.3, 1.0]))  # sup |H1| = sup |1/A|
    limit = 0.1 * peak_h1 ** 2
    for width in (1e2, 1e4):
        assert limit < tail_bound(m, 3, width) <= limit * 1.001


def test_pure_input_term_does_not_decay() -> None:
    """0.3 u^2: H2 = -0.3 / A(j(w1 + w2)) equals 0.3 sup|1/A| at w2 = -w1 + w_peak,
    however large w1 is."""
    m = load("u_squared")
    ref = 0.3 * float(mp_sup([1.0], [1.0, 0.2, 1.0]))
    for width in (10.0, 1e3, 1e5):
        assert ref <= tail_bound(m, 2, width) * (1 + 1e-12)


def cartpole_h5_near_zero() -> float:
    """|H5| at a generic point near w = 0 by probing (||H5|| >= this, ~0.01114)."""
    return abs(probe_kernel(load("cartpole"), [1.1e-4, -2.3e-4, 3.7e-4, 0.5e-4, -1.9e-4]))


def test_cartpole_tail_decays_below_half_the_norm() -> None:
    """The former recursion floored at 0.041 (> ||H5|| >= 0.0111): the theta^2 theta''
    slot s^2 H1 does not decay.  Sampling gives sup |H5| beyond W of about 0.0107 at
    W = 10 and 2.6e-5 at W = 300 (a 1/W^2 decay); the bound must fall below half the
    norm's lower value (what the branch-and-bound needs) at a finite W, and keep
    decaying like 1/W^2."""
    m = load("cartpole")
    lower = cartpole_h5_near_zero()
    assert 0.0111 < lower < 0.0112
    maj = majorant(m)
    assert tail_bound(m, 5, 1e3, maj) < 0.5 * lower
    assert tail_bound(m, 5, 1e4, maj) < 0.02 * tail_bound(m, 5, 1e3, maj)
    assert tail_bound(m, 5, 1e6, maj) < 1e-8


def test_cartpole_tail_bound_vs_sampled_far_sup() -> None:
    """The bound at W = 30 encloses the sampled sup beyond 30 and is below the old floor."""
    m = load("cartpole")
    found = far_sup(m, 5, 30.0, True, seed=4)
    bound = tail_bound(m, 5, 30.0)
    assert found <= bound < majorant(m).coefficients(5)[5, 0]


def test_cartpole_bracket_is_no_longer_floored() -> None:
    """The branch-and-bound's tail is now below its lower end (it used to be its floor)."""
    m = load("cartpole")
    r = branch_and_bound(m, 5, max_boxes=1000)
    assert r.tail < 0.5 * r.lower <= r.upper
    assert r.lower == pytest.approx(cartpole_h5_near_zero(), rel=1e-4)


def test_tail_bound_is_cheap_and_monotone_in_practice() -> None:
    """The bound never exceeds the majorant and shrinks as W doubles (cart-pole, H5)."""
    m = load("cartpole")
    maj = majorant(m)
    values = [tail_bound(m, 5, 20.0 * 2 ** k, maj) for k in range(10)]
    assert values[0] <= maj.coefficients(5)[5, 0]
    assert all(b <= a for a, b in itertools.pairwise(values))
    assert math.isfinite(values[-1]) and values[-1] > 0
