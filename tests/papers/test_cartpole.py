"""The paper-001 findings (cart-pole loop, input gain alpha, theta_3 reading).

Every number is pinned to an independent computation: Routh-Hurwitz and static series
in exact rationals (fractions.Fraction), closed forms of the pendulum majorant, direct
scipy integrations, python-control poles; never to copied outputs.
"""

from __future__ import annotations

import math
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from gfrf.model.modelfile import load_model
from gfrf.papers.cartpole import (
    inertia_reversal,
    lagged_loops,
    sign_margin,
    theorem2_obstruction,
)
from gfrf.papers.cartpole_trials import lagged_simulation, loop_drive
from gfrf.papers.gfrf_paper import alpha_variants, paper_checks, printed_match, theta_readings
from gfrf.sim.simulation import simulate
from gfrf.stability.loops import with_lags
from gfrf.stability.theorem2 import theta_series

MODELS = Path(__file__).resolve().parents[2] / "models"
REDUCED = MODELS / "cartpole_reduced.toml"
FULL = MODELS / "cartpole.toml"


def _q(x: float) -> Fraction:
    return Fraction(repr(float(x)))


def _constants(path: Path) -> dict[str, Fraction]:
    """The eq (16) constants as exact decimals, from the file's coefficient table."""
    mf = load_model(path)
    table = {r["monomial"]: _q(r["coefficient"]) for r in mf.plant.coefficient_table()}
    a, b, c = (_q(x) for x in mf.controller.num)
    return {"k": table["u"], "w2": -table["theta"], "cubic": table["theta**3"],
            "cross": -table["theta**2*u"], "a": a, "b": b, "c": c}


def _polymul(p: list[Fraction], q: list[Fraction]) -> list[Fraction]:
    out = [Fraction(0)] * (len(p) + len(q) - 1)
    for i, x in enumerate(p):
        for j, y in enumerate(q):
            out[i + j] += x * y
    return out


def _polyadd(p: list[Fraction], q: list[Fraction]) -> list[Fraction]:
    n = max(len(p), len(q))
    p, q = [Fraction(0)] * (n - len(p)) + p, [Fraction(0)] * (n - len(q)) + q
    return [x + y for x, y in zip(p, q, strict=True)]


def _routh_sign_changes(poly: list[Fraction]) -> int:
    """Sign changes of the Routh array's first column (= roots with Re s > 0); a zero in
    the first column (roots on the axis or symmetric about it) returns len(poly), which
    only means "not Hurwitz"."""
    poly = poly if poly[0] > 0 else [-x for x in poly]
    rows = [poly[0::2], poly[1::2]]
    width = len(rows[0])
    rows = [r + [Fraction(0)] * (width - len(r)) for r in rows]
    while len(rows) < len(poly):
        up, lo = rows[-2], rows[-1]
        if lo[0] == 0:
            return len(poly)
        rows.append([(lo[0] * up[i + 1] - up[0] * lo[i + 1]) / lo[0]
                     for i in range(width - 1)] + [Fraction(0)])
    first = [r[0] for r in rows]
    return sum((x > 0) != (y > 0) for x, y in zip(first, first[1:], strict=False))


def _loop_poly(k: dict[str, Fraction], sign: int, den_c: list[Fraction],
               c: Fraction | None = None) -> list[Fraction]:
    """chi = (s^2 - w2) D_C + sign k (a s^2 + b s + c): the model's u enters as +k u, and
    u = sign C theta, so theta'' - w2 theta + k sign C theta = 0."""
    cc = k["c"] if c is None else c
    return _polyadd(_polymul([Fraction(1), Fraction(0), -k["w2"]], den_c),
                    [sign * k["k"] * x for x in (k["a"], k["b"], cc)])


# --- the cart-pole loop ------------------------------------------------------------------

def test_ideal_loop_is_stable_only_by_reversing_the_inertia() -> None:
    k = _constants(REDUCED)
    result = inertia_reversal(load_model(REDUCED))
    expected = 1 - k["k"] * k["a"]  # 1 - 39.3185 * 15.6
    assert expected < 0 and result.reversed
    assert result.coefficient == pytest.approx(float(expected), rel=1e-12)
    chi = _loop_poly(k, -1, [Fraction(1)])
    assert all(x < 0 for x in chi)  # every coefficient negative: Hurwitz after a sign flip
    assert _routh_sign_changes(chi) == 0 and result.linear_stable
    exact = np.sort(np.roots([float(x) for x in chi]).real)
    assert np.allclose(np.sort([p.real for p in result.poles]), exact, rtol=1e-9)


