"""Input signals u(t) for simulation: text expressions in t (seconds) or a recorded CSV.

Text inputs are sympy expressions in the time ``t`` in seconds, e.g.
``0.1*sin(1.2*t)`` (1.2 rad/s), ``0.05*cos(t) + 0.02*sin(3*t + 0.4)`` (a sum of
tones), ``0.3*step(t - 1)`` (a step at t = 1 s; ``step``/``Heaviside`` are 1 at the
jump) or ``exp(-t)*sin(t)``.  Allowed functions: sin, cos, tan, exp, log, sqrt, tanh,
abs, sign, step, Heaviside; constants ``pi`` and ``E``.  Derivatives for models with
``D(u,k)`` terms are taken symbolically.  A recorded signal is ``csv:FILE`` or a path
ending in ``.csv`` with columns ``t,u`` (optional header); it is interpolated by a
cubic spline (derivatives from the spline) and held constant outside its time range.

:meth:`InputSignal.breakpoints` lists the times where u or one of its derivatives may
be non-smooth (a step, a kink, a CSV sample), so that a fixed-step integrator can put
them on step boundaries (:mod:`gfrf.sim.fastsim`).

A text input that is a plain sum ``sum_k A_k cos(w_k t + phi_k)`` (sin allowed) also
exposes its :attr:`InputSignal.tones`, which the Volterra prediction uses.

Examples
--------
>>> u = parse_input("0.1*sin(1.2*t)")
>>> round(float(u(0.5)), 6) == round(0.1 * __import__("math").sin(0.6), 6)
True
>>> [(round(a, 3), round(w, 3)) for a, w, _ in u.tones]
[(0.1, 1.2)]
"""

from __future__ import annotations

import math
import stat
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import sympy as sp
from scipy.interpolate import CubicSpline

from gfrf._results import Result
from gfrf.errors import ArgumentError, ModelError
from gfrf.model.expr import SIGNAL_FUNCTIONS, UnknownNames, parse_expression
from gfrf.model.limits import quote
from gfrf.model.tones import ToneTerm, read_tone_sum, tone_sum_function

__all__ = ["InputSignal", "parse_input", "zero_input", "tones_input", "T", "MAX_BREAKPOINTS"]

#: The time symbol of input expressions (seconds).
T = sp.Symbol("t", real=True)

#: DiracDelta(x) and its derivatives DiracDelta(x, k) evaluate to 0: the impulses of a
#: requested derivative inside the run are refused (:meth:`InputSignal.impulses`), one at
#: t = 0 is before the run starts.
_NUMPY_MODULES = [{"Heaviside": lambda x, _h0=1.0: np.heaviside(x, 1.0),
                   "DiracDelta": lambda x, _k=0: np.zeros_like(np.asarray(x, dtype=float))},
                  "numpy"]

#: Tones above which a plain sum of tones is read by :mod:`gfrf.model.tones` (linear
#: time, numpy evaluation, ``expr`` None) instead of sympy (milliseconds a term).
FAST_TONES = 32
#: Most breakpoints :meth:`InputSignal.breakpoints` reports (more: None, unknown).
MAX_BREAKPOINTS = 100_000
#: Largest input CSV file (``csv:FILE``), in bytes, refused before it is read.
MAX_CSV_BYTES = 200_000_000
#: Most rows of an input CSV file.
MAX_CSV_ROWS = 2_000_000
#: Functions of the input grammar that are smooth wherever they are finite.
_SMOOTH = (sp.sin, sp.cos, sp.tan, sp.sinh, sp.cosh, sp.tanh, sp.atan, sp.exp, sp.log)
#: Functions that jump, or whose derivative jumps, where their argument crosses zero
#: (DiracDelta: in the derivatives of a step).
_NON_SMOOTH = (sp.Heaviside, sp.sign, sp.Abs, sp.DiracDelta)

#: A tone (amplitude, angular frequency in rad/s, phase in rad) of A*cos(w*t + phi).
Tone = tuple[float, float, float]


