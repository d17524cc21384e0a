"""The one door for user text: a small whitelisted expression language and its parser.

Every text field gfrf reads (model equations, ``[parameters]`` values, controller
``num``/``den``/``equation``, ``physical_equation``, ``sample_time``, the ``--input``
signal of ``simulate``/``predict``, sweep template values) goes through
:func:`parse_expression`.  The text is *data*: it is tokenised and parsed here by a
recursive-descent parser of our own and the sympy expression is built node by node;
nothing is ever handed to Python's ``eval``, ``exec``, ``sympify`` or ``parse_expr``.

Grammar (Python's operator precedence and associativity)::

    expression := ["+"|"-"]* term (("+"|"-") term)*
    term       := factor (("*"|"/") factor)*
    factor     := ["+"|"-"]* power
    power      := atom ["**" ["+"|"-"]* INTEGER]          exponent: a literal integer
    atom       := NUMBER | NAME | NAME "(" expression ("," expression)* ")"
                | SIGNAL "[" "k" ["-" INTEGER] "]"            (discrete models only)
                | "(" expression ")"

A ``NAME`` is a signal, a parameter or constant of the context (``pi`` and ``E`` are
known unless a parameter of that name shadows them), and a call is one of a fixed
table of functions (``D``, ``sin``, ``cos``, ``exp``, ``sqrt``, ``step``, ...).  There
are no attributes, strings, keywords, subscripts other than lags, lambdas or
comprehensions: anything else is a :class:`~gfrf.errors.ModelError` naming it.

Every input is cheap to refuse: the nodes are built by the checked arithmetic of
:mod:`gfrf.model.limits`, under its limits (text length, nesting, terms, number sizes,
exponents, polynomial degree, monomials), so no text can make the parser (or the sympy
expansion that follows it) run long or grow large.

Examples
--------
>>> import sympy as sp
>>> y = sp.Symbol("y")
>>> parse_expression("2*y**3 - 0.5*y", names={"y": y}, variables=(y,)).expr
2*y**3 - 0.5*y
>>> parse_expression("__import__('os')", names={})
Traceback (most recent call last):
...
gfrf.errors.ModelError: unexpected character "'" at column 12 of "__import__('os')"
"""

from __future__ import annotations

import keyword
import math
import re
from collections.abc import Callable, Mapping, Sequence

import sympy as sp

from gfrf.errors import ModelError
from gfrf.model.limits import (
    MAX_EXPONENT,
    MAX_NAME_LENGTH,
    MAX_NUMBER_LENGTH,
    MAX_TERMS,
    MAX_TEXT_LENGTH,
    Parsed,
    _apply,
    _Context,
    _negate,
    _Node,
    _product,
    _quotient,
    _raise,
    _sum,
    quote,
)

__all__ = ["UnknownNames", "check_name", "parse_expression", "MODEL_FUNCTIONS",
           "SIGNAL_FUNCTIONS", "CONSTANTS"]

#: Functions allowed in model equations and parameter values (``D`` is added for ODEs).
MODEL_FUNCTIONS: dict[str, Callable[..., sp.Expr]] = {
    "sin": sp.sin, "cos": sp.cos, "tan": sp.tan, "sinh": sp.sinh, "cosh": sp.cosh,
    "tanh": sp.tanh, "atan": sp.atan, "exp": sp.exp, "log": sp.log, "sqrt": sp.sqrt,
}
#: Functions allowed in input signals u(t).
SIGNAL_FUNCTIONS: dict[str, Callable[..., sp.Expr]] = {
    **MODEL_FUNCTIONS, "abs": sp.Abs, "Abs": sp.Abs, "sign": sp.sign,
    "step": lambda x: sp.Heaviside(x, 1), "Heaviside": lambda x: sp.Heaviside(x, 1),
}
#: Named constants (a parameter of the same name takes precedence).
CONSTANTS: dict[str, sp.Expr] = {"pi": sp.pi, "E": sp.E}

