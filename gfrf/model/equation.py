"""Polynomial nonlinear input-output models: parsing, truncation and validation.

A continuous-time model is the class of eq (1) of the GFRF paper: a sum of terms

    c * prod_i D^{l_i} y * prod_j D^{k_j} u  =  0,

written as text the way a paper writes it, ``D(y,2) + 0.05*D(y) + 2.45*y - 0.41*y**3 = u``
(``D(y)`` is dy/dt, ``D(y,n)`` the n-th derivative).  A discrete-time NARX model uses
lags instead of derivatives, ``y[k] = 0.5*y[k-1] - 0.2*y[k-1]**2*u[k-2] + u[k-1]``, and
has a ``sample_time``; the same GFRF engine handles it with ``exp(-j*omega*T)`` in
place of ``j*omega``.

Non-polynomial terms (``sin(y)``, ``cos(y)``, ...) are allowed when a ``truncation``
order is given: the model is Taylor-expanded jointly in all signals up to that total
degree, and the untruncated equation is kept in :attr:`Model.physical` for simulation.

Examples
--------
>>> m = parse_model("D(y,2) + 0.05*D(y) + 2.45*y - 0.41*y**3 = u")
>>> m.equation()
'-0.41*y**3 + 2.45*y + 0.05*D(y) + D(y,2) - u = 0'
>>> m.linear_output
{0: 2.45, 1: 0.05, 2: 1.0}
>>> m.degree
3
"""

from __future__ import annotations

import math
import re
import sys
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Any

import sympy as sp

from gfrf._results import Result
from gfrf.errors import ModelError
from gfrf.model.exact import Written, as_fraction, coefficient_bounds, exact_value, float_as_written
from gfrf.model.expr import MODEL_FUNCTIONS, UnknownNames, check_name, parse_expression
from gfrf.model.limits import MAX_DEGREE, MAX_TEXT_LENGTH, Parsed, quote

__all__ = ["Term", "Model", "parse_model", "ModelTypeError", "coefficient_formulas",
           "MAX_DERIVATIVE_ORDER",
           "MAX_DEGREE", "MAX_TRUNCATION_WORK"]

_LARGEST_FLOAT = 1.7976931348623157e308
#: Largest a-priori work of a Taylor truncation: monomials of degree <= the truncation
#: order in the signal atoms, times the functions of the signals (the cart-pole's eq
#: (8)-(9) needs 35 x 5; 1000 takes about 3 s of sympy series on this machine).
MAX_TRUNCATION_WORK = 1000
#: Largest derivative order or lag accepted in a model text.
MAX_DERIVATIVE_ORDER = 20


@dataclass(frozen=True, order=True)
class Term:
    """One monomial ``coefficient * prod D^l y * prod D^k u`` of a model (sum of terms = 0).

    Parameters
    ----------
    y_orders : tuple of int
        Derivative orders (continuous) or lags (discrete) of the output factors, sorted.
    u_orders : tuple of int
        Derivative orders or lags of the input factors, sorted.
    coefficient : float
        The real coefficient (a double: estimates, kernels and simulation use it).
    output, input : str
        Names of the output and input signals.
    discrete : bool
        True for a NARX term (lags instead of derivatives).
    written : Written, optional
        The exact value of the coefficient as written in the model text (see
        :mod:`gfrf.model.exact`); the proofs read it through :attr:`exact` and
        :meth:`bounds`.
    """

    y_orders: tuple[int, ...]
    u_orders: tuple[int, ...]
    coefficient: float
    output: str = field(default="y", compare=False)
    input: str = field(default="u", compare=False)
    discrete: bool = field(default=False, compare=False)
    written: Written | None = field(default=None, compare=False, repr=False)

    @property
    def exact(self) -> Fraction | None:
        """The exact rational coefficient of the model as written (the double's own value
        for a coefficient that never was text); None when the written value is irrational."""
        return exact_value(self.coefficient, self.written)

    def bounds(self) -> tuple[Fraction, Fraction]:
        """Rational ``(lo, hi)`` containing the coefficient as written (equal when it is
        rational; see :func:`gfrf.model.exact.coefficient_bounds`)."""
        return coefficient_bounds(self.coefficient, self.written)

    @property
    def degree(self) -> int:
        """Total degree p + q of the monomial."""
        return len(self.y_orders) + len(self.u_orders)

    @property
    def is_linear_output(self) -> bool:
        """True for a term ``c * D^l y`` of the linear output part."""
        return len(self.y_orders) == 1 and not self.u_orders

    def _factor(self, name: str, order: int) -> str:
        if self.discrete:
            return f"{name}[k-{order}]" if order else f"{name}[k]"
        if order == 0:
            return name
        return f"D({name})" if order == 1 else f"D({name},{order})"

    def monomial(self) -> str:
        """The monomial without its coefficient, e.g. ``y**2*D(y,2)``."""
        parts = []
        for name, orders in ((self.output, self.y_orders), (self.input, self.u_orders)):
            for order in sorted(set(orders)):
                power = orders.count(order)
                factor = self._factor(name, order)
                parts.append(factor if power == 1 else f"{factor}**{power}")
        return "*".join(parts)

    def __str__(self) -> str:
        c = self.coefficient
        if c == 1:
            return self.monomial()
        if c == -1:
            return "-" + self.monomial()
        return f"{c:.12g}*{self.monomial()}"