@dataclass(frozen=True, kw_only=True, repr=False)
class InputSignal(Result):
    """A scalar input u(t), t in seconds, with derivatives up to :attr:`max_derivative`.

    Call it on a float or an array of times.  ``derivative(k)`` returns the callable
    of the k-th time derivative.  :attr:`tones` is the list ``[(A, w, phi), ...]``
    of ``A*cos(w*t + phi)`` (w in rad/s) for a pure sum of sinusoids, else None.
    ``to_dict`` gives the text, the expression as text and the tones; it leaves out
    ``max_derivative`` (how many derivatives were prepared: an evaluation setting) and
    the private fields (compiled callables).
    """

    _exclude = ("max_derivative",)
    _keys = {"expr": "expression"}

    text: str
    expr: sp.Expr | None
    max_derivative: int
    tones: tuple[Tone, ...] | None
    _funcs: tuple[Callable[[Any], Any], ...] = field(repr=False, compare=False)
    #: Candidate breakpoints of a signal without expression (e.g. CSV sample times),
    #: as a function of t_end; None: unknown.
    _breaks: Callable[[float], np.ndarray] | None = field(default=None, repr=False,
                                                          compare=False)
    #: The answers of :meth:`breakpoints`, :meth:`time_scale` and :meth:`unresolved_parts`
    #: for the last t_end asked, by (method, t_end): a prepared signal runs many times.
    _memo: dict[tuple[str, float], Any] = field(default_factory=dict, init=False,
                                                repr=False, compare=False)

    def __call__(self, t: Any) -> np.ndarray:
        """Value of u at time(s) ``t`` in seconds."""
        return self.derivative(0)(t)

    def derivative(self, k: int) -> Callable[[Any], np.ndarray]:
        """The k-th time derivative of u as a callable of t (seconds).

        Parameters
        ----------
        k : int
            The order, 0 <= k <= :attr:`max_derivative`.

        Returns
        -------
        callable
            ``f(t) -> numpy.ndarray``.
        """
        if not 0 <= k <= self.max_derivative:
            raise ArgumentError(f"derivative {k} of the input was not prepared "
                                f"(max_derivative={self.max_derivative})")
        f = self._funcs[k]

        def value(t: Any) -> np.ndarray:
            if isinstance(t, float):  # the ODE solvers' scalar calls: no array round trip
                with np.errstate(all="ignore"):  # 1/t at 0 is inf, as for arrays
                    return np.float64(f(np.float64(t)))  # type: ignore[return-value]
            t_arr = np.asarray(t, dtype=float)
            return np.broadcast_to(np.asarray(f(t_arr), dtype=float), t_arr.shape).copy()

        return value

    def breakpoints(self, t_end: float) -> np.ndarray | None:
        """Times in (0, t_end) s where u or a derivative of u may be non-smooth.

        For a text input: the zeros of the arguments of ``step``/``Heaviside``,
        ``sign``, ``abs`` and of the bases of fractional powers (``sqrt``), found exactly
        for arguments polynomial in t (real roots of the polynomial) and for
        ``A*sin(w*t + p)``, ``A*cos(w*t + p)`` (a square wave ``sign(sin(w*t))``).
        The other functions of the grammar are smooth where finite (their poles are not
        breakpoints: there u is infinite).  For a CSV input: its sample times (the
        spline's knots and the ends of its time range).

        Parameters
        ----------
        t_end : float
            End of the time range in seconds.

        Returns
        -------
        numpy.ndarray or None
            Sorted, distinct times strictly inside (0, t_end); None when they are not
            known: an argument of another form (``step(t**2 + sin(t))``), a signal
            built from a plain function, or more than :data:`MAX_BREAKPOINTS` of them.

        Examples
        --------
        >>> parse_input("step(t - 1) - step(2*t - 10)").breakpoints(10.0).tolist()
        [1.0, 5.0]
        >>> parse_input("0.1*sin(1.2*t)").breakpoints(10.0).tolist()
        []
        >>> parse_input("step(t - sin(t) - 1)").breakpoints(10.0) is None
        True
        """
        times = self._remembered("breakpoints", t_end, self._breakpoints)
        return None if times is None else times.copy()

    def _remembered(self, method: str, t_end: float, compute: Callable[[float], Any]) -> Any:
        """``compute(t_end)``, computed once per method for the last ``t_end`` asked."""
        if any(end != t_end for _, end in self._memo):
            self._memo.clear()
        if (method, t_end) not in self._memo:
            self._memo[method, t_end] = compute(t_end)
        return self._memo[method, t_end]

    def _breakpoints(self, t_end: float) -> np.ndarray | None:
        if self._breaks is not None:
            times: np.ndarray | None = np.asarray(self._breaks(t_end), dtype=float)
        elif self.expr is not None:
            times = _expr_breakpoints(self.expr, t_end)
        else:
            return None
        if times is None:
            return None
        times = np.unique(times[np.isfinite(times) & (times > 0) & (times < t_end)])
        return times if times.size <= MAX_BREAKPOINTS else None

    def impulses(self, t_end: float) -> np.ndarray | None:
        """Times in (0, t_end] s where a requested derivative of u is an impulse.

        Where u jumps (``step(t - 1)``), u' holds a Dirac delta (u'' where u' jumps,
        e.g. ``abs(t - 1)``); a model with D(u,k) terms would need it, and no integrator
        represents it (numerically the delta is 0, so the jump would silently vanish).
        Only the derivatives up to :attr:`max_derivative` count; t = 0 does not (the
        run starts after a jump there).  CSV inputs are splines: none.

        Parameters
        ----------
        t_end : float
            The end of the run in s.

        Returns
        -------
        numpy.ndarray or None
            Sorted times; None when an impulse's time is not known in closed form.

        Examples
        --------
        >>> parse_input("step(t - 1)", max_derivative=1).impulses(5.0).tolist()
        [1.0]
        >>> parse_input("abs(t - 1)", max_derivative=1).impulses(5.0).tolist()
        []
        """
        if self.expr is None or self.max_derivative == 0:
            return np.zeros(0)
        times = [np.zeros(0)]
        current = self.expr
        for _ in range(self.max_derivative):
            current = sp.expand(sp.diff(current, T))
            for delta in current.atoms(sp.DiracDelta):
                zeros = _zeros(delta.args[0], t_end)
                if zeros is None:
                    return None
                weight = current.coeff(delta)  # (t - 1)*DiracDelta(t - 1) is no impulse
                if len(delta.args) == 1 and weight.free_symbols <= {T} and not sp.expand(
                        current - weight * delta).has(delta):
                    zeros = np.array([x for x in zeros if weight.subs(T, x) != 0])
                times.append(zeros)
        found = np.concatenate(times)
        return np.unique(found[np.isfinite(found) & (found > 0) & (found <= t_end)])

    def time_scale(self, t_end: float) -> float | None:
        """The shortest time scale in s on which a smooth part of u changes in [0, t_end].

        For every smooth function of the grammar (``tanh``, ``sin``, ``exp``, ...) whose
        argument p(t) is a polynomial in t, 1 / max |p'(t)| over [0, t_end]: a smoothed
        jump ``tanh((t - 1)/w)`` gives w, a tone ``sin(w*t)`` gives 1/w.  Arguments of
        other forms do not count.

        Parameters
        ----------
        t_end : float
            End of the time range in seconds.

        Returns
        -------
        float or None
            The scale in s; None when no smooth function has a polynomial argument (a
            sum of tones read without sympy, a CSV input, a polynomial in t).

        Examples
        --------
        >>> parse_input("0.5*(1 + tanh((t - 1)/0.01))").time_scale(5.0)
        0.01
        >>> parse_input("step(t - 1)").time_scale(5.0) is None
        True
        """
        return self._remembered("time_scale", t_end, self._time_scale)

    def _time_scale(self, t_end: float) -> float | None:
        if self.expr is None:
            return None
        rates = [_largest_slope(f.args[0], t_end) for f in self.expr.atoms(sp.Function)
                 if isinstance(f, _SMOOTH) and f.args and f.args[0].is_polynomial(T)
                 and T in f.args[0].free_symbols]
        rates = [r for r in rates if r > 0]
        return 1.0 / max(rates) if rates else None

    def unresolved_parts(self, t_end: float) -> list[str]:
        """Parts of u whose smoothness over [0, t_end] :meth:`time_scale` cannot judge.

        A smooth function of an argument that is not a polynomial in t
        (``atan(1/(t - 1))``, which jumps at t = 1; ``tanh(tan(t))``), and a negative or
        fractional power of a polynomial with a real zero in (0, t_end] (a pole).

        Parameters
        ----------
        t_end : float
            End of the time range in seconds.

        Returns
        -------
        list of str
            The parts as text; empty when every part is judged (or for an input without
            expression: a CSV spline or a sum of many tones, smooth by construction).

        Examples
        --------
        >>> parse_input("0.02*atan(1/(t - 1))").unresolved_parts(3.0)
        ['1/(t - 1)', 'atan(1/(t - 1))']
        >>> parse_input("sin(2*t)/(1 + t)").unresolved_parts(3.0)
        []
        """
        return list(self._remembered("unresolved_parts", t_end, self._unresolved_parts))

    def _unresolved_parts(self, t_end: float) -> list[str]:
        if self.expr is None:
            return []
        parts = [f for f in self.expr.atoms(sp.Function)
                 if isinstance(f, _SMOOTH) and not f.args[0].is_polynomial(T)]
        for p in self.expr.atoms(sp.Pow):
            integer = p.exp.is_number and float(p.exp).is_integer() and float(p.exp) >= 0
            if T in p.base.free_symbols and not integer and (
                    not p.base.is_polynomial(T) or _has_zero(p.base, t_end)):
                parts.append(p)
        return sorted(str(part) for part in parts)

    def _computed(self) -> dict[str, Any]:
        """The expression as text."""
        return {"expression": None if self.expr is None else str(self.expr)}


