"""The implicit loop form of a plant under an improper controller, and its exactly
checked invariant polygon, against a hand-written cart-pole loop simulated by DOP853."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gfrf.model.modelfile import load_model
from gfrf.stability.implicit import implicit_form
from gfrf.stability.implicit_check import check_region
from gfrf.stability.implicit_region import certificate_at
from gfrf.stability.polysys import StateFormError
from tests.conftest import MODELS

A, B, C = 15.6, 379.3, 0.1331


def _theta_ddot(th: float, dth: float, u_without: float, full: bool) -> float:
    """eq (12) (or (16)) solved for theta'' with u = u_without - A theta'' (by hand)."""
    k = 39.3185 - 19.66 * th**2
    extra_m = 0.1475 * th**2 if full else 0.0
    extra_r = 0.1475 * th * dth**2 if full else 0.0
    # (1 + extra_m) th'' - 67.578 th + 11.2455 th^3 + extra_r + k (u_without - A th'') = 0
    return -(-67.578 * th + 11.2455 * th**3 + extra_r + k * u_without) / (1 + extra_m - A * k)


def _loop(d_of_t, full: bool = True):
    def rhs(t: float, x: np.ndarray) -> list[float]:
        th, dth = x
        return [dth, _theta_ddot(th, dth, d_of_t(t) - B * dth - C * th, full)]
    return rhs


@pytest.fixture(scope="module")
def cartpole():
    return implicit_form(load_model(MODELS / "cartpole.toml"))


@pytest.fixture(scope="module")
def certificate(cartpole):
    cert = certificate_at(cartpole, 100.0)
    assert cert is not None
    return cert


def test_state_form_matches_the_model_and_controller_with_a_smooth_reference(cartpole):
    w = 0.7
    r = (lambda t: 0.05 * np.sin(w * t), lambda t: 0.05 * w * np.cos(w * t),
         lambda t: -0.05 * w * w * np.sin(w * t))

    def direct(t: float, x: np.ndarray) -> list[float]:
        # u = C(r - theta) with r's derivatives: u = A (r'' - th'') + B (r' - th') + C (r - th)
        th, dth = x
        u_without = A * r[2](t) + B * (r[1](t) - dth) + C * (r[0](t) - th)
        return [dth, _theta_ddot(th, dth, u_without, True)]

    def form(t: float, x: np.ndarray) -> list[float]:
        d = A * r[2](t) + B * r[1](t) + C * r[0](t)
        return cartpole.field(list(x), d)

    ts = np.linspace(0, 4, 21)
    a = solve_ivp(direct, (0, 4), [0.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-14,
                  t_eval=ts)
    b = solve_ivp(form, (0, 4), [0.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-14, t_eval=ts)
    assert np.max(np.abs(a.y)) > 1e-3
    assert np.max(np.abs(a.y - b.y)) < 1e-8


def test_the_coefficient_of_theta_ddot_is_the_printed_one(cartpole):
    # 1 + 0.1475 th^2 - a (39.3185 - 19.66 th^2), times the sign of D(0) < 0
    assert cartpole.sign == -1
    assert float(cartpole.D[(0, 0, 0)]) == pytest.approx(1 - A * 39.3185, rel=1e-12)
    assert float(cartpole.D[(2, 0, 0)]) == pytest.approx(0.1475 + A * 19.66, rel=1e-12)


def test_a_controller_with_dynamics_has_no_implicit_form() -> None:
    from gfrf.model.equation import parse_model
    from gfrf.model.modelfile import Controller, ModelFile

    mf = ModelFile(plant=parse_model("D(y,2) + y + y**2*D(y,2) = u"),
                   controller=Controller(num=(1.0, 1.0), den=(1.0, 2.0)))
    with pytest.raises(StateFormError, match="dynamics"):
        implicit_form(mf)


def test_the_exact_check_refuses_a_perturbed_polygon(cartpole, certificate):
    assert check_region(cartpole, certificate) == ""
    bigger = dict(certificate, U=str(Fraction(certificate["U"]) * 3))
    assert "does not point strictly into" in check_region(cartpole, bigger)
    moved = [list(v) for v in certificate["vertices"]]
    i = len(moved) // 4
    moved[i] = [moved[i][0], str(Fraction(moved[i][1]) * 2)]
    assert check_region(cartpole, dict(certificate, vertices=moved)) != ""
    # a stated breakdown level the polygon does not keep (|D| down to 1/2 |D(0)|) is refused
    assert "not bounded away from 1/2" in check_region(cartpole, dict(certificate, level="1/2"))
    past = [list(v) for v in certificate["vertices"]]
    right = max(range(len(past)), key=lambda j: Fraction(past[j][0]))
    past[right] = ["3/2", past[right][1]]  # beyond the zero of D at |theta| = 1.41269
    assert check_region(cartpole, dict(certificate, vertices=past)) != ""


def test_bounded_inputs_below_the_certificate_never_leave_the_polygon(certificate):
    U = 0.99 * float(Fraction(certificate["U"]))
    ymax = max(abs(float(Fraction(v[0]))) for v in certificate["vertices"])
    rng = np.random.default_rng(5)
    inputs = [lambda t: U, lambda t: -U,
              lambda t: U * np.sign(np.sin(0.5 * t)), lambda t: U * np.sign(np.sin(3.0 * t))]
    for _ in range(3):
        a = rng.uniform(0, 1, 3)
        a = a / a.sum()
        w = rng.uniform(0.05, 30, 3)
        inputs.append(lambda t, a=a, w=w: U * float(np.sum(a * np.cos(w * t))))
    for d in inputs:
        sol = solve_ivp(_loop(d), (0, 15), [0.0, 0.0], method="DOP853", rtol=1e-9,
                        atol=1e-12, max_step=0.05)
        assert sol.status == 0
        assert np.max(np.abs(sol.y[0])) <= ymax
