"""Adversarial cases of the box enclosures, the branch-and-bound and the tail bound.

Attacks on gfrf.bounds.enclosure / gfrf.bounds.branch_bound and gfrf.bounds.tail:
lightly damped and clustered poles, unstable linear parts, relative degree 0
factors, input terms, asymmetric kernels, tiny boxes, boxes far out, poles on the axis,
and the ``gfrf norm --max-boxes`` command line.  References are independent: |H_n| in
closed form evaluated by mpmath at 50 digits (models A(D) y + a2 y^2 + a3 y^3 = u), or
dense samples of :func:`gfrf.kernels.recursion.kernel` away from ill-conditioned points.

Among them, the cases that guard: block sums of box centres rounded without widening
the interval of sigma, centre values trusted beyond their error bound, the split
coordinate of boxes without centre values, and the modulus factors on lightly damped
kernels.
"""

from __future__ import annotations

import itertools
import json
import math

import mpmath as mp
import numpy as np
import pytest

from gfrf.bounds.branch_bound import box_bounds
from gfrf.bounds.majorant import majorant
from gfrf.bounds.norms import kernel_norm
from gfrf.bounds.tail import tail_bound
from gfrf.cli import main
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model

#: Relative slack for float evaluations of the reference samples (rounding only).
SLACK = 1e-12


def _cubic(zeta: float) -> str:
    return f"D(y,2) + {2 * zeta!r}*D(y) + y + 0.4*y**2 - 0.3*y**3 = u"


def _mp_kernel(den: list[float], a2: float, a3: float):
    """|H_n(j w)| (n = 2, 3) of A(D) y + a2 y^2 + a3 y^3 = u in mpmath, symmetric kernel.

    H1 = 1/A, H2 = -a2 H1 H1 / A(s1+s2),
    H3 = -(a2 (2/3) sum_i H1(s_i) H2(s_j, s_k) + a3 H1 H1 H1) / A(s1+s2+s3).
    """
    coef = [mp.mpf(c) for c in den]
    b2, b3 = mp.mpf(a2), mp.mpf(a3)

    def h1(s):
        return 1 / mp.polyval(coef, s)

    def h2(s1, s2):
        return -b2 * h1(s1) * h1(s2) * h1(s1 + s2)

    def h3(s1, s2, s3):
        p = (b2 * mp.mpf(2) / 3 * (h1(s1) * h2(s2, s3) + h1(s2) * h2(s1, s3)
                                   + h1(s3) * h2(s1, s2)) + b3 * h1(s1) * h1(s2) * h1(s3))
        return -p * h1(s1 + s2 + s3)

    def modulus(*w: float) -> mp.mpf:
        with mp.workdps(50):
            s = [mp.mpc(0, mp.mpf(x)) for x in w]
            return abs({2: h2, 3: h3}[len(w)](*s))

    return modulus


def _corner_max(modulus, lo: np.ndarray, hi: np.ndarray) -> mp.mpf:
    return max(modulus(*c) for c in itertools.product(*zip(lo.tolist(), hi.tolist(),
                                                           strict=True)))


def test_mp_reference_matches_the_kernel() -> None:
    # the closed form is the same kernel as gfrf's (benign point, 1e-13)
    zeta = 0.05
    ref = _mp_kernel([1, 2 * zeta, 1], 0.4, -0.3)
    m = parse_model(_cubic(zeta))
    for w in ([0.3, -1.1], [0.3, 1.1, -0.7]):
        assert abs(kernel(m, len(w))(*w)) == pytest.approx(float(ref(*w)), rel=1e-13)