def zero_input(max_derivative: int = 0) -> InputSignal:
    """The input u(t) = 0 (simulation from initial conditions only).

    Parameters
    ----------
    max_derivative : int, optional
        Highest derivative of u prepared.

    Returns
    -------
    InputSignal
        The zero input.
    """
    zero = sp.Integer(0)
    funcs = tuple(sp.lambdify(T, zero, modules=_NUMPY_MODULES)
                  for _ in range(max_derivative + 1))
    return InputSignal(text="0", expr=zero, max_derivative=max_derivative, tones=(), _funcs=funcs)


def tones_input(tones: list[Tone] | tuple[Tone, ...], max_derivative: int = 0) -> InputSignal:
    """The multi-tone input ``sum_k A_k cos(w_k t + phi_k)`` (w in rad/s, phi in rad).

    Parameters
    ----------
    tones : sequence of tuple of float
        ``(A, omega, phi)`` per tone (omega in rad/s, phi in rad); empty: the zero input.
    max_derivative : int, optional
        Highest derivative of u prepared.

    Returns
    -------
    InputSignal
        The input.
    """
    text = " + ".join(f"{float(a)!r}*cos({float(w)!r}*t + {float(p)!r})" for a, w, p in tones)
    return parse_input(text or "0*t", max_derivative=max_derivative)


