"""Tests of gfrf.stability.loops: closed-loop polynomials derived by hand, sign conventions."""

from __future__ import annotations

import math
from collections.abc import Callable
from fractions import Fraction

import control
import numpy as np
import pytest

from gfrf.bounds.rational import rational_sup
from gfrf.errors import ArgumentError
from gfrf.model.modelfile import load_model, model_from_dict
from gfrf.papers.gfrf_paper import loop_sign_variants
from gfrf.stability.loops import closed_loop, controller_tf, linear_plant, with_lags

CARTPOLE = "models/cartpole_reduced.toml"


def test_cartpole_characteristic_by_hand() -> None:
    # theta'' - 67.578 theta + 39.3185 u = 0: H1 = -39.3185 / (s^2 - 67.578);
    # u = (15.6 s^2 + 379.3 s + 0.1331)(r - theta):
    # chi = (s^2 - 67.578) + (-39.3185)(15.6 s^2 + 379.3 s + 0.1331)
    loop = closed_loop(load_model(CARTPOLE))
    expected = [1 - 39.3185 * 15.6, -39.3185 * 379.3, -67.578 - 39.3185 * 0.1331]
    assert loop.characteristic == pytest.approx(expected, rel=1e-12)
    assert loop.stable and not loop.plant_stable
    a, b, c = expected
    disc = math.sqrt(b * b - 4 * a * c)
    roots = sorted([(-b + disc) / (2 * a), (-b - disc) / (2 * a)])
    assert sorted(loop.poles.real) == pytest.approx(roots, rel=1e-9)


def test_cartpole_sensitivity_peak_at_zero() -> None:
    loop = closed_loop(load_model(CARTPOLE))
    expected = 67.578 / (67.578 + 39.3185 * 0.1331)
    assert loop.sensitivity_peak == pytest.approx(expected, rel=1e-12)
    w = np.linspace(0, 200, 200001)
    sens = np.abs(np.polyval([1, 0, -67.578], 1j * w) / np.polyval(loop.characteristic, 1j * w))
    assert sens.max() <= loop.sensitivity_peak * (1 + 1e-12)


def test_improper_controller_reported() -> None:
    loop = closed_loop(load_model(CARTPOLE))
    assert not loop.controller_proper and math.isinf(loop.controller_norm)
    assert any("improper" in n for n in loop.notes)
    # python-control agrees on the closed-loop poles
    cl = control.feedback(loop.plant, loop.controller)
    assert sorted(control.poles(cl).real) == pytest.approx(sorted(loop.poles.real), rel=1e-9)


def test_positive_feedback_unstable() -> None:
    loop = closed_loop(load_model(CARTPOLE), feedback=1)
    assert not loop.stable
    assert max(loop.poles.real) > 0


def _lagged(t: float) -> dict:
    return {"equation": "D(y,2) + D(y) + 2*y + 0.1*y**3 = u",
            "controller": {"num": [1.0, 2.0], "den": [t**2, 2 * t, 1.0]}}


def test_proper_controller_norm() -> None:
    mf = model_from_dict(_lagged(0.1))
    loop = closed_loop(mf)
    w = np.linspace(0, 100, 400001)
    grid = np.abs(np.polyval([1.0, 2.0], 1j * w) / np.polyval([0.01, 0.2, 1.0], 1j * w)).max()
    assert loop.controller_proper
    assert grid <= loop.controller_norm <= grid * (1 + 1e-6)


def test_transfer_function_objects() -> None:
    mf = load_model(CARTPOLE)
    assert control.poles(linear_plant(mf.plant)).real.max() == pytest.approx(math.sqrt(67.578))
    assert controller_tf(mf.controller).num[0][0].tolist() == [15.6, 379.3, 0.1331]
    narx = linear_plant(load_model("models/narx_example.toml").plant)
    assert narx.dt == 0.1


def test_no_controller_refused() -> None:
    with pytest.raises(ArgumentError, match="controller"):
        closed_loop(load_model("models/duffing.toml"))