@dataclass(frozen=True, kw_only=True)
class Model(Result):
    """An immutable polynomial input-output model ``sum(terms) = 0``.

    Build it with :func:`parse_model` or :func:`gfrf.model.modelfile.load_model`.

    Attributes
    ----------
    terms : tuple of Term
        The monomials; their sum is zero along every trajectory.
    sample_time : float or None
        Sample time T in seconds of a discrete-time (NARX) model, None if continuous.
    output, input : str
        Names of the output and input signals.
    text : str
        The equation text as given.
    truncation : int or None
        Taylor truncation order used to make the equation polynomial, if any.
    physical : sympy.Expr
        The untruncated left-hand side minus right-hand side, in the atom symbols of
        :meth:`atom` (equal to the polynomial when no truncation was needed); not in
        :meth:`to_dict` (a sympy expression: ``equation`` and ``text`` say it).
    """

    _exclude = ("physical",)
    _order = ("equation", "text", "discrete", "sample_time", "output", "input", "truncation",
              "degree", "max_order", "terms")

    terms: tuple[Term, ...]
    sample_time: float | None = None
    output: str = "y"
    input: str = "u"
    text: str = ""
    truncation: int | None = None
    physical: Any = None

    @property
    def is_discrete(self) -> bool:
        """True for a discrete-time NARX model."""
        return self.sample_time is not None

    @property
    def degree(self) -> int:
        """Largest total degree of a term (N of the paper's eq (1))."""
        return max(t.degree for t in self.terms)

    @property
    def max_order(self) -> int:
        """Largest derivative order or lag appearing in the model (M of eq (1))."""
        return max(max(t.y_orders + t.u_orders) for t in self.terms)

    @property
    def linear_output(self) -> dict[int, float]:
        """Coefficients ``{l: a_l}`` of the linear output part A(s) = sum a_l s^l."""
        return {t.y_orders[0]: t.coefficient for t in self.terms if t.is_linear_output}

    @property
    def linear_input(self) -> dict[int, float]:
        """Coefficients ``{k: b_k}`` of the linear input part B(s); H1 = -B/A."""
        return {t.u_orders[0]: t.coefficient for t in self.terms
                if not t.y_orders and len(t.u_orders) == 1}

    @property
    def nonlinear_terms(self) -> tuple[Term, ...]:
        """Terms of degree >= 2."""
        return tuple(t for t in self.terms if t.degree >= 2)

    def atom(self, signal: str, order: int) -> sp.Symbol:
        """The sympy symbol standing for ``D^order signal`` (or ``signal[k-order]``).

        Parameters
        ----------
        signal : str
            The signal's name (the model's output or input).
        order : int
            The derivative order (continuous) or the lag (discrete), >= 0.

        Returns
        -------
        sympy.Symbol
            The symbol.
        """
        return _atom(signal, order)

    def polynomial(self) -> sp.Expr:
        """The polynomial ``sum(terms)`` as a sympy expression in the atom symbols."""
        expr = sp.Integer(0)
        for t in self.terms:
            mono = sp.Float(t.coefficient)
            for order in t.y_orders:
                mono *= _atom(self.output, order)
            for order in t.u_orders:
                mono *= _atom(self.input, order)
            expr += mono
        return expr

    def __repr__(self) -> str:
        kind = f", sample_time={self.sample_time!r}" if self.is_discrete else ""
        return f"Model({self.equation()!r}{kind})"

    def _repr_latex_(self) -> str:
        names = {}
        for signal in (self.output, self.input):
            for order in range(self.max_order + 1):
                if self.is_discrete:
                    name = f"{signal}_{{k-{order}}}" if order else f"{signal}_{{k}}"
                else:
                    name = {0: signal, 1: rf"\dot{{{signal}}}",
                            2: rf"\ddot{{{signal}}}"}.get(order, f"{signal}^{{({order})}}")
                names[_atom(signal, order)] = name
        expr = self.polynomial()
        expr = expr.xreplace({f: sp.Integer(int(f)) for f in expr.atoms(sp.Float)
                             if float(f).is_integer()})
        return f"${sp.latex(expr, symbol_names=names)} = 0$"

    def equation(self) -> str:
        """The polynomial model as text, ``... = 0``, in the model's own notation."""
        text = " + ".join(str(t) for t in sorted(self.terms, key=_display_key))
        return text.replace("+ -", "- ") + " = 0"

    def coefficient_table(self) -> list[dict[str, Any]]:
        """Rows ``{monomial, coefficient, y_orders, u_orders, kind}`` for display and JSON."""
        rows = []
        for t in sorted(self.terms, key=_display_key):
            if not t.u_orders:
                kind = "linear output" if t.degree == 1 else "pure output"
            elif not t.y_orders:
                kind = "linear input" if t.degree == 1 else "pure input"
            else:
                kind = "cross"
            rows.append({"monomial": t.monomial(), "coefficient": t.coefficient,
                         "y_orders": list(t.y_orders), "u_orders": list(t.u_orders),
                         "kind": kind})
        return rows

    def _computed(self) -> dict[str, Any]:
        return {"equation": self.equation(), "discrete": self.is_discrete,
                "degree": self.degree, "max_order": self.max_order,
                "terms": self.coefficient_table()}


