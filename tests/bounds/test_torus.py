"""Branch-and-bound of NARX kernels over the torus: sound box bounds, tight brackets.

References are independent of the code under test: derivatives of 1/A by mpmath's
numerical differentiation at 30 digits, kernel values from the explicit sympy form of
H_n (lower orders inlined, lambdified), a dense grid polished by scipy's Nelder-Mead and
re-evaluated in mpmath.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
import sympy as sp
from scipy.optimize import minimize

from gfrf.bounds.branch_bound import _longest, box_bounds, branch_and_bound
from gfrf.bounds.majorant import linear_polynomials, majorant
from gfrf.bounds.norms import kernel_norm
from gfrf.bounds.torus import InverseTrig
from gfrf.kernels.recursion import kernel
from gfrf.model.modelfile import load_model, resolve_model


def _explicit(model, n: int):
    """|H_n| at angular frequencies from the explicit sympy expression (numpy and mpmath)."""
    k = kernel(model, n)
    expr, qs = k.expr, k.variables
    t = model.sample_time
    f = sp.lambdify(qs, expr, modules="numpy")
    g = sp.lambdify(qs, expr, modules="mpmath")

    def numeric(*w: np.ndarray) -> np.ndarray:
        return np.abs(f(*(np.exp(-1j * t * np.asarray(x)) for x in w)))

    def precise(w: np.ndarray) -> float:
        with mpmath.workdps(30):
            return float(abs(g(*(mpmath.exp(-1j * mpmath.mpf(float(x)) * mpmath.mpf(t))
                                 for x in w))))

    return numeric, precise


def test_inverse_bounds_contain_mpmath_derivatives() -> None:
    model = load_model("models/identified_example.toml").plant
    _, den = linear_polynomials(model)
    t = model.sample_time
    inverse = InverseTrig(den, t, 0.0)
    rng = np.random.default_rng(3)
    centres = rng.uniform(-3 * math.pi / t, 3 * math.pi / t, 16)  # sums of frequencies
    radii = rng.choice([1e-3, 0.05, 0.5, 3.0, 20.0, 40.0], 16)
    sups = inverse.bounds(centres - radii, centres + radii)
    msups = inverse.modulus_bounds(centres - radii, centres + radii)

    def r(s: mpmath.mpf) -> mpmath.mpc:
        z = mpmath.exp(-1j * s * t)
        return 1 / sum(float(c) * z ** k for k, c in enumerate(den))

    with mpmath.workdps(30):
        for c, rad, sup, msup in zip(centres, radii, sups, msups, strict=True):
            for s in np.linspace(c - rad, c + rad, 7):
                for k in range(4):
                    assert abs(mpmath.diff(r, mpmath.mpf(s), k)) <= sup[k] * (1 + 1e-9)
                    assert abs(mpmath.diff(lambda x: abs(r(x)), mpmath.mpf(s), k)) \
                        <= msup[k] * (1 + 1e-9)


def test_tabulated_sups_are_tighter_on_wide_intervals() -> None:
    """The table of sups beats the Taylor bounds where a block's sum spans a wide interval."""
    model = load_model("models/identified_example.toml").plant
    _, den = linear_polynomials(model)
    t = model.sample_time
    inverse = InverseTrig(den, t, 0.0)
    centres = np.linspace(-math.pi / t, math.pi / t, 9)
    lo, hi = centres - 4.0, centres + 4.0
    assert np.all(inverse.bounds(lo, hi)[:, 3] < 0.5 * inverse._taylor_bounds(lo, hi)[:, 3])


