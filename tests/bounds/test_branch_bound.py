"""Tests of gfrf.bounds.branch_bound: soundness of the box and tail bounds, and closed gaps."""

from __future__ import annotations

import math

import numpy as np
import pytest
from mp_reference import mp_sup
from scipy.optimize import minimize

from gfrf.bounds.branch_bound import box_bounds, branch_and_bound
from gfrf.bounds.majorant import majorant
from gfrf.bounds.tail import tail_bound
from gfrf.errors import ArgumentError
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model

QUADRATIC = "D(y,2) + 0.2*D(y) + y + 0.4*y**2 = u"
MIXED = "D(y,2) + 0.3*D(y) + 1.5*y + 0.4*y**2 - 0.2*y**3 + 0.1*y*u = u"
CARTPOLE = "models/cartpole.toml"


def quadratic_h2(w: np.ndarray) -> np.ndarray:
    """H2 of QUADRATIC by hand: -0.4 H1(w1) H1(w2) / A(w1 + w2), H1 = 1/A."""

    def a(x: np.ndarray) -> np.ndarray:
        return 1.0 - x * x + 0.2j * x

    return -0.4 / (a(w[0]) * a(w[1]) * a(w[0] + w[1]))


def true_quadratic_max() -> float:
    """Fine grid on [-3, 3]^2 then Nelder-Mead polishing of the best points."""
    axis = np.linspace(-3.0, 3.0, 1201)
    w1, w2 = np.meshgrid(axis, axis, indexing="ij")
    values = np.abs(quadratic_h2(np.array([w1, w2])))
    best = 0.0
    for k in np.argsort(values, axis=None)[::-1][:8]:
        x0 = np.array([w1.flat[k], w2.flat[k]])
        res = minimize(lambda x: -abs(quadratic_h2(x)), x0, method="Nelder-Mead",
                       options={"xatol": 1e-13, "fatol": 1e-15, "maxiter": 4000})
        best = max(best, -float(res.fun))
    return best


@pytest.mark.parametrize(("text", "n", "symmetric"), [
    (QUADRATIC, 2, True), (MIXED, 3, True), (MIXED, 3, False),
    ("D(y,2) + 0.5*D(y) + 2*y + 0.3*y*D(y)**2 + 0.2*y**2*D(y,2) - 0.5*y**2*u = u", 3, True)])
def test_box_bounds_enclose_every_sampled_point(text: str, n: int, symmetric: bool) -> None:
    m = parse_model(text)
    rng = np.random.default_rng(7)
    centre = rng.uniform(-3, 3, (300, n))
    half = 10.0 ** rng.uniform(-4, 0.5, (300, 1)) * rng.uniform(0.2, 1.0, (300, n))
    lo, hi = centre - half, centre + half
    bound, value, _ = box_bounds(m, n, lo, hi, symmetric)
    k = kernel(m, n, symmetric)
    assert np.allclose(value, np.abs(k(*centre.T)), rtol=1e-12, atol=0)
    for _ in range(20):
        points = lo + rng.uniform(0, 1, lo.shape) * (hi - lo)
        points[:5] = np.where(rng.uniform(size=(5, n)) < 0.5, lo[:5], hi[:5])  # corners
        assert np.all(np.abs(k(*points.T)) <= bound * (1 + 1e-12))


@pytest.mark.parametrize(("text", "n", "width"), [
    ("models/cartpole.toml", 3, 20.0), (QUADRATIC, 4, 8.0), (MIXED, 3, 10.0),
    ("models/cartpole.toml", 5, 30.0)])
def test_tail_bound_encloses_far_points(text: str, n: int, width: float) -> None:
    m = load_model(text).plant if text.endswith(".toml") else parse_model(text)
    k = kernel(m, n)
    rng = np.random.default_rng(3)
    w = rng.uniform(-6 * width, 6 * width, (n, 100000))
    w[0] = np.where(np.abs(w[0]) > width, w[0], width + rng.uniform(0, 1, w.shape[1]))
    # the worst far points: two large coordinates that (nearly) cancel in the sum
    w[1, :20000] = -w[0, :20000] + rng.uniform(-2, 2, 20000)
    w[2:, :10000] = rng.uniform(-3, 3, (n - 2, 10000))
    bound = tail_bound(m, n, width)
    assert np.max(np.abs(k(*w))) <= bound <= majorant(m).coefficients(n)[n, 0] * (1 + 1e-12)


def test_tail_decays_for_relative_degree_two() -> None:
    # eq (16) has no derivative factors: every factor decays like 1/W^2
    m = load_model("models/cartpole_reduced.toml").plant
    assert tail_bound(m, 3, 320.0) < 0.1 * tail_bound(m, 3, 40.0)