def _display_key(t: Term) -> tuple:
    return (-t.degree, bool(t.u_orders), t.y_orders, t.u_orders)


def _atom(signal: str, order: int) -> sp.Symbol:
    return sp.Symbol(f"{signal}__{order}", real=True)


def _split_equation(text: str) -> tuple[str, str]:
    if not isinstance(text, str) or not text.strip():
        raise ModelError("empty equation: expected text such as 'D(y,2) + 2*D(y) + y = u'")
    if len(text) > MAX_TEXT_LENGTH:
        raise ModelError(f"the equation has {len(text)} characters, more than the limit "
                         f"MAX_TEXT_LENGTH = {MAX_TEXT_LENGTH}: {quote(text)}")
    text = " ".join(text.split())
    if "==" in text:
        raise ModelError(f"use a single '=' in the equation, not '==': {quote(text)}")
    sides = text.split("=")
    if len(sides) > 2:
        raise ModelError(f"the equation has more than one '=': {quote(text)}")
    if len(sides) == 1:
        return sides[0], "0"
    lhs, rhs = sides
    if not lhs.strip() or not rhs.strip():
        raise ModelError(f"one side of the equation is empty: {quote(text)}")
    return lhs, rhs


def _truncate(expr: sp.Expr, atoms: list[sp.Symbol], order: int) -> sp.Expr:
    scale = sp.Symbol("_scale")
    scaled = expr.xreplace({a: scale * a for a in atoms})
    try:
        series = sp.series(scaled, scale, 0, order + 1).removeO()
    except (ValueError, NotImplementedError, TypeError) as exc:
        raise ModelError(f"cannot Taylor-expand the equation to order {order}: {exc}") from None
    return sp.expand(series.subs(scale, 1))


