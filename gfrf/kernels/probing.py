"""Harmonic probing: an independent second algorithm for the symmetric GFRFs.

Used by tests and cross-checks only; it shares no code with :mod:`gfrf.kernels.recursion`.

Probe the model with u(t) = sum_{i=1..n} exp(j*omega_i*t) for generic (incommensurate)
angular frequencies.  The output is a sum of exponentials; the coefficient Y_B of
exp(j*sum_{i in B} omega_i * t) for a set B of distinct probe indices equals
|B|! * H_{|B|}^sym(omega_B).  Substituting the series into the model and equating the
coefficient of exp(j*Omega_B*t) on both sides gives, for each B in order of size,

    A(Omega_B) * Y_B = -(coefficient of exp(j*Omega_B*t) in the nonlinear and input terms),

where the right-hand side only involves Y_A for proper subsets A of B: a product of
factors contributes the sum over ordered splittings of B into disjoint subsets, one
per factor.  A derivative D^l (or lag l) acts on the exponential of a set A as
(j*Omega_A)^l (or exp(-j*l*T*Omega_A)).  Everything here is scalar complex
arithmetic on bitmasks: slow, simple, and obviously a different computation.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Sequence

from gfrf.model.equation import Model

__all__ = ["probe_kernel"]


def _operator(model: Model, omega: float, order: int) -> complex:
    if model.is_discrete:
        return cmath.exp(-1j * order * model.sample_time * omega)
    return (1j * omega) ** order


def probe_kernel(model: Model, omegas: Sequence[float]) -> complex:
    """Symmetric H_n(j*omega_1, ..., j*omega_n) by harmonic probing.

    Parameters
    ----------
    model : Model
        The polynomial model.
    omegas : sequence of float
        n angular frequencies in rad/s; they must be generic (no sub-sum of one subset
        equal to that of another), as random frequencies are.

    Returns
    -------
    complex
        The value of the symmetric n-th order GFRF.
    """
    n = len(omegas)
    full = (1 << n) - 1
    freq = [sum(omegas[i] for i in range(n) if mask >> i & 1) for mask in range(full + 1)]
    linear = [t for t in model.terms if len(t.y_orders) == 1 and not t.u_orders]
    others = [t for t in model.terms if t not in linear]
    y: dict[int, complex] = {}

    def factor(signal: str, order: int, mask: int) -> complex:
        """Coefficient of exp(j*Omega_mask*t) in D^order of one signal."""
        if signal == "u":
            if mask & (mask - 1):  # the input holds single probe exponentials only
                return 0.0
            return _operator(model, freq[mask], order)
        return y.get(mask, 0.0) * _operator(model, freq[mask], order)

    def product(factors: list[tuple[str, int]], mask: int) -> complex:
        """Coefficient at ``mask`` of a product: sum over ordered disjoint splittings."""
        if len(factors) == 1:
            return factor(*factors[0], mask)
        total = 0.0
        sub = (mask - 1) & mask
        while sub:
            head = factor(*factors[0], sub)
            if head != 0:
                total += head * product(factors[1:], mask & ~sub)
            sub = (sub - 1) & mask
        return total

    for mask in sorted(range(1, full + 1), key=lambda m: bin(m).count("1")):
        rhs = 0.0
        for term in others:
            factors = [("y", o) for o in term.y_orders] + [("u", o) for o in term.u_orders]
            if len(factors) <= bin(mask).count("1"):
                rhs += term.coefficient * product(factors, mask)
        a = sum(t.coefficient * _operator(model, freq[mask], t.y_orders[0]) for t in linear)
        y[mask] = -rhs / a
    return y[full] / math.factorial(n)