def test_quadratic_oscillator_gap_below_tol() -> None:
    exact = true_quadratic_max()
    m = parse_model(QUADRATIC)
    r = branch_and_bound(m, 2, tol=1e-7)
    assert r.converged and r.upper - r.lower <= 1e-7 * r.upper
    assert r.lower <= exact * (1 + 1e-12) <= r.upper * (1 + 1e-12)
    assert r.lower == pytest.approx(exact, rel=1e-9)
    assert r.upper < 0.25 * majorant(m).coefficients(2)[2, 0]  # the majorant is 5x loose


@pytest.mark.parametrize(("path", "n"), [(CARTPOLE, 3), ("models/cartpole_reduced.toml", 3)])
def test_cartpole_bracket_contains_grid_and_random_max(path: str, n: int) -> None:
    m = load_model(path).plant
    r = branch_and_bound(m, n)
    assert r.converged and r.upper - r.lower <= 1e-6 * r.upper
    k = kernel(m, n)
    axis = np.linspace(-12, 12, 97)
    grid = np.abs(k(*np.meshgrid(axis, axis, axis, indexing="ij"))).max()
    sample = np.abs(k(*np.random.default_rng(5).uniform(-30, 30, (n, 200000)))).max()
    assert max(grid, sample) <= r.upper
    assert abs(k(*r.argmax)) == pytest.approx(r.lower, rel=1e-12)


def test_mixed_model_bracket_against_local_search() -> None:
    m = parse_model(MIXED)
    k = kernel(m, 3)
    r = branch_and_bound(m, 3)
    assert r.converged
    rng = np.random.default_rng(2)
    points = rng.uniform(-4, 4, (3, 100000))
    values = np.abs(k(*points))
    assert values.max() <= r.upper
    x0 = points[:, int(np.argmax(values))]
    res = minimize(lambda x: -abs(complex(k(*x))), x0, method="Nelder-Mead",
                   options={"xatol": 1e-12, "fatol": 1e-15, "maxiter": 3000})
    assert -res.fun <= r.upper and r.lower >= -res.fun * (1 - 1e-6)


def test_budget_exhausted_gives_honest_bracket() -> None:
    m = load_model("models/hanging_pendulum.toml").plant
    r = branch_and_bound(m, 5, max_boxes=3000)
    assert not r.converged and r.lower < r.upper
    # the upper end is capped by the majorant: never looser, equal when the budget is tiny
    assert r.upper <= majorant(m).coefficients(5)[5, 0]
    assert abs(complex(kernel(m, 5)(*r.argmax))) == pytest.approx(r.lower, rel=1e-12)
    assert math.isfinite(r.tail) and r.tail < r.lower


def test_refusals() -> None:
    with pytest.raises(ArgumentError):
        branch_and_bound(parse_model(QUADRATIC), 6)
    with pytest.raises(ArgumentError):
        branch_and_bound(load_model("models/narx_example.toml").plant, 6)


# -- the tail bound on clustered poles ---------------------------------------------------
CLUSTER_DEN = [1.0, 6e-06, 3.000000000012, 1.2000000000008e-05, 3.000000000012, 6e-06, 1.0]


def mp_sup_beyond(num: list[float], den: list[float], v: float) -> float:
    """sup over |w| >= v of |N(jw)/D(jw)| at 50 digits (mpmath; independent of FLINT)."""
    return float(mp_sup(num, den, v, digits=50))


@pytest.mark.parametrize("v", [0.0, 0.5, 0.999, 1.5, 40.0])
def test_beyond_is_proven_on_a_pole_cluster(v: float) -> None:
    """(s^2 + 2e-6 s + 1)^3 with float coefficients: the old numpy-root tail gave 2.9e10
    where the sup is 1.25e17; the bound must be >= the 50-digit value and tight."""
    from gfrf.bounds.tail import _Beyond

    ref = mp_sup_beyond([1.0], CLUSTER_DEN, v)
    got = _Beyond(np.array([1.0]), np.array(CLUSTER_DEN)).sup(v)
    assert ref <= got <= ref * (1 + 1e-12)
    if v < 0.999:
        assert ref > 1e17


def test_beyond_with_numerator_power() -> None:
    """sup|s^2 / D| beyond v (the ell = 2 factors of the tail recursion)."""
    from gfrf.bounds.tail import _Beyond

    num = [1.0, 0.0, 0.0]
    beyond = _Beyond(np.array(num), np.array(CLUSTER_DEN))
    for v in (0.0, 1.2, 7.0):
        ref = mp_sup_beyond(num, CLUSTER_DEN, v)
        assert ref <= beyond.sup(v) <= ref * (1 + 1e-12)


