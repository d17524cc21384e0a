"""The baseline a user would write for a GFRF: sympy harmonic probing + ``lambdify(cse=True)``.

Independent of :mod:`gfrf.kernels` (it reads only the model's terms): probe the model with
u(t) = sum_{i=1..n} exp(s_i*t), write the output as y(t) = sum over nonempty subsets B of
{1..n} of Y_B * exp(s_B*t) (s_B the sum of the s_i in B), substitute into every term of
the model and equate the coefficients of exp((s_1 + ... + s_n)*t).  A derivative D^l
multiplies the exponential of B by s_B^l (a lag l of a discrete model by q_B^l, with
q_B the product of the q_i = exp(-s_i*T)); a product of factors contributes the sum over
ordered splittings of {1..n} into disjoint subsets, one per factor.  That gives

    A(s_1 + ... + s_n) * Y_{1..n} = -(the nonlinear and input terms' coefficient),

solved symbolically for Y_{1..n}; the lower Y_B are the same solution of order |B| at the
variables of B (memoised per order, renamed per subset), and H_n^sym = Y_{1..n} / n!
(probing with distinct frequencies gives the symmetric kernel directly).  The explicit
rational function is then compiled by ``sympy.lambdify(..., "numpy", cse=True)`` and
called at s_i = j*omega_i (q_i = exp(-j*omega_i*T)).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from typing import Any

import numpy as np
import sympy as sp

from gfrf.model.equation import Model

__all__ = ["ProbingBaseline", "probing_work"]


def probing_work(model: Model, n: int) -> int:
    """At most as many products as the probing of order ``n`` sums (a bound on its work).

    Parameters
    ----------
    model : Model
        The polynomial model.
    n : int
        Kernel order.

    Returns
    -------
    int
        Sum over the nonlinear and input terms of (factors)! * S(n, factors) (S: Stirling
        numbers of the second kind), the ordered splittings of n probes over the factors:
        the products of the coefficient of exp((s_1 + ... + s_n)*t) are at most that
        many; a bench caps the baseline by it.
    """
    total = 0
    for term in model.terms:
        if term.is_linear_output:
            continue
        p = term.degree
        total += math.factorial(p) * int(sp.functions.combinatorial.numbers.stirling(n, p))
    return total


class ProbingBaseline:
    """Explicit symmetric GFRFs of a model by sympy harmonic probing.

    Parameters
    ----------
    model : Model
        The polynomial model (continuous or discrete).
    """

    def __init__(self, model: Model) -> None:
        self.model = model
        self._solutions: dict[int, sp.Expr] = {}

    def variables(self, n: int) -> tuple[sp.Symbol, ...]:
        """The probe variables s1..sn (q1..qn for a discrete model).

        Parameters
        ----------
        n : int
            Kernel order.

        Returns
        -------
        tuple of sympy.Symbol
        """
        name = "q" if self.model.is_discrete else "s"
        return sp.symbols(f"{name}1:{n + 1}")

    def _operator(self, block: tuple[sp.Symbol, ...], order: int) -> sp.Expr:
        """D^order (or lag ``order``) on exp(s_B*t)."""
        if self.model.is_discrete:
            return sp.Mul(*block) ** order
        return sp.Add(*block) ** order

    def _coefficient(self, n: int) -> sp.Expr:
        """Y_{1..n}: n! times H_n^sym, explicit in s1..sn."""
        if n in self._solutions:
            return self._solutions[n]
        x = self.variables(n)
        full = tuple(range(n))

        renamed: dict[tuple[int, ...], sp.Expr] = {}

        def y_block(block: tuple[int, ...]) -> sp.Expr:
            if block not in renamed:  # Y_B: the solution of order |B| at the variables of B
                lower = self._coefficient(len(block))
                renamed[block] = lower.xreplace(
                    {v: x[i] for v, i in zip(self.variables(len(block)), block, strict=True)})
            return renamed[block]

        def factor(signal: str, order: int, block: tuple[int, ...]) -> sp.Expr:
            if signal == "u":
                if len(block) != 1:  # the input holds single probe exponentials only
                    return sp.Integer(0)
                return self._operator((x[block[0]],), order)
            return y_block(block) * self._operator(tuple(x[i] for i in block), order)

        rhs = sp.Integer(0)
        for term in self.model.terms:
            if term.is_linear_output:
                continue
            factors = [("y", o) for o in term.y_orders] + [("u", o) for o in term.u_orders]
            if len(factors) > n:
                continue
            products = []
            for labels in itertools.product(range(len(factors)), repeat=n):
                if len(set(labels)) != len(factors):  # every factor takes a nonempty subset
                    continue
                blocks = [tuple(i for i in full if labels[i] == k) for k in range(len(factors))]
                products.append(sp.Mul(*(factor(*f, b) for f, b in zip(factors, blocks,
                                                                        strict=True))))
            rhs += sp.Float(term.coefficient) * sp.Add(*products)
        a = sp.Add(*(sp.Float(c) * self._operator(x, order)
                     for order, c in self.model.linear_output.items()))
        self._solutions[n] = -rhs / a
        return self._solutions[n]

    def explicit(self, n: int) -> sp.Expr:
        """H_n^sym as an explicit sympy expression in :meth:`variables`.

        Parameters
        ----------
        n : int
            Kernel order.

        Returns
        -------
        sympy.Expr
        """
        return self._coefficient(n) / math.factorial(n)

    def function(self, n: int) -> Callable[..., Any]:
        """``f(w1, ..., wn)``: H_n^sym at angular frequencies in rad/s, by lambdify(cse=True).

        Parameters
        ----------
        n : int
            Kernel order.

        Returns
        -------
        callable
            Takes n real arrays, returns the complex values (broadcast).
        """
        compiled = sp.lambdify(self.variables(n), self.explicit(n), "numpy", cse=True)
        if self.model.is_discrete:
            sample_time = float(self.model.sample_time or 0.0)
            return lambda *w: compiled(*(np.exp(-1j * sample_time * np.asarray(v)) for v in w))
        return lambda *w: compiled(*(1j * np.asarray(v) for v in w))
