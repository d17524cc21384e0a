"""HAM: paper's (30) regenerated, convergence with order, residual-optimal h."""

import numpy as np
import pytest
import sympy as sp

from gfrf.periodic.averaging import averaging_transition
from gfrf.periodic.homotopy import ham, ham_optimal, paper_ham_first_order
from gfrf.periodic.shooting import transition_delta


def test_paper_gamma0_and_gamma1():
    c, d, e, h = sp.symbols("c delta epsilon h")
    out = paper_ham_first_order()
    assert sp.expand(out["gamma0"] - (-d * (c**2 - 8) / 8)) == 0
    # linear autonomous limit (c -> 0, eps = 0): gamma = delta exactly, so gamma1 -> 0;
    # the printed gamma1 = delta^2 (c^2-8)(9c^2-8) h/64 tends to delta^2 h instead
    assert out["gamma1"].subs({c: 0, e: 0}) == 0
    printed = d**2 * (c**2 - 8) * (9 * c**2 - 8) * h / 64
    assert printed.subs({c: 0, e: 0}) != 0
    # Lindstedt: x'' + x - x^3/6 with x(0) = c has omega^2 = 1 - c^2/8 - c^4/1536 + ...
    assert sp.expand((out["gamma0"] + out["gamma1"]).subs({d: 1, e: 0, h: -1})
                     - (1 - c**2 / 8 - c**4 / 1536)) == 0


def test_order_zero_is_harmonic_balance():
    assert ham(0.2, 0.5, "1/4", 0).delta == pytest.approx(averaging_transition(0.2, 0.5))


@pytest.mark.parametrize("branch", ["0", "1/4"])
def test_converges_with_order(branch):
    exact = transition_delta(0.3, 0.5, branch).delta
    errs = [abs(ham_optimal(0.3, 0.5, branch, m).delta - exact) for m in (2, 4, 6)]
    assert errs[0] > errs[1] > errs[2]
    assert errs[2] < 1e-4


def test_optimal_h_beats_paper_h():
    exact = transition_delta(0.2, 0.5, "1/4")
    best = ham_optimal(0.2, 0.5, "1/4", 4)
    paper_h = ham(0.2, 0.5, "1/4", 4, h=-1 / 1000)
    assert best.residual < paper_h.residual
    t = np.linspace(0, 4 * np.pi, 101)
    assert np.max(np.abs(best.solution(t) - exact.evaluate(t))) < 1e-5