@pytest.mark.parametrize("name", ["identified_example", "narx_example"])
def test_series_sups_of_short_intervals_contain_mpmath_derivatives(name: str) -> None:
    """The cell bounds from Taylor series with Cauchy's remainder hold (mpmath's numerical
    derivatives of 1/A and 1/|A| at 30 digits) and are within 5 % of them, where the
    quotient-rule bound of the third derivative of 1/|A| is several times larger."""
    model = load_model(f"models/{name}.toml").plant
    _, den = linear_polynomials(model)
    t = model.sample_time
    peak = 1 / min(abs(sum(float(c) * np.exp(-1j * k * x) for k, c in enumerate(den)))
                   for x in np.linspace(-math.pi, math.pi, 20001))
    inverse = InverseTrig(den, t, 0.999 / peak)  # a floor below the sampled min |A|
    rng = np.random.default_rng(7)
    centres = rng.uniform(-math.pi / t, math.pi / t, 6)
    half = math.pi / t / 4096
    lo, hi = centres - half, centres + half

    def r(s: mpmath.mpf) -> mpmath.mpc:
        z = mpmath.exp(-1j * s * t)
        return 1 / sum(float(c) * z ** k for k, c in enumerate(den))

    functions = (r, lambda x: abs(r(x)))
    with mpmath.workdps(30):
        for kind, f in enumerate(functions):
            sups = inverse._series_bounds(lo, hi, kind)
            for a, b, sup in zip(lo, hi, sups, strict=True):
                truth = [max(abs(mpmath.diff(f, mpmath.mpf(float(s)), k))
                             for s in np.linspace(a, b, 5)) for k in range(4)]
                for k in range(4):
                    assert truth[k] <= sup[k] * (1 + 1e-12)
                    assert sup[k] <= 1.05 * truth[k]
    loose = inverse._taylor_modulus_bounds(lo, hi)[:, 3] / inverse._series_bounds(lo, hi, 1)[:, 3]
    assert np.median(loose) > 2


@pytest.mark.parametrize("radius", [0.02, 0.3, 2.0])
def test_box_bounds_contain_sampled_values(radius: float) -> None:
    model = load_model("models/identified_example_true.toml").plant
    numeric, _ = _explicit(model, 3)
    t = model.sample_time
    rng = np.random.default_rng(5)
    centres = rng.uniform(-math.pi / t, math.pi / t, (40, 3))
    lo, hi = centres - radius, centres + radius
    bound, centre_value, _ = box_bounds(model, 3, lo, hi)
    assert np.allclose(centre_value, numeric(*centres.T), rtol=1e-9)
    for _ in range(20):
        x = rng.uniform(lo, hi)
        assert np.all(numeric(*x.T) <= bound * (1 + 1e-12))
    if radius <= 0.02:  # Taylor enclosure: tight on small boxes (against the vertices)
        corners = np.array(np.meshgrid(*([[-1.0, 1.0]] * 3), indexing="ij")).reshape(3, -1)
        top = np.max([numeric(*(centres + radius * c).T) for c in corners.T], axis=0)
        assert np.all(bound <= 1.001 * np.maximum(top, centre_value))


def _grid_sup(model, n: int, points: int) -> tuple[float, np.ndarray]:
    """Dense grid over the torus, best point polished by Nelder-Mead (explicit form)."""
    numeric, precise = _explicit(model, n)
    t = model.sample_time
    axis = np.linspace(-math.pi / t, math.pi / t, points, endpoint=False)
    grid = np.meshgrid(*([axis] * n), indexing="ij")
    values = numeric(*grid)
    start = np.array([g.flat[int(np.argmax(values))] for g in grid])
    res = minimize(lambda x: -float(numeric(*x)), start, method="Nelder-Mead",
                   options={"xatol": 1e-10, "fatol": 1e-15, "maxiter": 4000})
    return precise(res.x), res.x


@pytest.mark.parametrize("name", ["identified_example_true",
                                  pytest.param("identified_example", marks=pytest.mark.slow)])
def test_narx_h3_bracket_is_tight_and_contains_the_grid_sup(name: str) -> None:
    model = load_model(f"models/{name}.toml").plant
    b = kernel_norm(model, 3)
    value, _ = _grid_sup(model, 3, 72)
    assert b.upper_proof == "float" and b.lower_proof == "interval"
    assert b.gap <= 1e-3
    assert b.lower <= value * (1 + 1e-9) and value <= b.upper * (1 + 1e-12)
    assert b.upper - value <= 1e-3 * b.upper  # the sup is found by both