# -- box bounds: sound attacks -------------------------------------------------------
@pytest.mark.parametrize("zeta", [1e-4, 1e-6])
def test_boxes_straddling_a_light_resonance_hold_against_mpmath(zeta: float) -> None:
    # centres with w1 + w2 + w3 within 30 zeta of the resonance, widths 1e-8 .. 1e-2
    ref = _mp_kernel([1, 2 * zeta, 1], 0.4, -0.3)
    m = parse_model(_cubic(zeta))
    rng = np.random.default_rng(3)
    c = rng.uniform(0.1, 0.6, (25, 3))
    c[:, 0] += 1.0 - c.sum(axis=1) + rng.uniform(-30, 30, 25) * zeta
    half = 10.0 ** rng.uniform(-8, -2, (25, 1)) * rng.uniform(0.3, 1.0, (25, 3))
    lo, hi = c - half, c + half
    bound, _, _ = box_bounds(m, 3, lo, hi)
    for j in range(25):
        inner = lo[j] + rng.uniform(0, 1, (12, 3)) * (hi[j] - lo[j])
        # the resonance sigma = sqrt(1 - 2 zeta^2) inside the box, if it is
        peak = c[j].copy()
        peak[0] += math.sqrt(1 - 2 * zeta * zeta) - c[j].sum()
        points = [*inner, peak] if lo[j, 0] <= peak[0] <= hi[j, 0] else list(inner)
        true = max(_corner_max(ref, lo[j], hi[j]), *(ref(*p) for p in points))
        assert true <= bound[j] * (1 + SLACK), (j, float(true), bound[j])


@pytest.mark.parametrize(("text", "n", "symmetric"), [
    ("D(y,2) + 0.05*D(y) + y + y**2*D(y,2) + 0.3*y**3 = u", 3, True),  # relative degree 0
    ("D(y,2) + 0.05*D(y) + y + y*D(y)**2 - 0.2*D(y)**2 = u", 3, False),
    ("D(y,2) + 0.1*D(y) + y + u*y**2 + 0.5*y**2 = u", 3, False),  # input in a term
    ("D(y,2) - 0.05*D(y) + y + 0.4*y**2 - 0.3*y**3 = u", 2, True),  # unstable linear part
    ("D(y) + y + D(y)*y**2 + 0.5*y**2 = u", 3, True),  # relative degree 1
])
def test_boxes_hold_for_hostile_structures(text: str, n: int, symmetric: bool) -> None:
    m = parse_model(text)
    k = kernel(m, n, symmetric)
    rng = np.random.default_rng(n)
    c = rng.uniform(-2, 2, (30, n))
    half = 10.0 ** rng.uniform(-5, 0, (30, 1)) * rng.uniform(0.1, 1, (30, n))
    lo, hi = c - half, c + half
    bound, _, _ = box_bounds(m, n, lo, hi, symmetric=symmetric)
    for j in range(30):
        pts = lo[j] + rng.uniform(0, 1, (300, n)) * (hi[j] - lo[j])
        pts = np.vstack([pts, list(itertools.product(*zip(lo[j], hi[j], strict=True))), c[j]])
        assert np.abs(k(*pts.T)).max() <= bound[j] * (1 + SLACK)


def test_boxes_holding_a_pole_on_the_axis_are_unbounded_not_nan() -> None:
    undamped = parse_model("D(y,2) + y + 0.4*y**2 = u")  # A(j) = 0
    integrator = parse_model("D(y,2) + D(y) + 0.4*y**2 = u")  # A(0) = 0
    with np.errstate(all="ignore"):
        for m, c in ((undamped, [0.5, 0.5]), (integrator, [0.0, 0.0])):
            for h in (0.0, 1e-3):
                bound, _, _ = box_bounds(m, 2, np.array([c]) - h, np.array([c]) + h)
                assert bound[0] == math.inf
        bound, _, _ = box_bounds(undamped, 2, np.array([[0.3, 0.2]]) - 1e-3,
                                 np.array([[0.3, 0.2]]) + 1e-3)
    assert math.isfinite(bound[0])


def test_identically_zero_kernel_has_zero_bounds() -> None:
    # H2 of a model without quadratic terms is 0: the enclosure gets the float 0.0 back
    # from the generated code (not an interval) and must still bound it
    m = parse_model("D(y,2) + 0.05*D(y) + y + 0.3*y**3 = u")
    bound, _, _ = box_bounds(m, 2, np.array([[0.1, 0.2]]), np.array([[0.3, 0.4]]))
    assert bound[0] == 0.0


