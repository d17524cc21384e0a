"""Straight-line code generation for a GFRF: one fused function per model, order and kind.

:class:`gfrf.kernels.recursion.GFRFGenerator` evaluates H_n bottom-up over the subsets of the
frequencies with a Python-level memo.  Here the same recursion is unrolled once into
Python source: one assignment per lower-order kernel on a block, each the block's
recursion step after common-subexpression elimination, then the top-level kernel.
The source runs as is on numpy arrays, and compiled with numba (when installed) it
becomes a scalar function wrapped in a numpy ufunc, which is the fast path for
millions of points (no temporary arrays at all).

Compiled kernels are cached on disk, so that a second process pays no compile: the
generated module is written to :func:`cache_dir` (``$GFRF_CACHE_DIR/kernels``, by
default the platform's user cache directory, e.g. ``~/.cache/gfrf/kernels``) under
the hash of its source, and numba's ``cache=True`` keeps the machine code beside it.
The code that runs is always the source generated in this process: a cached file is
only the anchor of numba's cache, rewritten when it differs from that source.  When
the directory is unusable or fails the checks of :mod:`gfrf._cache` (a folder of this
user's, writable by nobody else), the kernel is compiled in memory, uncached.
On Linux with a C compiler driver the kernel is instead a shared library in the same
folder (:mod:`gfrf.kernels.native`), which a second process loads without numba.
"""

from __future__ import annotations

import hashlib
import importlib.util
import math
import re
import sys
from collections.abc import Hashable
from functools import lru_cache
from pathlib import Path
from typing import Any, Protocol

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from gfrf._cache import cache_root, load_generated
from gfrf.kernels.realcode import FASTMATH, grouped_numerator, real_step_lines
from gfrf.kernels.subsets import real_on_the_axis as _real_on_the_axis
from gfrf.model.equation import Model

__all__ = ["kernel_source", "numba_ufunc", "HAVE_NUMBA", "cache_dir", "Recursion", "rename",
           "step_text", "compile_pays", "MIN_POINTS"]


class Recursion(Hashable, Protocol):
    """What code generation needs of :class:`gfrf.kernels.recursion.GFRFGenerator` (a protocol, so
    that this module does not import :mod:`gfrf.kernels.recursion`, which imports it)."""

    model: Model

    def plan(self, n: int, symmetric: bool) -> Any:
        """The recursion step of H_n: ``is_zero``, ``blocks``, ``placeholders``,
        ``numerator``.

        Parameters
        ----------
        n : int
            The order of the kernel, >= 1.
        symmetric : bool
            The symmetric kernel (average over the permutations of the frequencies) instead
            of the asymmetric one.
        """

    def variables(self, n: int) -> tuple[sp.Symbol, ...]:
        """The symbolic variables s1..sn (or q1..qn).

        Parameters
        ----------
        n : int
            The number of variables (the order of the kernel).
        """

#: Whether numba (the optional ``fast`` extra) is installed; it is imported only when a
#: kernel is compiled (importing it costs about half a second).
HAVE_NUMBA: bool = importlib.util.find_spec("numba") is not None


class _Printer(PythonCodePrinter):
    """Plain arithmetic: rationals as float literals, complex unit as 1j."""

    def _print_Rational(self, expr: sp.Rational) -> str:
        return repr(float(expr))

    def _print_ImaginaryUnit(self, expr: sp.Expr) -> str:
        return "1j"

    def _print_Pow(self, expr: sp.Pow, rational: bool = False) -> str:
        """Small integer powers as products: complex ``**`` is a slow library call."""
        base, exponent = expr.args
        if exponent.is_Integer and 1 < int(exponent) <= 8:
            factor = self.parenthesize(base, 100)
            return "(" + "*".join([factor] * int(exponent)) + ")"
        return super()._print_Pow(expr, rational=rational)


_NAME = re.compile(r"\b[A-Za-z_][A-Za-z0-9_]*\b")


def rename(text: str, mapping: dict[str, str]) -> str:
    """``text`` with every identifier in ``mapping`` replaced (one pass, so a new name
    is never renamed again).

    Parameters
    ----------
    text : str
        Generated Python source.
    mapping : dict of str to str
        Old identifier -> new identifier; identifiers not in it are kept.

    Returns
    -------
    str
        The renamed source.
    """
    return _NAME.sub(lambda m: mapping.get(m.group(0), m.group(0)), text)


