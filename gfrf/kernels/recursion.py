"""GFRFs H1..Hn by the recursive (Billings / Peyton Jones) algorithm.

For a model ``sum(terms) = 0`` with linear output part A(s) = sum a_l s^l, the n-th
order kernel is

    H_n(s_1..s_n) = -P_n(s_1..s_n) / A(s_1 + ... + s_n),

where P_n collects the contributions of every other term: pure-input terms of
degree n, and for each term with p output factors (orders l_1..l_p) and q input
factors (orders k_1..k_q) the H_{n-q,p} products of lower-order kernels,

    H_{m,p}(s_1..s_m) = sum over compositions m = m_1 + ... + m_p of
                        prod_i H_{m_i}(block_i) * (sum of block_i)^{l_i},

times prod_j s_{m+j}^{k_j} for the input factors (the Peyton Jones 1989 recursion
written in closed form).  The *asymmetric* kernel uses contiguous blocks in that
order; the *symmetric* kernel (the average over all permutations of s_1..s_n, unique
for a given system) is computed directly as a sum over ordered set partitions with
weights prod|B_i|!/n!, so no n!-term symmetrisation is ever formed.

A discrete-time model uses the backward shift q_i = exp(-j*omega_i*T) in place of
s_i = j*omega_i; the frequency sum of a block becomes the product of its q_i and a
lag l the power q^l.

Symbolic work (the polynomial P_n in the variables and in placeholders for the
lower-order kernels on each block) happens once per model, order and kind, and is
memoised; numeric evaluation compiles P_n with common-subexpression elimination
and evaluates the lower-order kernels bottom-up on arrays, so no symbolic object
is touched per point.  Angular frequencies are in rad/s.  The symbolic recursion lives in
:mod:`gfrf.kernels.generator`, the numpy evaluation in :mod:`gfrf.kernels.numeric`, the
compiled kernels in :mod:`gfrf.kernels.compiled`; this module is the public face.

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> duffing = parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")
>>> H3 = kernel(duffing, 3)
>>> complex(H3(1.0, 1.0, -1.0)) == complex(-0.5 * kernel(duffing, 1)(1.0)**2
...                                         * kernel(duffing, 1)(-1.0) * kernel(duffing, 1)(1.0))
True
>>> kernel(duffing, 2).is_zero
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import sympy as sp

from gfrf.errors import ArgumentError
from gfrf.kernels.compiled import MIN_POINTS, compile_pays
from gfrf.kernels.generator import GFRFGenerator, generator
from gfrf.kernels.work import MAX_PLAN_TERMS, MAX_RECURSION_WORK, check_recursion_work
from gfrf.model.equation import Model

__all__ = ["Kernel", "GFRFGenerator", "generator", "kernel", "check_order", "MAX_KERNEL_ORDER",
           "MAX_RECURSION_WORK", "MAX_PLAN_TERMS", "check_recursion_work"]

#: Largest kernel order the generator accepts (the symbolic sums grow like p! S(n, p)).
MAX_KERNEL_ORDER = 12


@dataclass(frozen=True)
class Kernel:
    """The n-th order GFRF H_n of a model, symmetric (default) or asymmetric.

    Call it with n arrays of **angular frequencies in rad/s** (broadcast like numpy)
    to get complex128 values: ``H(w1, ..., wn)`` is H_n at s_i = j*w_i, not at
    s_i = w_i (python-control's ``sys(x)`` evaluates at s = x; here pass ``w`` for
    s = j*w).  :meth:`at_s` evaluates at complex s_i; ``.expr`` is the explicit
    sympy form in s1..sn or, for a discrete model, q1..qn (q_i = exp(-j*w_i*T)).

    Examples
    --------
    >>> import sympy as sp
    >>> from gfrf.model.equation import parse_model
    >>> H1 = kernel(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"), 1)
    >>> complex(H1(1.0))  # at s = 1j rad/s: 1 / (0.2j)
    -5j
    >>> s = -0.5 + 2j
    >>> abs(complex(H1.at_s(s)) - 1 / (s**2 + 0.2*s + 1)) < 1e-15
    True
    >>> f = sp.lambdify(H1.variables, H1.expr)  # the same from the sympy form
    >>> abs(f(s) - complex(H1.at_s(s))) < 1e-15
    True
    """

    model: Model
    order: int
    symmetric: bool = True
    _gen: GFRFGenerator = field(repr=False, compare=False, default=None)  # type: ignore[assignment]

    @property
    def is_zero(self) -> bool:
        """True when H_n vanishes identically (structurally or by cancellation)."""
        if not self._gen.structurally_nonzero(self.order):
            return True
        return self._gen.plan(self.order, self.symmetric).is_zero

    @property
    def variables(self) -> tuple[sp.Symbol, ...]:
        """The symbolic variables s1..sn (or q1..qn)."""
        return self._gen.variables(self.order)

    @property
    def expr(self) -> sp.Expr:
        """Explicit sympy rational function of the variables (lower orders inlined)."""
        return self._gen.explicit(self.order, self.symmetric)

    @property
    def recursive_expr(self) -> sp.Expr:
        """Compact form in which lower-order kernels appear as ``H_m(...)`` functions."""
        return self._gen.recursive(self.order, self.symmetric)

    def __repr__(self) -> str:
        kind = "" if self.symmetric else ", asymmetric"
        return f"Kernel(H{self.order} of {self.model.text or self.model.equation()!r}{kind})"

    def _repr_latex_(self) -> str:
        return f"$H_{{{self.order}}} = {sp.latex(self.recursive_expr)}$"

    def plot(self, **options: Any) -> Any:
        """Figure of the kernel: Bode plot of H1, |H2| map, slices of Hn >= 3.

        Parameters
        ----------
        **options
            ``omega_range``, ``what``, ``mark``, ``fixed`` of
            :func:`gfrf.kernels.plot.plot_kernel`.

        Returns
        -------
        matplotlib.figure.Figure
            Made without pyplot (no window opens).
        """
        from gfrf.kernels.plot import plot_kernel

        return plot_kernel(self, **options)

    def __call__(self, *omega: Any) -> np.ndarray:
        """Evaluate H_n at angular frequencies omega_1..omega_n in rad/s.

        Parameters
        ----------
        *omega : array_like
            n real arrays (or scalars) that broadcast together.

        Returns
        -------
        numpy.ndarray of complex128
            H_n(j*omega_1, ..., j*omega_n) with the broadcast shape (discrete models:
            at q_i = exp(-j*omega_i*T)).

        Notes
        -----
        The evaluation path is chosen by the work: the vectorised numpy recursion (a
        symmetric kernel that is real on the axis: subset convolution on real arrays,
        :mod:`gfrf.kernels.subsets`), or,
        for a call of millions of points where compiling pays back within the call
        (:func:`gfrf.kernels.compiled.compile_pays`, a decision on counts of points and
        operations only), the numba ufunc of :meth:`compiled`.  Both agree to rounding.

        See Also
        --------
        at_s : values at complex s_i (``H(w)`` is ``H.at_s(1j * w)``).
        """
        if len(omega) != self.order:
            raise ArgumentError(f"H{self.order} takes {self.order} angular frequencies, "
                                f"got {len(omega)}")
        arrays = []
        for w in omega:
            a = np.asarray(w, dtype=float)
            if not np.all(np.isfinite(a)):
                raise ArgumentError("angular frequencies must be finite real numbers (rad/s)")
            arrays.append(a)
        points = math.prod(np.broadcast_shapes(*(a.shape for a in arrays)))
        if points >= MIN_POINTS and not self.is_zero and compile_pays(
                self._gen, self.order, self.symmetric, points):
            try:  # millions of points: the compile pays back within this call
                with np.errstate(all="ignore"):
                    return np.asarray(self._gen.ufunc(self.order, self.symmetric)(*arrays),
                                      dtype=np.complex128)
            except ZeroDivisionError:  # a point on a pole: the numpy path gives inf/nan
                pass
        return self._gen.evaluate(self.order, arrays, self.symmetric)

    def at_s(self, *s: Any) -> np.ndarray:
        """Evaluate H_n at complex Laplace variables s_1..s_n (1/s).

        ``H.at_s(1j * w)`` equals ``H(w)``; a discrete (NARX) model is evaluated at
        q_i = exp(-s_i*T), its backward shift at s_i.

        Parameters
        ----------
        *s : array_like
            n complex arrays (or scalars) that broadcast together.

        Returns
        -------
        numpy.ndarray of complex128
            H_n(s_1, ..., s_n) with the broadcast shape (inf or nan at a pole).

        Raises
        ------
        ArgumentError
            Not n values, or a value that is not a finite complex number.

        Examples
        --------
        >>> from gfrf.model.equation import parse_model
        >>> H1 = kernel(parse_model("D(y) + 2*y = u"), 1)
        >>> complex(H1.at_s(1.0))  # 1 / (s + 2) at s = 1
        (0.3333333333333333+0j)
        """
        if len(s) != self.order:
            raise ArgumentError(f"H{self.order} takes {self.order} values of s, got {len(s)}")
        omegas = []
        for value in s:
            a = np.asarray(value)
            if a.dtype.kind not in "biufc":
                raise ArgumentError(f"s must be complex numbers (1/s), got {value!r}")
            a = a.astype(np.complex128)
            if not np.all(np.isfinite(a)):
                raise ArgumentError("s must be finite complex numbers (1/s)")
            omegas.append(-1j * a)  # s = j*omega exactly (multiplying by -1j is exact)
        return self._gen.evaluate(self.order, omegas, self.symmetric)

    def compiled(self) -> Any:
        """A numba-compiled numpy ufunc of this kernel: ``f(w1, ..., wn)`` in rad/s.

        The fast path for millions of points (no temporaries); compiled on first use
        (about a second) and cached.  No argument checking: pass finite floats.

        Raises
        ------
        ImportError
            If numba (the ``fast`` extra) is not installed.
        """
        if self.is_zero:
            return lambda *w: np.zeros(np.broadcast_shapes(*(np.shape(x) for x in w)),
                                       dtype=np.complex128)
        return self._gen.ufunc(self.order, self.symmetric)


def check_order(order: object, name: str = "order",
                limit: tuple[str, int] = ("MAX_KERNEL_ORDER", MAX_KERNEL_ORDER)) -> int:
    """The one check of an order, before any work: an integer in ``1..MAX_KERNEL_ORDER``
    (every function and command that takes an order calls it, so all say the same).

    Parameters
    ----------
    order : int
        The order to check.
    name : str
        How the caller names it in the message (``"--order"``, ``"kernel order"``).
    limit : (str, int)
        The largest order and the name of its constant, for the message (the OFRF has
        its own, ``("MAX_OFRF_ORDER", 64)``).

    Returns
    -------
    int
        ``order`` as a Python int.

    Raises
    ------
    ArgumentError
        ``order`` is not an integer (bool included) or is outside ``1..limit``.

    >>> check_order(13, "--order")
    Traceback (most recent call last):
    ...
    gfrf.errors.ArgumentError: --order must be an integer between 1 and ... = 12, got 13
    """
    label, top = limit
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) \
            or not 1 <= order <= top:
        raise ArgumentError(f"{name} must be an integer between 1 and {label} = {top}, "
                            f"got {order!r}")
    return int(order)


def kernel(model: Model, n: int, symmetric: bool = True, max_terms: int | None = None
           ) -> Kernel:
    """The n-th order GFRF of ``model``.

    Parameters
    ----------
    model : Model
        A polynomial model from :func:`gfrf.model.equation.parse_model` or a model file.
    n : int
        Kernel order, 1 <= n <= :data:`MAX_KERNEL_ORDER`.
    symmetric : bool, optional
        The symmetric kernel (default; unique for the system) or the asymmetric one
        produced by the recursion in the order the model's factors are written.
    max_terms : int, optional
        Most symbolic terms of the recursion (default :data:`MAX_PLAN_TERMS`, about 9 s
        of work); see :func:`check_recursion_work`.

    Returns
    -------
    Kernel
    """
    check_order(n, "kernel order")
    if max_terms is not None and (isinstance(max_terms, bool) or not isinstance(
            max_terms, (int, np.integer)) or max_terms < 1):
        raise ArgumentError(f"max_terms (gfrf kernel --max-work) must be a positive integer, "
                            f"got {max_terms!r}")
    check_recursion_work(generator(model), int(n), bool(symmetric), max_terms)
    return Kernel(model, int(n), bool(symmetric), generator(model))
