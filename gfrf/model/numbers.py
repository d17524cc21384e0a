"""Numbers of a model file: TOML numbers or expression texts, as doubles and as written.

:func:`parse_number` gives the double every estimate and simulation uses;
:func:`exact_number` the exact value as written (``0.145`` is 29/200, ``"2.45/6"`` is
49/120), which the proofs use (see :mod:`gfrf.model.exact`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import sympy as sp

from gfrf.errors import ModelError
from gfrf.model.exact import float_as_written
from gfrf.model.expr import UnknownNames, check_name, parse_expression
from gfrf.model.limits import quote

__all__ = ["parse_number", "exact_number", "parameter_table", "MAX_PARAMETERS"]

#: Most entries of a ``[parameters]`` table.
MAX_PARAMETERS = 500


def parse_number(value: Any, key: str, parameters: Mapping[str, float]) -> float:
    """A finite number from a TOML value: a number, or an expression text such as
    ``"1/(m*L**2)"`` in the named ``parameters`` (parsed by :mod:`gfrf.model.expr`, never
    evaluated as code).

    Parameters
    ----------
    value : object
        The TOML value: an int, a float or an expression text.
    key : str
        The key it was read from, for the message.
    parameters : mapping of str to float
        The names an expression may use, with their values.

    Returns
    -------
    float
        The finite value.

    Raises
    ------
    ModelError
        Not a number, unknown names, a non-real or non-finite value; the message names
        ``key``.
    """
    if isinstance(value, bool):
        raise ModelError(f"{key}: expected a number, got {value!r}")
    if isinstance(value, (int, float)):
        try:
            result = float(value)
        except OverflowError:
            raise ModelError(f"{key}: the integer is too large for a float") from None
    elif isinstance(value, str):
        names = {k: sp.Float(v) for k, v in parameters.items()}
        try:
            expr = parse_expression(value, names=names).expr
        except UnknownNames as exc:
            raise ModelError(f"{key}: {quote(value)} uses unknown symbol(s) "
                             f"{', '.join(exc.names)}") from None
        except ModelError as exc:
            raise ModelError(f"{key}: {exc}") from None
        if not expr.is_number or not expr.is_real:
            raise ModelError(f"{key}: {quote(value)} is not a real number")
        try:
            result = float(expr)
        except OverflowError:
            result = math.inf
    else:
        raise ModelError(f"{key}: expected a number or an expression, got {value!r}")
    if not math.isfinite(result):
        raise ModelError(f"{key}: {quote(str(value))} is not finite")
    return result


def parameter_table(table: Any, where: str, exact: dict[str, sp.Expr]) -> dict[str, float]:
    """The values of a ``[parameters]`` table, each read by :func:`parse_number`.

    Parameters
    ----------
    table : object
        The TOML table (None: no parameters).
    where : str
        Its name, for messages.
    exact : dict of str to sympy.Expr
        The exact values of the names the table's expressions may use; the table's own
        exact values as written (:func:`exact_number`) are added to it.

    Returns
    -------
    dict of str to float

    Raises
    ------
    ModelError
        Not a table, more than :data:`MAX_PARAMETERS` entries, a bad name or value.
    """
    if table is None:
        return {}
    if not isinstance(table, dict):
        raise ModelError(f"{where} must be a table of name = number")
    if len(table) > MAX_PARAMETERS:
        raise ModelError(f"{where} has {len(table)} entries, more than the limit "
                         f"MAX_PARAMETERS = {MAX_PARAMETERS}")
    values: dict[str, float] = {}
    for name, value in table.items():
        check_name(name, f"{where}: parameter name")
        values[name] = parse_number(value, f"{where}.{name}", values)
        exact[name] = exact_number(value, exact)
    return values


def exact_number(value: Any, parameters: Mapping[str, sp.Expr]) -> sp.Expr:
    """The exact value of a TOML number or expression text already accepted by
    :func:`parse_number`: an int is itself, a float its shortest decimal
    (:func:`gfrf.model.exact.float_as_written`), a text is read with its decimals as
    rationals (``"2.45/6"`` is 49/120).

    Parameters
    ----------
    value : object
        The TOML value.
    parameters : mapping of str to sympy.Expr
        The exact values of the names the text may use.

    Returns
    -------
    sympy.Expr
        An exact sympy number (rational, or irrational such as ``sqrt(2)``); a sympy
        Float (no rational value: the proofs refuse it) when the exact reading exceeds a
        limit of the parser.
    """
    if isinstance(value, (int, float)):
        return sp.Rational(float_as_written(value))
    try:
        return parse_expression(value, names=dict(parameters), exact=True).expr
    except ModelError:
        return sp.Float(parse_number(value, "", {k: float(v) for k, v in parameters.items()}))