# -- tail bound -------------------------------------------------------------------------
@pytest.mark.parametrize(("text", "n", "symmetric"), [
    ("D(y,2) + 0.1*D(y) + y + 0.3*u**3 + 0.2*y**2 = u", 3, True),  # tail nearly attained
    ("D(y,2) + 0.1*D(y) + y + u*y**2 + 0.5*u**2*y + 0.3*y*D(y,2) = u", 3, False),
    ("D(y,2) + 0.1*D(y) + y + y**2*D(y,2) = u", 3, True),
    ("D(y,2) + 0.1*D(y) + y + 0.5*u**2 + 0.2*y**2 = u", 2, True),
])
def test_tail_bound_holds_beyond_the_width(text: str, n: int, symmetric: bool) -> None:
    # |w_i| >= W for one coordinate i, the others placed so that block sums resonate
    m = parse_model(text)
    k = kernel(m, n, symmetric)
    maj = majorant(m)
    rng = np.random.default_rng(5)
    for width in (4.0, 32.0):
        tail = tail_bound(m, n, width, maj)
        w = rng.choice([-1.0, 0.0, 1.0], (20000, n)) + rng.normal(0, 0.05, (20000, n))
        big = rng.integers(0, n, 20000)
        rows = np.arange(20000)
        w[rows, big] = rng.choice([-1, 1], 20000) * width * (1 + rng.exponential(0.2, 20000))
        partner = (big + 1) % n  # half the points: that pair sums to about +-1
        pair = rng.uniform(size=20000) < 0.5
        w[rows[pair], partner[pair]] = (-w[rows[pair], big[pair]]
                                        + rng.choice([-1.0, 1.0], pair.sum())
                                        + rng.normal(0, 0.05, pair.sum()))
        assert np.abs(k(*w.T)).max() <= tail * (1 + SLACK)


# -- the whole bracket ---------------------------------------------------------------------
@pytest.mark.parametrize(("zeta", "n"), [(1e-6, 2), (3e-7, 3)])
def test_tight_bracket_of_a_lightly_damped_kernel_holds(zeta: float, n: int) -> None:
    # asked for 1e-12, the upper end must stay above |H_n| (mpmath) at the maximiser it
    # reports and at the resonant point (1, 0) / (1, -1, 1)
    ref = _mp_kernel([1, 2 * zeta, 1], 0.4, -0.3)
    b = kernel_norm(parse_model(_cubic(zeta)), n, tol=1e-12, max_boxes=20_000)
    resonant = [1.0, 0.0] if n == 2 else [1.0, -1.0, 1.0]
    assert b.upper >= float(ref(*b.argmax)) * (1 - 1e-15)
    assert b.upper >= float(ref(*resonant)) * (1 - 1e-15)
    assert b.lower <= b.upper


# At damping zeta the a-priori Horner error of A(j w) at the resonance is ~1e-15 / zeta
# relative, so box bounds are inflated by that much (centre values are trusted only to
# their error bound): a gap of 1e-12 is not certifiable in doubles there, 1e-6 is.
def test_lightly_damped_bracket_of_order_two_closes() -> None:
    b = kernel_norm(parse_model(_cubic(1e-6)), 2, tol=1e-6, max_boxes=20_000)
    assert b.gap <= 1e-6


def test_lightly_damped_bracket_of_order_three_closes() -> None:
    # moduli of the common factors alone leave gap 0.13 here at 20k boxes; the
    # enclosure keeps the smaller of the complex and the modulus bounds per box
    b = kernel_norm(parse_model(_cubic(3e-7)), 3, tol=1e-6, max_boxes=20_000)
    assert b.gap <= 1e-6


@pytest.mark.parametrize(("text", "n", "symmetric"), [
    ("D(y,4) + 0.004*D(y,3) + 2.0000040199999995*D(y,2) + 0.00400000004*D(y) "
     "+ 1.0000000199999999*y + 0.4*y**2 = u", 2, True),  # poles 1e-8 apart
    ("D(y,2) - 0.02*D(y) + y + 0.4*y**2 + 0.3*y*D(y) = u", 2, True),  # unstable
    ("D(y,2) + 0.1*D(y) + y + u*y**2 + 0.3*y**2 = u", 3, False),
])
def test_bracket_upper_is_above_dense_samples(text: str, n: int, symmetric: bool) -> None:
    m = parse_model(text)
    b = kernel_norm(m, n, symmetric, tol=1e-3, max_boxes=20_000)
    k = kernel(m, n, symmetric)
    rng = np.random.default_rng(1)
    x = np.array(b.argmax)
    pts = np.vstack([x + rng.normal(0, s, (4000, n)) for s in (1e-6, 1e-3, 1e-1)]
                    + [rng.choice([-1.0, 1.0], (4000, n)) + rng.normal(0, 1e-3, (4000, n))])
    assert np.abs(k(*pts.T)).max() <= b.upper * (1 + SLACK)