@pytest.mark.parametrize("tau", [1e-3, 3e-3, 1e-2])
def test_any_lag_gives_a_right_half_plane_pole(tau: float) -> None:
    k = _constants(REDUCED)
    rows = {r.lags: r for r in lagged_loops(load_model(REDUCED), taus=(tau,), lags=(1, 3))}
    t = _q(tau)
    one = _loop_poly(k, -1, [t, Fraction(1)])
    assert _routh_sign_changes(one) == 1 == len(rows[1].unstable)
    root = max(np.roots([float(x) for x in one]).real)
    assert rows[1].unstable[0].real == pytest.approx(root, rel=1e-8)
    assert root == pytest.approx(float((k["k"] * k["a"] - 1) / t), rel=1e-3)
    three = _loop_poly(k, -1, _polymul(_polymul([t, Fraction(1)], [t, Fraction(1)]),
                                       [t, Fraction(1)]))
    assert _routh_sign_changes(three) == len(rows[3].unstable) >= 1


@pytest.mark.parametrize("tau", [1e-3, 1e-2])
def test_lagged_nonlinear_loop_diverges_at_the_rate_of_the_pole(tau: float) -> None:
    mf = load_model(FULL)
    run = lagged_simulation(mf, tau)  # eq (12), from 5 degrees
    pole = lagged_loops(mf, taus=(tau,), lags=(1,))[0].unstable[0].real
    assert run.diverged and run.escape_time < 50.0 / pole
    small = lagged_simulation(mf, tau, theta0=1e-7)
    assert small.growth_rate == pytest.approx(pole, rel=0.01)
    # the library's own closed-loop simulator (controller states) agrees: it blows up
    res = simulate(with_lags(mf, (tau,)), None, t_end=50.0 / pole, closed_loop=True,
                   equation="polynomial", initial=[math.radians(5.0), 0.0],
                   method="dop853", rtol=1e-9, atol=1e-12, blowup=1.0)
    assert not res.bounded


def test_physical_sign_needs_c_above_the_routh_threshold() -> None:
    k = _constants(REDUCED)
    m = sign_margin(load_model(REDUCED))
    assert m.c_min == k["w2"] / k["k"]  # 67.578/39.3185, exact
    assert _routh_sign_changes(_loop_poly(k, +1, [Fraction(1)])) == 1  # c = 0.1331
    rhp = [p for p in m.poles_file if p.real > 0]
    chi = [float(x) for x in _loop_poly(k, +1, [Fraction(1)])]
    assert len(rhp) == 1 and rhp[0].real == pytest.approx(max(np.roots(chi).real), rel=1e-8)
    assert any(p.real > 0 for p in m.poles_below)
    assert all(p.real < 0 for p in m.poles_above)
    for tau, c_max in m.c_max.items():
        t = _q(tau)
        for c, changes in ((m.c_min * Fraction(999, 1000), 1),
                           (m.c_min * Fraction(1001, 1000), 0),
                           (_q(c_max) * Fraction(1001, 1000), 2),
                           (_q(c_max) * Fraction(999, 1000), 0)):
            assert _routh_sign_changes(_loop_poly(k, +1, [t, Fraction(1)], c)) == changes
        assert all(p.real < 0 for p in m.lag_poles_above[tau])


@pytest.fixture(scope="module")
def obstruction():
    return theorem2_obstruction(load_model(REDUCED))


def test_theorem2_ceiling_from_the_static_branch(obstruction) -> None:
    k = _constants(REDUCED)
    beta = k["k"] / k["w2"]
    # static eq: -w2 theta + cubic theta^3 + k u - cross theta^2 u = 0, order u^3
    c3 = (k["cubic"] * beta ** 3 - k["cross"] * beta ** 2) / k["w2"]
    assert obstruction.beta1_floor == beta and obstruction.c3 == c3
    assert obstruction.kernel_h1_0 == pytest.approx(float(beta), rel=1e-12)
    assert obstruction.kernel_h3_0 == pytest.approx(float(c3), rel=1e-9)
    assert obstruction.holds and 4 * beta ** 3 < 27 * abs(c3)
    best = minimize_scalar(lambda y: -(float(beta) * y - float(abs(c3)) * y ** 3),
                           bounds=(0.0, 10.0), method="bounded", options={"xatol": 1e-10})
    assert obstruction.ceiling == pytest.approx(-best.fun, rel=1e-8) and -best.fun < 1
    # eq (12)'s extra terms vanish at zero frequency: the same obstruction
    assert theorem2_obstruction(load_model(FULL), grid=()).c3 == c3


