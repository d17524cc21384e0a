"""Soundness: every certified number is right or refused.

Each case is checked against an independent reference computed here:
closed forms evaluated with mpmath at 50 digits on the model's coefficients as written
(decimals as exact rationals; the interval level proves that model), mpmath root finding
at 60 digits, or exact rationals.
A proven enclosure must contain the reference; a float-certified value must match it
to the stated rounding.
"""

from __future__ import annotations

import json
import math
from fractions import Fraction

import mpmath as mp
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gfrf.bounds.exact import hurwitz, poles, schur
from gfrf.bounds.exact_sup import sup_abs_beyond
from gfrf.bounds.majorant import majorant, radius
from gfrf.bounds.norms import h1_norm, kernel_norm
from gfrf.cli import main
from gfrf.model.equation import Model, parse_model
from gfrf.stability.criteria import verdict

DPS = 50


def coefficients(model: Model) -> dict[str, mp.mpf]:
    """a2, a1, a0, b, c3 of ``a2 y'' + a1 y' + a0 y + c3 y^3 = b u`` as written, as mpf."""
    out = {}
    for t in model.terms:
        key = {((2,), ()): "a2", ((1,), ()): "a1", ((0,), ()): "a0",
               ((0, 0, 0), ()): "c3", ((), (0,)): "b"}[(t.y_orders, t.u_orders)]
        out[key] = (mp.mpf(t.exact.numerator) / t.exact.denominator
                    * (-1 if key == "b" else 1))
    return out


def second_order_references(model: Model) -> tuple[mp.mpf, mp.mpf, mp.mpf]:
    """(||H1||, ||H3||, majorant radius) of a y^3 oscillator, closed forms at 50 digits.

    K = sup|1/A| = peak / |a2|, peak = sup|1/(s^2 + p s + q)| (p = a1/a2, q = a0/a2):
    1/(p sqrt(q - p^2/4)) when p^2 < 2q, else 1/q at w = 0; ||H1|| = |b| K;
    ||H3|| = |c3| ||H1||^3 K (attained at (w_r, w_r, -w_r)); the majorant
    X = ||H1|| r + |c3| K X^3 has the branch point r* = 2 / (3 ||H1|| sqrt(3 |c3| K)).
    """
    with mp.workdps(DPS):
        c = coefficients(model)
        p, q = c["a1"] / c["a2"], c["a0"] / c["a2"]
        peak = 1 / (p * mp.sqrt(q - p ** 2 / 4)) if p ** 2 < 2 * q else 1 / q
        k = peak / abs(c["a2"])
        h1 = abs(c["b"]) * k
        h3 = abs(c["c3"]) * h1 ** 3 * k
        r_star = 2 / (3 * h1 * mp.sqrt(3 * abs(c["c3"]) * k))
        return h1, h3, r_star


def scaled_text(a2: float, a1: float, a0: float, c3: float, b: float, k: int) -> str:
    s = float(f"1e{k}")
    return (f"{a2 * s!r}*D(y,2) + {a1 * s!r}*D(y) + {a0 * s!r}*y + {c3 * s!r}*y**3 "
            f"= {b * s!r}*u")


def run_json(capsys: pytest.CaptureFixture[str], *argv: str) -> dict:
    code = main([*argv, "--json"])
    out = capsys.readouterr().out
    assert code in (0, 1)
    assert "nan" not in out.lower()
    return json.loads(out)


# -- 1. scale dependence -----------------------------------------------------------------
@pytest.mark.parametrize("k", [-200, -90, -85, 0, 77, 100, 150, 155, 200])
def test_scaled_equation_gives_the_same_numbers(k: int) -> None:
    m = parse_model(scaled_text(1.0, 1.0, 1.0, 1.0, 1.0, k))
    h1, h3, r_star = second_order_references(m)
    b1 = h1_norm(m)
    assert b1.proof == "interval" and b1.lower <= h1 <= b1.upper
    assert b1.upper - b1.lower <= 1e-15 * b1.upper
    assert float(majorant(m).coefficients(3)[3, 0]) == pytest.approx(float(h3), rel=1e-14)
    v = verdict(m, order=1, amplitude=0.35, with_norms=False)
    assert v.verdict == "inconclusive"  # r* = 0.3102016 < 0.35 whatever the scale
    assert v.radius == pytest.approx(float(r_star), rel=2e-9)
    assert verdict(m, order=1, amplitude=0.3, with_norms=False).verdict == "stable"


def test_scaled_equation_cli(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, "verdict", "1e-90*D(y,2) + 1e-90*D(y) + 1e-90*y + 1e-90*y**3 = "
                    "1e-90*u", "--amplitude", "0.35", "--order", "1")
    assert data["verdict"] == "inconclusive"
    assert data["radius"] == pytest.approx(2 / (3 * (2 / 3**0.5) ** 1.5 * 3**0.5), rel=2e-9)
    assert data["norms"][0]["lower"] <= 2 / 3**0.5 <= data["norms"][0]["upper"]


