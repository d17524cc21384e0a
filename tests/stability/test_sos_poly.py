"""Degree-4 storage functions (V-lambda iteration): exact re-checks, sampling on the level
set, and DOP853 runs with square-wave, bang-bang and tone inputs below the proven radius."""

from __future__ import annotations

import copy
import math
from fractions import Fraction

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gfrf.model.equation import parse_model
from gfrf.stability.polysys import pdiff, peval, state_form
from gfrf.stability.sos import sos_certificate
from gfrf.stability.sos_check import check_dict, poly_from, vdot

CUBIC_DAMPING = "D(y,2) + 0.2*D(y) + y - 0.3*D(y)**3 = u"


@pytest.fixture(scope="module")
def quartic() -> tuple:
    system = state_form(parse_model(CUBIC_DAMPING))
    res, _ = sos_certificate(system, global_search=False)
    quad, _ = sos_certificate(system, global_search=False, degree=2)
    assert res is not None and quad is not None
    return system, res, quad


def _level_points(V, n: int, count: int, seed: int) -> np.ndarray:
    """Points of {V = 1} on random rays: the smallest positive root of V(s d) = 1."""
    rng = np.random.default_rng(seed)
    out = []
    deg = max(sum(k) for k in V)
    for d in rng.normal(size=(count, n)):
        coef = np.zeros(deg + 1)
        for k, c in V.items():
            coef[deg - sum(k)] += float(c) * np.prod(d ** np.asarray(k[:-1]))
        coef[deg] -= 1.0
        roots = np.roots(coef)
        s = min(r.real for r in roots if abs(r.imag) < 1e-9 and r.real > 0)
        out.append(s * d)
    return np.array(out)


def _run_stays_in(V, rhs, inputs, n: int, t_end: float) -> None:
    for u in inputs:
        sol = solve_ivp(rhs(u), (0, t_end), np.zeros(n), method="DOP853", rtol=1e-9,
                        atol=1e-12, max_step=0.05)
        pts = np.hstack([sol.y.T, np.zeros((sol.y.shape[1], 1))])
        assert sol.status == 0
        assert np.max(peval(V, pts)) <= 1 + 1e-6


def test_quartic_certificate_holds_and_beats_the_quadratic(quartic) -> None:
    system, res, quad = quartic
    cert = res.certificate
    assert check_dict(system, cert) == ""
    assert max(sum(k) for k, _ in cert["V"]) == 4 and cert["c"] == "1"
    assert res.radius > quad.radius
    # a square wave of sup 0.0616 blows up (a DOP853 run): the radius stays below it
    assert res.radius < 0.0616


def test_sampling_on_the_level_set_agrees(quartic) -> None:
    """dV/dt < 0 at sampled points of {V = 1} for |u| <= U (the exact identity's claim),
    and V >= gamma |x|^2 there."""
    system, res, _ = quartic
    V = poly_from(res.certificate["V"], 3)
    x = _level_points(V, 2, 3000, seed=6)
    assert np.all(np.sum(x**2, axis=1) <= 1 / float(Fraction(res.certificate["gamma"])))
    dv = vdot(V, system)
    for frac in np.linspace(-1, 1, 9):
        pts = np.hstack([x, np.full((len(x), 1), frac * res.radius)])
        assert np.all(peval(dv, pts) < 0)


def test_perturbed_quartic_certificate_is_refused(quartic) -> None:
    system, res, _ = quartic
    for block, text in (("sigma_V", "differs from its SOS"), ("sigma", "identity fails")):
        bad = copy.deepcopy(res.certificate)
        Q = bad["multipliers"][block]["Q"]
        Q[1][1] = str(Fraction(Q[1][1]) + Fraction(1, 10**9))
        assert text in check_dict(system, bad)
    bad = copy.deepcopy(res.certificate)
    del bad["gamma"]  # a quartic V without its radial bound is not accepted
    assert "quadratic form" in check_dict(system, bad)


