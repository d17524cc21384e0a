"""Output frequency response functions (OFRF) and NOFRFs of a multi-tone input.

For a model whose parameter ``c`` enters only the terms other than the linear output
part A (the nonlinear terms, and possibly the linear input part B), every Volterra
component of the steady state is a polynomial in ``c`` (Lang & Billings' OFRF):

    Y(jW) = P_0(jW) + P_1(jW) c + P_2(jW) c^2 + ...

:func:`ofrf` computes the polynomials P_k exactly (in floating point, nothing is
fitted) by the GFRF recursion applied to the input's phasors: with the input
``u = sum_i a_i e^{j w_i t}`` (the 2K signed tones of ``sum A cos(w t + phi)``), the
order-n output ``y_n = sum Y_n(v) e^{j W(v) t}`` (v an integer vector of tone counts,
W(v) = sum v_i w_i) satisfies, term by term,

    A(jW) Y_n(W) = - sum_terms coef_t(c) * [sum over compositions m_1 + .. + m_p = n - q
                   of the products of D^{l_i} y_{m_i} and of the q input factors D^{k_j} u]

which is the Peyton Jones recursion of :mod:`gfrf.kernels.recursion` summed over the
tones (so ``Y_n(W) = sum of H_n(w_i1..w_in) a_i1...a_in`` over the tuples reaching W,
the n-th order term of :func:`gfrf.sim.volterra.predict`).  Each Y_n(v) is carried as a
polynomial in ``c`` (a coefficient array), so the polynomial in ``c`` is the result of
the recursion, not of a fit.

Convention (as ``gfrf predict``): the output component at W > 0 is
``amplitude * cos(W t + phase)``; its *complex amplitude* is ``amplitude * e^{j phase}``
= 2 Y(W) (Y(0) at W = 0).  :attr:`OFRF.coefficients` are the coefficients of that
complex amplitude, lowest power first.

The nonlinear output frequency response functions (NOFRFs, Lang & Billings 2005) of
the same input are ``G_n(jW) = Y_n(W) / U_n(W)`` with ``U_n(W)`` the component at W of
``u(t)^n``; undefined (None) where ``U_n(W) = 0`` (e.g. even n at the fundamental of
one tone).

The OFRF is that of the polynomial model the GFRFs describe (a file's ``truncation`` of
``sin`` etc. applied), as for ``gfrf predict``.

What kind of number: the coefficients are the exact order-N truncation of the Volterra
series, evaluated in float arithmetic (an *estimate* of the steady state).  The
truncated series approximates the steady state only for input amplitudes below the
radius r* of the series at the parameter's value
(:func:`gfrf.sim.volterra.series_radius`); :attr:`OFRF.radius` is r* at the model file's
own value.  :attr:`OFRF.truncation_bound` bounds the truncation error there: the tail
sum_{n > N} ||H_n|| a^n of the norm series at the input amplitude a (the order-n part
of the complex amplitude at W is at most ||H_n|| a^n), from the certified majorant
(:func:`gfrf.bounds.series_tail.series_tail`), with its proof level.  When that bound is
above the accuracy needed, simulation + a fit is the better tool.

Examples
--------
>>> data = {"equation": "D(y,2) + 0.2*D(y) + y + c*y**3 = u", "parameters": {"c": 0.5}}
>>> o = ofrf(data, "c", [(0.1, 1.0, 0.0)], omega=1.0, order=3)
>>> len(o.coefficients), round(abs(o.coefficients[0]), 6)   # P0 = H1(j) * 0.1
(2, 0.5)
"""

from __future__ import annotations

import cmath
import math
import os
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from gfrf._results import Result, short_repr
from gfrf.errors import ArgumentError
from gfrf.model.equation import Model
from gfrf.model.modelfile import (
    MODEL_TYPES,
    ModelFile,
    looks_like_path,
    model_from_dict,
    read_table,
)
from gfrf.model.template import parameter_names
from gfrf.sim.volterra import _check_tones, _steady_state_problem, series_radius

__all__ = ["OFRF", "ofrf", "check_ofrf_order", "MAX_OFRF_WORK", "MAX_OFRF_ORDER"]

