"""Switching inputs u = +-U sign(c . z): the compiled feedback run against an independent
event-located DOP853 run of the same feedback, and the witness on stiff one-line models."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gfrf import parse_model
from gfrf.cli import main
from gfrf.sim.system import build_system
from gfrf.twosided.escape import escape_region
from gfrf.twosided.switching import replay, run_switching, switching_module

EQ = "D(y,2) + 0.5*D(y) + 2.45*y - 0.4*y**3 = u"


def _feedback_dop853(U: float, t_end: float) -> tuple[list[float], float | None]:
    """u = U sign(y') with the sign changes located as events (closed loop, scipy only)."""
    def rhs(t: float, z: np.ndarray, u: float) -> list[float]:
        return [z[1], -0.5 * z[1] - 2.45 * z[0] + 0.4 * z[0] ** 3 + u]

    def turn(t: float, z: np.ndarray, u: float) -> float:
        return z[1]

    def big(t: float, z: np.ndarray, u: float) -> float:
        return abs(z[0]) - 10.0

    turn.terminal = big.terminal = True  # type: ignore[attr-defined]
    z, t, u, switches = np.zeros(2), 0.0, U, []
    while t < t_end:
        # y' leaves 0 in u's direction after a switch: the next switch is the crossing
        # against u (so the restart point is not taken as an event)
        turn.direction = -1 if u > 0 else 1  # type: ignore[attr-defined]
        sol = solve_ivp(rhs, (t, t_end), z, method="DOP853", rtol=1e-11, atol=1e-14,
                        events=(turn, big), args=(u,))
        if sol.t_events[1].size:
            return switches, float(sol.t_events[1][0])
        if not sol.t_events[0].size:
            return switches, None
        t = float(sol.t_events[0][0])
        z = sol.y_events[0][0]
        z[1] = 0.0
        switches.append(t)
        u = -u
    return switches, None


def test_compiled_feedback_switches_where_event_location_does() -> None:
    model = parse_model(EQ)
    system = build_system(model, equation="polynomial")
    h, U = 1e-3, 1.0
    run = run_switching(switching_module(system), 2, np.array([0.0, 1.0]), U, 1, h, 40_000,
                        np.array([10.0, 1e3]))
    ref, t_big = _feedback_dop853(U, 40.0)
    assert run.escaped and t_big is not None
    n = min(len(ref), len(run.switch_times))
    assert n >= 3
    assert np.allclose(run.switch_times[:n], ref[:n], atol=5 * h)
    # the recorded open-loop input escapes when replayed (switches as boundaries)
    region = escape_region(model, U)
    t_escape = replay(system, U, 1, run.switch_times, 40.0, np.array([10.0, 1e3]), 1e-10,
                      region)
    assert t_escape is not None and t_escape <= t_big + 1e-6


@pytest.mark.parametrize("equation", [
    "D(y) + 1000*y - y**2 = u",
    pytest.param("D(y) + 20000*y - y**2 = u", marks=pytest.mark.slow)])
def test_stiff_first_order_saddle_node(equation: str, capsys: pytest.CaptureFixture[str]
                                       ) -> None:
    """y' = -a y + y^2 + u escapes under a constant u iff u > a^2/4 (the saddle-node):
    the answer brackets it, and the work stays bounded (a fixed number of RK4 steps)."""
    a = float(equation.split("+ ")[1].split("*")[0])
    code = main(["threshold", equation, "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0
    assert data["lower"] <= a * a / 4 <= data["upper"] <= 1.1 * a * a / 4


def test_narx_sign_witness_escapes_in_an_independent_recursion(
        capsys: pytest.CaptureFixture[str]) -> None:
    """The NARX example's witness u[k] = +-U (switches at sample times), replayed by the
    recursion written out here from the equation y[k] = 0.5 y[k-1] - 0.2 y[k-1]^2 u[k-2]
    + u[k-1]."""
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "models" / "narx_example.toml"
    assert main(["threshold", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    w = data["witness"]
    assert data["upper_proof"] == "interval" and data["upper"] >= data["lower"]
    if w["kind"] != "switching":
        pytest.skip("a tone witness won")
    flips = {round(t / 0.1) for t in w["switch_times"]}
    sign, u, y = w["first_sign"], [], []
    for k in range(int(round(w["t_escape"] / 0.1)) + 1):
        if k in flips:
            sign = -sign
        u.append(sign * w["amplitude"])
        prev = y[k - 1] if k >= 1 else 0.0
        y.append(0.5 * prev - 0.2 * prev**2 * (u[k - 2] if k >= 2 else 0.0)
                 + (u[k - 1] if k >= 1 else 0.0))
    assert abs(y[-1]) >= 1e6 and all(abs(v) < 1e6 for v in y[:-1])


def test_narx_beam_search_beats_the_fixed_sign_rules_and_its_witness_replays() -> None:
    """identified_example: the beam over sign sequences escapes at a smaller U than every
    fixed rule, and its sign sequence escapes in the recursion written out here."""
    from pathlib import Path

    from gfrf.model.modelfile import load_model
    from gfrf.twosided.falsify import _edge
    from gfrf.twosided.narx_signs import RULES
    from gfrf.twosided.runner import EscapeRunner

    mf = load_model(Path(__file__).resolve().parents[2] / "models" / "identified_example.toml")
    runner = EscapeRunner(build_system(mf, equation="polynomial"), mf.plant, 10.0)
    edges = {r: _edge(lambda a, r=r: runner.switch(r, a).escaped, 40.0) for r in RULES}
    beam = edges.pop("beam")
    assert beam is not None
    assert all(e is None or beam < 0.97 * e for e in edges.values()), (beam, edges)
    run = runner.switch("beam", beam)
    assert run.escaped and run.t_escape is not None
    assert run.switch_times == runner.switch("beam", beam).switch_times  # deterministic
    flips = {round(t / 0.1) for t in run.switch_times}
    sign, u, y = run.first_sign, [], []
    for k in range(round(run.t_escape / 0.1) + 1):
        if k in flips:
            sign = -sign
        u.append(sign * beam)
        y1, y2 = (y[k - 1] if k >= 1 else 0.0), (y[k - 2] if k >= 2 else 0.0)
        u1, u2 = (u[k - 1] if k >= 1 else 0.0), (u[k - 2] if k >= 2 else 0.0)
        y.append(0.5951575491 * y1 - 0.1979410468 * y2 + 0.4991094922 * u1
                 + 0.3025633491 * u2 + 0.1508917809 * y1 * u1 - 0.100037633 * u1**2
                 - 0.04852880773 * y1**3)
    assert abs(y[-1]) >= 1e6 and all(abs(v) < 1e6 for v in y[:-1])


def _terms_rhs(model: object) -> tuple[int, object]:
    """(n, rhs(z, u)) of a continuous model evaluated term by term from its coefficients
    (y^(n) = -(the other terms) / a_n), not from the generated right-hand side."""
    terms = model.terms  # type: ignore[attr-defined]
    n = max(max(t.y_orders, default=0) for t in terms)
    lead = next(t.coefficient for t in terms if t.y_orders == (n,) and not t.u_orders)

    def rhs(z: np.ndarray, u: float) -> list[float]:
        total = 0.0
        for t in terms:
            if t.y_orders == (n,) and not t.u_orders:
                continue
            total += t.coefficient * np.prod([z[o] for o in t.y_orders]) * u ** len(t.u_orders)
        return [*z[1:n], -total / lead]

    return n, rhs


@pytest.mark.slow
@pytest.mark.parametrize("name", ["hanging_pendulum", "hanging_pendulum_damped",
                                  "hanging_pendulum_eq2", "hanging_pendulum_eq2_damped"])
def test_every_bundled_switching_witness_escapes_in_an_independent_replay(name: str) -> None:
    """The witness u = +-U at its switch times, replayed by DOP853 on the model evaluated
    term by term (each switch an integration boundary, the escape level an event), leaves
    the level where the falsifier says it escapes (or its step size collapses there)."""
    from pathlib import Path

    from gfrf.model.modelfile import load_model
    from gfrf.stability.static import radius_upper
    from gfrf.twosided.falsify import falsify

    mf = load_model(Path(__file__).resolve().parents[2] / "models" / f"{name}.toml")
    bound = radius_upper(mf.plant)
    assert bound is not None
    f = falsify(mf, 10 * float(bound.value))
    assert f.kind == "switching" and f.upper is not None and f.t_escape is not None
    n, rhs = _terms_rhs(mf.plant)
    level = f.levels[0]

    def out(_t: float, z: np.ndarray, u: float) -> float:
        return abs(z[0]) - level

    out.terminal = True  # type: ignore[attr-defined]
    end = f.t_escape + 50.0
    edges = [0.0, *[t for t in f.switch_times if t < end], end]
    z, sign, hit = np.zeros(n), f.first_sign, None
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        with np.errstate(all="ignore"):
            sol = solve_ivp(lambda t, x, u: rhs(x, u), (a, b), z, method="DOP853",  # type: ignore[operator]
                            rtol=1e-11, atol=1e-14, events=out, args=(sign * f.upper,))
        if sol.status != 0:  # the level reached, or the step size collapsed (a blow-up)
            hit = float(sol.t_events[0][0]) if sol.status == 1 else float(sol.t[-1])
            break
        z, sign = sol.y[:, -1], -sign
    assert hit is not None and f.t_escape - 1e-6 <= hit <= f.t_escape + 20.0
