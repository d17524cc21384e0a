"""Tests of gfrf.stability.theorem1, theorem2 and criteria (Theorems 1 and 2, r*, margins)
and gfrf.papers.gfrf_paper."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gfrf.bounds.majorant import majorant
from gfrf.errors import ArgumentError
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model, model_from_dict
from gfrf.papers.gfrf_paper import paper_checks, printed_match
from gfrf.stability.criteria import parameter_margin, verdict
from gfrf.stability.theorem1 import theorem1
from gfrf.stability.theorem2 import phi_series, theorem2, theta_series

C3 = 9.8 / (6 * 4.0)  # g / (6 L) of the hanging pendulum


def pendulum_radius(b: float, c: float = 2.45) -> float:
    """r* of B = beta1 r + g B^3, beta1 = sup|1/A| (unit input gain), g = C3 beta1."""
    beta1 = 1 / (b * math.sqrt(c - b * b / 4))
    return 2 / (3 * beta1 * math.sqrt(3 * C3 * beta1))


@pytest.mark.parametrize(("name", "b"), [("hanging_pendulum", 0.05),
                                         ("hanging_pendulum_damped", 0.5)])
def test_pendulum_radius_closed_form(name: str, b: float) -> None:
    v = verdict(load_model(f"models/{name}.toml"), order=3)
    assert v.theorem == 1
    assert v.radius == pytest.approx(pendulum_radius(b), rel=1e-8)
    assert v.radius_certified
    assert v.verdict == "inconclusive"  # r = 1 > r* for both paper examples
    assert [c.passed for c in v.conditions] == [True, True, None]


def test_pendulum_stable_inside_radius() -> None:
    mf = load_model("models/hanging_pendulum_damped.toml")
    v = verdict(mf, order=3, amplitude=0.99 * pendulum_radius(0.5))
    assert v.verdict == "stable"
    assert all(c.passed for c in v.conditions)


def test_damping_margin() -> None:
    # r* = 1 <=> beta1^(3/2) = 2 / (3 sqrt(3 C3)); with beta1 = 1/(b sqrt(c - b^2/4)):
    # x = b^2 solves x^2 - 4 c x + 4 / beta1^2 = 0, and rho = b m L^2 = 16 b.
    beta1 = (2 / (3 * math.sqrt(3 * C3))) ** (2 / 3)
    x = 2 * 2.45 - math.sqrt(4 * 2.45**2 - 4 / beta1**2)
    margin = parameter_margin(load_model("models/hanging_pendulum.toml"), "rho")
    assert margin.direction == "above"
    assert margin.value == pytest.approx(16 * math.sqrt(x), rel=1e-5)


def test_unstable_open_loop() -> None:
    v = theorem1(parse_model("D(y,2) - D(y) + 2*y + y**3 = u"), order=3)
    assert v.verdict == "unstable"
    assert v.conditions[1].passed is False
    assert "inapplicable" in v.conditions[1].detail


def test_imaginary_axis_poles_inconclusive() -> None:
    v = theorem1(parse_model("D(y,2) + 2*y + y**3 = u"), order=3)
    assert v.verdict == "inconclusive"
    assert v.conditions[1].passed is False


def test_cartpole_theorem2_improper_controller() -> None:
    v = verdict(load_model("models/cartpole_reduced.toml"), order=3)
    assert v.theorem == 2 and v.verdict == "inconclusive"
    names = {c.name: c for c in v.conditions}
    assert names["plant h_n and controller s_n proper rational"].passed is False
    assert names["linear closed loop L2 stable"].passed is True
    rho = names["sum theta_n rho_1^n r^n converges"].value["rho_1"]
    assert rho == pytest.approx(67.578 / (67.578 + 39.3185 * 0.1331), rel=1e-12)


def test_theta_series_by_hand() -> None:
    # theta_2 = rho1 phi2 lam^2; theta_3 = rho1 (phi2 lam^2 2 theta_2 + phi3 lam^3)
    phi, lam, rho = [0.7, 0.3, 0.2], 0.5, 0.9
    t = theta_series(phi, lam, rho, 3)
    t2 = rho * 0.3 * lam**2
    assert t == pytest.approx([1.0, t2, rho * (0.3 * lam**2 * 2 * t2 + 0.2 * lam**3)])


def test_theorem2_radius_matches_series_ratio() -> None:
    # Proper lag controller: the fixed-point radius must agree with the ratio test of
    # the explicit theta_n rho_1^n series built from the majorant coefficients.
    mf = model_from_dict({"equation": "D(y,2) + D(y) + 2*y + 0.3*y**3 = u",
                          "controller": {"num": [0.5], "den": [0.1, 1.0]}})
    v = theorem2(mf, order=3, amplitude=0.01)
    lam = v.conditions[2].value["lambda_1"]
    rho = v.conditions[4].value["rho_1"]
    n = 301
    phi = majorant(mf.plant).coefficients(n)[1:, 0].tolist()
    theta = np.array(theta_series(phi, lam, rho, n))
    terms = theta * rho ** np.arange(1, n + 1)
    estimate = (terms[n - 3] / terms[n - 1]) ** 0.5
    assert v.radius == pytest.approx(estimate, rel=2e-2)
    assert v.verdict == "stable"


def test_bad_amplitude_and_order() -> None:
    mf = load_model("models/duffing.toml")
    with pytest.raises(ArgumentError):
        verdict(mf, amplitude=-1.0)
    with pytest.raises(ArgumentError):
        verdict(mf, order=0)


def test_discrete_radius_is_certified() -> None:
    # y[k] = 0.5 y[k-1] - 0.2 y[k-1]^2 u[k-2] + u[k-1]: |q| = 1, sup|1/A| = sup|q/A| = 2
    # at q = 1, so X = 2 r + 2 * 0.2 r X^2, whose branch point is 1 - 3.2 r^2 = 0
    v = verdict(load_model("models/narx_example.toml"), order=3, amplitude=0.1)
    exact = 1 / math.sqrt(3.2)
    assert v.radius_certified and v.verdict == "stable"
    assert v.radius == pytest.approx(exact, rel=2e-9)
    assert v.norms[0].lower <= 2.0 <= v.norms[0].upper and v.norms[0].proof == "interval"


def test_paper_checks_rows() -> None:
    rows = {(r.section, r.quantity): r for r in paper_checks()}
    r1 = rows[("3 (rho = 0.8)", "rho_1 = ||H1||")]
    assert r1.match and r1.ours == pytest.approx(1 / (0.05 * math.sqrt(2.45 - 0.05**2 / 4)))
    r3 = rows[("3 (rho = 0.8)", "rho_3 = |c3| sup|1/A| (cubic gain)")]
    assert not r3.match
    assert printed_match(r3.paper, 0.41 * r1.ours)  # the reason: rounded 0.41
    assert r3.ours == pytest.approx(C3 * r1.ours)
    damped = rows[("3 (rho = 8)", "rho_1 = ||H1||")]
    assert not damped.match and printed_match(1.2944, damped.ours)
    rho = rows[("5 (cart-pole, eq (16))", "rho_1 = sup|(1 + h1 s1)^-1|")]
    assert rho.paper == 0.0016 and rho.ours == pytest.approx(0.928, abs=1e-3)
    assert math.isinf(rows[("5 (cart-pole, eq (16))", "lambda_1 = ||s1||")].ours)
    assert all(r.match or r.reason for r in rows.values())


PLANT = "D(y,2) + D(y) + 2*y + 0.3*y**3 = u"


def test_polynomial_controller_linear_equals_transfer_function() -> None:
    tf = theorem2(model_from_dict({"equation": PLANT,
                                   "controller": {"num": [5.0], "den": [1.0, 10.0]}}), order=3)
    eq = theorem2(model_from_dict({"equation": PLANT,
                                   "controller": {"equation": "D(u) + 10*u = 5*y"}}), order=3)
    assert eq.radius == pytest.approx(tf.radius, rel=1e-12)


def test_polynomial_controller_radius_matches_series_ratio() -> None:
    # Controller u-part: D(u) + 10 u = 5 y + 0.5 y^3: lambda_1 = 0.5, and its H3 =
    # 0.5 / (S + 10) has sup 0.05 = alpha_3 lambda_1^3, so alpha_3 = 0.4 (by hand).
    mf = model_from_dict({"equation": PLANT,
                          "controller": {"equation": "D(u) + 10*u = 5*y + 0.5*y**3"}})
    v = theorem2(mf, order=3, amplitude=0.01)
    alpha = v.conditions[2].value["alpha"]
    assert alpha == pytest.approx([1.0, 0.0, 0.4], rel=1e-12)
    lam, rho = 0.5, v.conditions[4].value["rho_1"]
    n = 301
    beta = majorant(mf.plant).coefficients(n)[1:, 0].tolist()
    cmaj = majorant(mf.controller.model).coefficients(n)[1:, 0]
    alpha_n = (cmaj / lam ** np.arange(1, n + 1)).tolist()
    theta = np.array(theta_series(phi_series(beta, alpha_n, n), lam, rho, n))
    terms = theta * rho ** np.arange(1, n + 1)
    estimate = (terms[n - 3] / terms[n - 1]) ** 0.5
    assert v.radius == pytest.approx(estimate, rel=2e-2)
    linear = theorem2(model_from_dict({"equation": PLANT, "controller": {
        "equation": "D(u) + 10*u = 5*y"}}), order=3)
    assert v.radius < linear.radius


def test_phi_series_by_hand() -> None:
    # phi_3 = beta_1 alpha_3 + beta_2 (2 alpha_1 alpha_2) + beta_3 alpha_1^3
    phi = phi_series([2.0, 3.0, 5.0], [1.0, 0.5, 0.25], 3)
    assert phi == pytest.approx([2.0, 2 * 0.5 + 3.0, 2 * 0.25 + 3 * 2 * 0.5 + 5.0])


def test_verdict_of_a_bare_model_and_a_stiff_cubic_radius():
    # B = beta1 r + k sup|1/A| B^3 with sup|1/A| = beta1 (H1 = 1/A): the branch point of
    # r = (B - g B^3)/beta1, g = k beta1, is at B^2 = 1/(3g): r* = 2/(3 sqrt(3 g) beta1).
    from gfrf.model.equation import parse_model

    k, b = 1e6, 0.2
    beta1 = 1 / (b * math.sqrt(1 - b**2 / 4))
    expected = 2 / (3 * math.sqrt(3 * k * beta1) * beta1)
    result = verdict(parse_model(f"D(y,2) + {b}*D(y) + y + {k}*y**3 = u"), with_norms=False)
    assert result.theorem == 1
    assert result.radius == pytest.approx(expected, rel=1e-8)


def test_length_margin_is_a_stable_below_boundary() -> None:
    # Pendulum with length L (m = 1, rho = 0.8, g = 9.8): b = rho/L^2, c = g/L, c3 = g/(6L);
    # B = beta1 r + c3 beta1 B^3 (sup|1/A| = beta1) has r* = 2/(3 sqrt(3 c3) beta1^(3/2)).
    from scipy.optimize import brentq

    def radius_minus_one(length: float) -> float:
        b, c = 0.8 / length**2, 9.8 / length
        beta1 = 1 / (b * math.sqrt(c - b**2 / 4))
        return 2 / (3 * math.sqrt(3 * c / 6) * beta1**1.5) - 1

    expected = brentq(radius_minus_one, 0.5, 4.0, xtol=1e-12)
    margin = parameter_margin(load_model("models/hanging_pendulum.toml"), "L")
    assert margin.direction == "below"
    assert margin.value == pytest.approx(expected, rel=1e-5)


# -- levels of proof -------------------------------------------------------------------
LAG_LOOP = {"equation": "D(y,2) + D(y) + 2*y + 0.3*y**3 = u",
            "controller": {"num": [0.5], "den": [0.1, 1.0]}}


def test_theorem2_radius_is_proven_in_ball_arithmetic() -> None:
    from gfrf.stability.loops import closed_loop
    from gfrf.stability.theorem2 import _loop_proves

    mf = model_from_dict(LAG_LOOP)
    v = theorem2(mf, order=1, amplitude=0.01, with_norms=False)
    assert v.radius_proof == "interval" and v.verdict == "stable"
    floated = theorem2(mf, order=1, amplitude=0.01, with_norms=False, proof="float")
    assert floated.radius_proof == "float"
    assert floated.radius == pytest.approx(v.radius, rel=1e-9)
    # the ball check refuses a point beyond the radius: no z >= 0 passes there, in
    # particular not a large one or the one at the radius
    loop, maj = closed_loop(mf), majorant(mf.plant)
    lam, rho = loop.controller_norm_upper, loop.sensitivity_peak_upper
    for z in (np.full(2, 1e3), np.full(2, 1e-3), np.array([v.radius, v.radius])):
        assert not _loop_proves(maj, lam, rho, None, z, 1.5 * v.radius)


def test_polynomial_controller_radius_is_proven() -> None:
    mf = model_from_dict({"equation": PLANT,
                          "controller": {"equation": "D(u) + 10*u = 5*y + 0.5*y**3"}})
    v = theorem2(mf, order=1, amplitude=0.01, with_norms=False)
    assert v.radius_proof == "interval"


def test_proof_none_never_stable_and_float_agrees() -> None:
    model = parse_model("D(y,2) + D(y) + 2*y + y**3 = u")
    levels = {p: theorem1(model, order=3, amplitude=0.1, proof=p)
              for p in ("interval", "float", "none")}
    assert levels["interval"].verdict == levels["float"].verdict == "stable"
    assert levels["none"].verdict == "inconclusive" and not levels["none"].radius_certified
    assert [levels[p].radius_proof for p in levels] == ["interval", "float", "none"]
    assert levels["float"].radius == pytest.approx(levels["interval"].radius, rel=1e-12)
    assert levels["none"].to_dict()["radius_proof"] == "none"
    with pytest.raises(ArgumentError, match="proof must be one of"):
        verdict(model, proof="certified")


def test_axis_pole_proves_a_zero_series_radius_and_no_estimate_above_it() -> None:
    """||H1|| = inf (undamped: poles +-j sqrt(2), exact test) makes sum ||H_n|| r^n diverge
    for every r > 0: the proven upper bound of its radius is 0 and no estimate exceeds
    it (an estimate of 6e-7 used to be printed)."""
    v = theorem1(parse_model("D(y,2) + 2*y + y**3 = u"), order=3)
    assert v.radius_upper == 0.0 and v.radius_estimate is None
    damped = theorem1(parse_model("D(y,2) + 0.4*D(y) + 2*y + y**3 = u"), order=3)
    assert damped.radius_estimate is not None and damped.radius_estimate > 0