def test_inputs_below_the_quartic_radius_stay_in_the_set(quartic) -> None:
    """Square wave, bang-bang on the sign of dV/du and a tone sum with sup|u| <= U."""
    _, res, _ = quartic
    V = poly_from(res.certificate["V"], 3)
    U = res.radius
    g = pdiff(V, 1)

    def rhs(u):
        return lambda t, z: [z[1], -0.2 * z[1] - z[0] + 0.3 * z[1] ** 3 + u(t, z)]

    def bang(t, z):
        return U * math.copysign(1.0, float(peval(g, np.array([[z[0], z[1], 0.0]]))[0]))

    _run_stays_in(V, rhs, (bang, lambda t, z: U * math.copysign(1.0, math.sin(0.95 * t)),
                           lambda t, z: 0.5 * U * (math.cos(t) + math.cos(1.7 * t + 1))),
                  2, 30)


@pytest.mark.slow
def test_third_order_plant_lower_within_a_factor_one_and_a_half_of_an_escape() -> None:
    """y''' + 1.2y'' + 3y' + y + 0.6y^2 + y^3 = 2u: inputs below the proven radius stay in
    {V <= 1}; a square wave of 1.5 times the radius escapes in a DOP853 run, so the
    proven radius is within a factor 1.5 of instability."""
    import control

    import gfrf

    system = state_form(gfrf.from_tf(control.tf([2], [1, 1.2, 3, 1]), {2: 0.3, 3: 0.5}))
    res, _ = sos_certificate(system, global_search=False)
    assert res is not None and check_dict(system, res.certificate) == ""
    V = poly_from(res.certificate["V"], 4)
    U = res.radius
    g = pdiff(V, 2)

    def rhs(u):
        return lambda t, z: [z[1], z[2], -1.2 * z[2] - 3 * z[1] - z[0] - 0.6 * z[0] ** 2
                             - z[0] ** 3 + 2 * u(t, z)]

    def bang(t, z):
        return U * math.copysign(1.0, float(peval(g, np.array([[*z, 0.0]]))[0]))

    _run_stays_in(V, rhs, (bang, lambda t, z: U * math.copysign(1.0, math.sin(0.7 * t)),
                           lambda t, z: -U * math.copysign(1.0, math.sin(1.5 * t))), 3, 60)
    A = 1.5 * U

    def big(t, z):
        return abs(z[0]) - 1e3

    big.terminal = True  # type: ignore[attr-defined]
    sol = solve_ivp(rhs(lambda t, z: A * math.copysign(1.0, math.sin(1.5 * t))), (0, 150),
                    np.zeros(3), method="DOP853", rtol=1e-9, atol=1e-12, events=big)
    assert sol.status == 1


@pytest.mark.slow
def test_pi_loop_references_below_lower_stay_in_the_set() -> None:
    """Plant y'' + 0.2y' + y + 0.5y^3 = u under u = 0.5(r - y) + 0.2 int(r - y): square
    waves and bang-bang references with sup|r| <= lower keep V <= 1 (written by hand,
    states y, y', the integral of r - y)."""
    from gfrf.model.modelfile import Controller, ModelFile

    mf = ModelFile(plant=parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"),
                   controller=Controller(num=(0.5, 0.2), den=(1.0, 0.0)))
    system = state_form(mf)
    res, _ = sos_certificate(system)
    assert res is not None and 0 < res.radius < math.inf
    assert check_dict(system, res.certificate) == ""
    V = poly_from(res.certificate["V"], 4)
    R = res.radius
    gy, gz = pdiff(V, 1), pdiff(V, 2)

    def rhs(r):
        def f(t, s):
            e = r(t, s) - s[0]
            return [s[1], -0.2 * s[1] - s[0] - 0.5 * s[0] ** 3 + 0.5 * e + 0.2 * s[2], e]
        return f

    def bang(t, s):  # the reference enters y'' (0.5) and z' (1): sign of dV/dr
        p = np.array([[*s, 0.0]])
        return R * math.copysign(1.0, 0.5 * float(peval(gy, p)[0]) + float(peval(gz, p)[0]))

    _run_stays_in(V, rhs, (bang, lambda t, s: R * math.copysign(1.0, math.sin(0.6 * t)),
                           lambda t, s: R * math.copysign(1.0, math.sin(2.0 * t))), 3, 60)


THIRD_ORDER_PI = {"equation": "D(y,3) + 1.2*D(y,2) + 3*D(y) + y + 0.6*y**2 + y**3 = 2*u",
                  "controller": {"num": [0.5, 0.2], "den": [1.0, 0.0]}}