# -- command line ------------------------------------------------------------------------
def _run(args: list[str]) -> int:
    """Exit code of the CLI (argparse errors exit through SystemExit)."""
    try:
        return main(args)
    except SystemExit as stop:
        return int(stop.code or 0)


@pytest.mark.parametrize("value", ["-1", "1e9", "abc", "30000000", "20000001"])
def test_cli_rejects_bad_budgets(value: str, capsys: pytest.CaptureFixture[str]) -> None:
    code = _run(["norm", "models/duffing.toml", "--order", "5", "--max-boxes", value])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and "max" in err and "boxes" in err
    assert "Traceback" not in err


def test_cli_norm_json_is_valid_and_deterministic(capsys: pytest.CaptureFixture[str]) -> None:
    args = ["norm", "D(y,2) + 0.2*D(y) + y + 0.4*y**2 - 0.3*y**3 = u", "--order", "3",
            "--max-boxes", "2000", "--json"]
    outputs = []
    for _ in range(2):
        assert _run(args) == 0
        outputs.append(capsys.readouterr().out)
    assert outputs[0] == outputs[1]
    data = json.loads(outputs[0])
    assert data["lower"] <= data["upper"] and math.isfinite(data["upper"])


# -- defects reported to the lead --------------------------------------------------------
def test_block_sum_cancellation_far_out() -> None:
    # w1 + w2 + w3 close to the resonance with |w1|, |w3| ~ 8e5: fl(c1 + c2) loses 6e-11,
    # |A| ~ 2e-5 near sigma = 1 (zeta = 1e-6): bound 5.7e-5 below the true corner value
    zeta = 1e-6
    ref = _mp_kernel([1, 2 * zeta, 1], 0.4, -0.3)
    lo = np.array([781115.9211142284, 0.21720248721220053, -781115.1383191003])
    hi = np.array([781115.9211142285, 0.21720248721220056, -781115.1383191001])
    bound, _, _ = box_bounds(parse_model(_cubic(zeta)), 3, lo[None], hi[None])
    assert _corner_max(ref, lo, hi) <= bound[0] * (1 + SLACK)


def test_block_sum_rounding_near_the_origin() -> None:
    # coordinates ~8, box 4 ulps wide: bound 4.8e-9 below the true corner value
    zeta = 1e-8
    ref = _mp_kernel([1, 2 * zeta, 1], 0.4, -0.3)
    lo = np.array([8.07692555740627, 0.3737708588694639, -7.450696234660307])
    hi = np.array([8.076925557406277, 0.3737708588694641, -7.450696234660303])
    bound, _, _ = box_bounds(parse_model(_cubic(zeta)), 3, lo[None], hi[None])
    assert _corner_max(ref, lo, hi) <= bound[0] * (1 + SLACK)


def test_centre_values_accepted_at_1e8_relative_accuracy() -> None:
    # no cancellation here (w1 + w2 ~ 1): widening the sigma interval alone leaves
    # 4e-10; _POINT_RTOL = 1e-12 fixes it but stalls the search, so the centre values'
    # error has to enter the bound
    zeta = 1e-8
    ref = _mp_kernel([1, 2 * zeta, 1], 0.4, -0.3)
    lo = np.array([0.9010856295273699, 0.09891460213544959])
    hi = np.array([0.9010856295273703, 0.09891460213544961])
    bound, _, _ = box_bounds(parse_model(_cubic(zeta)), 2, lo[None], hi[None])
    assert _corner_max(ref, lo, hi) <= bound[0] * (1 + SLACK)


def test_boxes_without_centre_values_split_their_widest_coordinate() -> None:
    m = parse_model("D(y,2) + 2e-07*D(y) + y + 0.4*y**2 = u")
    lo, hi = np.array([[1 - 1e-12, -1.0]]), np.array([[1 + 1e-12, 1.0]])
    _, _, split = box_bounds(m, 2, lo, hi)
    assert split[0] == 1
