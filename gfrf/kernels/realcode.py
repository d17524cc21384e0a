"""A recursion step as straight-line code on real and imaginary parts, for the compiler.

In a compiled kernel every complex operation costs the full complex formula (the compiler
may not drop a product with a zero imaginary part: it could be an infinity or a NaN).
Yet most of a step's arithmetic is on the frequencies: for a continuous model s = j*w,
so a sum of s is purely imaginary, its square real, and the powers of the frequency sums
that the derivatives bring are real polynomials in w.  Here each value of the
common-subexpression-eliminated step (the numerator P_m with s_i = j*w_i substituted)
is tracked as *real*, *imaginary* or *complex* and written as float arithmetic on its
parts only: a real times a complex is two products, not a complex product.  The
lower-order kernels (the placeholders) and a discrete model's q_i = exp(-j*w_i*T) are
complex.  The result is the same polynomial, rounded differently (to rounding).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import sympy as sp

__all__ = ["real_step_lines", "grouped_numerator", "FASTMATH"]

#: LLVM's floating-point freedom for the step functions: fused multiply-adds only (one
#: rounding instead of two; no assumption on infinities, NaNs or signed zeros): the
#: cart-pole's H5 evaluates in 0.036 s instead of 0.048 s at 10^5 points.
FASTMATH = {"contract"}
#: Most terms of one printed sum (Python's compiler nests a long chain of ``+``).
_CHUNK = 500


@dataclass(frozen=True)
class _Value:
    """A value as its parts: ``re`` and/or ``im`` (source text); a missing part is 0."""

    re: str | None
    im: str | None


class _Emitter:
    """Writes assignments of real temporaries ``_t0, _t1, ..`` for the parts of values."""

    def __init__(self, env: dict[sp.Basic, _Value]) -> None:
        self.env = env
        self.lines: list[str] = []
        self.count = 0

    def bind(self, text: str) -> str:
        name = f"_t{self.count}"
        self.count += 1
        self.lines.append(f"{name} = {text}")
        return name

    def total(self, parts: list[tuple[str, str]]) -> str | None:
        """The sum of signed parts ``[(sign, text)]``, None for no part."""
        if not parts:
            return None
        while len(parts) > _CHUNK:
            parts = [("+", self.total(parts[i:i + _CHUNK]) or "0.0")
                     for i in range(0, len(parts), _CHUNK)]
        text = " ".join(f"{sign} {part}" for sign, part in parts)
        return self.bind(text[2:] if text.startswith("+ ") else text)

    def value(self, expr: sp.Basic) -> _Value:
        """The parts of ``expr``, written once (memoised on the expression)."""
        if expr in self.env:
            return self.env[expr]
        if expr is sp.I:
            result = _Value(None, "1.0")
        elif expr.is_Number:
            result = _Value(repr(float(expr)), None)
        elif expr.is_Add:
            re: list[tuple[str, str]] = []
            im: list[tuple[str, str]] = []
            for term in expr.args:
                coefficient, rest = term.as_coeff_Mul()
                sign, v = ("-", self.value(rest)) if coefficient == -1 else ("+",
                                                                             self.value(term))
                re += [(sign, v.re)] if v.re is not None else []
                im += [(sign, v.im)] if v.im is not None else []
            result = _Value(self.total(re), self.total(im))
        elif expr.is_Mul:
            coefficient, rest = expr.as_coeff_Mul()
            # reals first (one product each), then imaginaries, then complex values
            values = sorted((self.value(a) for a in sp.Mul.make_args(rest)),
                            key=lambda v: (v.im is not None, v.re is not None))
            if coefficient not in (1, -1):
                values.insert(0, _Value(repr(float(coefficient)), None))
            result = values[0]
            for other in values[1:]:
                result = self.product(result, other)
            if coefficient == -1:
                result = _Value(self.bind(f"-{result.re}") if result.re else None,
                                self.bind(f"-{result.im}") if result.im else None)
        elif expr.is_Pow and expr.exp.is_Integer and int(expr.exp) >= 1:
            base, exponent = self.value(expr.base), int(expr.exp)
            result = base
            for _ in range(exponent - 1):
                result = self.product(result, base)
        else:
            raise NotImplementedError(f"no real code for {expr.func.__name__}")
        self.env[expr] = result
        return result

    def product(self, a: _Value, b: _Value) -> _Value:
        """``a * b`` on parts: (ar + j ai)(br + j bi) with the zero parts left out."""
        re = [f"{a.re} * {b.re}"] if a.re is not None and b.re is not None else []
        if a.im is not None and b.im is not None:
            re.append(f"-({a.im} * {b.im})" if not re else f"- {a.im} * {b.im}")
        im = []
        if a.re is not None and b.im is not None:
            im.append(f"{a.re} * {b.im}")
        if a.im is not None and b.re is not None:
            im.append(f"{a.im} * {b.re}")
        return _Value(self.bind(" ".join(re)) if re else None,
                      self.bind(" + ".join(im)) if im else None)


def grouped_numerator(numerator: sp.Expr, placeholders: tuple[sp.Symbol, ...]) -> sp.Expr:
    """``numerator`` as a sum over its distinct products of placeholders, each times the
    sum of its coefficients (polynomials in the variables).

    The recursion step sums over ordered set partitions, so one product of lower-order
    kernels comes with many weights (one per term of the model and per assignment of the
    derivatives); summing the weights first leaves one product of kernels per partition
    (the cart-pole's P_5: 30 products of kernels instead of 90, about 0.4x the
    operations after common-subexpression elimination).  The same polynomial.

    Parameters
    ----------
    numerator : sympy.Expr
        A polynomial in the variables and the placeholders.
    placeholders : tuple of sympy.Symbol
        The placeholders of the lower-order kernels.

    Returns
    -------
    sympy.Expr
        ``sum_M M * c_M`` with ``M`` the products of placeholders.
    """
    kernels = set(placeholders)
    groups: dict[sp.Expr, list[sp.Expr]] = {}
    for term in sp.Add.make_args(numerator):
        weight: list[sp.Basic] = []
        product: list[sp.Basic] = []
        for factor in sp.Mul.make_args(term):
            (product if factor.free_symbols & kernels else weight).append(factor)
        groups.setdefault(sp.Mul(*product), []).append(sp.Mul(*weight))
    return sp.Add(*(product * sp.Add(*weights) for product, weights in groups.items()))


@lru_cache(maxsize=256)
def real_step_lines(gen: Any, m: int, symmetric: bool) -> tuple[tuple[str, ...],
                                                                tuple[str, ...], str]:
    """The numerator of the recursion step of order ``m`` as real straight-line code.

    Parameters
    ----------
    gen : gfrf.kernels.compiled.Recursion
        The model's GFRF generator.
    m : int
        The order of the step, >= 1 and not identically zero.
    symmetric : bool
        The symmetric kernel's step instead of the asymmetric one's.

    Returns
    -------
    arguments : tuple of str
        The step function's arguments: the block's frequencies (continuous: the real
        angular frequencies w_i, named like the variables; discrete: the complex q_i),
        then the placeholders of the lower-order kernels (complex).
    lines : tuple of str
        Assignments, unindented: the parts of every subexpression.
    numerator : str
        The numerator P_m as a complex expression ``complex(re, im)``.
    """
    plan = gen.plan(m, symmetric)
    variables = gen.variables(m)
    numerator = grouped_numerator(plan.numerator, plan.placeholders)
    env: dict[sp.Basic, _Value] = {}
    unpack = []
    if gen.model.is_discrete:
        for v in variables:
            unpack += [f"{v}_r = {v}.real", f"{v}_i = {v}.imag"]
            env[v] = _Value(f"{v}_r", f"{v}_i")
    else:
        real = {v: sp.Symbol(str(v), real=True) for v in variables}
        numerator = numerator.xreplace({v: sp.I * real[v] for v in variables})
        for v in variables:
            env[real[v]] = _Value(str(v), None)
    for p in plan.placeholders:
        unpack += [f"{p}_r = {p}.real", f"{p}_i = {p}.imag"]
        env[p] = _Value(f"{p}_r", f"{p}_i")
    replacements, (reduced,) = sp.cse(numerator, symbols=sp.numbered_symbols("_c"))
    emitter = _Emitter(env)
    for symbol, expr in replacements:
        env[symbol] = emitter.value(expr)
    result = emitter.value(reduced)
    arguments = tuple(str(v) for v in variables) + tuple(str(p) for p in plan.placeholders)
    return (arguments, tuple(unpack + emitter.lines),
            f"complex({result.re or '0.0'}, {result.im or '0.0'})")