def _signal_expression(text: str, local: dict[str, sp.Expr | Parsed], output: str, input_: str,
                       discrete: bool, exact: bool = False
                       ) -> tuple[sp.Expr, list[sp.Symbol], bool]:
    """Left-hand side minus right-hand side in the atom symbols, the atoms present, and
    whether a signal sits inside a function or a denominator (truncation needed)."""
    lhs_text, rhs_text = _split_equation(text)
    names: dict[str, sp.Expr | Parsed] = {**local, output: _atom(output, 0),
                                          input_: _atom(input_, 0)}
    grammar: dict[str, Any] = {
        "names": names, "variables": (names[output], names[input_]),
        "signals": (output, input_), "max_order": MAX_DERIVATIVE_ORDER, "exact": exact,
        "hints": {"t": "the equation depends explicitly on time t: only time-invariant "
                       "models have GFRFs"},
        ("lag" if discrete else "derivative"): _atom}
    try:
        sides = [parse_expression(side, **grammar) for side in (lhs_text, rhs_text)]
    except UnknownNames as exc:
        raise ModelError(f"{exc}: give their values as parameters") from None
    except ModelError as exc:
        raise ModelError(f"cannot parse the equation: {exc}") from None
    expr = sides[0].expr - sides[1].expr
    analytic = sides[0].analytic or sides[1].analytic
    atoms = sorted((a for a in expr.free_symbols
                    if a.name.startswith((f"{output}__", f"{input_}__"))),
                   key=lambda a: a.name)
    return expr, atoms, analytic


def _monomial_orders(monom: tuple[int, ...], atoms: list[sp.Symbol], output: str
                     ) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """Sorted output and input derivative orders (or lags) of one monomial's exponents."""
    y_orders: list[int] = []
    u_orders: list[int] = []
    for atom, power in zip(atoms, monom, strict=True):
        name, order = atom.name.rsplit("__", 1)
        (y_orders if name == output else u_orders).extend([int(order)] * power)
    return tuple(sorted(y_orders)), tuple(sorted(u_orders))


def coefficient_formulas(text: str, *, output: str = "y", input: str = "u",
                         discrete: bool = False, truncation: int | None = None,
                         symbols: dict[str, sp.Expr | Parsed] | None = None
                         ) -> dict[tuple[tuple[int, ...], tuple[int, ...]], sp.Expr]:
    """Coefficient of every monomial of an equation as a sympy expression.

    The symbolic counterpart of :func:`parse_model` for parameter sweeps: named
    constants may stay free symbols (``symbols`` maps names to values or symbols),
    so the structure is parsed once and only the formulas are evaluated per point.
    The text is assumed valid (parse it once with :func:`parse_model` first).

    Parameters
    ----------
    text : str
        The equation, already accepted by :func:`parse_model`.
    output, input : str, optional
        Names of the output and input signals.
    discrete : bool, optional
        A NARX equation (lags) instead of an ODE (derivatives).
    truncation : int, optional
        Total Taylor order to which non-polynomial terms are expanded; None: the equation
        is expanded as it is.
    symbols : dict, optional
        Names mapped to values or sympy symbols (a symbol stays free in the formulas).

    Returns
    -------
    dict
        ``{(y_orders, u_orders): coefficient}`` with sorted derivative orders or lags.
    """
    expr, atoms, _ = _signal_expression(text, dict(symbols or {}), output, input, discrete)
    polynomial = _truncate(expr, atoms, truncation) if truncation else sp.expand(expr)
    formulas = {}
    for monom, coeff in sp.Poly(polynomial, *atoms).terms():
        orders = _monomial_orders(monom, atoms, output)
        if orders != ((), ()):
            formulas[orders] = coeff
    return formulas


class ModelTypeError(ModelError, TypeError):
    """:func:`parse_model` was given something other than a str (e.g. a python-control
    system: see :func:`gfrf.from_tf` and :func:`gfrf.from_nlsys`)."""