_PLAIN_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*")
_NOT_FINITE = frozenset({"inf", "infinity", "oo", "nan", "zoo", "Infinity", "NaN"})

_TOKEN = re.compile(r"""
    (?P<space>\s+)
  | (?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)
  | (?P<name>[A-Za-z_][A-Za-z0-9_]*)
  | (?P<op>\*\*|[-+*/(),\[\]^])
""", re.VERBOSE | re.ASCII)


def check_name(name: object, what: str) -> str:
    """``name`` if it is a plain identifier: ASCII letters, digits and single underscores,
    not a Python keyword, not starting with ``_``, at most :data:`MAX_NAME_LENGTH` long.

    Parameters
    ----------
    name : object
        The name to check.
    what : str
        What it names (e.g. ``"parameter"``), for the message.

    Returns
    -------
    str
        ``name``.

    Raises
    ------
    ModelError
        Naming ``what`` and the offending name.
    """
    if not isinstance(name, str) or not _PLAIN_NAME.fullmatch(name) or "__" in name \
            or keyword.iskeyword(name) or len(name) > MAX_NAME_LENGTH:
        raise ModelError(f"{what} {quote(str(name))} is not a plain identifier (ASCII "
                         f"letters, digits and single underscores, not starting with '_', "
                         f"not a keyword, at most MAX_NAME_LENGTH = {MAX_NAME_LENGTH} "
                         f"characters)")
    return name


class UnknownNames(ModelError):
    """The text uses names that are neither signals, parameters nor constants.

    Attributes
    ----------
    names : tuple of str
        The unknown names, sorted.
    """

    def __init__(self, message: str, names: Sequence[str]) -> None:
        super().__init__(message)
        self.names = tuple(names)


def parse_expression(text: str, *, names: Mapping[str, sp.Expr | Parsed] | None = None,
                     functions: Mapping[str, Callable[..., sp.Expr]] | None = None,
                     variables: Sequence[sp.Symbol] = (),
                     signals: Sequence[str] = (),
                     derivative: Callable[[str, int], sp.Expr] | None = None,
                     lag: Callable[[str, int], sp.Expr] | None = None,
                     max_order: int = 20,
                     hints: Mapping[str, str] | None = None,
                     series: bool = True, exact: bool = False) -> Parsed:
    """Parse ``text`` of the gfrf expression language into a sympy expression.

    Parameters
    ----------
    text : str
        The text (data, never evaluated as code).
    names : mapping, optional
        Allowed names and the sympy values they stand for (numbers or symbols), or a
        :class:`Parsed` whose degree and size bounds carry over.  The constants ``pi``
        and ``E`` are added unless ``names`` defines them.
    functions : mapping, optional
        Allowed function names and the sympy functions they build (default
        :data:`MODEL_FUNCTIONS`).
    variables : sequence of sympy.Symbol
        Symbols that count for the polynomial degree (the signals, or time ``t``).
    signals : sequence of str
        Names that ``D(name, n)`` and the lag ``name[k-n]`` apply to.
    derivative, lag : callable, optional
        ``(signal, order) -> expr`` for ``D(signal, order)`` (continuous models) and for
        ``signal[k-order]`` (discrete models); None forbids the notation.
    max_order : int
        Largest derivative order or lag.
    hints : mapping, optional
        A message for particular unknown names (e.g. ``{"t": "... time t ..."}``).
    series : bool
        The expression will be expanded or Taylor-truncated in the ``variables`` (model
        equations, sweep templates): functions of the variables are then limited by
        :data:`~gfrf.model.limits.MAX_FUNCTION_NESTING` and
        :data:`~gfrf.model.limits.MAX_FUNCTION_CALLS`, and ``log`` of a variable is
        refused (``exp(n*log(X))`` would be ``X**n``).  False for input signals u(t),
        which are only differentiated and evaluated.
    exact : bool
        Read decimal literals as the exact rationals they write (``0.2`` is 1/5, ``2.45/6``
        is 49/120) instead of as doubles: the expression is then the model as written,
        for the exact and ball-arithmetic proofs (the doubles stay the path of estimates
        and simulation).

    Returns
    -------
    Parsed

    Raises
    ------
    ModelError
        Anything outside the grammar or beyond a limit; the message names the limit or
        the offending part and its column.  :class:`UnknownNames` for unknown names.
    """
    if not isinstance(text, str):
        raise ModelError(f"expected text, got {type(text).__name__}")
    if len(text) > MAX_TEXT_LENGTH:
        raise ModelError(f"the text has {len(text)} characters, more than the limit "
                         f"MAX_TEXT_LENGTH = {MAX_TEXT_LENGTH}: {quote(text)}")
    ctx = _Context(text=text, names={**CONSTANTS, **(names or {})},
                   functions=MODEL_FUNCTIONS if functions is None else functions,
                   variables=frozenset(variables), derivative=derivative, lag=lag,
                   signals=tuple(signals), max_order=max_order, hints=hints or {},
                   series=series, exact=exact)
    ctx.tokens = _tokenize(ctx)
    _check_names(ctx)
    node = _expression(ctx)
    kind, token, column = ctx.peek()
    if kind != "end":
        raise ctx.fail(f"unexpected {token!r}", column)
    return Parsed(node.expr, node.degree, node.analytic, node.monomials, node.varying,
                  node.nesting)