def test_narx_h2_bracket_contains_the_closed_form_sup() -> None:
    # y[k] = a y[k-1] + u[k-1] + c1 y[k-1]^2 + c2 u[k-1]^2: with A(q) = 1 - a q,
    # H1(q) = q / A(q) and H2 = q1 q2 (c1 H1(q1) H1(q2) + c2) / A(q1 q2) (q = e^{-j w T});
    # c1 and c2 of opposite signs cancel, so the majorant is not attained
    a, c1, c2, t = 0.6, 0.3, -0.5, 0.1
    model = resolve_model(f"y[k] = {a}*y[k-1] + u[k-1] + {c1}*y[k-1]**2 + {c2}*u[k-1]**2",
                          sample_time=t).plant

    def closed(th1: np.ndarray, th2: np.ndarray) -> np.ndarray:
        q1, q2 = np.exp(-1j * th1), np.exp(-1j * th2)
        h1, h2 = q1 / (1 - a * q1), q2 / (1 - a * q2)
        return np.abs(q1 * q2 * (c1 * h1 * h2 + c2) / (1 - a * q1 * q2))

    axis = np.linspace(-math.pi, math.pi, 801)
    g1, g2 = np.meshgrid(axis, axis, indexing="ij")
    values = closed(g1, g2)
    start = np.array([g1.flat[int(np.argmax(values))], g2.flat[int(np.argmax(values))]])
    res = minimize(lambda x: -float(closed(x[0], x[1])), start, method="Nelder-Mead",
                   options={"xatol": 1e-12, "fatol": 1e-15})
    sup = max(float(values.max()), -float(res.fun))
    b = kernel_norm(model, 2)
    assert b.upper < 0.999 * float(majorant(model).coefficients(2)[2, 0])  # B&B lowered it
    assert b.lower <= sup * (1 + 1e-12) and sup <= b.upper * (1 + 1e-12)
    assert b.gap <= 1e-3


@pytest.fixture(scope="module")
def h5_peak():
    """The identified example's H5, its explicit form and a maximiser of |H5| (dense random
    sample of the torus polished by scipy's Nelder-Mead, all on the explicit form)."""
    model = load_model("models/identified_example.toml").plant
    numeric, _ = _explicit(model, 5)
    t = model.sample_time
    rng = np.random.default_rng(11)
    points = rng.uniform(-math.pi / t, math.pi / t, (30_000, 5))
    start = points[int(np.argmax(numeric(*points.T)))]
    res = minimize(lambda x: -float(numeric(*x)), start, method="Nelder-Mead",
                   options={"xatol": 1e-9, "fatol": 1e-15, "maxiter": 2000})
    return model, numeric, res.x, -res.fun


@pytest.mark.parametrize("radius", [0.05, 0.5, 3.0])
def test_h5_box_bounds_contain_sampled_values(h5_peak, radius: float) -> None:
    model, numeric, peak, _ = h5_peak
    t = model.sample_time
    rng = np.random.default_rng(12)
    centres = np.vstack([peak + rng.uniform(-0.5, 0.5, (10, 5)),
                         rng.uniform(-math.pi / t, math.pi / t, (20, 5))])
    lo, hi = centres - radius, centres + radius
    bound, centre_value, _ = box_bounds(model, 5, lo, hi)
    assert np.allclose(centre_value, numeric(*centres.T), rtol=1e-9)
    x = rng.uniform(lo, hi, (40, 30, 5))  # 40 points per box, one vectorised call
    x[:, :, :2] = np.where(rng.uniform(size=(40, 30, 2)) < 0.5, lo[:, :2], hi[:, :2])
    assert np.all(numeric(*x.reshape(-1, 5).T).reshape(40, 30) <= bound * (1 + 1e-12))