def parse_input(text: str, *, max_derivative: int = 0) -> InputSignal:
    """Build an :class:`InputSignal` from text or a CSV recording.

    Parameters
    ----------
    text : str
        An expression in ``t`` (seconds), or ``csv:FILE`` / ``FILE.csv`` with columns t,u.
    max_derivative : int, optional
        Highest time derivative of u that will be requested (the largest k of D(u,k)).

    Returns
    -------
    InputSignal

    Raises
    ------
    ArgumentError
        Unparsable text, unknown symbols or functions, an expression that does not
        depend on t, a missing or malformed CSV file.
    """
    if not isinstance(text, str) or not text.strip():
        raise ArgumentError("empty input: give an expression in t such as '0.1*sin(1.2*t)'")
    if max_derivative < 0:
        raise ArgumentError(f"max_derivative must be >= 0, got {max_derivative}")
    stripped = text.strip()
    if stripped.startswith("csv:") or stripped.lower().endswith(".csv"):
        return _csv_input(stripped.removeprefix("csv:"), max_derivative)
    try:
        terms = read_tone_sum(stripped)
    except ModelError as exc:  # the tokenizer's refusal, worded as the general parser's
        raise ArgumentError(f"cannot parse the input: {exc}") from None
    if terms is not None and len(terms) > FAST_TONES:
        sums = tuple(tone_sum_function(terms, k) for k in range(max_derivative + 1))
        return InputSignal(text=stripped, expr=None, max_derivative=max_derivative,
                           tones=_float_tones(terms), _funcs=sums,
                           _breaks=lambda t_end: np.zeros(0))
    expr = _parse_expression(stripped)
    funcs = [sp.lambdify(T, expr, modules=_NUMPY_MODULES)]
    current = expr
    for _ in range(max_derivative):  # no derivative beyond the last one asked for
        current = sp.diff(current, T)
        funcs.append(sp.lambdify(T, current, modules=_NUMPY_MODULES))
    return InputSignal(text=stripped, expr=expr, max_derivative=max_derivative,
                       tones=_tones(expr), _funcs=tuple(funcs))


