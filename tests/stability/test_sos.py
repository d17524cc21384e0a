"""Sum-of-squares certificates: exact re-checks, and independent simulations below them."""

from __future__ import annotations

import copy
import json
import math
from fractions import Fraction

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gfrf.cli import main
from gfrf.model.equation import parse_model
from gfrf.stability.polysys import peval, state_form
from gfrf.stability.sos import sos_certificate
from gfrf.stability.sos_check import check_dict, is_psd, poly_from, vdot

DAMPING = "D(y,2) + 0.4*D(y) + 2*y + 0.5*y**2*D(y) + 0.8*y**3 = u"
CUBIC_DAMPING = "D(y,2) + 0.2*D(y) + y - 0.3*D(y)**3 = u"


@pytest.fixture(scope="module")
def local() -> tuple:
    system = state_form(parse_model(CUBIC_DAMPING))
    res, _ = sos_certificate(system, global_search=False, degree=2)
    assert res is not None
    return system, res


def _rhs(u):
    def f(t, z):
        return [z[1], -0.2 * z[1] - z[0] + 0.3 * z[1] ** 3 + u(t, z)]
    return f


def test_companion_form_reproduces_the_equation() -> None:
    """f(x, u) of the state form against the equation solved by hand for y''."""
    system = state_form(parse_model(DAMPING))
    pts = np.random.default_rng(1).uniform(-2, 2, size=(50, 3))
    y, yd, u = pts.T
    assert np.allclose(peval(system.f[0], pts), yd)
    assert np.allclose(peval(system.f[1], pts), -0.4 * yd - 2 * y - 0.5 * y**2 * yd
                       - 0.8 * y**3 + u)


def test_exact_psd_agrees_with_eigenvalues() -> None:
    rng = np.random.default_rng(2)
    for _ in range(20):
        B = rng.integers(-3, 4, size=(5, 5))
        A = B @ B.T - rng.integers(0, 3) * np.eye(5, dtype=int)
        Q = [[Fraction(int(x)) for x in row] for row in A]
        eig = np.linalg.eigvalsh(A.astype(float))
        if abs(eig.min()) > 1e-9:
            assert is_psd(Q) == (eig.min() > 0)


