"""Hard cases where floats fail and intervals do not.

Each case compares the interval path (``proof="interval"``) and the float path
(``proof="float"``) with an independent reference: mpmath at 50+ digits on the exact
values of the float coefficients (roots of the stationary polynomial P'Q - PQ' by
``mpmath.polyroots``, no FLINT), or a closed form.  The interval enclosure must
contain the reference and be tight; the float path's result is shown beside it (run
with ``-s`` to see the table): it refuses (inf, "ill-conditioned") where double
precision cannot resolve the sup, and is asserted never to be finite and wrong.
"""

from __future__ import annotations

import math
from fractions import Fraction

import mpmath as mp
import numpy as np
import pytest
from mp_reference import mp_sup as reference_sup

from gfrf.bounds.norms import kernel_norm
from gfrf.bounds.rational import rational_sup
from gfrf.model.equation import parse_model
from gfrf.stability.theorem1 import theorem1

DIGITS = 60


def mp_sup(num: list[float], den: list[float]) -> mp.mpf:
    """sup over real w of |N(jw)/D(jw)| at DIGITS digits (coefficients highest first)."""
    return reference_sup(num, den, digits=DIGITS)


def _contains(lower: float, upper: float, ref: mp.mpf) -> bool:
    with mp.workdps(DIGITS):
        return mp.mpf(lower) <= ref <= mp.mpf(upper)


def _rel(x: float, ref: mp.mpf) -> float:
    with mp.workdps(DIGITS):
        return float(abs(mp.mpf(x) - ref) / ref) if mp.isfinite(mp.mpf(x)) else float("inf")


CASES = {
    "damping 1e-9": ([1.0], [1.0, 1e-9, 1.0]),
    "double resonance, poles 1e-8 apart, damping 1e-6": (
        [1.0], np.polymul([1.0, 2e-6, 1.0], [1.0, 2e-6 * (1 + 1e-8), (1 + 1e-8) ** 2]).tolist()),
    "double resonance, poles 1e-8 apart, damping 1e-9": (
        [1.0], np.polymul([1.0, 1e-9, 1.0], [1.0, 1e-9, (1 + 1e-8) ** 2]).tolist()),
    "triple cluster (s^2 + 2e-6 s + 1)^3 in floats": (
        [1.0], [1.0, 6e-06, 3.000000000012, 1.2000000000008e-05, 3.000000000012, 6e-06, 1.0]),
    "exact cancellation (s + 0.5)": ([1.0, 2.5, 1.0], [1.0, 0.75, 4.125, 2.0]),
    "near cancellation, zero 1e-12 from a pole": (
        [1.0, 0.5 + 1e-12], np.polymul([1.0, 0.5], [1.0, 1e-3, 1.0]).tolist()),
    "coefficients over 12 orders of magnitude": (
        [1e6, 1.0], np.polymul([1e-6, 1.0], [1.0, 1e-6, 1e6]).tolist()),
    "coefficients 1e-9 .. 1e6, slow pole and fast resonance": (
        [1.0, 1e3], np.polymul([1.0, 1e-6], [1.0, 1e-3, 1e6]).tolist()),
}


@pytest.mark.parametrize("name", list(CASES))
def test_interval_encloses_the_50_digit_sup(name: str) -> None:
    num, den = CASES[name]
    ref = mp_sup(num, den)
    proven = rational_sup(num, den, proof="interval")
    floated = rational_sup(num, den, proof="float")
    assert proven.proof == "interval" and proven.exact
    assert _contains(proven.lower, proven.upper, ref)
    assert _rel(proven.upper, ref) <= 4e-16 and _rel(proven.lower, ref) <= 4e-16
    print(f"\n{name}: mpmath {mp.nstr(ref, 20)}; interval [{proven.lower!r}, "
          f"{proven.upper!r}]; float {floated.value!r} (relative error "
          f"{_rel(floated.value, ref):.2g})")


def test_exact_cancellation_is_reported() -> None:
    num, den = CASES["exact cancellation (s + 0.5)"]
    proven = rational_sup(num, den)
    assert proven.cancelled == (complex(-0.5, 0.0),)
    # the reduced function (s + 2) / (s^2 + 0.25 s + 4), by mpmath
    assert _contains(proven.lower, proven.upper, mp_sup([1.0, 2.0], [1.0, 0.25, 4.0]))


def test_float_path_refuses_where_the_interval_path_proves() -> None:
    """The reason for the proof: on these cases double precision cannot resolve the sup
    (numpy roots of the stationary polynomial lose a cluster, |D|^2 at the peak is below
    its rounding error).  The float path then fails closed, inf with the reason, and is
    otherwise within 1e-8: it never returns a wrong finite number."""
    refused = []
    for name, (num, den) in CASES.items():
        floated = rational_sup(num, den, proof="float")
        if floated.upper == float("inf"):
            assert "ill-conditioned in double precision" in floated.reason
            refused.append(name)
        else:
            assert _rel(floated.value, mp_sup(num, den)) <= 1e-8
    print("\nfloat path refused (the interval path encloses):", ", ".join(refused))
    assert {"damping 1e-9", "triple cluster (s^2 + 2e-6 s + 1)^3 in floats"} <= set(refused)


# -- through the majorant: ||H3|| and r* with damping 1e-9 ---------------------------
LIGHT = "D(y,2) + 1e-9*D(y) + y + 0.1*y**3 = u"