def parse_model(text: str, *, sample_time: float | None = None, truncation: int | None = None,
                parameters: dict[str, float] | None = None, output: str = "y",
                input: str = "u", exact_parameters: dict[str, sp.Expr] | None = None,
                exact: bool = True) -> Model:
    """Parse a polynomial ODE (or NARX) equation into a :class:`Model`.

    Parameters
    ----------
    text : str
        The equation, e.g. ``"D(y,2) + 0.05*D(y) + 2.45*y - 0.41*y**3 = u"``, or for a
        discrete model ``"y[k] = 0.5*y[k-1] + u[k-1]"``.  ``D(y)`` is the first
        derivative in time (seconds), ``D(y,n)`` the n-th.
    sample_time : float, optional
        Sample time in seconds; giving it makes the model discrete-time.
    truncation : int, optional
        Total Taylor order to which non-polynomial terms (``sin(y)``, ...) are expanded.
    parameters : dict, optional
        Values of named constants used in the text (e.g. ``{"rho": 0.8}``).
    output, input : str
        Names of the output and input signals (default ``y`` and ``u``).
    exact_parameters : dict, optional
        The exact sympy values of the ``parameters`` as written (a model file's
        ``"2.45/6"`` is 49/120); by default each float is read as its shortest decimal
        (:func:`gfrf.model.exact.float_as_written`).
    exact : bool
        Also read the text with its decimals as exact rationals and record every
        coefficient's exact value in :attr:`Term.written` (the proofs use it); False
        skips that second reading (a text kept only for simulation).

    Returns
    -------
    Model

    Raises
    ------
    ModelError
        Unparsable text, a missing input or output, a non-polynomial term without
        truncation, no linear output term (H1 undefined), a NaN/infinite coefficient,
        an absurd derivative order, an explicit dependence on time.
    """
    if not isinstance(text, str):
        kind = type(text).__module__.split(".")[0]
        hint = (" (a python-control system: build the model with gfrf.from_tf(G, "
                "nonlinearity=...) or gfrf.from_nlsys(sys, x0, u0, order=N))"
                if kind == "control" else "")
        raise ModelTypeError(f"parse_model takes the equation as a str, got "
                             f"{type(text).__name__}{hint}")
    parameters = dict(parameters or {})
    discrete = sample_time is not None
    if discrete:
        if not isinstance(sample_time, (int, float)) or not math.isfinite(sample_time) \
                or sample_time < sys.float_info.min:
            raise ModelError(f"sample_time must be a positive normal number of seconds "
                             f"(>= {sys.float_info.min:.3g}), got {sample_time!r}")
        sample_time = float(sample_time)
    if truncation is not None:
        if isinstance(truncation, bool) or not isinstance(truncation, int) or truncation < 1:
            raise ModelError(f"truncation must be a positive integer, got {truncation!r}")
        if truncation > MAX_DEGREE:
            raise ModelError(f"truncation {truncation} exceeds the limit {MAX_DEGREE}")
    for name in (output, input):
        check_name(name, "signal name")
    if output == input:
        raise ModelError(f"output and input have the same name {output!r}")

    local: dict[str, sp.Expr] = {}
    for name, value in parameters.items():
        check_name(name, "parameter name")
        if name in (output, input, "D", "t", "k") or name in MODEL_FUNCTIONS:
            raise ModelError(f"parameter name {name!r} clashes with a signal, operator or "
                             f"function")
        if isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not abs(value) <= _LARGEST_FLOAT:  # also NaN
            raise ModelError(f"parameter {name!r} must be a finite number, got "
                             f"{quote(repr(value))}")
        local[name] = sp.Float(value) if isinstance(value, float) else sp.Integer(value)
    expr, atoms, analytic = _signal_expression(text, local, output, input, discrete)

    if expr.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
        raise ModelError(f"the equation {quote(text)} has a NaN or infinite coefficient")
    if analytic and truncation is not None:
        _check_truncation_work(expr, atoms, truncation, text)
    physical = expr
    polynomial = sp.expand(expr)
    if not polynomial.is_polynomial(*atoms):
        if truncation is None:
            bad = [str(a) for a in sp.Add.make_args(polynomial)
                   if not a.is_polynomial(*atoms)]
            raise ModelError(f"term {_pretty(bad[0], output, input, discrete)!r} is not "
                             f"polynomial in the signals: give a truncation order")
        polynomial = _truncate(expr, atoms, truncation)
        if not polynomial.is_polynomial(*atoms):
            raise ModelError(f"the equation {quote(text)} is not analytic at y = u = 0")
    elif truncation is not None:
        polynomial = _truncate(expr, atoms, truncation)
    terms = _collect_terms(polynomial, atoms, output, input, discrete, text)
    if exact:
        if exact_parameters is None:
            exact_parameters = {k: sp.Rational(float_as_written(v)) for k, v in local.items()}
        terms = _with_written(terms, text, exact_parameters, output, input, discrete, truncation)
    return Model(terms=terms, sample_time=sample_time, output=output, input=input,
                 text=text, truncation=truncation, physical=physical)