@lru_cache(maxsize=256)
def step_text(gen: Recursion, m: int, symmetric: bool) -> tuple[tuple[tuple[str, str], ...],
                                                                 str]:
    """The recursion step of order ``m`` after common-subexpression elimination, as text
    in the generic names (variables ``s1..``/``q1..``, placeholders ``h_..``,
    subexpressions ``_c0, _c1, ..``, partial sums of a long sum ``_r_0, ..``):
    ``((name, value), ...)`` and the numerator.

    Computed once per order (sympy's ``cse`` and printing are the costly part of code
    generation) and renamed per block with :func:`rename`.
    """
    printer = _Printer()
    plan = gen.plan(m, symmetric)
    replacements, (reduced,) = sp.cse(grouped_numerator(plan.numerator, plan.placeholders),
                                      symbols=sp.numbered_symbols("_c"))
    assignments = [pair for sym, value in replacements
                   for pair in _chunked(str(sym), value, printer)]
    if len(sp.Add.make_args(reduced)) <= _CHUNK:
        return tuple(assignments), printer.doprint(reduced)
    return tuple(assignments + _chunked("_r", reduced, printer)), "_r"


#: Most terms of one printed sum: Python's compiler nests a long chain of ``+`` (a sum
#: of thousands of terms exceeds its recursion limit), so longer sums are split.
_CHUNK = 500


def _chunked(name: str, expr: sp.Expr, printer: _Printer) -> list[tuple[str, str]]:
    """``[(name, text)]``, or for a sum of more than :data:`_CHUNK` terms its partial sums
    ``name_0, name_1, ..`` and then ``name`` as their sum."""
    terms = sp.Add.make_args(expr)
    if len(terms) <= _CHUNK:
        return [(name, printer.doprint(expr))]
    parts = [(f"{name}_{i}", printer.doprint(sp.Add(*terms[start:start + _CHUNK])))
             for i, start in enumerate(range(0, len(terms), _CHUNK))]
    return parts + [(name, " + ".join(part for part, _ in parts))]


def kernel_source(gen: Recursion, n: int, symmetric: bool, name: str = "kernel") -> str:
    """Python source of ``name(w0, ..., w{n-1}) -> H_n`` (angular frequencies in rad/s).

    Parameters
    ----------
    gen : Recursion
        The model's GFRF generator.
    n : int
        The order of the kernel, >= 1.
    symmetric : bool
        The symmetric kernel instead of the asymmetric one.
    name : str, optional
        Name of the generated function.

    Returns
    -------
    str
        The source of one plain-Python function (no numba), using ``cmath_exp`` for a
        discrete model.
    """
    model = gen.model
    lines = [f"def {name}({', '.join(f'w{i}' for i in range(n))}):"]
    for i in range(n):
        if model.is_discrete:
            lines.append(f"    x{i} = cmath_exp(-1j * {model.sample_time!r} * w{i})")
        else:
            lines.append(f"    x{i} = 1j * w{i}")
    names: dict[tuple[int, ...], str] = {}
    linear = model.linear_output

    def emit(block: tuple[int, ...]) -> str:
        if block in names:
            return names[block]
        plan = gen.plan(len(block), symmetric)
        label = "h_" + "_".join(map(str, block))
        if plan.is_zero:
            names[block] = "0.0"
            return "0.0"
        assignments, reduced = step_text(gen, len(block), symmetric)
        mapping = {str(v): f"x{block[i]}" for i, v in enumerate(gen.variables(len(block)))}
        for sub, placeholder in zip(plan.blocks, plan.placeholders, strict=True):
            mapping[str(placeholder)] = emit(tuple(block[j] for j in sub))
        mapping.update({lhs: f"{label}{lhs}" for lhs, _ in assignments})
        for lhs, value in assignments:
            lines.append(f"    {label}{lhs} = {rename(value, mapping)}")
        reduced = rename(reduced, mapping)
        xs = [f"x{i}" for i in block]
        combined = " * ".join(xs) if model.is_discrete else "(" + " + ".join(xs) + ")"
        lines.append(f"    {label}_z = {combined}")
        denominator = _horner([linear.get(p, 0.0) for p in range(max(linear) + 1)],
                              f"{label}_z")
        lines.append(f"    {label} = -({reduced}) / ({denominator})")
        names[block] = label
        return label

    result = emit(tuple(range(n)))
    lines.append(f"    return {result}")
    return "\n".join(lines) + "\n"