# -- 2. clustered poles near the axis ----------------------------------------------------
CLUSTER = ("1.0*y + 6e-06*D(y) + 3.000000000012*D(y,2) + 1.2000000000008e-05*D(y,3) + "
           "3.000000000012*D(y,4) + 6e-06*D(y,5) + 1.0*D(y,6) + 0.1*y**3 = u")


def cluster_references(written: bool = True) -> tuple[mp.mpf, mp.mpf]:
    """(max Re of the roots, sup |1/A(j w)|) at 60 digits of the coefficients as written
    (decimals as exact rationals), or of their doubles."""
    m = parse_model(CLUSTER)
    a: dict[int, Fraction] = {}
    for t in m.terms:
        if t.is_linear_output:
            a[t.y_orders[0]] = t.exact if written else Fraction(t.coefficient)
    with mp.workdps(60):
        high = [mp.mpf(a[k].numerator) / a[k].denominator for k in range(6, -1, -1)]
        roots = mp.polyroots(high, maxsteps=500, extraprec=400)
        max_re = max(mp.re(r) for r in roots)
        # |A(j w)|^2 = E(w)^2 + O(w)^2; its stationary points in w > 0
        low = list(reversed(high))
        even = [low[k] * (-1) ** (k // 2) if k % 2 == 0 else 0 for k in range(7)]
        odd = [low[k] * (-1) ** (k // 2) if k % 2 == 1 else 0 for k in range(7)]
        sq = [mp.mpf(0)] * 13
        for i in range(7):
            for j in range(7):
                sq[i + j] += even[i] * even[j] + odd[i] * odd[j]
        deriv = [k * sq[k] for k in range(1, 13)]
        stationary = mp.polyroots(list(reversed(deriv)), maxsteps=500, extraprec=600)
        best = 1 / mp.sqrt(sq[0])
        for w in stationary:
            if abs(mp.im(w)) < mp.mpf(10) ** -40 and mp.re(w) > 0:
                value = 1 / mp.sqrt(mp.polyval(list(reversed(sq)), mp.re(w)))
                best = max(best, value)
        return max_re, best


def test_clustered_poles_stable_and_exact_norm() -> None:
    max_re, peak = cluster_references()
    assert -1.1e-6 < max_re < -9e-7  # the reference: stable, max Re = -1e-6 as written
    m = parse_model(CLUSTER)
    a = m.linear_output
    assert hurwitz([a[k] for k in range(6, -1, -1)])
    b1 = h1_norm(m)
    assert b1.stable and b1.proof == "interval"
    assert b1.lower <= peak <= b1.upper and b1.upper - b1.lower <= 1e-15 * b1.upper
    v = verdict(m, order=1, amplitude=1.0, with_norms=False)
    assert v.conditions[1].passed is True and v.verdict != "unstable"


def test_tail_sup_beyond_a_frequency_on_the_cluster() -> None:
    # the tail bound a branch-and-bound needs: sup over |w| >= v of |1/A(j w)|
    a = parse_model(CLUSTER).linear_output
    den = [a[k] for k in range(6, -1, -1)]
    _, peak = cluster_references(written=False)  # the sup of these doubles
    assert sup_abs_beyond([1.0], den, 0.5).lower <= peak <= sup_abs_beyond([1.0], den, 0.5).upper
    with mp.workdps(DPS):  # beyond the resonance |A(j w)| increases: the sup is at w = 1.2
        value = 1 / abs(mp.polyval([mp.mpf(c) for c in den], mp.mpc(0, mp.mpf(1.2))))
    tail = sup_abs_beyond([1.0], den, 1.2)
    assert tail.lower <= value <= tail.upper and tail.omega == 1.2


def cluster_coefficients(zeta: float, power: int) -> list[float]:
    """Float coefficients of (s^2 + 2 zeta s + 1)^power, multiplied out in floats."""
    out = np.array([1.0])
    for _ in range(power):
        out = np.polymul(out, [1.0, 2 * zeta, 1.0])
    return [float(c) for c in out]


def test_rounded_cluster_on_the_axis_is_decided_exactly() -> None:
    # (s^2 + 2e-12 s + 1)^3 rounded to floats is (s^2 + 1)^2 (s^2 + 6e-12 s + 1): a double
    # pole pair exactly on the axis (exact rational gcd with (s^2 + 1)^2), so ||H1|| = inf
    # and the pole is on the boundary, not outside
    import sympy as sp

    coeffs = cluster_coefficients(1e-12, 3)
    s = sp.Symbol("s")
    poly = sum(sp.Rational(c) * s ** (6 - i) for i, c in enumerate(coeffs))
    assert sp.rem(sp.expand(poly), sp.expand((s**2 + 1) ** 2), s) == 0
    text = " + ".join(f"{c!r}*D(y,{6 - i})" for i, c in enumerate(coeffs)) + " = u"
    b = h1_norm(parse_model(text.replace("*D(y,0)", "*y")))
    assert math.isinf(b.upper) and b.stable is False
    v = verdict(parse_model(text.replace("*D(y,0)", "*y")), order=1, with_norms=False)
    assert v.verdict == "inconclusive" and "boundary" in v.conditions[1].detail


def test_rounded_fivefold_cluster_is_unstable() -> None:
    # (s^2 + 2e-9 s + 1)^5 in floats: rounding splits the cluster by ~1e-5 > 1e-9
    coeffs = cluster_coefficients(1e-9, 5)
    with mp.workdps(80):
        roots = mp.polyroots([mp.mpf(c) for c in coeffs], maxsteps=800, extraprec=2000)
        max_re = max(mp.re(r) for r in roots)
    assert max_re > 1e-6  # the reference: a root in the right half plane
    text = " + ".join(f"{c!r}*D(y,{10 - i})" for i, c in enumerate(coeffs)) + " = u"
    v = verdict(parse_model(text.replace("*D(y,0)", "*y")), order=1, with_norms=False)
    assert v.verdict == "unstable"


# -- 3. radius without a cap -------------------------------------------------------------
def test_radius_beyond_1e12_is_finite() -> None:
    # A = (s + 1)(s + 1e9): sup|1/A| = 1/A(0) = 1e-9, X = 1e-9 r + 0.5e-9 X^3
    m = parse_model("D(y,2) + 1000000001.0*D(y) + 1000000000.0*y + 0.5*y**3 = u")
    with mp.workdps(DPS):
        beta = 1 / mp.mpf(1000000000.0)
        exact = 2 / (3 * beta * mp.sqrt(3 * mp.mpf(0.5) * beta))
    assert float(exact) == pytest.approx(1.7213259e13, rel=1e-7)
    v = verdict(m, order=1, amplitude=1e14, with_norms=False)
    assert math.isfinite(v.radius) and v.verdict != "stable"
    assert v.radius == pytest.approx(float(exact), rel=2e-9)
    assert verdict(m, order=1, amplitude=1e13, with_norms=False).verdict == "stable"


@pytest.mark.parametrize("k", [-150, 0, 150])
def test_proven_radius_and_majorant_upper(k: int) -> None:
    m = parse_model(scaled_text(1.0, 0.3, 2.0, -0.7, 1.5, k))
    _, h3, r_star = second_order_references(m)
    maj = majorant(m)
    assert maj.proven_upper(3) >= h3  # ||H3|| is attained by the majorant: no rounding slack
    assert kernel_norm(m, 3).upper >= h3
    rad = radius(lambda x, r: maj.rhs(x, r), len(maj.powers))
    assert rad.certified_below <= r_star
    assert maj.proves(rad.solution, rad.certified_below)
    # beyond the branch point no supersolution exists: the ball check must refuse
    assert not maj.proves(rad.solution, float(r_star) * 1.001)
    assert verdict(m, order=1, amplitude=0.1, with_norms=False).radius_proof == "interval"


def test_radius_of_a_linear_model_is_infinite() -> None:
    v = verdict(parse_model("D(y,2) + D(y) + y = u"), order=1, with_norms=False)
    assert math.isinf(v.radius)


# -- 5. axis decided exactly -------------------------------------------------------------
def test_tiny_damping_is_finite_and_exact() -> None:
    b = h1_norm(parse_model("D(y,2) + 1e-12*D(y) + y = u"))
    with mp.workdps(DPS):
        z = mp.mpf(1e-12)
        exact = 1 / (z * mp.sqrt(1 - z ** 2 / 4))
    assert b.lower <= exact <= b.upper and b.stable
    undamped = h1_norm(parse_model("D(y,2) + y = u"))
    assert math.isinf(undamped.upper) and undamped.stable is False


def test_exact_hurwitz_and_schur_against_rationals() -> None:
    # (s^2 + eps s + 1) with eps the smallest positive double is Hurwitz, eps = 0 is not
    assert hurwitz([1.0, 5e-324, 1.0]) and not hurwitz([1.0, 0.0, 1.0])
    assert not hurwitz([1.0, -5e-324, 1.0])
    # z^2 - (1 - 2^-52) has roots +-sqrt(1 - 2^-52) inside; z^2 - 1 on the circle
    assert schur([1.0, 0.0, -float(1 - Fraction(1, 2**52))]) and not schur([1.0, 0.0, -1.0])


# -- 6. NARX poles on the unit circle, cancellation --------------------------------------
def test_narx_pole_at_minus_one_is_infinite(capsys: pytest.CaptureFixture[str]) -> None:
    for sign in ("-", ""):
        data = run_json(capsys, "norm", f"y[k] = {sign}y[k-1] + 0.1*y[k-1]**3 + u[k-1]",
                        "--sample-time", "0.1", "--order", "1")
        assert data["upper"] == "inf" and data["stable"] is False
    # y[k] = -0.5 y[k-1] + u[k-1]: |q / (1 + 0.5 q)| peaks at q = -1: 1 / 0.5 = 2
    b = h1_norm(parse_model("y[k] = -0.5*y[k-1] + u[k-1]", sample_time=0.1))
    assert b.lower <= 2.0 <= b.upper and b.argmax[0] == pytest.approx(math.pi / 0.1)


def test_cancellation_is_reported_not_nan(capsys: pytest.CaptureFixture[str]) -> None:
    # H1 = s / (s^2 + s) = 1 / (s + 1) after the exact cancellation of s: sup = 1 at w = 0
    data = run_json(capsys, "norm", "D(y,2) + D(y) = D(u)", "--order", "1")
    assert data["lower"] <= 1.0 <= data["upper"] and data["upper"] == 1.0
    assert any("cancellation" in n for n in data["notes"])


# -- property: random stable models x random scales ----------------------------------------
@pytest.mark.slow
@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(a1=st.floats(1e-3, 3.0), a0=st.floats(0.1, 10.0),
       c3=st.floats(0.05, 2.0) | st.floats(-2.0, -0.05), b=st.floats(0.1, 3.0),
       k=st.integers(-200, 200))
def test_property_scale_invariance_and_containment(a1: float, a0: float, c3: float, b: float,
                                                   k: int) -> None:
    base = parse_model(scaled_text(1.0, a1, a0, c3, b, 0))
    scaled = parse_model(scaled_text(1.0, a1, a0, c3, b, k))
    h1_ref, h3_ref, r_ref = second_order_references(scaled)
    b1, b1_base = h1_norm(scaled), h1_norm(base)
    assert b1.lower <= h1_ref <= b1.upper
    assert b1.upper == pytest.approx(b1_base.upper, rel=1e-13)
    m3 = float(majorant(scaled).coefficients(3)[3, 0])
    assert m3 == pytest.approx(float(h3_ref), rel=1e-13)
    assert m3 == pytest.approx(float(majorant(base).coefficients(3)[3, 0]), rel=1e-13)
    b3, b3_base = kernel_norm(scaled, 3), kernel_norm(base, 3)
    assert b3.lower <= h3_ref * (1 + 1e-13) and b3.upper >= h3_ref  # float witness, proven upper
    assert b3.upper == pytest.approx(b3_base.upper, rel=1e-13)
    assert b3.lower == pytest.approx(b3_base.lower, rel=1e-9)
    v = verdict(scaled, order=1, amplitude=0.5, with_norms=False)
    assert v.radius == pytest.approx(float(r_ref), rel=2e-9)
    assert v.radius == pytest.approx(verdict(base, order=1, amplitude=0.5,
                                             with_norms=False).radius, rel=2e-9)
    assert v.verdict == ("stable" if 0.5 < float(r_ref) * (1 - 1e-8) else
                         "inconclusive" if 0.5 > float(r_ref) * (1 + 1e-8) else v.verdict)


@pytest.mark.parametrize("k", [-120, 130])
def test_h3_bracket_scaled_contains_reference(k: int) -> None:
    m = parse_model(scaled_text(1.0, 0.2, 2.0, 0.5, 1.0, k))
    _, h3, _ = second_order_references(m)
    b3 = kernel_norm(m, 3)
    # the lower end is a float witness (~1e-15), the upper the certified majorant
    assert b3.lower <= h3 * (1 + 1e-13) and b3.upper >= h3 * (1 - 1e-13)
    assert b3.gap <= 1e-9


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-10.0, 10.0).filter(lambda x: x == 0 or abs(x) > 1e-3),
                min_size=2, max_size=9).filter(lambda c: c[0] != 0))
def test_property_exact_stability_agrees_with_roots(c: list[float]) -> None:
    # reference: numpy roots (well conditioned here: moderate coefficients), used only
    # where every root is 1e-6 away from the boundary
    roots = np.roots(c)
    worst = float(np.max(roots.real))
    if abs(worst) > 1e-6:
        assert hurwitz(c) == (worst < 0)
        report = poles(c)
        assert report.stable == (worst < 0) and report.outside == (worst > 0)
    radius_ = float(np.max(np.abs(roots)))
    if abs(radius_ - 1) > 1e-6:
        assert schur(c) == (radius_ < 1)