def _with_written(terms: tuple[Term, ...], text: str, exact_parameters: dict[str, sp.Expr],
                  output: str, input_: str, discrete: bool, truncation: int | None
                  ) -> tuple[Term, ...]:
    """``terms`` with the exact value of every coefficient as written (decimals read as
    rationals); a monomial whose written coefficient is not zero but whose double is gets
    a term of its own, and a text whose exact reading exceeds a limit gets no rational
    values (the proofs then refuse, as for an irrational coefficient)."""
    try:
        expr, atoms, _ = _signal_expression(text, dict(exact_parameters), output, input_,
                                            discrete, exact=True)
        polynomial = _truncate(expr, atoms, truncation) if truncation else sp.expand(expr)
        exact = {_monomial_orders(m, atoms, output): c
                 for m, c in sp.Poly(polynomial, *atoms).terms()}
    except ModelError:
        return tuple(replace(t, written=Written(t.coefficient, None)) for t in terms)
    if exact.get(((), ()), 0) != 0:
        raise ModelError(f"the equation {quote(text)} as written has a constant term: "
                         f"y = u = 0 must be an equilibrium")
    out = []
    for t in terms:
        value = exact.pop((t.y_orders, t.u_orders), sp.Integer(0))
        out.append(replace(t, written=Written(t.coefficient, as_fraction(value))))
    for (y_orders, u_orders), value in exact.items():
        if value == 0 or not y_orders + u_orders:
            continue
        double = float(value)
        if not math.isfinite(double) or double == 0.0:
            raise ModelError(f"the coefficient {value} of the equation {quote(text)} as "
                             f"written has no double")
        out.append(Term(y_orders=y_orders, u_orders=u_orders, coefficient=double,
                        output=output, input=input_, discrete=discrete,
                        written=Written(double, as_fraction(value))))
    return tuple(sorted(out))


def _check_truncation_work(expr: sp.Expr, atoms: list[sp.Symbol], truncation: int,
                           text: str) -> None:
    """Refuse a Taylor truncation whose a-priori work exceeds :data:`MAX_TRUNCATION_WORK`:
    the monomials of degree <= ``truncation`` in the atoms, times the functions of the
    signals to expand (sympy's series cost grows about as the 1.5th power of that)."""
    calls = sum(1 for f in expr.atoms(sp.Function) if f.free_symbols & set(atoms))
    work = math.comb(len(atoms) + truncation, truncation) * max(1, calls)
    if work > MAX_TRUNCATION_WORK:
        raise ModelError(f"truncating {calls} function(s) of {len(atoms)} signal atoms to order "
                         f"{truncation} is {work} monomial expansions, more than "
                         f"MAX_TRUNCATION_WORK = {MAX_TRUNCATION_WORK}: {quote(text)}")


def _pretty(s: str, output: str, input_: str, discrete: bool) -> str:
    def repl(m: re.Match[str]) -> str:
        name, order = m.group(1), int(m.group(2))
        if discrete:
            return f"{name}[k-{order}]" if order else f"{name}[k]"
        return name if order == 0 else (f"D({name})" if order == 1 else f"D({name},{order})")
    return re.sub(rf"\b({re.escape(output)}|{re.escape(input_)})__(\d+)", repl, s)


def _collect_terms(polynomial: sp.Expr, atoms: list[sp.Symbol], output: str, input_: str,
                   discrete: bool, text: str) -> tuple[Term, ...]:
    if polynomial == 0:
        raise ModelError(f"the equation {quote(text)} is identically zero")
    poly = sp.Poly(polynomial, *atoms) if atoms else None
    if poly is None:
        raise ModelError(f"the equation {quote(text)} contains neither the output {output!r} "
                         f"nor the input {input_!r}")
    terms = []
    for monom, coeff in poly.terms():
        if not coeff.is_number or not coeff.is_real:
            raise ModelError(f"coefficient {coeff} in {quote(text)} is not a real number")
        value = float(coeff)
        if not math.isfinite(value):
            raise ModelError(f"coefficient {coeff} in {quote(text)} is not finite")
        if value == 0.0:
            continue
        y_orders, u_orders = _monomial_orders(monom, atoms, output)
        if not y_orders and not u_orders:
            raise ModelError(f"constant term {value:g} in {quote(text)}: y = u = 0 must be an "
                             f"equilibrium")
        terms.append(Term(y_orders, u_orders, value, output, input_, discrete))
    if not any(t.y_orders for t in terms):
        raise ModelError(f"the equation {quote(text)} has no output {output!r}")
    if not any(t.u_orders for t in terms):
        raise ModelError(f"the equation {quote(text)} has no input {input_!r}")
    if not any(t.is_linear_output for t in terms):
        raise ModelError(f"the equation {quote(text)} has no linear term in the output {output!r}: "
                         f"H1 is undefined")
    return tuple(sorted(terms))