def _horner(coefficients: list[float], variable: str) -> str:
    """``a0 + z*(a1 + z*(a2 + ...))`` as source text."""
    text = repr(coefficients[-1])
    for coefficient in reversed(coefficients[:-1]):
        text = f"{coefficient!r} + {variable} * ({text})"
    return text


#: Fewest points of a call for which :func:`compile_pays` is asked at all (below it the
#: numpy path always runs: no numba import, no compile on a command's path).
MIN_POINTS = 1_000_000
#: Calibration of :func:`compile_pays`, CPU seconds on one core of a 2-core 2026 machine
#: (the cart-pole's H5 and H7 at 10^5 points, steps grouped by products of kernels): per
#: point and operation of the recursion by the numpy path (1.6-2.0 s for H7) and by the
#: compiled ufunc (0.35 s), and the compile per operation of the generated step
#: functions (H7: 14 s, H5: 3.5 s) plus a fixed part (numba's import and target set-up).
NUMPY_SECONDS_PER_OP = 2.4e-9
COMPILED_SECONDS_PER_OP = 0.5e-9
COMPILE_SECONDS_PER_OP = 0.008
COMPILE_SECONDS = 1.0
#: The numpy path's time where the kernel is real on the axis (the subset convolution of
#: :mod:`gfrf.kernels.subsets`), as a share of the recursion's: the cart-pole's H5 and H7
#: at 10^5 points measured 0.58-0.63 and 0.39.
SUBSET_SHARE = 0.45


def _operations(text: str) -> int:
    return sum(text.count(c) for c in "+-*/")


def compile_pays(gen: Recursion, n: int, symmetric: bool, points: int) -> bool:
    """Whether compiling H_n (numba) pays back within one call at ``points`` points.

    A decision on counts of work only (points, and the operations of the CSE'd
    recursion: per point every block of every order, at compile each order's step
    once), never on time or on the state of the cache, so the same call takes the same
    path, with the same bits, every run.  False without numba or below
    :data:`MIN_POINTS`.  With the calibration constants above, the cart-pole's H7 pays
    from about 4e6 points, its H5 from about 1e7.

    Parameters
    ----------
    gen : Recursion
        The model's GFRF generator.
    n : int
        The order of the kernel, >= 1.
    symmetric : bool
        The symmetric kernel instead of the asymmetric one.
    points : int
        The number of frequency points of the call.

    Returns
    -------
    bool
        True when the compiled kernel is predicted to be cheaper, compile included.
    """
    if not HAVE_NUMBA or points < MIN_POINTS:
        return False
    per_point = code = 0
    for m in range(1, n + 1):
        if gen.plan(m, symmetric).is_zero:
            continue
        assignments, reduced = step_text(gen, m, symmetric)
        ops = _operations(reduced) + sum(_operations(v) for _, v in assignments) + 2
        per_point += math.comb(n, m) * ops
        code += ops
    numpy_rate = NUMPY_SECONDS_PER_OP
    if symmetric and _real_on_the_axis(gen, n):  # the subset convolution on real arrays
        numpy_rate *= SUBSET_SHARE
    saving = points * per_point * (numpy_rate - COMPILED_SECONDS_PER_OP)
    return saving > COMPILE_SECONDS + COMPILE_SECONDS_PER_OP * code


def cache_dir() -> Path:
    """Directory of the compiled-kernel cache: ``$GFRF_CACHE_DIR/kernels``, else the
    platform's user cache directory (``$XDG_CACHE_HOME`` or ``~/.cache`` on Linux,
    ``~/Library/Caches`` on macOS, ``%LOCALAPPDATA%`` on Windows) ``/gfrf/kernels``
    (see :mod:`gfrf._cache` for what it must be to be used)."""
    return cache_root() / "kernels"