#: Largest a-priori number of component products (pairs of frequency components
#: multiplied over all terms and orders, :func:`_work`) :func:`ofrf` accepts: about 2-7 s
#: CPU at the limit (2.5 us per product for one tone, 6.5 us for two).
MAX_OFRF_WORK = 1_000_000
#: Highest truncation order of :func:`ofrf`.  The recursion runs on the input's spectra,
#: not on the kernels, so it goes beyond the kernels' MAX_KERNEL_ORDER wherever
#: :data:`MAX_OFRF_WORK` allows (one tone and a cubic term: order 51).
MAX_OFRF_ORDER = 64

#: Relative tolerance under which two output frequencies are the same (commensurate tones).
_FREQ_TOL = 1e-9

Key = tuple[int, ...]
Spectrum = dict[Key, np.ndarray]


@dataclass(frozen=True, kw_only=True, repr=False)
class OFRF(Result):
    """The OFRF of one parameter at one output frequency, and the NOFRFs there.

    ``to_dict`` gives complex numbers as ``[re, im]``, adds the convention, the value at
    the file's value, the NOFRFs (with ``input_spectrum``, which is left out as a field),
    ``reached``, ``warning`` and the kind of number.

    Attributes
    ----------
    parameter : str
        The parameter's name in the model file.
    value : float
        Its value in the model file.
    omega : float
        Output frequency W in rad/s.
    order : int
        Truncation order N of the Volterra series.
    tones : tuple of (A, w, phi)
        The input ``sum A cos(w t + phi)``.
    coefficients : tuple of complex
        Complex amplitude at W (``amplitude * e^{j phase}`` as ``gfrf predict``) =
        ``sum coefficients[k] * c**k``, lowest power first.
    by_order : dict
        ``{n: coefficients of the order-n contribution}`` (their sum is ``coefficients``).
    input_spectrum : dict
        ``{n: U_n(W)}``, the component at W of ``u(t)**n`` (complex phasor).
    amplitude : float
        Input amplitude (sum of the tone amplitudes).
    radius : float
        r* of the Volterra series at ``value``; the truncated series means something only
        for ``amplitude`` below it.
    radius_proof : str
        Proof level of ``radius`` (:data:`gfrf._results.PROOF_WORDS`).
    truncation_bound : float
        Upper bound on |complex amplitude of the steady state at W minus the order-N
        value| at the file's value: the tail sum_{n > N} ||H_n|| amplitude^n of the norm
        series (:func:`gfrf.bounds.series_tail.series_tail`; the tuples of tones reaching
        W > 0 carry at most half of amplitude^n, which the factor 2 of the complex
        amplitude doubles back); ``inf`` when the amplitude is not below the certified
        radius.
    truncation_proof : str
        Proof level of ``truncation_bound`` (``"interval"``, ``"float"`` or ``"none"``).
    """

    parameter: str
    value: float
    omega: float
    order: int
    tones: tuple[tuple[float, float, float], ...]
    coefficients: tuple[complex, ...]
    by_order: dict[int, tuple[complex, ...]]
    input_spectrum: dict[int, complex]
    amplitude: float
    radius: float
    radius_proof: str
    truncation_bound: float
    truncation_proof: str

    _exclude = ("input_spectrum",)
    _order = ("parameter", "value", "omega", "order", "tones", "convention", "coefficients",
              "by_order", "at_value", "nofrf", "amplitude", "radius", "radius_proof",
              "reached", "warning", "truncation_bound", "truncation_proof", "kind")

    def __call__(self, value: float) -> complex:
        """Complex amplitude of the output at W for the parameter ``value``."""
        return _horner(self.coefficients, value)

    def nofrf(self, value: float | None = None) -> dict[int, complex | None]:
        """NOFRFs ``G_n(jW) = Y_n(W) / U_n(W)`` at ``value`` (default: the file's value).

        None where ``U_n(W) = 0``; orders with no contribution at W are 0 where defined.

        Parameters
        ----------
        value : float, optional
            The parameter's value; None: the file's value.

        Returns
        -------
        dict of int to complex or None
            ``G_n`` for n = 1..order.
        """
        v = self.value if value is None else value
        out: dict[int, complex | None] = {}
        for n in range(1, self.order + 1):
            u = self.input_spectrum.get(n, 0j)
            y = _horner(self.by_order.get(n, ()), v)
            scale = 1.0 if self.omega == 0 else 2.0  # by_order holds complex amplitudes
            out[n] = None if abs(u) == 0 else complex(y / scale / u)
        return out

    @property
    def reached(self) -> bool:
        """True when W is a harmonic or intermodulation frequency of the input up to the
        order (some U_n(W) != 0); else every coefficient is 0."""
        return any(abs(u) > 0 for u in self.input_spectrum.values())

    @property
    def warning(self) -> str | None:
        """Set when W is not reached by the input, or the input amplitude is at or beyond
        r* at the file's value."""
        if not self.reached:
            return (f"omega = {self.omega:.6g} rad/s is not a sum of at most {self.order} "
                    f"input tone frequencies: the output has no component there")
        if self.amplitude < self.radius:
            return None
        return (f"input amplitude {self.amplitude:.6g} is at or beyond the radius r* = "
                f"{self.radius:.6g} of the Volterra series at {self.parameter} = "
                f"{self.value:.6g}: the truncated series is not known to converge there")

    def __repr__(self) -> str:
        return short_repr(self, "parameter", "omega", "order",
                          degree=len(self.coefficients) - 1)

    def _repr_markdown_(self) -> str:
        from gfrf.sim.views import ofrf_markdown

        return ofrf_markdown(self)

    def plot(self, values: Any = None) -> Any:
        """|Y(jW)| against the parameter's ``values``; a matplotlib Figure made without
        pyplot.

        Parameters
        ----------
        values : array_like, optional
            Values of the parameter; default 201 points from ``value - |value|`` to
            ``value + |value|``.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        from gfrf.sim.views import ofrf_figure

        return ofrf_figure(self, values)

    def _computed(self) -> dict[str, Any]:
        """Complex numbers as ``[re, im]``, the value at the file's value, the NOFRFs."""
        def pair(z: complex) -> list[float]:
            return [float(z.real), float(z.imag)]

        at_value = self(self.value)
        return {"convention": "complex amplitude amplitude*exp(j*phase) of the output "
                              "component amplitude*cos(omega*t + phase), as gfrf predict; "
                              "= sum coefficients[k]*value**k",
                "coefficients": [pair(c) for c in self.coefficients],
                "by_order": {str(n): [pair(c) for c in cs] for n, cs in self.by_order.items()},
                "at_value": {"re": at_value.real, "im": at_value.imag,
                             "amplitude": abs(at_value), "phase": cmath.phase(at_value)},
                "nofrf": [{"order": n, "value": None if g is None else pair(g),
                           "input_spectrum": pair(self.input_spectrum.get(n, 0j))}
                          for n, g in self.nofrf().items()],
                "reached": self.reached, "warning": self.warning,
                "kind": "estimate (exact order-N truncation of the Volterra series in float "
                        "arithmetic; its truncation error at value is at most "
                        "truncation_bound)"}