def _tokenize(ctx: _Context) -> list[tuple[str, str, int]]:
    text = ctx.text
    tokens: list[tuple[str, str, int]] = []
    pos = 0
    while pos < len(text):
        match = _TOKEN.match(text, pos)
        if match is None:
            char = text[pos]
            if char == "=":
                raise ctx.fail("unexpected '=' (a single '=' separates the two sides of an "
                               "equation)", pos)
            raise ctx.fail(f"unexpected character {char!r}", pos)
        kind = match.lastgroup or ""
        value = match.group()
        if kind == "number":
            following = text[match.end():match.end() + 1]
            if following and (following.isalnum() or following in "_."):
                raise ctx.fail(f"malformed number {text[pos:match.end() + 1]!r} (write 2*y "
                               f"for a product; complex, hexadecimal and underscore numbers "
                               f"are not accepted)", pos)
            if len(value) > MAX_NUMBER_LENGTH:
                raise ctx.fail(f"the number literal of {len(value)} characters exceeds the "
                               f"limit MAX_NUMBER_LENGTH = {MAX_NUMBER_LENGTH}", pos)
        elif kind == "name" and len(value) > MAX_NAME_LENGTH:
            raise ctx.fail(f"a name longer than the limit MAX_NAME_LENGTH = "
                           f"{MAX_NAME_LENGTH}", pos)
        elif kind == "op" and value == "^":
            raise ctx.fail("'^' is not a power here: write y**3 for y cubed", pos)
        if kind != "space":
            tokens.append((kind, value, pos))
        pos = match.end()
    tokens.append(("end", "", len(text)))
    return tokens


def _check_names(ctx: _Context) -> None:
    """Refuse unknown names up front, all of them in one message."""
    unknown: set[str] = set()
    tokens = ctx.tokens
    for i, (kind, value, column) in enumerate(tokens):
        if kind != "name":
            continue
        after = tokens[i + 1][1]
        if after == "(":
            if value == "D" and ctx.derivative is not None:
                continue
            if value not in ctx.functions:
                hint = ""
                if value == "D":
                    hint = " (discrete models use y[k-n], not D)" if ctx.lag else \
                        " (D(...) is for model equations)"
                known = ", ".join(sorted(ctx.functions)) or "none"
                raise ctx.fail(f"unknown function {value!r}{hint}; allowed: {known}", column)
            continue
        if after == "[":
            if ctx.lag is None:
                raise ctx.fail(f"'{value}[...]': subscripts are only the lags y[k-n] of a "
                               f"discrete model's signals (give a sample_time)", column)
            if value not in ctx.signals:
                raise ctx.fail(f"unknown signal {value!r} in a lag: the signals are "
                               f"{ctx.signals[0]!r} (output) and {ctx.signals[1]!r} (input)",
                               column)
            continue
        if i >= 2 and tokens[i - 1][1] == "(" and tokens[i - 2][1] == "D" \
                and ctx.derivative is not None:
            continue  # the signal of D(signal, n), checked by the derivative rule
        if value == "k" and i > 0 and tokens[i - 1][1] == "[":
            continue
        if value in _NOT_FINITE and value not in ctx.names:
            raise ctx.fail(f"{value!r} is not finite (NaN or infinite)", column)
        if value not in ctx.names:
            if value in ctx.hints:
                raise ModelError(ctx.hints[value])
            unknown.add(value)
    if unknown:
        listed = ", ".join(sorted(unknown))
        raise UnknownNames(f"unknown symbol(s) {listed} in {quote(ctx.text)}", sorted(unknown))


