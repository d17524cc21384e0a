"""Tests of gfrf.bounds.norms, gfrf.bounds.majorant and gfrf.bounds.rational against
hand-derived closed forms."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

import gfrf.bounds.fixed_point as fixed_point
from gfrf.bounds.majorant import majorant, radius
from gfrf.bounds.norms import h1_norm, kernel_norm
from gfrf.errors import ArgumentError
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model

C = 2.45


def peak(b: float, c: float = C) -> float:
    """Peak of |1/(c - w^2 + j b w)| for b^2 < 2c: 1/(b sqrt(c - b^2/4))."""
    return 1.0 / (b * math.sqrt(c - b * b / 4.0))


@pytest.mark.parametrize("b", [0.5, 0.05, 1e-3, 1e-6, 1e-9])
def test_h1_second_order_peak(b: float) -> None:
    m = parse_model(f"D(y,2) + {b!r}*D(y) + {C}*y = u")
    bound = h1_norm(m)
    with mpmath.workdps(50):  # the closed form on the exact float coefficients
        exact = 1 / (mpmath.mpf(b) * mpmath.sqrt(mpmath.mpf(C) - mpmath.mpf(b) ** 2 / 4))
        assert bound.lower <= exact <= bound.upper and bound.proof == "interval"
    assert bound.upper == pytest.approx(peak(b), rel=1e-9)
    assert bound.argmax[0] == pytest.approx(math.sqrt(C - b * b / 2), rel=1e-6)
    assert bound.certified and bound.stable


def test_h1_cross_check_python_control() -> None:
    bound = h1_norm(parse_model("D(y,2) + 0.05*D(y) + 2.45*y = u"), cross_check=True)
    assert bound.reference == pytest.approx(bound.upper, rel=1e-5)


def test_h1_overdamped_peak_at_zero() -> None:
    # b^2 = 9 > 2c = 4: |A(jw)|^2 = (2 - w^2)^2 + 9 w^2 increases, sup = 1/c at w = 0
    bound = h1_norm(parse_model("D(y,2) + 3*D(y) + 2*y = u"))
    assert bound.upper == pytest.approx(0.5, rel=1e-12)
    assert bound.argmax == (0.0,)


def test_h1_improper_is_infinite_with_reason() -> None:
    bound = h1_norm(parse_model("D(y,2) + D(y) + y = D(u,3)"))
    assert math.isinf(bound.upper) and math.isinf(bound.lower)
    assert any("improper" in n for n in bound.notes)


def test_h1_imaginary_axis_pole_is_infinite() -> None:
    bound = h1_norm(parse_model("D(y,2) + 2*y = u"))
    assert math.isinf(bound.upper)
    assert any("imaginary axis" in n for n in bound.notes)


def test_h1_unstable_flagged_with_finite_axis_sup() -> None:
    # |2 - w^2 - j w| = |2 - w^2 + j w|: the same sup as the stable mirror, 1/sqrt(1.75)
    bound = h1_norm(parse_model("D(y,2) - D(y) + 2*y = u"))
    assert bound.stable is False
    assert bound.upper == pytest.approx(1 / math.sqrt(1.75), rel=1e-9)


@pytest.mark.parametrize("b", [0.2, 0.05, 1e-6])
def test_h3_duffing_closed_form(b: float) -> None:
    # H3 = -c3 H1(w1) H1(w2) H1(w3) / A(w1+w2+w3), H1 = 1/A: sup = |c3| peak^4,
    # attained at (w_r, w_r, -w_r).
    m = parse_model(f"D(y,2) + {b!r}*D(y) + y + 0.5*y**3 = u")
    bound = kernel_norm(m, 3)
    expected = 0.5 * peak(b, 1.0) ** 4
    assert bound.upper == pytest.approx(expected, rel=1e-9)
    assert bound.lower == pytest.approx(expected, rel=1e-8)
    assert bound.gap < 1e-8 and bound.certified


def test_pendulum_h3_symmetric_equals_asymmetric() -> None:
    m = load_model("models/hanging_pendulum.toml").plant
    sym, asym = kernel_norm(m, 3), kernel_norm(m, 3, symmetric=False)
    assert not asym.symmetric
    assert sym.upper == pytest.approx(asym.upper, rel=1e-12)
    assert sym.lower == pytest.approx(asym.lower, rel=1e-8)


def test_cartpole_h3_exact_value_inside_bracket() -> None:
    # Reduced cart-pole: x_i = H1(j w_i) = 39.3185/(w_i^2 + 67.578) in (0, beta1], and
    # |H3| = |11.2455 x1x2x3 - (19.66/3)(x1x2 + x1x3 + x2x3)| / (S^2 + 67.578),
    # increasing in each x_i on (0, beta1]: the sup is at w = 0.
    m = load_model("models/cartpole_reduced.toml").plant
    beta1 = 39.3185 / 67.578
    exact = (19.66 * beta1**2 - 11.2455 * beta1**3) / 67.578
    bound = kernel_norm(m, 3, tol=1e-6)
    assert bound.lower == pytest.approx(exact, rel=1e-9)
    assert bound.upper >= exact
    # the branch-and-bound closes the majorant's gap ((11.2455 beta1^3 + 19.66 beta1^2)
    # / 67.578, twice the sup) to the asked tolerance ...
    assert bound.upper <= exact / (1 - 1e-6) and bound.gap <= 1e-6
    # ... and to the default one (1e-3) without any argument
    default = kernel_norm(m, 3)
    assert exact <= default.upper <= exact / (1 - 1e-3) and default.gap <= 1e-3
    assert default.lower <= exact * (1 + 1e-12)


def test_bracket_contains_random_grid_max() -> None:
    m = parse_model("D(y,2) + 0.3*D(y) + 1.5*y + 0.4*y**2 - 0.2*y**3 + 0.1*y*u = u")
    rng = np.random.default_rng(1)
    for n in (2, 3):
        bound = kernel_norm(m, n)
        w = rng.uniform(-4, 4, size=(n, 20000))
        grid = float(np.max(np.abs(kernel(m, n)(*w))))
        assert grid <= bound.upper * (1 + 1e-12)
        assert bound.lower >= grid * (1 - 1e-9)


def test_zero_kernel() -> None:
    bound = kernel_norm(load_model("models/hanging_pendulum.toml").plant, 2)
    assert bound.lower == bound.upper == 0.0 and bound.certified


def test_input_derivative_term_gives_honest_infinite_upper() -> None:
    bound = kernel_norm(parse_model("D(y,2) + D(y) + y + y*D(u) = u"), 2)
    assert math.isinf(bound.upper) and math.isfinite(bound.lower)
    assert any("input derivative" in n for n in bound.notes)


def test_bad_tolerance() -> None:
    with pytest.raises(ArgumentError):
        kernel_norm(parse_model("D(y,2) + D(y) + y + y**3 = u"), 3, tol=0)


def test_majorant_pure_cubic_coefficients_and_radius() -> None:
    # B = beta1 r + g B^3: B3 = g beta1^3, B5 = 3 g^2 beta1^5, branch point
    # 1 = 3 g B^2 gives r* = 2 / (3 beta1 sqrt(3 g)).
    m = parse_model("D(y,2) + 0.5*D(y) + 2.45*y - 0.3*y**3 = u")
    maj = majorant(m)
    beta1 = peak(0.5)
    g = 0.3 * beta1
    coefficients = maj.coefficients(5)[:, 0]
    assert coefficients[3] == pytest.approx(g * beta1**3, rel=1e-12)
    assert coefficients[5] == pytest.approx(3 * g**2 * beta1**5, rel=1e-12)
    rad = radius(lambda x, r: maj.rhs(x, r), len(maj.powers))
    assert rad.value == pytest.approx(2 / (3 * beta1 * math.sqrt(3 * g)), rel=1e-8)
    assert rad.certified_below <= rad.value


def test_linear_model_has_infinite_radius() -> None:
    maj = majorant(parse_model("D(y,2) + D(y) + y = u"))
    assert math.isinf(radius(lambda x, r: maj.rhs(x, r), 1).value)


@pytest.mark.slow
def test_order_9_bracket() -> None:
    m = load_model("models/duffing.toml").plant
    bound = kernel_norm(m, 9)
    rng = np.random.default_rng(2)
    w = rng.uniform(-1.5, 1.5, size=(9, 3000))
    grid = float(np.max(np.abs(kernel(m, 9)(*w))))
    assert grid <= bound.lower <= bound.upper
    assert math.isfinite(bound.upper) and bound.certified


def test_imaginary_axis_pole_makes_h3_infinite() -> None:
    # H3 = -H1(w1) H1(w2) H1(w3) / A(j(w1+w2+w3)), A(j sqrt 2) = 0: unbounded, never a
    # big finite number
    bound = kernel_norm(parse_model("D(y,2) + 2*y + y**3 = u"), 3)
    assert math.isinf(bound.lower) and math.isinf(bound.upper)


def test_narx_linear_stability_and_h1() -> None:
    # y[k] = 0.5 y[k-1] + u[k-1]: H1 = q / (1 - 0.5 q), |H1| max at w = 0: 1 / 0.5 = 2;
    # y[k] = 1.5 y[k-1] + u[k-1] has its pole z = 1.5 outside the unit circle.
    stable = h1_norm(parse_model("y[k] = 0.5*y[k-1] + u[k-1]", sample_time=0.1))
    assert stable.stable and stable.upper == pytest.approx(2.0, rel=1e-9)
    assert stable.certified and stable.proof == "interval"  # exact on the unit circle
    assert stable.lower <= 2.0 <= stable.upper
    assert h1_norm(parse_model("y[k] = 1.5*y[k-1] + u[k-1]", sample_time=0.1)).stable is False


FOLD_MODELS = {
    "pendulum": "models/hanging_pendulum.toml",
    "duffing": "models/duffing.toml",
    "cartpole plant": "models/cartpole.toml",
    "cartpole with input term": "models/cartpole_reduced.toml",
    "quadratic": "D(y,2) + 0.3*D(y) + y + 0.4*y**2 = u",
    "cross terms": "D(y,2) + 0.2*D(y) + y + 0.3*y*D(y) + 0.1*y**2*D(y,2) + 0.05*D(y)**3 = u",
    "large radius": "D(y,2) + 0.2*D(y) + y + 1e-9*y**2 = u",
}


@pytest.mark.parametrize("name", list(FOLD_MODELS))
def test_branch_point_radius_matches_bisection(name: str, monkeypatch: pytest.MonkeyPatch
                                               ) -> None:
    source = FOLD_MODELS[name]
    model = load_model(source).plant if source.endswith(".toml") else parse_model(source)
    maj = majorant(model)
    calls: list[float] = []
    fold = fixed_point._fold

    def counted(*args: object) -> object:
        result = fold(*args)  # type: ignore[arg-type]
        calls.append(math.nan if result is None else result[0])
        return result

    monkeypatch.setattr(fixed_point, "_fold", counted)
    fast = radius(lambda x, r: maj.rhs(x, r), len(maj.powers))
    slow = radius(lambda x, r: maj.rhs(x, r), len(maj.powers), fold=False)
    assert len(calls) == 1 and math.isfinite(calls[0])  # the fast path ran, bisection did not
    assert fast.value == pytest.approx(slow.value, rel=1e-9)
    assert fast.certified_below <= fast.value <= fast.certified_below * (1 + 1e-10)
    assert fast.value == pytest.approx(calls[0], rel=2e-9)
    assert fast.solution is not None
    assert np.all(maj.rhs(fast.solution, fast.certified_below) <= fast.solution * (1 + 1e-12))


def test_branch_point_of_quadratic_closed_form() -> None:
    # B = beta1 r + g B^2: the branch point 1 = 2 g B gives B = 1/(2 g), r* = 1/(4 g beta1).
    maj = majorant(parse_model("D(y,2) + 0.3*D(y) + y + 0.4*y**2 = u"))
    beta1 = peak(0.3, 1.0)
    point = fixed_point._fold(lambda x, r: maj.rhs(x, r), 1, 0.01, np.array([0.01 * beta1]))
    assert point is not None
    assert point[0] == pytest.approx(1 / (4 * 0.4 * beta1**2), rel=1e-12)
    assert point[1][0] == pytest.approx(1 / (2 * 0.4 * beta1), rel=1e-6)


def test_failed_branch_point_falls_back_to_bisection(monkeypatch: pytest.MonkeyPatch) -> None:
    maj = majorant(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"))
    slow = radius(lambda x, r: maj.rhs(x, r), 1, fold=False)
    monkeypatch.setattr(fixed_point, "_fold", lambda *args: None)
    fallback = radius(lambda x, r: maj.rhs(x, r), 1)
    assert (fallback.value, fallback.certified_below) == (slow.value, slow.certified_below)


# -- levels of proof -------------------------------------------------------------------
def test_h3_closed_form_at_each_level() -> None:
    """Duffing-type pure cubic: ||H3|| = |c3| beta^4 (the majorant is attained)."""
    b, c3 = 0.05, 0.41
    m = parse_model(f"D(y,2) + {b}*D(y) + {C}*y - {c3}*y**3 = u")
    with mpmath.workdps(50):
        exact = mpmath.mpf(c3) / (mpmath.mpf(b) * mpmath.sqrt(C - mpmath.mpf(b) ** 2 / 4)) ** 4
    proven = kernel_norm(m, 3, proof="interval")
    assert (proven.proof, proven.upper_proof, proven.lower_proof) == ("interval",) * 3
    assert mpmath.mpf(proven.lower) <= exact <= mpmath.mpf(proven.upper)  # both ends proven
    floated = kernel_norm(m, 3, proof="float")
    assert floated.certified and floated.upper_proof == "float"
    assert floated.upper == pytest.approx(float(exact), rel=1e-12)
    estimate = kernel_norm(m, 3, proof="none")
    assert not estimate.certified and estimate.proof == "none"
    assert "branch-and-bound" not in estimate.method
    d = proven.to_dict()
    assert (d["proof"], d["upper_proof"], d["lower_proof"]) == ("interval",) * 3


def test_h1_levels_and_refusal() -> None:
    m = parse_model("D(y,2) + 0.05*D(y) + 2.45*y = u")
    levels = {p: h1_norm(m, p) for p in ("interval", "float", "none")}
    assert [levels[p].proof for p in levels] == ["interval", "float", "none"]
    assert levels["interval"].lower <= peak(0.05) <= levels["interval"].upper
    assert levels["float"].upper == pytest.approx(peak(0.05), rel=1e-12)
    assert levels["float"].certified and not levels["none"].certified
    with pytest.raises(ArgumentError, match="proof must be one of"):
        h1_norm(m, "exact")
    with pytest.raises(ArgumentError, match="proof must be one of"):
        kernel_norm(m, 3, proof="proven")


def test_branch_and_bound_upper_is_labelled_float() -> None:
    """An upper end lowered by the branch-and-bound is certified in floats only."""
    bound = kernel_norm(load_model("models/cartpole_reduced.toml").plant, 3)
    assert "branch-and-bound" in bound.method
    assert bound.upper_proof == "float" and bound.proof == "float"


def test_h1_cross_check_is_off_by_default() -> None:
    bound = h1_norm(parse_model("D(y,2) + 0.05*D(y) + 2.45*y = u"))
    assert bound.reference is None and "control.norm" not in bound.method