# -- polynomials in the parameter (coefficient arrays, lowest power first) ------------
def _horner(coefficients: Sequence[complex], value: float) -> complex:
    """sum c_k value**k (an overflow gives inf or nan, never an exception)."""
    out = 0j
    for c in reversed(coefficients):
        out = out * value + c
    return out


def _add(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    if a.size < b.size:
        a, b = b, a
    out = a.copy()
    out[:b.size] += b
    return out


def _formulas(data: Mapping[str, Any], name: str, path: str
              ) -> tuple[Model, float, dict[tuple, np.ndarray]]:
    """The plant, the parameter's value and every term's coefficient as a polynomial in it."""
    import sympy as sp

    from gfrf.model.limits import Parsed
    from gfrf.model.template import _coefficients, _symbolic_table

    where = parameter_names(data)
    if where.get(name) != "parameters":
        known = ", ".join(n for n, t in where.items() if t == "parameters") or "none"
        raise ArgumentError(f"--param {name!r} is not a key of the model's [parameters] "
                            f"(known: {known})")
    if data.get("controller") is not None:
        raise ArgumentError("ofrf works on an open-loop plant; this model file has a "
                            "[controller]")
    base = model_from_dict(dict(data), path=path)
    symbol = sp.Symbol("_p0", real=True)
    swept = {name: Parsed(symbol, 1, False, 1, True)}
    values = _symbolic_table(data.get("parameters"), swept, {}, "parameters")
    formulas = _coefficients(data["equation"], base.plant, values)
    polys: dict[tuple, np.ndarray] = {}
    for orders, expr in formulas.items():
        label = _monomial(base.plant, orders)
        try:
            poly = sp.Poly(sp.expand(expr), symbol)
        except sp.PolynomialError:
            poly = None
        if poly is None or any(not c.is_number for c in poly.coeffs()):
            raise ArgumentError(f"the coefficient of {label} is not a polynomial in {name}: "
                                f"the OFRF needs polynomial coefficients")
        coeffs = np.array([complex(c) for c in reversed(poly.all_coeffs())], dtype=complex)
        ys, us = orders
        if len(ys) == 1 and not us and coeffs.size > 1:
            raise ArgumentError(f"{name} enters the linear output part A (coefficient of "
                                f"{label}): the output spectrum is then not a polynomial in "
                                f"{name}; the OFRF needs a parameter of the other terms")
        polys[orders] = coeffs
    return base.plant, float(base.parameters[name]), polys


def _monomial(model: Model, orders: tuple) -> str:
    from gfrf.model.equation import Term

    ys, us = orders
    return Term(ys, us, 1.0, model.output, model.input, model.is_discrete).monomial()


def _operator(model: Model, omega: float, order: int) -> complex:
    """D^order on e^{j omega t}: (j omega)^order, or the lag e^{-j omega T order}."""
    if model.is_discrete:
        return cmath.exp(-1j * omega * model.sample_time * order)
    return (1j * omega) ** order


def _work(n_tones: int, order: int, model: Model) -> int:
    """A-priori count of component products of :func:`_recursion`: sizes of the order-m
    spectra are at most C(2K + m - 1, m) (multisets of signed tones)."""
    size = {m: math.comb(2 * n_tones + m - 1, m) for m in range(order + 1)}
    total = sum(size[m - 1] * 2 * n_tones for m in range(2, order + 1))  # the powers U_m
    for t in model.terms:
        p, q = len(t.y_orders), len(t.u_orders)
        if p + q < 2:
            continue
        if p == 0:
            total += (2 * n_tones) ** q if q <= order else 0
            continue
        for j in range(2, p + 1):  # the chains Q_j[s] of the output factors
            total += sum(size[s - m] * size[m] for s in range(j, order - q + 1)
                         for m in range(1, s - j + 2))
        if q:  # the input factors times Q_p[n - q]
            total += sum(size[n - q] for n in range(p + q, order + 1)) * (2 * n_tones) ** q
    return total


def check_ofrf_order(order: object, name: str = "order") -> int:
    """The check of an OFRF truncation order, before any work: an integer in
    ``1..MAX_OFRF_ORDER`` (:func:`gfrf.kernels.recursion.check_order` with this limit;
    the work it implies is checked by :func:`ofrf`).

    Parameters
    ----------
    order : int
        The order to check.
    name : str
        How the caller names it in the message (``"--order"``).

    Returns
    -------
    int
        ``order`` as a Python int.

    Raises
    ------
    ArgumentError
        ``order`` is not an integer (bool included) or is outside ``1..MAX_OFRF_ORDER``.
    """
    from gfrf.kernels.recursion import check_order

    return check_order(order, name, ("MAX_OFRF_ORDER", MAX_OFRF_ORDER))


def _table(data: Any, path: str) -> tuple[Mapping[str, Any], str]:
    """The model table behind any model argument of :func:`ofrf`, and its path."""
    if isinstance(data, ModelFile):
        if not data.path:
            raise ArgumentError("ofrf needs the model's [parameters] as symbols: pass the "
                                "model file's path, or a ModelFile read by gfrf.load_model")
        return read_table(data.path), path or data.path
    if isinstance(data, os.PathLike) or (isinstance(data, str) and looks_like_path(data)):
        return read_table(data), path or os.fspath(data)
    if isinstance(data, str):
        return {"equation": data, "name": "inline model"}, path
    if isinstance(data, Mapping):
        return data, path
    raise TypeError(f"ofrf takes {MODEL_TYPES.replace('a Model or ', '')} read from a file, "
                    f"or a model file's table (a Model has its parameters substituted), "
                    f"not {type(data).__name__}")


def ofrf(data: Mapping[str, Any] | str | Path | ModelFile, parameter: str,
         tones: Sequence[Any] | str, omega: float, order: int, *, path: str = "") -> OFRF:
    """OFRF of ``parameter`` at the output frequency ``omega`` for ``tones`` up to ``order``.

    Parameters
    ----------
    data : mapping, str, Path or ModelFile
        A model file (its path, or what :func:`gfrf.load_model` returned), an equation
        string, or a model file's table (:func:`gfrf.model.modelfile.read_table`), with
        ``parameter`` in its ``[parameters]`` (the parameter stays a symbol: a
        :class:`~gfrf.model.equation.Model` has it substituted, and is refused).
    parameter : str
        The parameter; it may enter any term except the linear output part A, as a
        polynomial.
    tones : sequence of (A, w, phi), or str
        The input ``sum A cos(w t + phi)``, w in rad/s, or its text as ``gfrf ofrf
        --input`` takes it (e.g. ``"0.1*cos(1.0*t)"``).
    omega : float
        Output frequency W >= 0 in rad/s (a harmonic or intermodulation frequency).
    order : int
        Truncation order N of the Volterra series, 1..:data:`MAX_OFRF_ORDER`.
    path : str
        The file, for messages.

    Returns
    -------
    OFRF

    Raises
    ------
    ArgumentError
        Unknown parameter, a parameter in A or non-polynomial, no steady state (linear
        part not asymptotically stable), bad tones, order or omega, or too much work.
    """
    data, path = _table(data, path)
    tones = _check_tones(tones)
    order = check_ofrf_order(order)
    omega = float(omega)
    if not math.isfinite(omega) or omega < 0:
        raise ArgumentError(f"omega must be a finite frequency >= 0 in rad/s, got {omega!r}")
    model, value, polys = _formulas(data, parameter, path)
    work = _work(len(tones), order, model)
    if work > MAX_OFRF_WORK:
        raise ArgumentError(f"{len(tones)} tones to order {order} need about {work} component "
                            f"products, above MAX_OFRF_WORK = {MAX_OFRF_WORK} "
                            f"(gfrf.sim.ofrf): use fewer tones or a lower order")
    problem = _steady_state_problem(model)
    if problem is not None:
        raise ArgumentError(problem)
    try:
        with np.errstate(all="ignore"):
            result = _evaluate(model, polys, tones, omega, order, parameter, value=value)
            checks = [*result.coefficients, result(value), *result.input_spectrum.values(),
                      *(g for g in result.nofrf().values() if g is not None)]
    except OverflowError:
        checks = [complex(math.inf)]
    if not all(cmath.isfinite(c) for c in checks):
        raise ArgumentError(f"the OFRF of {parameter} = {value:g} at omega = {omega:g} "
                            f"rad/s to order {order} overflows floating point (beyond "
                            f"{sys.float_info.max:.3g}): scale the model, the input or "
                            f"omega, or lower the order")
    return result


def _evaluate(model: Model, polys: dict[tuple, np.ndarray],
              tones: tuple[tuple[float, float, float], ...],
              omega: float, order: int, parameter: str, value: float) -> OFRF:
    """The OFRF from the recursion (no check of its finiteness)."""
    by_order, spectra = _recursion(model, polys, tones, order)
    freqs = [s * w for _, w, _ in tones for s in (1, -1)]
    scale = 1.0 if omega == 0 else 2.0

    def at(spectrum: Spectrum) -> np.ndarray:
        out = np.zeros(1, dtype=complex)
        for key, poly in spectrum.items():
            if abs(_frequency(key, freqs) - omega) <= _FREQ_TOL * max(1.0, omega):
                out = _add(out, poly)
        return out

    per_order = {n: _trim(scale * at(y)) for n, y in by_order.items()}
    total = np.zeros(1, dtype=complex)
    for poly in per_order.values():
        total = _add(total, poly)
    u_spectrum = {n: complex(at(s)[0]) for n, s in spectra.items()}
    from gfrf.bounds.majorant import majorant
    from gfrf.bounds.series_tail import series_tail

    r_star, _, proof = series_radius(model)
    amplitude = float(sum(abs(a) for a, _, _ in tones))
    bound, bound_proof = series_tail(majorant(model), amplitude, order)
    return OFRF(parameter=parameter, value=value, omega=omega, order=order, tones=tones,
                coefficients=tuple(complex(c) for c in _trim(total)),
                by_order={n: tuple(complex(c) for c in p) for n, p in per_order.items()},
                input_spectrum=u_spectrum, amplitude=amplitude, radius=r_star,
                radius_proof=proof, truncation_bound=bound, truncation_proof=bound_proof)


def _trim(poly: np.ndarray) -> np.ndarray:
    """Drop trailing exact zeros (keep at least the constant)."""
    nz = np.flatnonzero(poly)
    return poly[: (nz[-1] + 1 if nz.size else 1)]


def _frequency(key: Key, freqs: Sequence[float]) -> float:
    return float(sum(k * w for k, w in zip(key, freqs, strict=True)))


def _multiply(a: Spectrum, b: Spectrum) -> Spectrum:
    out: Spectrum = {}
    for ka, pa in a.items():
        for kb, pb in b.items():
            key = tuple(x + y for x, y in zip(ka, kb, strict=True))
            prod = np.convolve(pa, pb)
            out[key] = _add(out[key], prod) if key in out else prod
    return out


def _derivative(model: Model, spectrum: Spectrum, order: int, freqs: Sequence[float]
                ) -> Spectrum:
    if order == 0:
        return spectrum
    return {k: p * _operator(model, _frequency(k, freqs), order) for k, p in spectrum.items()}


def _accumulate(out: Spectrum, spectrum: Spectrum) -> None:
    """``out += spectrum`` (component-wise polynomial sums)."""
    for key, poly in spectrum.items():
        out[key] = _add(out[key], poly) if key in out else poly


def _recursion(model: Model, polys: Mapping[tuple, np.ndarray], tones: Sequence[Any],
               order: int) -> tuple[dict[int, Spectrum], dict[int, Spectrum]]:
    """Order-n output spectra Y_n and input-power spectra U_n, n = 1..order.

    A term's output factors are summed over the compositions of the order as a chain of
    series products, ``Q_j[s] = sum_m Q_{j-1}[s - m] * D^{l_j} Y_m`` (the order-s part
    of the product of its first j factors), each kept once: per order O(order) spectrum
    products per factor instead of one per composition."""
    size = 2 * len(tones)
    freqs = [s * w for _, w, _ in tones for s in (1, -1)]
    u: Spectrum = {}
    for i, (a, _, phi) in enumerate(tones):
        for j, s in enumerate((1, -1)):
            key = tuple(1 if k == 2 * i + j else 0 for k in range(size))
            u[key] = np.array([a / 2 * cmath.exp(s * 1j * phi)])
    powers = {1: u}
    for n in range(2, order + 1):
        powers[n] = _multiply(powers[n - 1], u)
    linear = {orders[0][0]: poly[0] for orders, poly in polys.items()
              if len(orders[0]) == 1 and not orders[1]}
    others = [(orders, poly) for orders, poly in polys.items()
              if not (len(orders[0]) == 1 and not orders[1]) and np.any(poly)]
    ys: dict[int, Spectrum] = {}
    derived: dict[tuple[int, int], Spectrum] = {}
    chains: dict[tuple[int, int, int], Spectrum] = {}

    def dy(m: int, lag: int) -> Spectrum:
        if (m, lag) not in derived:
            derived[m, lag] = _derivative(model, ys[m], lag, freqs)
        return derived[m, lag]

    def chain(term: int, j: int, s: int) -> Spectrum:
        """Q_j[s] of term ``term``'s output factors (needs Y_m for m <= s - j + 1)."""
        if (term, j, s) not in chains:
            lags = others[term][0][0]
            if j == 1:
                chains[term, j, s] = dy(s, lags[0]) if s >= 1 else {}
            else:
                out: Spectrum = {}
                for m in range(1, s - j + 2):
                    head, factor = chain(term, j - 1, s - m), dy(m, lags[j - 1])
                    if head and factor:
                        _accumulate(out, _multiply(head, factor))
                chains[term, j, s] = out
        return chains[term, j, s]

    inputs: list[Spectrum | None] = []
    for (_, u_orders), _ in others:
        product: Spectrum | None = None
        for k in u_orders:
            factor = _derivative(model, u, k, freqs)
            product = factor if product is None else _multiply(product, factor)
        inputs.append(product)
    for n in range(1, order + 1):
        rhs: Spectrum = {}
        for index, ((y_orders, u_orders), coef) in enumerate(others):
            p, q = len(y_orders), len(u_orders)
            if n < p + q or (p == 0 and n != q):
                continue
            prod = inputs[index]
            if p:
                outputs = chain(index, p, n - q)
                prod = outputs if prod is None or not outputs else _multiply(prod, outputs)
            _accumulate(rhs, {key: np.convolve(coef, poly) for key, poly in (prod or {}).items()})
        ys[n] = {k: -p / sum(a * _operator(model, _frequency(k, freqs), lag)
                              for lag, a in linear.items())
                 for k, p in rhs.items() if np.any(p)}
    return ys, powers