# -- the grammar ----------------------------------------------------------------------

def _expression(ctx: _Context) -> _Node:
    operands: list[_Node] = []
    sign = _signs(ctx)
    while True:
        node = _term(ctx)
        operands.append(_negate(node) if sign < 0 else node)
        ctx.terms += 1
        if ctx.terms > MAX_TERMS:
            raise ctx.fail(f"more than MAX_TERMS = {MAX_TERMS} terms", ctx.peek()[2])
        token = ctx.peek()[1]
        if token not in ("+", "-"):
            break
        ctx.take()
        sign = -1 if token == "-" else 1
    return operands[0] if len(operands) == 1 else _sum(ctx, operands)


def _signs(ctx: _Context) -> int:
    sign = 1
    while ctx.peek()[1] in ("+", "-"):
        if ctx.take()[1] == "-":
            sign = -sign
    return sign


def _term(ctx: _Context) -> _Node:
    node = _factor(ctx)
    while ctx.peek()[1] in ("*", "/"):
        _, op, column = ctx.take()
        right = _factor(ctx)
        node = _product(ctx, node, right, column) if op == "*" else \
            _quotient(ctx, node, right, column)
    return node


def _factor(ctx: _Context) -> _Node:
    sign = _signs(ctx)
    node = _power(ctx)
    return _negate(node) if sign < 0 else node


def _power(ctx: _Context) -> _Node:
    base = _atom(ctx)
    if ctx.peek()[1] != "**":
        return base
    column = ctx.take()[2]
    sign = _signs(ctx)
    parenthesised = ctx.peek()[1] == "("
    if parenthesised:
        ctx.take()
        sign *= _signs(ctx)
    kind, value, at = ctx.take()
    if kind != "number" or not value.isdigit() or (parenthesised and ctx.peek()[1] != ")"):
        raise ctx.fail("the exponent after '**' must be an integer literal such as 2 or 3 "
                       "(use sqrt(x) for a square root)", at)
    if parenthesised:
        ctx.expect(")")
    if ctx.peek()[1] == "**":
        raise ctx.fail("the exponent after '**' must be an integer literal: a tower "
                       "a**b**c is not accepted", ctx.peek()[2])
    exponent = sign * int(value)
    if abs(exponent) > MAX_EXPONENT:
        raise ctx.fail(f"the exponent {exponent} exceeds the limit MAX_EXPONENT = "
                       f"{MAX_EXPONENT}", column)
    return _raise(ctx, base, exponent, column)


def _atom(ctx: _Context) -> _Node:
    kind, value, column = ctx.take()
    if kind == "number":
        return _number(ctx, value, column)
    if value == "(":
        ctx.enter(column)
        node = _expression(ctx)
        ctx.expect(")")
        ctx.leave()
        return node
    if kind == "name":
        following = ctx.peek()[1]
        if following == "(":
            return _call(ctx, value, column)
        if following == "[" and value in ctx.signals and ctx.lag is not None:
            return _lagged(ctx, value, column)
        return _name(ctx, value)
    found = "the end of the text" if kind == "end" else repr(value)
    raise ctx.fail(f"expected a number, a name or '(' but found {found}", column)