def test_no_pd_controller_is_certified_and_each_stays_under_its_ceiling(obstruction) -> None:
    k = _constants(REDUCED)
    stable = obstruction.stabilising
    assert len(stable) >= 10
    for t in obstruction.trials:
        chi = _polyadd(_polymul([Fraction(1), Fraction(0), -k["w2"]],
                                [_q(t.tau_f), Fraction(1)]),
                       [k["k"] * _q(t.kd), k["k"] * _q(t.kp)])
        assert t.stable == (_routh_sign_changes(chi) == 0)
        if t.stable:
            assert t.kp > float(k["w2"] / k["k"])  # |s1(0)| > 1/beta, step (i)
            assert t.lambda1 >= t.kp and t.rho1 >= 1.0  # steps (i), (ii)
            assert t.verdict != "stable" and 0 <= t.radius <= t.bound < obstruction.ceiling
    # the lower-bound theta series (phi_3 = |c3| only) of the best controller explodes
    best = obstruction.best
    order = 41
    phi = [float(obstruction.beta1_floor), 0.0, float(abs(obstruction.c3))] + [0.0] * order
    theta = theta_series(phi, best.lambda1, best.rho1, order)
    assert theta[-1] * best.rho1 ** order > 1e20


def test_loop_drive_runs_many_periods_at_the_corner() -> None:
    k = _constants(REDUCED)
    drive = loop_drive(load_model(FULL), angles_deg=(5.0, 15.0), periods=40)
    chi = [float(x) for x in _loop_poly(k, -1, [Fraction(1)])]
    assert chi[1] ** 2 > 4 * chi[0] * chi[2] and not drive.resonant  # real poles
    assert drive.omega == pytest.approx(max(abs(np.roots(chi))), rel=1e-9)
    assert drive.t_end * drive.omega / (2 * math.pi) == pytest.approx(40)
    assert {t.equation for t in drive.trials} == {"polynomial", "physical"}
    for t in drive.trials:
        # started on the linear steady state: the peak is the linear angle, up to the
        # cubic terms (theta^3/6 ~ 0.2 % of theta at 15 deg, attenuated by the loop)
        assert t.bounded and t.peak == pytest.approx(math.radians(t.target_deg), rel=2e-3)
        # the reference of u = C(r - y): |y/r| of the tracking loop is 1 at the corner
        assert t.amplitude == pytest.approx(math.radians(t.target_deg) / drive.gain, rel=1e-12)
    k_c = [float(x) for x in (k["a"], k["b"], k["c"])]
    s = 1j * drive.omega
    pc = -float(k["k"]) / (s * s - float(k["w2"])) * np.polyval(k_c, s)
    assert drive.gain == pytest.approx(abs(pc / (1 + pc)), rel=1e-9)


# --- section 4: the input gain alpha and the theta_3 reading -----------------------------

def _pendulum_radius(rho: float, alpha: float, m: float = 1.0, length: float = 4.0,
                     g: float = 9.8) -> float:
    """r* of E = rho1 r + rho3 E^3 (rho1 = alpha S, rho3 = g/(6L) S, S = sup 1/|A|)."""
    b, w2 = rho / (m * length ** 2), g / length
    s = 1.0 / (b * math.sqrt(w2 - b * b / 4))
    return 2.0 / (3.0 * alpha * s * math.sqrt(3.0 * g / (6 * length) * s))


def _threshold(alpha: float, m: float = 1.0, length: float = 4.0, g: float = 9.8) -> float:
    """Damping rho at which the closed-form r* equals 1."""
    w2, c3 = g / length, g / (6 * length)
    s = (2.0 / (3.0 * alpha * math.sqrt(3.0 * c3))) ** (2.0 / 3.0)
    b = math.sqrt(2.0 * (w2 - math.sqrt(w2 ** 2 - 1.0 / s ** 2)))
    return b * m * length ** 2


@pytest.fixture(scope="module")
def alpha_rows():
    return {r.model: r for r in alpha_variants(MODELS, tolerance=1e-7, t_end=60.0)}