@pytest.fixture(scope="module")
def third_order_pi() -> tuple:
    """The third-order plant under u = 0.5(r - y) + 0.2 int(r - y): four states, so the
    quartic V has the structured bases (the full ones exceed MAX_GRAM)."""
    from gfrf.model.modelfile import model_from_dict

    system = state_form(model_from_dict(THIRD_ORDER_PI))
    res, _ = sos_certificate(system)
    assert res is not None
    return system, res


def _third_order_loop(r):
    """The loop written by hand: states y, y', y'', z = int(r - y)."""
    def f(t, s):
        e = r(t, s) - s[0]
        u = 0.5 * e + 0.2 * s[3]
        return [s[1], s[2], -1.2 * s[2] - 3 * s[1] - s[0] - 0.6 * s[0] ** 2 - s[0] ** 3 + 2 * u,
                e]
    return f


@pytest.mark.slow
def test_third_order_pi_loop_references_below_lower_stay_in_the_set(third_order_pi) -> None:
    """A quartic V (exactly re-checked) whose radius is more than half of a square wave
    that escapes (DOP853); random tone sums, square waves and bang-bang references on the
    sign of dV/dr with sup|r| <= lower keep V <= 1."""
    system, res = third_order_pi
    cert = res.certificate
    assert check_dict(system, cert) == ""
    assert max(sum(k) for k, _ in cert["V"]) == 4 and cert["c"] == "1"
    V = poly_from(cert["V"], 5)
    R = res.radius
    assert 0 < R < math.inf
    gw, gz = pdiff(V, 2), pdiff(V, 3)

    def bang(t, s):  # r enters y''' (2 * 0.5) and z' (1)
        p = np.array([[*s, 0.0]])
        return R * math.copysign(1.0, float(peval(gw, p)[0]) + float(peval(gz, p)[0]))

    rng = np.random.default_rng(3)
    tones = []
    for _ in range(3):
        w = rng.uniform(0.2, 3.0, size=3)
        ph = rng.uniform(0, 2 * math.pi, size=3)
        a = rng.dirichlet(np.ones(3)) * R  # sum of amplitudes = R: sup|r| <= R
        tones.append(lambda t, s, a=a, w=w, ph=ph: float(np.sum(a * np.cos(w * t + ph))))
    squares = [lambda t, s, w=w: R * math.copysign(1.0, math.sin(w * t)) for w in (0.4, 1.1)]
    _run_stays_in(V, _third_order_loop, (bang, *squares, *tones), 4, 60)

    def big(t, s):
        return abs(s[0]) - 1e3

    big.terminal = True  # type: ignore[attr-defined]
    A = 2 * R
    sol = solve_ivp(_third_order_loop(lambda t, s: A * math.copysign(1.0, math.sin(1.6 * t))),
                    (0, 200), np.zeros(4), method="DOP853", rtol=1e-9, atol=1e-12, events=big)
    assert sol.status == 1


@pytest.mark.slow
def test_third_order_pi_loop_perturbed_certificate_file_is_refused(third_order_pi, tmp_path,
                                                                   cli) -> None:
    import json

    _, res = third_order_pi
    model = tmp_path / "loop.toml"
    model.write_text('equation = "D(y,3) + 1.2*D(y,2) + 3*D(y) + y + 0.6*y**2 + y**3 = 2*u"\n'
                     "[controller]\nnum = [0.5, 0.2]\nden = [1.0, 0.0]\n", encoding="utf-8")
    good = tmp_path / "good.json"
    good.write_text(json.dumps(res.certificate), encoding="utf-8")
    assert cli("certificate", "check", str(model), str(good))[0] == 0
    for block in ("sigma", "mu", "sigma_V"):
        bad = copy.deepcopy(res.certificate)
        Q = bad["multipliers"][block]["Q"]
        Q[0][0] = str(Fraction(Q[0][0]) + Fraction(1, 10**9))
        path = tmp_path / f"bad_{block}.json"
        path.write_text(json.dumps(bad), encoding="utf-8")
        assert cli("certificate", "check", str(model), str(path))[0] == 1, block
