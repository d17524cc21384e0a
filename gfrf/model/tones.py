"""A linear-time reader of a sum of tones ``A*sin(w*t + p) + B*cos(v*t) - ...``.

An input with thousands of tones (a multisine) costs sympy milliseconds a term (each
``sin`` is evaluated symbolically, each product flattened with its assumptions): 2,000
tones took about 8 s to parse and lambdify.  This reader takes the same text through
the same tokenizer and limits of :mod:`gfrf.model.expr` (number and name lengths, text
length, :data:`~gfrf.model.limits.MAX_TERMS`) and, when every term has the form

    [number *] sin|cos ( [sign] [number *] t [+|- number] )

(each term with its sign), returns the tones as floats, with an evaluator of the sum
and its time derivatives in numpy: one pass over the tokens, no sympy.  Any other text
returns None and goes through the general parser.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from gfrf.model.expr import _Context, _tokenize
from gfrf.model.limits import MAX_TERMS, MAX_TEXT_LENGTH

__all__ = ["ToneTerm", "read_tone_sum", "tone_sum_function"]

#: One term A * f(w*t + p) of the sum, f = "sin" or "cos" (the text's own numbers).
ToneTerm = tuple[float, str, float, float]

#: Times evaluated per chunk (bounds the (times x tones) temporary to about 16 MB).
_CHUNK_ELEMENTS = 2_000_000


class _Reader:
    """A cursor over the tokens; every method returns None when the form does not match."""

    def __init__(self, tokens: list[tuple[str, str, int]]) -> None:
        self.tokens, self.pos = tokens, 0

    def peek(self) -> str:
        return self.tokens[self.pos][1]

    def kind(self) -> str:
        return self.tokens[self.pos][0]

    def take(self, value: str) -> bool:
        if self.peek() == value and self.kind() != "end":
            self.pos += 1
            return True
        return False

    def number(self) -> float | None:
        if self.kind() != "number":
            return None
        value = float(self.peek())
        if not math.isfinite(value):
            return None
        self.pos += 1
        return value

    def sign(self) -> float:
        sign = 1.0
        while self.peek() in ("+", "-") and self.kind() == "op":
            sign = -sign if self.peek() == "-" else sign
            self.pos += 1
        return sign

    def term(self, sign: float) -> ToneTerm | None:
        amplitude = 1.0
        if self.kind() == "number":
            value = self.number()
            if value is None or not self.take("*"):
                return None
            amplitude = value
        function = self.peek()
        if function not in ("sin", "cos") or self.kind() != "name":
            return None
        self.pos += 1
        if not self.take("("):
            return None
        omega = self.sign()
        if self.kind() == "number":
            value = self.number()
            if value is None or not self.take("*"):
                return None
            omega *= value
        if not self.take("t"):
            return None
        phase = 0.0
        if self.peek() in ("+", "-"):
            negative = self.peek() == "-"
            self.pos += 1
            value = self.number()
            if value is None:
                return None
            phase = -value if negative else value
        if not self.take(")"):
            return None
        return sign * amplitude, function, omega, phase


def read_tone_sum(text: str) -> list[ToneTerm] | None:
    """The terms of ``text`` if it is a plain sum of tones in ``t``, else None.

    The text is tokenized by the model language's tokenizer (its limits apply: a text
    it refuses raises :class:`gfrf.errors.ModelError` as the general parser would);
    more than :data:`~gfrf.model.limits.MAX_TERMS` terms, or any other form, gives None
    (the general parser then refuses or reads it).

    Parameters
    ----------
    text : str
        The input text.

    Returns
    -------
    list of ToneTerm or None
        The terms, or None.

    Examples
    --------
    >>> read_tone_sum("0.5*sin(2*t + 0.1) - cos(3*t)")
    [(0.5, 'sin', 2.0, 0.1), (-1.0, 'cos', 3.0, 0.0)]
    >>> read_tone_sum("sin(t)**2") is None
    True
    """
    if not isinstance(text, str) or len(text) > MAX_TEXT_LENGTH:
        return None
    ctx = _Context(text=text, names={}, functions={}, variables=frozenset(), derivative=None,
                   lag=None, signals=(), max_order=0, hints={})
    reader = _Reader(_tokenize(ctx))
    terms: list[ToneTerm] = []
    sign = reader.sign()
    while True:
        term = reader.term(sign)
        if term is None or len(terms) >= MAX_TERMS:
            return None
        terms.append(term)
        if reader.kind() == "end":
            return terms
        if reader.peek() not in ("+", "-"):
            return None
        sign = reader.sign()


def tone_sum_function(terms: list[ToneTerm], k: int) -> Callable[[Any], Any]:
    """The k-th time derivative of the sum of ``terms`` as a numpy function of t (s).

    d/dt sin(w t + p) = w cos(w t + p) and d/dt cos(w t + p) = -w sin(w t + p): each
    term keeps its own function and numbers (no conversion to a common phase form).

    Parameters
    ----------
    terms : list of ToneTerm
        The terms of :func:`read_tone_sum`.
    k : int
        The order of the derivative, >= 0.

    Returns
    -------
    callable
        ``f(t) -> numpy.ndarray``.
    """
    amplitude = np.array([a for a, _, _, _ in terms], dtype=float)
    omega = np.array([w for _, _, w, _ in terms], dtype=float)
    phase = np.array([p for _, _, _, p in terms], dtype=float)
    is_sin = np.array([f == "sin" for _, f, _, _ in terms])
    # after k derivatives: sin -> (cos, -sin, -cos, sin), cos -> (-sin, -cos, sin, cos)
    step = k % 4
    use_sin = is_sin if step % 2 == 0 else ~is_sin
    sign = np.where(is_sin, 1.0 if step in (0, 1) else -1.0, 1.0 if step in (0, 3) else -1.0)
    weight = sign * amplitude * omega ** k
    sin_rows, cos_rows = np.flatnonzero(use_sin), np.flatnonzero(~use_sin)
    chunk = max(1, _CHUNK_ELEMENTS // max(len(terms), 1))

    def value(t: Any) -> Any:
        t_arr = np.asarray(t, dtype=float)
        flat = t_arr.reshape(-1)
        out = np.empty(flat.size)
        for start in range(0, flat.size, chunk):
            times = flat[start:start + chunk]
            total = np.zeros(times.size)
            if sin_rows.size:
                total += np.sin(np.multiply.outer(times, omega[sin_rows]) + phase[sin_rows]) \
                    @ weight[sin_rows]
            if cos_rows.size:
                total += np.cos(np.multiply.outer(times, omega[cos_rows]) + phase[cos_rows]) \
                    @ weight[cos_rows]
            out[start:start + chunk] = total
        return out.reshape(t_arr.shape) if t_arr.ndim else out[0]

    return value
