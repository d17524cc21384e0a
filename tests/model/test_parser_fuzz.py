"""Fuzzing the model parser: any string gives a Model or a ModelError, nothing else.

Strings are random sequences of tokens of the model grammar (signals, D(.,n), lags,
operators, numbers, functions) and arbitrary text.  Tokens that would execute code
(``parse_expr`` evaluates Python) are deliberately absent: the parser is documented
for model text, not as a sandbox.  Regression strings found by fuzzing are listed
explicitly.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gfrf.errors import ModelError
from gfrf.model.equation import Model, parse_model

TOKENS = ["y", "u", "D(", "D(y)", "D(u)", "D(y,2)", ",", ")", "(", "+", "-", "*", "**", "/",
          "=", "==", "0", "1", "2", "3", "9", "0.5", "1e308", "1e-308", "-1", "sin(", "cos(",
          "exp(", "sqrt(", "tanh(", "[k]", "[k-1]", "[k+1]", "y[k-2]", "u[k-1]", "t", "x",
          "rho", "I", "oo", "nan", "zoo", "pi", "E", " ", ".", "%", "//", "<", "lambda:", "if",
          "else", "[", "]", "{", "}", "'", ";", "\\", "\n", "#", "@", "&", "|", "~", "!", "^",
          "Abs(", "Heaviside(", "1j", "99999999999999999999"]

SETTINGS = settings(max_examples=80, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])

token_strings = st.lists(st.sampled_from(TOKENS), min_size=0, max_size=14).map("".join)
equation_like = st.tuples(token_strings, token_strings).map(lambda p: f"{p[0]} = {p[1]}")


def _parse_or_model_error(text: str, **kwargs: object) -> None:
    try:
        result = parse_model(text, **kwargs)
    except ModelError:
        return
    assert isinstance(result, Model)


@SETTINGS
@given(st.one_of(token_strings, equation_like, st.text(max_size=40)))
def test_continuous_parser_raises_only_model_error(text: str) -> None:
    _parse_or_model_error(text)


@SETTINGS
@given(st.one_of(token_strings, equation_like))
def test_truncated_parser_raises_only_model_error(text: str) -> None:
    _parse_or_model_error(text, truncation=3, parameters={"rho": 0.8})


@SETTINGS
@given(st.one_of(token_strings, equation_like, st.text(max_size=40)))
def test_discrete_parser_raises_only_model_error(text: str) -> None:
    _parse_or_model_error(text, sample_time=0.1)


@pytest.mark.parametrize(("text", "fragment"), [
    # Found by fuzzing the former sympy-based parser: sympy computed 9**(9**9) (hung),
    # expanded y**100000 into a dense polynomial (memory); a Python lambda crashed Poly
    # (PolynomialError) or hashing (TypeError); integer division by zero raised
    # ZeroDivisionError.  The expression language refuses each before any work.
    ("D(y) + y + 9**9**9*y = u", "exponent after '**' must be an integer literal"),
    ("D(y) + y + y**100000 = u", "exponent 100000 exceeds the limit MAX_EXPONENT"),
    ("D(y) + y = u + (y + u)**40", "exponent 40 exceeds the limit MAX_EXPONENT"),
    ("D(y) + y = lambda: 0", "unexpected character ':'"),
    ("lambda:[k]", "unexpected character ':'"),
    ("0//0", "cannot parse the equation"),
])
def test_fuzz_regressions(text: str, fragment: str) -> None:
    with pytest.raises(ModelError) as info:
        parse_model(text)
    assert fragment in str(info.value)


def test_ordinary_powers_still_parse() -> None:
    model = parse_model("D(y,2) + 2**-3*D(y) + y + 0.5*y**3 = u")
    assert dict(model.linear_output) == {2: 1.0, 1: 0.125, 0: 1.0}
    assert model.degree == 3