def _step_functions(gen: Recursion, n: int, symmetric: bool) -> tuple[str, str]:
    """(one function ``step_m`` per nonzero order m <= n, body of ``scalar_kernel``).

    ``step_m(variables, placeholders)`` is the recursion step of order m (CSE'd once, in
    real arithmetic on the parts of its values, :func:`gfrf.kernels.realcode.real_step_lines`;
    a continuous model's variables are the real w_i); the kernel calls it once per block.
    So the compiler sees each order's code once, not once per block: the cart-pole's H7
    compiles in about 20 s instead of about 480 s (and a fraction of the memory).
    """
    model = gen.model
    linear = model.linear_output
    coefficients = [linear.get(p, 0.0) for p in range(max(linear) + 1)]
    functions: list[str] = []
    done: set[int] = set()
    body = [f"def scalar_kernel({', '.join(f'w{i}' for i in range(n))}):"]
    if model.is_discrete:
        body += [f"    x{i} = cmath_exp(-1j * {model.sample_time!r} * w{i})" for i in range(n)]
    frequency = "x" if model.is_discrete else "w"  # continuous: the real w_i themselves
    names: dict[tuple[int, ...], str] = {}

    def step(m: int) -> None:
        if m in done:
            return
        done.add(m)
        arguments, code, numerator = real_step_lines(gen, m, symmetric)
        variables = list(arguments[:m])
        lines = ["@njit(cache=CACHE)", f"def step_{m}({', '.join(arguments)}):"]
        lines += [f"    {line}" for line in code]
        combined = (" * ".join(variables) if model.is_discrete
                    else "1j * (" + " + ".join(variables) + ")")
        lines.append(f"    _z = {combined}")
        lines.append(f"    return -({numerator}) / ({_horner(coefficients, '_z')})")
        functions.append("\n".join(lines) + "\n")

    def emit(block: tuple[int, ...]) -> str:
        if block not in names:
            plan = gen.plan(len(block), symmetric)
            if plan.is_zero:
                names[block] = "0j"
            else:
                args = [f"{frequency}{i}" for i in block] + [emit(tuple(block[j] for j in sub))
                                                   for sub in plan.blocks]
                step(len(block))
                label = "h_" + "_".join(map(str, block))
                body.append(f"    {label} = step_{len(block)}({', '.join(args)})")
                names[block] = label
        return names[block]

    body.append(f"    return {emit(tuple(range(n)))}")
    return "\n\n".join(functions), "\n".join(body) + "\n"


def _module_source(parts: tuple[str, str], n: int, cache: bool) -> str:
    """Source of a module defining the ufunc ``scalar_kernel`` of H_n (``parts``: its
    :func:`_step_functions`)."""
    signature = f"complex128({', '.join(['float64'] * n)})"
    return ("from cmath import exp as cmath_exp\n\nfrom numba import njit as _njit, vectorize\n\n"
            f"CACHE = {cache}\n\n\ndef njit(**options):\n"
            f"    return _njit(fastmath={FASTMATH!r}, **options)\n\n\n{parts[0]}\n\n"
            f"@vectorize([{signature!r}], cache=CACHE)\n" + parts[1])


def numba_ufunc(gen: Recursion, n: int, symmetric: bool) -> Any:
    """A numba-compiled numpy ufunc ``f(w1..wn) -> complex128`` of H_n, cached on disk.

    Measured on a 2-core machine (numba 0.68, one step function per order), the
    cart-pole model: order 5 compiles in 2.5-3.5 s and a later process loads it in
    0.12-0.19 s as a shared library (:mod:`gfrf.kernels.native`, Linux with ``cc``), else
    from numba's on-disk cache (:func:`cache_dir`) in 0.9 s (numba's import and target
    set-up are most of that); order 7 compiles in about 14 s (real-arithmetic steps
    grouped by products of kernels).

    Parameters
    ----------
    gen : Recursion
        The model's GFRF generator.
    n : int
        The order of the kernel, >= 1.
    symmetric : bool
        The symmetric kernel instead of the asymmetric one.

    Returns
    -------
    gfrf.kernels.native.NativeKernel or numba ufunc
        Vectorised ``f(w1, ..., wn) -> complex128`` over float64 angular frequencies in
        rad/s.

    Raises
    ------
    ImportError
        If numba is not installed (``pip install gfrf[fast]``).
    """
    if not HAVE_NUMBA:
        raise ImportError("the compiled kernel needs numba: pip install 'gfrf[fast]'")
    parts = _step_functions(gen, n, symmetric)  # generated once
    from gfrf.kernels.native import native_kernel

    native = native_kernel(parts, n)  # a shared library: later processes skip numba
    if native is not None:
        return native
    source = _module_source(parts, n, cache=True)
    name = "gfrf_kernel_" + hashlib.sha256(source.encode()).hexdigest()[:24]
    if name in sys.modules:
        return sys.modules[name].scalar_kernel
    module = load_generated("kernels", name, lambda cache: _module_source(parts, n, cache))
    return module.scalar_kernel