def _parse_expression(text: str) -> sp.Expr:
    try:
        expr = parse_expression(text, names={"t": T}, functions=SIGNAL_FUNCTIONS,
                                variables=(T,), series=False).expr
    except UnknownNames as exc:
        raise ArgumentError(f"unknown symbol(s) {', '.join(exc.names)} in the input "
                            f"{quote(text)}: the only variable is the time t (seconds)") \
            from None
    except ModelError as exc:
        raise ArgumentError(f"cannot parse the input: {exc}") from None
    if T not in expr.free_symbols:
        raise ArgumentError(f"the input {quote(text)} is not a function of t; a constant "
                            f"input is e.g. '0.1*step(t)', and no input means omit it")
    if expr.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
        raise ArgumentError(f"the input {quote(text)} is not finite")
    if expr.has(sp.I):
        raise ArgumentError(f"the input {quote(text)} is complex: u(t) must be real")
    return expr


def _float_tones(terms: list[ToneTerm]) -> tuple[Tone, ...]:
    """The (A, w, phi) of A*cos(w*t + phi) of read tone terms (as :func:`_tones` gives)."""
    tones = []
    for amp, function, w, phi in terms:
        if function == "sin":
            phi -= math.pi / 2
        if w < 0:
            w, phi = -w, -phi
        if amp < 0:
            amp, phi = -amp, phi + math.pi
        tones.append((amp, w, math.remainder(phi, 2 * math.pi)))
    return tuple(tones)


def _tones(expr: sp.Expr) -> tuple[Tone, ...] | None:
    tones = []
    for term in sp.Add.make_args(expr):
        coeff, rest = term.as_coeff_Mul()
        if not isinstance(rest, (sp.sin, sp.cos)):
            return None
        poly = sp.Poly(rest.args[0], T) if rest.args[0].is_polynomial(T) else None
        if poly is None or poly.degree() != 1:
            return None
        w, phi = (float(c) for c in poly.all_coeffs())
        tones.append((float(coeff), "sin" if isinstance(rest, sp.sin) else "cos", w, phi))
    return _float_tones(tones)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _csv_numbers(path: Path, path_text: str) -> np.ndarray:
    """The numbers of a CSV file: :func:`numpy.loadtxt` (one fast parse) of the whole file,
    or of the rows after a header (a first line without any number); a file it cannot
    read (empty cells, text in a row) by :func:`numpy.genfromtxt`, which reads what is
    not a number as NaN (refused by the caller unless the whole row is)."""
    with path.open(encoding="utf-8", errors="replace") as fh:
        first = fh.readline(10_000).split("#", 1)[0]
    header = not any(_is_number(field) for field in first.split(","))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # an empty file: checked by the caller
        try:
            return np.loadtxt(path, delimiter=",", ndmin=2, skiprows=int(header),
                              dtype=float, max_rows=MAX_CSV_ROWS + 1)
        except ValueError:
            pass
        try:
            return np.genfromtxt(path, delimiter=",", names=None, dtype=float)
        except ValueError as exc:
            raise ArgumentError(f"input CSV {path_text!r}: {' '.join(str(exc).split())}"
                                ) from None


def _csv_input(path_text: str, max_derivative: int) -> InputSignal:
    path = Path(path_text)
    try:
        mode = path.stat().st_mode  # before any open: a FIFO would block, /dev/zero never end
    except FileNotFoundError:
        raise ArgumentError(f"input CSV file {path_text!r} does not exist") from None
    except OSError as exc:
        raise ArgumentError(f"input CSV file {path_text!r}: {exc.strerror or exc}") from None
    if stat.S_ISDIR(mode):
        raise ArgumentError(f"input CSV file {path_text!r} is a directory")
    if not stat.S_ISREG(mode):
        raise ArgumentError(f"input CSV file {path_text!r} is not a regular file (a device, "
                            f"FIFO or socket); save the samples t,u to a file first")
    size = path.stat().st_size
    if size > MAX_CSV_BYTES:
        raise ArgumentError(f"input CSV file {path_text!r}: {size} bytes, above the limit "
                            f"{MAX_CSV_BYTES}")
    data = np.atleast_2d(_csv_numbers(path, path_text))
    if data.shape[0] > MAX_CSV_ROWS:
        raise ArgumentError(f"input CSV {path_text!r}: more than {MAX_CSV_ROWS} rows")
    data = data[~np.isnan(data).all(axis=1)] if data.size else data
    if data.ndim != 2 or data.shape[1] != 2 or len(data) < 2 or not np.isfinite(data).all():
        raise ArgumentError(f"input CSV {path_text!r} must have two numeric columns t,u "
                            f"(seconds, input) and at least two rows")
    t, u = data[:, 0], data[:, 1]
    if np.any(np.diff(t) <= 0):
        raise ArgumentError(f"input CSV {path_text!r}: the times must increase strictly")
    spline = CubicSpline(t, u)
    lo, hi = float(t[0]), float(t[-1])

    def make(k: int) -> Callable[[Any], np.ndarray]:
        def f(tt: Any) -> np.ndarray:
            arr = np.asarray(tt, dtype=float)
            value = spline(np.clip(arr, lo, hi), k)
            if k:
                value = np.where((arr < lo) | (arr > hi), 0.0, value)
            return value
        return f

    return InputSignal(text=f"csv:{path_text}", expr=None, max_derivative=max_derivative,
                       tones=None, _funcs=tuple(make(k) for k in range(max_derivative + 1)),
                       _breaks=lambda t_end: t)