def test_box_modulus_bounds_are_sound_on_a_pole_cluster() -> None:
    """The box bounds' sup |1/A| over an interval holding the cluster is >= the 50-digit
    sup (float critical points of |A|^2 gave 1/3.4e-11 = 2.9e10 for 1.25e17)."""
    from gfrf.bounds.inverse import InverseA

    ref = mp_sup_beyond([1.0], CLUSTER_DEN, 0.0)  # sup over R of 1/|A|, attained near 1
    inverse = InverseA(np.array(CLUSTER_DEN))
    for lo, hi in ((0.99, 1.01), (-1.01, -0.99), (0.5, 1.5)):
        m0 = inverse.bounds(np.array([lo]), np.array([hi]))[:, 0]
        assert ref <= m0[0] <= 1.01 * ref
    # centre values where |A| is below its rounding error are not used (NaN)
    sigma = np.array([0.9999990000005, 2.0])
    value, _, _ = inverse.point(sigma, inverse.centre_error(sigma, np.zeros(2), np.zeros(2)))
    assert np.isnan(value[0]) and np.isfinite(value[1])


def test_domain_keeps_interior_boxes_and_drops_face_only_boxes() -> None:
    from gfrf.bounds.branch_bound import _in_domain

    rng = np.random.default_rng(3)
    n = 4
    lo = rng.uniform(-2, 2, (4000, n))
    hi = lo + rng.uniform(0.01, 1.5, (4000, n))
    kept = _in_domain(lo, hi, True)
    # a box holding a random point of the open domain (sorted, positive sum) is kept
    for k in range(lo.shape[0]):
        points = np.sort(rng.uniform(lo[k], hi[k], (200, n)), axis=1)[:, ::-1]
        strict = np.all(np.diff(points, axis=1) < 0, axis=1) & (points.sum(axis=1) > 0)
        inside = np.all((points >= lo[k]) & (points <= hi[k]), axis=1)
        if np.any(strict & inside):
            assert kept[k]
    # [a, b] x [b, c]: only the face w_1 = w_2 = b is sorted, so it is dropped, and its
    # mirror [b, c] x [a, b] (wholly sorted) is kept
    face = _in_domain(np.array([[0.0, 1.0]]), np.array([[1.0, 2.0]]), True)
    mirror = _in_domain(np.array([[1.0, 0.0]]), np.array([[2.0, 1.0]]), True)
    assert not face[0] and mirror[0]
    assert not _in_domain(np.array([[-2.0, -1.0]]), np.array([[0.0, 0.0]]), False)[0]


def test_progress_bar_reports_boxes_and_changes_nothing(capsys: pytest.CaptureFixture) -> None:
    m = parse_model(QUADRATIC)
    quiet = branch_and_bound(m, 2, max_boxes=3000)
    assert capsys.readouterr().err == ""
    shown = branch_and_bound(m, 2, max_boxes=3000, progress=True)
    err = capsys.readouterr().err
    assert "||H2|| bracket" in err and "box" in err
    assert shown == quiet


def test_a_long_search_keeps_no_box_batch_alive() -> None:
    """Memory stays bounded by the open boxes however many boxes a search evaluates: with
    the cyclic garbage collector off (it runs late in a long search), every evaluated
    batch of boxes is freed when its enclosure returns, and the search retains almost
    nothing of the ~3,000 boxes it evaluated."""
    import gc
    import tracemalloc

    from gfrf.bounds import enclosure

    # a NARX H3 to a zero gap: its boxes never close it, so the budget is spent (the
    # pendulum's H3 reaches its attained majorant within a hundred boxes)
    m = load_model("models/identified_example.toml").plant
    branch_and_bound(m, 3, tol=0.0, max_boxes=200)  # imports and caches first
    gc.collect()
    gc.disable()
    tracemalloc.start()
    try:
        r = branch_and_bound(m, 3, tol=0.0, max_boxes=3000)
        retained, _ = tracemalloc.get_traced_memory()
        alive = sum(isinstance(o, enclosure._Boxes) for o in gc.get_objects())
    finally:
        tracemalloc.stop()
        gc.enable()
    assert 2998 <= r.boxes <= 3000 and alive == 0
    assert retained < 2_000_000, retained


def test_a_kernel_that_is_identically_zero_is_bracketed_at_zero() -> None:
    # the pendulum's restoring force is odd: its H2 vanishes everywhere
    r = branch_and_bound(load_model("models/hanging_pendulum.toml").plant, 2)
    assert r.lower == 0.0 and r.upper == 0.0