def test_h5_box_bound_is_tight_around_the_peak(h5_peak) -> None:
    """A box of side 2 pi / 128 in every theta = w T around the maximiser is bounded
    within 2 % of the largest sampled |H5| in it (quadratic Taylor models with their
    remainders)."""
    model, numeric, peak, value = h5_peak
    half = math.pi / 128 / model.sample_time
    bound, _, _ = box_bounds(model, 5, (peak - half)[None], (peak + half)[None])
    rng = np.random.default_rng(13)
    inside = max(value, float(numeric(*rng.uniform(peak - half, peak + half, (2000, 5)).T)
                              .max()))
    assert inside <= bound[0] <= 1.02 * inside


def test_h5_bracket_of_a_short_search_contains_the_random_search_sup(h5_peak) -> None:
    """A budget-limited H5 search (open gap) still brackets the sup that dense random
    sampling polished by scipy's Nelder-Mead finds on the explicit form."""
    model, numeric, peak, value = h5_peak
    r = branch_and_bound(model, 5, tol=1e-3, max_boxes=1500)
    assert r.lower <= value * (1 + 1e-9) and value <= r.upper * (1 + 1e-12)
    assert numeric(*np.array(r.argmax)[:, None])[0] == pytest.approx(r.lower, rel=1e-9)


@pytest.mark.slow
def test_h5_search_closes_to_1e3_and_brackets_the_random_search_sup(h5_peak) -> None:
    """Given the work (60,000 boxes, about 20 s), the H5 search closes the gap to 1e-3
    around the sup that dense random sampling polished by scipy's Nelder-Mead finds."""
    model, numeric, peak, value = h5_peak
    r = branch_and_bound(model, 5, tol=1e-3, max_boxes=60_000)
    assert r.converged and r.upper - r.lower <= 1e-3 * r.upper
    assert r.lower <= value * (1 + 1e-9) and value <= r.upper * (1 + 1e-12)


def test_upper_end_never_rises_with_more_boxes() -> None:
    """A child's bound is at most its parent's, so a longer search (which passes through
    the shorter one's state) ends with an upper end no higher."""
    model = load_model("models/identified_example_true.toml").plant
    uppers = [branch_and_bound(model, 3, tol=1e-12, max_boxes=b).upper
              for b in (200, 600, 1800)]
    assert uppers[0] >= uppers[1] >= uppers[2]


def test_coarse_torus_boxes_are_halved_along_a_longest_side() -> None:
    side = np.array([[0.4, 0.8, 0.8], [0.4, 0.8, 0.8], [0.1, 0.05, 0.05], [0.3, 0.1, 0.1]])
    preferred = np.array([0, 2, 1, 1])
    # coarse boxes: a longest side, the preferred one where it is longest; fine boxes keep
    # the preferred axis
    assert _longest(side, preferred, 0.2).tolist() == [1, 2, 1, 0]


def test_narx_h3_bracket_contains_the_closed_form_norm_at_the_torus_corner() -> None:
    # y[k] = a y[k-1] + u[k-1] + c y[k-1]^3 with a < 0: H1(q) = q / (1 - a q) and
    # H3 = c q1 q2 q3 H1(q1) H1(q2) H1(q3) / (1 - a q1 q2 q3); every factor's modulus
    # peaks at q = -1 (w = pi / T), and q1 = q2 = q3 = -1 gives q1 q2 q3 = -1 too, so
    # ||H3|| = |c| / (1 - |a|)^4, attained at the corner (pi/T, pi/T, pi/T) of the torus
    a, c, t = -0.6, 0.2, 0.1
    model = resolve_model(f"y[k] = {a}*y[k-1] + u[k-1] + {c}*y[k-1]**3",
                          sample_time=t).plant
    exact = abs(c) / (1 - abs(a)) ** 4
    b = kernel_norm(model, 3)
    assert b.lower <= exact * (1 + 1e-12) and exact <= b.upper * (1 + 1e-12)
    assert b.gap <= 1e-3
