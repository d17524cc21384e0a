"""Method-vs-ground-truth comparison: conventions, errors shrinking at the expected rate."""

import math

import pytest

from gfrf.errors import ArgumentError, ConvergenceError
from gfrf.periodic.compare import compare_periodic, error_table, method_transition


def test_unknown_method_and_branch():
    with pytest.raises(ArgumentError, match="unknown method"):
        method_transition("galerkin", 0.1, 0.5, "0")
    with pytest.raises(ArgumentError, match="branch"):
        method_transition("averaging", 0.1, 0.5, "0")


def test_exact_method_is_zero_error():
    r = compare_periodic("exact", 0.1, 0.5, "1/4")
    assert r.max_error == 0 and r.delta_error == 0


@pytest.mark.parametrize("method,rate", [("averaging", 2), ("perturbation", 3)])
def test_error_rate_in_eps(method, rate):
    # amplitude ~ eps keeps the 1/4-branch expansions uniform; order 2 is the paper's
    errs = [compare_periodic(method, e, 2 * e, "1/4", 2).delta_error for e in (0.1, 0.05)]
    assert errs[0] / errs[1] == pytest.approx(2**rate, rel=0.35)


def test_orbit_error_grows_with_amplitude():
    rows = error_table(("averaging", "energy"), (0.1,), (0.1, 0.5), "1/4")
    by = {(r.method, r.amplitude_exact): r.max_error for r in rows}
    assert by[("averaging", 0.1)] < by[("averaging", 0.5)]
    assert by[("energy", 0.1)] < by[("energy", 0.5)]


def test_energy_without_root_gives_nan():
    r = compare_periodic("energy", 0.4, 0.5, "1/4")
    assert math.isnan(r.delta_method) and math.isnan(r.max_error)


def test_fixed_delta_mode():
    r = compare_periodic("perturbation", 0.2, 0.6, "1/4", 6, delta=0.16)
    assert r.delta_error < 1e-12
    assert abs(r.amplitude_method - r.amplitude_exact) < 1e-3
    with pytest.raises(ConvergenceError):
        compare_periodic("perturbation", 0.2, 0.1, "1/4", 4, delta=0.1)