def test_paper_sign_convention() -> None:
    variants = loop_sign_variants()
    good = [v for v in variants if v["reproduces"]]
    assert len(good) == 2
    for v in good:
        assert v["plant_denominator"] == "s^2 + 67.568"
        assert v["b"] == pytest.approx(12554 / 39.3185)
        assert v["gain"] * -v["feedback"] > 0  # loop gain +39.3185 s1 in chi
    own = next(v for v in variants if v["gain"] < 0 and v["plant_denominator"] == "s^2 - 67.568"
               and v["feedback"] == -1 and v["b"] == 379.3)
    assert own["stable"] and not own["reproduces"]


def test_stiff_closed_loop_poles() -> None:
    # chi = 612.3686 s^2 + 12554 s + 72.80: poles ~ -20.5 and -0.0058 (ratio ~3500)
    own = next(v for v in loop_sign_variants() if v["gain"] < 0 and v["feedback"] == -1
               and v["plant_denominator"] == "s^2 - 67.568" and v["b"] != 379.3)
    a, b, c = own["characteristic"]
    p = sorted(z.real for z in own["poles"])
    assert p[0] * p[1] == pytest.approx(c / a, rel=1e-10)
    assert p[0] + p[1] == pytest.approx(-b / a, rel=1e-12)
    assert p[0] < -20 and -0.01 < p[1] < 0


def test_neglected_lags_destabilise_the_model_sign_loop() -> None:
    # chi = (s^2 - 67.578)(T s + 1)^3 - 39.3185 (15.6 s^2 + 379.3 s + 0.1331): for any
    # T > 0 the s^5 coefficient T^3 > 0 while the s^2 coefficient ~ 1 - 613 < 0, so
    # the coefficients change sign and the loop is unstable (it is stable at T = 0 only
    # because the improper controller flips the leading coefficient).
    mf = load_model(CARTPOLE)
    assert closed_loop(with_lags(mf, (0.0, 0.0, 0.0))).stable
    for t in (1e-2, 1e-3):
        loop = closed_loop(with_lags(mf, (t, t, t)))
        assert loop.controller_proper and not loop.stable
    with pytest.raises(ArgumentError):
        with_lags(mf, (-1.0,))


# -- exact closed-loop polynomial and stability (float roots misclassify) ---------------
CLUSTER_C = [1.0, 4e-06, 2.000000000004, 4e-06, 1.0]  # (s^2 + 2e-6 s + 1)^2 in floats


def _cluster_loop(gain: float) -> dict:
    """Plant 1/(s^2 + 2e-6 s + 1), controller gain/(s^2 + 2e-6 s + 1)^2, negative
    feedback: chi = (s^2 + 2e-6 s + 1)^3 (floats) + gain, a triple cluster at +-j."""
    return {"name": "cluster loop", "equation": "D(y,2) + 2e-6*D(y) + y = u",
            "controller": {"num": [gain], "den": CLUSTER_C, "feedback": -1}}


def _mp_max_real(chi: list) -> float:
    """Largest real part of the roots of the exact chi at 60 digits (mpmath)."""
    import mpmath as mp

    with mp.workdps(60):
        roots = mp.polyroots([mp.mpf(c.numerator) / c.denominator for c in chi],
                             maxsteps=500, extraprec=800)
        return float(max(mp.re(r) for r in roots))