def test_input_gain_kept_certifies_rho_8_at_r_1(alpha_rows) -> None:
    for name, r in alpha_rows.items():
        mf = load_model(MODELS / f"{name}.toml")
        p = mf.parameters
        alpha = 1.0 if "eq2" not in name else 1.0 / (p["m"] * p["L"] ** 2)
        assert r.alpha == pytest.approx(alpha, rel=1e-12)
        assert r.radius == pytest.approx(_pendulum_radius(r.rho, alpha), rel=1e-7)
        assert r.margin == pytest.approx(_threshold(alpha), rel=1e-6)
        assert r.verdict == ("stable" if r.radius > 1 else "inconclusive")
    assert alpha_rows["hanging_pendulum_eq2_damped"].verdict == "stable"
    assert alpha_rows["hanging_pendulum_eq2"].radius < 1  # the series diverges at r = 1


def _direct(rho: float, alpha: float, w: float, t_end: float) -> tuple[bool, float]:
    """theta'' + b theta' + (g/L)(theta - theta^3/6) = alpha cos(w t), by solve_ivp."""
    b, w2 = rho / 16.0, 9.8 / 4.0

    def f(t: float, x: np.ndarray) -> list[float]:
        return [x[1], alpha * math.cos(w * t) - b * x[1] - w2 * (x[0] - x[0] ** 3 / 6)]

    def big(_t: float, x: np.ndarray) -> float:
        return abs(x[0]) - 1e3

    big.terminal = True  # type: ignore[attr-defined]
    sol = solve_ivp(f, (0, t_end), [0.0, 0.0], rtol=1e-9, atol=1e-12, events=big,
                    max_step=0.05)
    return not sol.t_events[0].size, float(np.max(np.abs(sol.y[0])))


def test_resonance_runs_match_a_direct_integration(alpha_rows) -> None:
    for r in alpha_rows.values():
        bounded, peak = _direct(r.rho, r.alpha, r.resonance, r.t_end)
        assert r.bounded == bounded
        if bounded:
            assert r.peak == pytest.approx(peak, rel=1e-3)
    assert not alpha_rows["hanging_pendulum"].bounded  # eq (6), rho = 0.8 escapes
    assert alpha_rows["hanging_pendulum_eq2"].bounded  # eq (2): the series, not theta


def test_printed_theta3_drops_rho1_in_both_sections() -> None:
    readings = theta_readings(MODELS)
    assert all(r.matches_dropped and not r.matches_kept for r in readings)
    five = readings[-1]
    exact = _q(five.phi3) * _q(five.lambda1) ** 3  # 2.56 * 0.1331^3
    assert five.dropped == pytest.approx(float(exact), rel=1e-12)
    assert printed_match(five.printed, float(exact))
    assert five.kept == pytest.approx(float(exact * _q(five.rho1)), rel=1e-12)
    for r in readings[:2]:  # section 3: theta_3 = rho_3 = phi_3 (lambda_1 = 1)
        assert r.dropped == r.printed


def test_paper_rows_quote_the_findings() -> None:
    rows = {r.quantity: r for r in paper_checks(MODELS) if r.section.startswith("5")}
    assert "-612.369" in rows["closed-loop poles"].reason
    assert "rho_1 dropped" in rows["theta_3"].reason
    assert "0.6664" in rows["verdict"].reason


def test_report_sections_quote_the_result_objects(alpha_rows) -> None:
    from gfrf.papers.cartpole_trials import has_physical_equation
    from gfrf.report import paper_gfrf
    from gfrf.report._format import cell

    text, summary = paper_gfrf._alpha_section(list(alpha_rows.values()))
    page = "\n".join(text)
    for r in alpha_rows.values():
        assert f"| {cell(r.radius)} |" in page and f"| {cell(r.margin)} |" in page
    damped = alpha_rows["hanging_pendulum_eq2_damped"]
    assert f"r* = {paper_gfrf.num(damped.radius, 4)}" in summary
    rendered = paper_gfrf.simulation_table([["m", "physical", "x", 1.0, None, None, True,
                                             0.5, None]])
    assert rendered.splitlines()[2] == "| m | physical | x | 1 | - | n/a | yes | 0.5 | - |"
    # eq (16)'s file has no untruncated equation of its own: no duplicated 'physical' runs
    assert has_physical_equation(load_model(FULL))
    assert not has_physical_equation(load_model(REDUCED))
