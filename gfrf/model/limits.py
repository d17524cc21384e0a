"""The limits of the expression language and the checked arithmetic that keeps to them.

The parser of :mod:`gfrf.model.expr` reads text into nodes; this module holds what it
builds them with: the parse state (:class:`_Context`, which counts nesting, terms and
function calls and formats the refusals), the node (:class:`_Node`, a sympy expression
with bounds of its polynomial degree and size), the :class:`Parsed` result, and the
node arithmetic (sums, negation, products, quotients, integer powers, function calls)
that checks every limit *before* sympy computes anything.

Every input is cheap to refuse: the limits below bound the text, the nesting, the
number of terms, the size of number literals and of exact intermediate numbers, the
exponents, the total polynomial degree and the number of monomials that expanding the
expression can produce, so no text can make the parser (or the sympy expansion that
follows it) run long or grow large.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import sympy as sp

from gfrf.errors import ModelError

__all__ = ["Parsed", "quote", "MAX_TEXT_LENGTH", "MAX_NESTING", "MAX_TERMS",
           "MAX_NUMBER_LENGTH", "MAX_NUMBER_BITS", "MAX_EXPONENT", "MAX_DEGREE",
           "MAX_MONOMIALS", "MAX_NAME_LENGTH", "MAX_FUNCTION_NESTING", "MAX_FUNCTION_CALLS"]

#: Longest text accepted in one field, in characters.
MAX_TEXT_LENGTH = 100_000
#: Deepest nesting of parentheses, calls and lags.
MAX_NESTING = 32
#: Most additive terms (operands of + and -) in one text, counted over all levels.
MAX_TERMS = 5_000
#: Longest number literal, in characters.
MAX_NUMBER_LENGTH = 40
#: Largest exact (integer or rational) intermediate number, in bits of its numerator
#: or denominator; float-valued intermediates must stay finite.
MAX_NUMBER_BITS = 2048
#: Largest absolute value of an integer exponent.
MAX_EXPONENT = 15
#: Largest total polynomial degree of a term in the signals (products ``y*y*...`` count).
MAX_DEGREE = 15
#: Most monomials that expanding the expression may produce (an a-priori bound).
MAX_MONOMIALS = 20_000
#: Longest name (signal, parameter, function).
MAX_NAME_LENGTH = 64
#: Deepest nesting of functions of the signals (``sin(cos(y))`` is 2).
MAX_FUNCTION_NESTING = 2
#: Most calls of functions of the signals in one text.
MAX_FUNCTION_CALLS = 32

_QUOTE_LENGTH = 80


def quote(text: str) -> str:
    """``repr`` of ``text`` shortened to about 80 characters, for error messages.

    Parameters
    ----------
    text : str
        User text.

    Returns
    -------
    str
        The quoted text.
    """
    if len(text) <= _QUOTE_LENGTH:
        return repr(text)
    return repr(text[:_QUOTE_LENGTH - 20] + " ... " + text[-15:])


@dataclass(frozen=True)
class Parsed:
    """A parsed expression and what the parser learnt about it.

    Attributes
    ----------
    expr : sympy.Expr
        The expression (sympy's automatic simplification applied, nothing expanded).
    degree : int
        Upper bound of the total polynomial degree in the ``variables``.
    analytic : bool
        True if a variable appears inside a function or a denominator, so the
        expression is not a polynomial and needs a Taylor truncation.
    monomials : int
        Upper bound of the number of monomials of the expanded expression.
    varying : bool
        True if the expression depends on a variable.
    nesting : int
        Deepest nesting of functions of the variables (``sin(cos(y))`` is 2).

    A ``Parsed`` may stand as the value of a name in a later parse (a parameter
    defined by an expression of swept parameters): the bounds then carry over.
    """

    expr: sp.Expr
    degree: int
    analytic: bool
    monomials: int = 1
    varying: bool = False
    nesting: int = 0


@dataclass(frozen=True)
class _Node:
    expr: sp.Expr
    degree: int = 0          # polynomial degree bound in the variables
    monomials: int = 1       # bound on the monomials of the expanded expression
    analytic: bool = False   # a variable sits inside a function or a denominator
    varying: bool = False    # depends on a variable at all
    nesting: int = 0         # nesting of functions of the variables


@dataclass
class _Context:
    text: str
    names: Mapping[str, sp.Expr | Parsed]
    functions: Mapping[str, Callable[..., sp.Expr]]
    variables: frozenset[sp.Symbol]
    derivative: Callable[[str, int], sp.Expr] | None
    lag: Callable[[str, int], sp.Expr] | None
    signals: tuple[str, ...]
    max_order: int
    hints: Mapping[str, str]
    series: bool = True
    exact: bool = False
    tokens: list[tuple[str, str, int]] = field(default_factory=list)
    pos: int = 0
    depth: int = 0
    terms: int = 0
    calls: int = 0

    # -- errors ------------------------------------------------------------------
    def fail(self, message: str, column: int | None = None) -> ModelError:
        where = f" at column {column + 1}" if column is not None else ""
        return ModelError(f"{message}{where} of {quote(self.text)}")

    # -- tokens ------------------------------------------------------------------
    def peek(self) -> tuple[str, str, int]:
        return self.tokens[self.pos]

    def take(self) -> tuple[str, str, int]:
        token = self.tokens[self.pos]
        if token[0] != "end":  # the end token is never passed: reading on keeps seeing it
            self.pos += 1
        return token

    def expect(self, value: str) -> None:
        kind, text, column = self.take()
        if text != value:
            found = "the end of the text" if kind == "end" else repr(text)
            raise self.fail(f"expected {value!r} but found {found}", column)

    def enter(self, column: int) -> None:
        self.depth += 1
        if self.depth > MAX_NESTING:
            raise self.fail(f"nesting deeper than the limit MAX_NESTING = {MAX_NESTING}",
                            column)

    def leave(self) -> None:
        self.depth -= 1


# -- building sympy expressions under the limits --------------------------------------

def _checked_number(ctx: _Context, expr: sp.Expr, column: int | None) -> sp.Expr:
    """Refuse exact numbers beyond MAX_NUMBER_BITS and float numbers beyond double range."""
    if expr.is_Rational:
        if max(int(expr.p).bit_length(), int(expr.q).bit_length()) > MAX_NUMBER_BITS:
            raise ctx.fail(f"an intermediate number exceeds MAX_NUMBER_BITS = "
                           f"{MAX_NUMBER_BITS} bits", column)
    elif expr.is_Float and not math.isfinite(float(expr)):
        raise ctx.fail("an intermediate number overflows double precision", column)
    return expr


def _sum(ctx: _Context, operands: list[_Node]) -> _Node:
    expr = sp.Add(*(o.expr for o in operands))
    varying = any(o.varying for o in operands)
    monomials = sum(o.monomials for o in operands) if varying else 1
    if monomials > MAX_MONOMIALS:
        raise ctx.fail(f"the expression would expand to more than MAX_MONOMIALS = "
                       f"{MAX_MONOMIALS} monomials")
    if expr.is_number:
        expr = _checked_number(ctx, expr, None)
    return _Node(expr, max(o.degree for o in operands), monomials,
                 any(o.analytic for o in operands), varying, max(o.nesting for o in operands))


def _negate(node: _Node) -> _Node:
    return _Node(-node.expr, node.degree, node.monomials, node.analytic, node.varying,
                 node.nesting)


def _product(ctx: _Context, left: _Node, right: _Node, column: int) -> _Node:
    degree = left.degree + right.degree
    if degree > MAX_DEGREE:
        raise ctx.fail(f"a product of total degree {degree} exceeds the limit MAX_DEGREE = "
                       f"{MAX_DEGREE}", column)
    monomials = left.monomials * right.monomials
    if monomials > MAX_MONOMIALS:
        raise ctx.fail(f"the product would expand to more than MAX_MONOMIALS = "
                       f"{MAX_MONOMIALS} monomials", column)
    _check_operands(ctx, left, right, column)
    expr = left.expr * right.expr
    if expr.is_number:
        expr = _checked_number(ctx, expr, column)
    return _Node(expr, degree, monomials, left.analytic or right.analytic,
                 left.varying or right.varying, max(left.nesting, right.nesting))


def _check_operands(ctx: _Context, left: _Node, right: _Node, column: int) -> None:
    """Refuse a product or quotient of two exact numbers whose result could exceed
    :data:`MAX_NUMBER_BITS` by much, before sympy computes it."""
    if left.expr.is_Rational and right.expr.is_Rational:
        bits = sum(max(int(e.p).bit_length(), int(e.q).bit_length())
                   for e in (left.expr, right.expr))
        if bits > 2 * MAX_NUMBER_BITS:
            raise ctx.fail(f"an intermediate number exceeds MAX_NUMBER_BITS = "
                           f"{MAX_NUMBER_BITS} bits", column)


def _quotient(ctx: _Context, left: _Node, right: _Node, column: int) -> _Node:
    if right.varying:
        # The inverse keeps the degree and size bounds of its base: sympy may cancel
        # 1/(1/X) back to X, so an inverse must not launder X's size.
        inverse = _Node(1 / right.expr, right.degree, right.monomials, True, True,
                        right.nesting)
        return _product(ctx, left, inverse, column)
    _check_operands(ctx, left, right, column)
    expr = left.expr / right.expr
    if expr.is_number and expr.is_finite:
        expr = _checked_number(ctx, expr, column)
    return _Node(expr, left.degree, left.monomials, left.analytic, left.varying, left.nesting)


def _raise(ctx: _Context, base: _Node, exponent: int, column: int) -> _Node:
    count = abs(exponent)  # X**-n is bounded like X**n: sympy may cancel the inverse
    degree = base.degree * count
    if degree > MAX_DEGREE:
        raise ctx.fail(f"the power of total degree {degree} exceeds the limit MAX_DEGREE = "
                       f"{MAX_DEGREE}", column)
    monomials = min(base.monomials ** count,
                    math.comb(base.monomials + count - 1, count)) if base.varying else 1
    if monomials > MAX_MONOMIALS:
        raise ctx.fail(f"the power would expand to more than MAX_MONOMIALS = "
                       f"{MAX_MONOMIALS} monomials", column)
    if base.expr.is_Rational:
        bits = max(int(base.expr.p).bit_length(), int(base.expr.q).bit_length())
        if bits * abs(exponent) > MAX_NUMBER_BITS:
            raise ctx.fail(f"the power exceeds MAX_NUMBER_BITS = {MAX_NUMBER_BITS} bits",
                           column)
    if base.expr == 0 and exponent < 0:
        expr: sp.Expr = sp.zoo
    else:
        expr = base.expr ** exponent
    if expr.is_number and expr.is_finite:
        expr = _checked_number(ctx, expr, column)
    return _Node(expr, degree, monomials, base.analytic or (base.varying and exponent < 0),
                 base.varying, base.nesting)


_EXACT_OPS = 40
"""Largest operation count of a constant argument that gets sympy's exact evaluation."""


def _apply(ctx: _Context, name: str, arg: _Node, column: int) -> _Node:
    if arg.varying and ctx.series:
        if name == "log":
            raise ctx.fail("log() of a signal is not accepted (write its Taylor polynomial)",
                           column)
        ctx.calls += 1
        if ctx.calls > MAX_FUNCTION_CALLS:
            raise ctx.fail(f"more than MAX_FUNCTION_CALLS = {MAX_FUNCTION_CALLS} calls of "
                           f"functions of the signals", column)
        if arg.nesting + 1 > MAX_FUNCTION_NESTING:
            raise ctx.fail(f"functions of the signals nested deeper than "
                           f"MAX_FUNCTION_NESTING = {MAX_FUNCTION_NESTING}", column)
        # A function keeps its argument's bounds (sympy may simplify f(g(X)) to X).
        return _Node(ctx.functions[name](arg.expr), arg.degree, arg.monomials, True, True,
                     arg.nesting + 1)
    if arg.varying:
        return _Node(ctx.functions[name](arg.expr), arg.degree, arg.monomials, True, True,
                     arg.nesting + 1)
    argument = arg.expr
    if name == "tan" and argument.is_number and sp.cos(argument) == 0:
        # decided exactly on the parser's tree (cos(pi/2) is 0): 30 digits of pi/2
        # would give tan = 1.2e31, a number, where the function has a pole
        raise ctx.fail("tan() of its argument is at a pole (the cosine of the argument is "
                       "exactly 0)", column)
    if argument.is_number and not (argument.is_Rational or argument.is_Float):
        if sp.count_ops(argument) <= _EXACT_OPS:
            # sympy's exact special values first (cos(pi/2) = 0, log(exp(0)) = 0): a zero
            # must stay 0, not the 1e-31 of 30 digits (1 / cos(pi/2) would be 1.6e31)
            exact = ctx.functions[name](argument)
            if exact == 0:
                return _Node(sp.Integer(0), 0, 1, arg.analytic, False, arg.nesting)
            if exact.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
                raise ctx.fail(f"{name}() of its argument is at a pole (exact)", column)
        # An irrational number (sin(1) + ... + sin(2000)): one numeric evaluation here,
        # so nested calls never re-evaluate a large exact tree.
        argument = argument.evalf(30)
    expr = ctx.functions[name](argument)
    if expr.is_number:
        try:
            value = complex(expr)
        except (TypeError, ValueError, OverflowError):
            value = complex(math.nan)
        if not (math.isfinite(value.real) and math.isfinite(value.imag)):
            raise ctx.fail(f"{name}() of its argument is not finite", column)
        if value.imag != 0:
            raise ctx.fail(f"{name}() of its argument is not a real number", column)
    return _Node(expr, 0, 1, arg.analytic, False, arg.nesting)