def _expr_breakpoints(expr: sp.Expr, t_end: float) -> np.ndarray | None:
    """Zeros in [0, t_end] of the arguments of the non-smooth parts of ``expr``, or None."""
    arguments = []
    for f in expr.atoms(sp.Function):
        if isinstance(f, _NON_SMOOTH):
            arguments.append(f.args[0])
        elif not isinstance(f, _SMOOTH):
            return None
    for p in expr.atoms(sp.Pow):  # sqrt(b), b**0.3: not smooth where b = 0
        fractional = not (p.exp.is_number and float(p.exp).is_integer())
        if fractional and T in p.base.free_symbols and not p.base.is_positive:
            arguments.append(p.base)
    times = [np.zeros(0)]
    for argument in arguments:
        zeros = _zeros(argument, t_end)
        if zeros is None:
            return None
        times.append(zeros)
    return np.concatenate(times)


def _zeros(argument: sp.Expr, t_end: float) -> np.ndarray | None:
    """Real zeros of ``argument`` in t (those in [0, t_end] at least), or None if unknown.

    Exact for a polynomial in t (real roots of its coefficients as exact rationals) and
    for ``A*sin(w*t + p)``/``A*cos(w*t + p)``; None for any other form, or for more
    than :data:`MAX_BREAKPOINTS` zeros in [0, t_end].
    """
    if argument.free_symbols - {T}:
        return None
    if argument.is_polynomial(T):
        coefficients = [sp.Rational(c.evalf(30)) for c in sp.Poly(argument, T).all_coeffs()]
        if len(coefficients) == 2:  # linear: one exact division
            return np.array([float(-coefficients[1] / coefficients[0])])
        if len(coefficients) < 2:
            return np.zeros(0)
        return np.array([float(r.evalf(20)) for r in
                         sp.Poly(coefficients, T, domain="QQ").real_roots(multiple=True)])
    _, wave = argument.as_independent(T, as_Add=False)
    if not isinstance(wave, (sp.sin, sp.cos)) or not wave.args[0].is_polynomial(T):
        return None
    phase = sp.Poly(wave.args[0], T)
    if phase.degree() != 1:
        return None
    w, p = (float(c) for c in phase.all_coeffs())
    # w t + p = k pi + shift, shift = 0 (sin) or pi/2 (cos), over t in [0, t_end]
    shift = 0.0 if isinstance(wave, sp.sin) else math.pi / 2
    lo, hi = sorted((p - shift, w * t_end + p - shift))
    k = np.arange(math.ceil(lo / math.pi), math.floor(hi / math.pi) + 1) \
        if (hi - lo) / math.pi <= MAX_BREAKPOINTS else None
    return None if k is None else (k * math.pi + shift - p) / w


def _largest_slope(argument: sp.Expr, t_end: float) -> float:
    """max |p'(t)| over [0, t_end] of a polynomial p in t (ends and critical points)."""
    slope = sp.Poly(sp.diff(argument, T), T)
    candidates = [0.0, float(t_end)]
    if slope.degree() >= 1:
        candidates += [float(r) for r in sp.Poly(sp.diff(slope.as_expr(), T), T)
                       .nroots(n=15) if abs(sp.im(r)) < 1e-12 and 0 <= sp.re(r) <= t_end]
    values = np.abs(np.polyval([float(c) for c in slope.all_coeffs()], candidates))
    return float(np.max(values))


def _has_zero(argument: sp.Expr, t_end: float) -> bool:
    """True when the polynomial ``argument`` has a real zero in (0, t_end] (or unknown;
    a zero at t = 0 is the start, whose values are checked where the run begins)."""
    zeros = _zeros(argument, t_end)
    return zeros is None or bool(np.any((zeros > 0) & (zeros <= t_end)))