@pytest.mark.parametrize(("gain", "stable"), [(1e-20, True), (1e-14, False)])
def test_cluster_loop_decided_exactly(gain: float, stable: bool) -> None:
    """numpy.roots of the float chi puts the stable 1e-20 loop's cluster at Re = +2.3e-6;
    the exact chi (sympy-free: Fractions) and 60-digit roots say stable.  The decision
    and the poles are of the loop as written (decimals as exact rationals: the cluster
    moves by 6e-11 from the loop of the doubles)."""
    from fractions import Fraction

    loop = closed_loop(model_from_dict(_cluster_loop(gain)))

    def product(convert: Callable[[float], Fraction]) -> list[Fraction]:
        """Independent exact chi of the coefficients read by ``convert``."""
        plant, ctrl = [convert(c) for c in (1.0, 2e-6, 1.0)], [convert(c) for c in CLUSTER_C]
        chi = [Fraction(0)] * 7
        for i, a in enumerate(plant):
            for k, b in enumerate(ctrl):
                chi[i + k] += a * b
        chi[-1] += convert(gain)
        return chi

    assert list(loop.characteristic_exact) == product(Fraction)  # of the doubles
    chi = product(lambda c: Fraction(repr(c)))  # as written
    ref = _mp_max_real(chi)
    assert (ref < 0) is stable
    assert loop.stable is stable and loop.outside is (not stable)
    if stable:  # the float path this replaces gets it wrong
        assert np.max(np.roots([float(c) for c in chi]).real) > 0
        assert math.isfinite(loop.sensitivity_peak)
    assert max(p.real for p in loop.poles) == pytest.approx(ref, rel=1e-6)


def test_cluster_loop_verdict_is_not_unstable() -> None:
    """Theorem 2 calls a loop unstable only on an exact right-half-plane pole."""
    from gfrf.stability.theorem2 import theorem2

    v = theorem2(model_from_dict(_cluster_loop(1e-20)), order=1, amplitude=1e-3)
    assert v.verdict != "unstable"
    assert v.conditions[1].passed is True



def test_sensitivity_peak_proven_for_the_loop_as_written() -> None:
    # plant s^2 + c s + 1 with c = 0.1 + 0.2 - 0.3: 0 as written, 5.55e-17 in doubles;
    # the static controller 1 gives chi = s^2 + c s + 2: poles on the axis as written
    mf = model_from_dict({"equation": "D(y,2) + (0.1+0.2-0.3)*D(y) + y = u",
                          "controller": {"num": [1.0], "den": [1.0]}})
    doubles = rational_sup([1.0, 0.1 + 0.2 - 0.3, 1.0], [1.0, 0.1 + 0.2 - 0.3, 2.0])
    assert math.isfinite(doubles.upper)  # what a proof on the doubles would claim
    loop = closed_loop(mf)
    assert loop.sensitivity_peak_upper == math.inf and not loop.stable


def test_controller_norm_proven_for_the_written_rationals() -> None:
    # lambda_1 = sup |1 / (0.1 s + 0.3)| = 1 / 0.3 = 10/3 at w = 0 as written
    mf = model_from_dict({"equation": "D(y,2) + D(y) + 2*y = u",
                          "controller": {"num": [1.0], "den": [0.1, 0.3]}})
    upper = Fraction(closed_loop(mf).controller_norm_upper)
    assert Fraction(10, 3) <= upper <= Fraction(10, 3) * (1 + Fraction(1, 10**15))


def test_sensitivity_peak_enclosed_for_an_irrational_damping() -> None:
    # rho_1 = sup |(s^2 + c s + 1) / (s^2 + c s + 2)|, c = pi/10: in x = w^2 the ratio
    # ((1 - x)^2 + c^2 x) / ((2 - x)^2 + c^2 x), maximised by mpmath at 50 digits
    import mpmath

    mf = model_from_dict({"equation": "D(y,2) + pi/10*D(y) + y = u",
                          "controller": {"num": [1.0], "den": [1.0]}})
    loop = closed_loop(mf)
    with mpmath.workdps(50):
        c = mpmath.pi / 10

        def ratio(x: mpmath.mpf) -> mpmath.mpf:
            return ((1 - x) ** 2 + c * c * x) / ((2 - x) ** 2 + c * c * x)

        start = max((mpmath.mpf(i) / 100 for i in range(400)), key=ratio)
        peak = mpmath.sqrt(ratio(mpmath.findroot(lambda x: mpmath.diff(ratio, x), start)))
        assert loop.sensitivity_peak_upper >= peak
        assert loop.sensitivity_peak_upper <= peak * (1 + 1e-12)