def _number(ctx: _Context, value: str, column: int) -> _Node:
    if value.isdigit():
        return _Node(sp.Integer(int(value)))
    number = float(value)
    if not math.isfinite(number):
        raise ctx.fail(f"the number {value} is not finite in double precision", column)
    return _Node(sp.Rational(value) if ctx.exact else sp.Float(number))


def _name(ctx: _Context, value: str) -> _Node:
    expr = ctx.names[value]
    if isinstance(expr, Parsed):
        return _Node(expr.expr, expr.degree, expr.monomials, expr.analytic, expr.varying,
                     expr.nesting)
    varying = bool(ctx.variables & expr.free_symbols)
    return _Node(expr, degree=1 if varying else 0, varying=varying)


def _signal_atom(ctx: _Context, expr: sp.Expr) -> _Node:
    return _Node(expr, degree=1, varying=True)


def _call(ctx: _Context, name: str, column: int) -> _Node:
    ctx.take()  # "("
    ctx.enter(column)
    if name == "D" and ctx.derivative is not None:
        node = _derivative(ctx, column)
    else:
        args = [_expression(ctx)]
        while ctx.peek()[1] == ",":
            ctx.take()
            args.append(_expression(ctx))
        ctx.expect(")")
        if len(args) != 1:
            raise ctx.fail(f"{name}() takes one argument, got {len(args)}", column)
        node = _apply(ctx, name, args[0], column)
    ctx.leave()
    return node


def _derivative(ctx: _Context, column: int) -> _Node:
    if ctx.peek()[0] == "end":
        raise ctx.fail("D( is not closed", column)
    kind, signal, at = ctx.take()
    order = 1
    order_text = ""
    if ctx.peek()[1] == ",":
        ctx.take()
        negative = _signs(ctx) < 0
        kind_o, order_text, at_o = ctx.take()
        if kind_o != "number":
            raise ctx.fail(f"D({signal}, ...): the order must be a non-negative integer",
                           at_o)
        value = float(order_text)
        if negative and value:
            raise ctx.fail(f"'D({signal},-{order_text})': negative derivative order "
                           f"-{order_text}", at_o)
        if not value.is_integer():
            raise ctx.fail(f"'D({signal},{order_text})': the order must be a non-negative "
                           f"integer", at_o)
        order = int(value)
    if kind != "name" or signal not in ctx.signals or ctx.peek()[1] != ")":
        shown = signal if kind == "name" else "..."
        raise ctx.fail(f"'D({shown})': the first argument must be the output "
                       f"{ctx.signals[0]!r} or the input {ctx.signals[1]!r}, the second "
                       f"the order", at)
    ctx.take()
    if order > ctx.max_order:
        raise ctx.fail(f"'D({signal},{order})': order {order} exceeds the limit "
                       f"{ctx.max_order}", column)
    assert ctx.derivative is not None
    return _signal_atom(ctx, ctx.derivative(signal, order))


def _lagged(ctx: _Context, signal: str, column: int) -> _Node:
    ctx.take()  # "["
    kind, value, at = ctx.take()
    if value != "k":
        raise ctx.fail(f"cannot read the lag of {signal!r}: write {signal}[k], "
                       f"{signal}[k-1], ...", at)
    lag = 0
    if ctx.peek()[1] in ("-", "+"):
        _, op, at_op = ctx.take()
        kind, number, at_n = ctx.take()
        if kind != "number" or not number.isdigit():
            raise ctx.fail(f"the lag of {signal!r} must be an integer", at_n)
        if op == "+" and int(number):
            raise ctx.fail(f"'{signal}[k+{number}]' looks into the future: write lags as "
                           f"{signal}[k-n] with n >= 0", at_op)
        lag = int(number)
    ctx.expect("]")
    if lag > ctx.max_order:
        raise ctx.fail(f"'{signal}[k-{lag}]': lag {lag} exceeds the limit {ctx.max_order}",
                       column)
    assert ctx.lag is not None
    return _signal_atom(ctx, ctx.lag(signal, lag))