def _light_closed_forms() -> tuple[mp.mpf, mp.mpf]:
    """||H3|| = |c3| beta^4 (beta = ||H1|| = sup|1/A|) and the majorant radius
    r* = 2 / (3 beta sqrt(3 |c3| beta)) of X = beta r + |c3| beta X^3, at 50 digits, for
    the model as written (1e-9 and 0.1 are the rationals 1/10^9 and 1/10)."""
    with mp.workdps(DIGITS):
        b = mp.mpf(1) / 10 ** 9
        beta = 1 / (b * mp.sqrt(1 - b * b / 4))
        c3 = mp.mpf(1) / 10
        return c3 * beta ** 4, 2 / (3 * beta * mp.sqrt(3 * c3 * beta))


def test_h3_bracket_with_damping_1e9() -> None:
    h3, _ = _light_closed_forms()
    model = parse_model(LIGHT)
    proven = kernel_norm(model, 3, proof="interval")
    assert proven.upper_proof == proven.lower_proof == proven.proof == "interval"
    with mp.workdps(DIGITS):
        assert mp.mpf(proven.lower) <= h3 <= mp.mpf(proven.upper)  # both ends proven
    assert _rel(proven.lower, h3) <= 1e-12  # the witness attains the sup to its digits
    floated = kernel_norm(model, 3, proof="float")
    print(f"\n||H3||, damping 1e-9: closed form {mp.nstr(h3, 17)}; interval upper "
          f"{proven.upper!r}; float upper {floated.upper!r}")


def test_radius_with_damping_1e9() -> None:
    _, radius = _light_closed_forms()
    model = parse_model(LIGHT)
    v = theorem1(model, order=1, amplitude=1e-14, with_norms=False, proof="interval")
    assert v.radius_proof == "interval" and v.verdict == "stable"
    with mp.workdps(DIGITS):
        assert mp.mpf(v.radius) <= radius * (1 + mp.mpf(1e-12))
    assert _rel(v.radius, radius) <= 1e-8
    floated = theorem1(model, order=1, amplitude=1e-14, with_norms=False, proof="float")
    print(f"\nr*, damping 1e-9: closed form {mp.nstr(radius, 17)}; interval {v.radius!r}; "
          f"float {floated.radius!r} ({floated.verdict})")
    assert floated.verdict != "unstable"  # the float path may fail, but closed


def test_enclosure_endpoints_are_exact_dyadics() -> None:
    """lower/upper are floats compared exactly (no decimal rounding in the check)."""
    num, den = CASES["damping 1e-9"]
    proven = rational_sup(num, den)
    b = Fraction(1e-9)
    # sup^2 = 1 / (b^2 (1 - b^2/4)) exactly, for A = s^2 + b s + 1
    exact_sq = 1 / (b * b * (1 - b * b / 4))
    assert Fraction(proven.lower) ** 2 <= exact_sq <= Fraction(proven.upper) ** 2


@pytest.mark.slow
def test_bench_section_proof_levels() -> None:
    """The 'Proof levels' bench section times every quantity at every level in one run."""
    from gfrf.bench import SECTION_MODULES
    from gfrf.bench.proof import run

    assert "gfrf.bench.proof" in SECTION_MODULES
    section = run(quick=True)
    assert section.title == "Proof levels"
    quantities = {row[1] for row in section.rows}
    assert {"sup \\|H1\\|", "\\|\\|H1\\|\\|", "\\|\\|H3\\|\\|", "r*"} <= quantities
    for row in section.rows:
        assert all(float(x) > 0 for x in row[2:7])
    # r* of the hanging pendulum (b = 0.05, c = 2.45, c3 = g / (6 L) with L = 4):
    # X = beta r + c3 beta X^3 with beta = 1 / (b sqrt(c - b^2/4))
    beta = 1 / (0.05 * (2.45 - 0.05 ** 2 / 4) ** 0.5)
    radius = 2 / (3 * beta * (3 * (9.8 / 24) * beta) ** 0.5)
    hanging = next(row for row in section.rows if row[:2] == ["hanging_pendulum", "r*"])
    assert float(hanging[7]) == pytest.approx(radius, rel=1e-8)


def test_exact_sups_are_memoised_and_clearable() -> None:
    from gfrf.bounds import exact_sup

    exact_sup.clear_caches()
    first = exact_sup.sup_abs([1.0], [1.0, 0.1, 2.0])
    again = exact_sup.sup_abs([1.0], [1.0, 0.1, 2.0])
    assert again == first
    assert exact_sup._sup_continuous.cache_info().hits >= 1
    exact_sup.discrete_sup_abs([1.0], [1.0, -0.5], 0.1)
    exact_sup.discrete_sup_abs([1.0], [1.0, -0.5], 0.1)
    assert exact_sup._sup_discrete.cache_info().hits >= 1
    exact_sup.clear_caches()
    assert exact_sup._sup_continuous.cache_info().currsize == 0


def test_float_discrete_sup_agrees_or_refuses_with_a_reason() -> None:
    """q^2 / (1 - q/2): sup 2 at q = 1 (its |N/D|^2 has a harmless double stationary
    point at x = -1, which once made the float path refuse without saying why); clustered
    lightly damped poles: the float path equals the interval value or refuses, naming why."""
    from gfrf.bounds import exact_sup

    assert exact_sup.discrete_sup_abs([0, 0, 1], [1, -0.5], 1.0, "float").upper == 2.0
    for gap in (1e-2, 1e-5, 1e-8):
        theta1, theta2, radius = 0.3, 0.3 + gap, 0.999
        first = [1.0, -2 * radius * np.cos(theta1), radius**2]
        second = [1.0, -2 * radius * np.cos(theta2), radius**2]
        den = np.convolve(first, second)
        flt = exact_sup.discrete_sup_abs([1.0], den, 0.1, "float")
        ball = exact_sup.discrete_sup_abs([1.0], den, 0.1, "interval")
        if math.isinf(flt.upper):
            assert flt.reason
        else:
            assert abs(flt.upper - ball.upper) <= 1e-9 * ball.upper
