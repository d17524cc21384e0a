"""OFRF: the work limit counts the input-power spectra; overflow is a clean refusal."""

from __future__ import annotations

import pytest

import gfrf.sim.ofrf as ofrf_module
from gfrf.cli import main
from gfrf.errors import ArgumentError

DUFFING = "D(y,2) + 0.2*D(y) + y + c*y**3 = u"
EIGHT_TONES = "+".join(f"0.01*cos({k}.0*t)" for k in range(1, 9))


def test_input_powers_count_in_the_work_limit(monkeypatch: pytest.MonkeyPatch,
                                              capsys: pytest.CaptureFixture) -> None:
    """8 tones to order 9: U_9 alone has C(24, 9) = 1,307,504 components, each made by 16
    products from U_8 (C(23, 8) = 490,314): above MAX_OFRF_WORK before any product."""
    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("the recursion started before the work limit was checked")

    monkeypatch.setattr(ofrf_module, "_recursion", refuse)
    code = main(["ofrf", "D(y,2) + 0.2*D(y) + y = c*u + 0.1*u**2", "--param", "c=1",
                 "--input", EIGHT_TONES, "--omega", "1", "--order", "9"])
    out, err = capsys.readouterr()
    assert code == 2 and out == ""
    assert "MAX_OFRF_WORK" in err and err.count("\n") == 1
    assert 490_314 * 16 > ofrf_module.MAX_OFRF_WORK


@pytest.mark.parametrize(("param", "tones", "omega", "order"), [
    ("c=1e150", "0.1*cos(1.0*t)", "3", "7"),        # c**3 = 1e450
    ("c=0.5", "0.1*cos(1e300*t)", "3e300", "5"),    # (j omega)**2 = -1e600
    ("c=0.5", "1e300*cos(1.0*t)", "3", "5"),        # A**3 = 1e900
])
def test_overflow_is_one_line_exit_2(capsys: pytest.CaptureFixture, param: str, tones: str,
                                     omega: str, order: str) -> None:
    code = main(["ofrf", DUFFING, "--param", param, "--input", tones, "--omega", omega,
                 "--order", order])
    out, err = capsys.readouterr()
    assert code == 2 and out == ""
    assert err.startswith("gfrf: error: ") and "overflows floating point" in err
    assert err.count("\n") == 1 and "nan" not in err


def test_overflow_from_the_api_is_an_argument_error() -> None:
    table = {"equation": DUFFING, "parameters": {"c": 1e150}}
    with pytest.raises(ArgumentError, match="overflows"):
        ofrf_module.ofrf(table, "c", [(0.1, 1.0, 0.0)], 3.0, 7)


def test_a_large_finite_value_still_answers() -> None:
    """c = 1e100 to order 3: the only order-3 term at 3 rad/s is -c (A/2)**3 / A(3j) /
    A(j)**3 with A(s) = s**2 + 0.2 s + 1 (closed form), times 2 (complex amplitude)."""
    table = {"equation": DUFFING, "parameters": {"c": 1e100}}
    result = ofrf_module.ofrf(table, "c", [(0.1, 1.0, 0.0)], 3.0, 3)

    def a(s: complex) -> complex:
        return s * s + 0.2 * s + 1

    expected = -2 * 1e100 * 0.05 ** 3 / (a(3j) * a(1j) ** 3)
    assert abs(result(1e100) - expected) <= 1e-12 * abs(expected)