def test_global_certificate_of_nonlinear_damping_and_bang_bang_runs(capsys) -> None:
    """lower = inf (bounded for every bounded input): large bang-bang and square-wave
    inputs stay bounded in DOP853 runs."""
    assert main(["threshold", DAMPING, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["lower"] == "inf" and data["lower_proof"] == "interval"
    assert "sum-of-squares" in data["lower_method"]
    for u in (lambda t, z: 20.0 * math.copysign(1.0, z[1]),
              lambda t, z: 20.0 * math.copysign(1.0, math.sin(1.3 * t))):
        sol = solve_ivp(lambda t, z, u=u: [z[1], -0.4 * z[1] - 2 * z[0] - 0.5 * z[0]**2 * z[1]
                                           - 0.8 * z[0]**3 + u(t, z)],
                        (0, 60), [0.0, 0.0], method="DOP853", rtol=1e-8, atol=1e-10,
                        max_step=0.05)
        assert sol.status == 0 and np.max(np.abs(sol.y)) < 100


def test_inputs_below_lower_stay_in_the_invariant_set(local) -> None:
    """Square wave, bang-bang on the sign of dV/du and a random sum of tones, all with
    sup|u| <= U: V along a DOP853 run never exceeds c (the exact check's claim)."""
    system, res = local
    cert = res.certificate
    V = poly_from(cert["V"], 3)
    c = float(Fraction(cert["c"]))
    U = res.radius
    rng = np.random.default_rng(3)
    amps = rng.uniform(size=4)
    amps *= U / amps.sum()
    ws, ph = rng.uniform(0.3, 3, size=4), rng.uniform(0, 2 * np.pi, size=4)
    dVdp = [(k, float(x)) for k, x in V.items() if k[1]]
    for u in (lambda t, z: U * math.copysign(1.0, math.sin(0.95 * t)),
              lambda t, z: U * math.copysign(1.0, sum(x * k[1] * z[0]**k[0] * z[1]**(k[1] - 1)
                                                      for k, x in dVdp)),
              lambda t, z: float(np.sum(amps * np.cos(ws * t + ph)))):
        sol = solve_ivp(_rhs(u), (0, 80), [0.0, 0.0], method="DOP853", rtol=1e-9,
                        atol=1e-12, max_step=0.05)
        pts = np.hstack([sol.y.T, np.zeros((sol.y.shape[1], 1))])
        assert sol.status == 0 and np.max(peval(V, pts)) <= c * (1 + 1e-6)


def test_sampling_agrees_with_the_exact_check(local) -> None:
    """dV/dt < 0 at random points of {V = c} for |u| <= U (what the exact identity proves)."""
    system, res = local
    cert = res.certificate
    V = poly_from(cert["V"], 3)
    c = float(Fraction(cert["c"]))
    P = np.array([[float(V.get((2, 0, 0), 0)), float(V.get((1, 1, 0), 0)) / 2],
                  [float(V.get((1, 1, 0), 0)) / 2, float(V.get((0, 2, 0), 0))]])
    s = np.random.default_rng(4).normal(size=(4000, 2))
    s /= np.linalg.norm(s, axis=1, keepdims=True)
    x = math.sqrt(c) * np.linalg.solve(np.linalg.cholesky(P).T, s.T).T
    dv = vdot(V, system)
    for frac in (-1, -0.5, 0, 0.5, 1):
        pts = np.hstack([x, np.full((len(x), 1), frac * res.radius)])
        assert np.all(peval(dv, pts) < 0)
    # and beyond the proven radius far enough, sampling finds a violation somewhere
    pts = np.hstack([x, np.full((len(x), 1), 50 * res.radius)])
    assert np.any(peval(dv, pts) > 0)


def test_perturbed_certificate_is_refused(local, tmp_path, capsys) -> None:
    system, res = local
    assert check_dict(system, res.certificate) == ""
    bad = copy.deepcopy(res.certificate)
    Q = bad["multipliers"]["sigma"]["Q"]
    Q[2][2] = str(Fraction(Q[2][2]) + Fraction(1, 10**9))
    assert "identity fails" in check_dict(system, bad)
    good, wrong = tmp_path / "good.json", tmp_path / "bad.json"
    good.write_text(json.dumps(res.certificate))
    wrong.write_text(json.dumps(bad))
    assert main(["certificate", "check", CUBIC_DAMPING, str(good)]) == 0
    assert capsys.readouterr().out.startswith("holds")
    assert main(["certificate", "check", CUBIC_DAMPING, str(wrong), "--json"]) == 1
    assert json.loads(capsys.readouterr().out)["valid"] is False
    # another model is refused too
    assert main(["certificate", "check", "D(y,2) + 0.2*D(y) + y - 0.4*D(y)**3 = u",
                 str(good)]) == 1


@pytest.mark.slow
def test_tone_radius_is_not_the_lower(capsys) -> None:
    """Theorem 1's r* = 0.0628 covers sums of tones only; a square wave of sup 0.0616
    blows up, so the top-level lower (every input with sup|u| <= lower) stays below it."""
    assert main(["threshold", CUBIC_DAMPING, "--json"]) in (0, 1)
    data = json.loads(capsys.readouterr().out)
    assert data["lower"] < 0.0616 and data["lower_class"].startswith("every input")
    r_star = data["certificates"][0]
    assert r_star["radius"] > 0.0616 and "sums of tones" in r_star["input_class"]
    sol = solve_ivp(_rhs(lambda t, z: 0.0616 * math.copysign(1.0, math.sin(t))), (0, 200),
                    [0.0, 0.0], method="DOP853", rtol=1e-9, atol=1e-12, max_step=0.05,
                    events=lambda t, z: abs(z[1]) - 1e3)
    assert sol.t_events[0].size or np.max(np.abs(sol.y)) > 10


@pytest.mark.slow
def test_pi_loop_gets_a_finite_proven_lower() -> None:
    """A PI loop (integral state) is a polynomial system: a finite proven lower > 0."""
    import gfrf
    from gfrf.model.modelfile import Controller, ModelFile

    mf = ModelFile(plant=parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"),
                   controller=Controller(num=(0.5, 0.2), den=(1.0, 0.0)))
    t = gfrf.threshold(mf)
    assert 0 < t.lower < math.inf and t.lower_proof == "interval"


@pytest.mark.slow
def test_third_order_plant_inputs_below_lower_stay_in_the_set() -> None:
    """y''' + 1.2y'' + 3y' + y + 0.6y^2 + y^3 = 2u (from_tf with a feedback nonlinearity):
    square waves, bang-bang on dV/du and random tone sums with sup|u| <= lower keep V <= c
    in DOP853 runs, and never escape."""
    import control

    import gfrf

    model = gfrf.from_tf(control.tf([2], [1, 1.2, 3, 1]), {2: 0.3, 3: 0.5})
    system = state_form(model)
    res, _ = sos_certificate(system, global_search=False)
    assert res is not None
    V = poly_from(res.certificate["V"], 4)
    c = float(Fraction(res.certificate["c"]))
    U = res.radius
    g = [(k, float(x)) for k, x in V.items() if k[2]]  # dV/dx3 (input drives x3)
    rng = np.random.default_rng(5)
    amps = rng.uniform(size=5)
    amps *= U / amps.sum()
    ws, ph = rng.uniform(0.2, 4, size=5), rng.uniform(0, 2 * np.pi, size=5)

    def rhs(u):
        return lambda t, z: [z[1], z[2], -1.2 * z[2] - 3 * z[1] - z[0] - 0.6 * z[0]**2
                             - z[0]**3 + 2 * u(t, z)]

    def dvdx3(z):
        return sum(x * k[2] * z[0]**k[0] * z[1]**k[1] * z[2]**(k[2] - 1) for k, x in g)

    for u in (lambda t, z: U * math.copysign(1.0, math.sin(0.7 * t)),
              lambda t, z: U * math.copysign(1.0, dvdx3(z)),
              lambda t, z: float(np.sum(amps * np.cos(ws * t + ph)))):
        sol = solve_ivp(rhs(u), (0, 60), [0.0, 0.0, 0.0], method="DOP853", rtol=1e-9,
                        atol=1e-12, max_step=0.05)
        pts = np.hstack([sol.y.T, np.zeros((sol.y.shape[1], 1))])
        assert sol.status == 0 and np.max(peval(V, pts)) <= c * (1 + 1e-6)
