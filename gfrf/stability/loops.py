"""Linear plant, controller and closed loop as python-control objects (continuous time).

The loop of a model file with a controller C is ``y = P[u]``, ``u = C[r + f y]``
with ``f = controller.feedback`` (-1, the default, is negative feedback
``u = C(r - y)``, python-control's ``feedback(C*P, 1)``; the one convention of gfrf,
simulation included).  Its linear part has the characteristic polynomial

    chi(s) = D_P(s) D_C(s) - f * N_P(s) N_C(s),

where H1 = P = N_P / D_P (``N_P = -B``, ``D_P = A`` of the plant model) and
C = N_C / D_C.  The sensitivity g1 = (1 - f P C)^{-1} = D_P D_C / chi is the
paper's g1 = [1 + h1 s1]^{-1} of section 5, and its peak sup |g1(j w)| (rad/s) is the
rho_1 of Theorem 2 as section 5 uses it.

The characteristic polynomial and the sensitivity's numerator are formed *exactly*,
in rationals, from the exact values of the float coefficients of plant and
controller (:func:`characteristic_exact`); closed-loop stability is decided on that
exact polynomial by Routh's test with exact boundary roots (:func:`gfrf.bounds.exact.poles`),
and the sensitivity peak and lambda_1 are proven enclosures on exact polynomials
(:func:`gfrf.bounds.rational.rational_sup`).  Floating-point roots (numpy.roots) of a
rounded chi can put a cluster of lightly damped poles on the wrong side of the axis;
here they are only displayed (midpoints of rigorous Arb enclosures).
python-control refuses improper transfer functions in some operations (``norm``,
conversion to state space), so ``control`` objects are only built for the returned
:class:`control.TransferFunction` objects (from the float-rounded polynomials).  An improper
controller (the paper's ``a s^2 + b s + c`` without its lags) has an infinite
H-infinity norm lambda_1; that is reported, not replaced by a big number.

Examples
--------
>>> from gfrf.model.modelfile import load_model
>>> loop = closed_loop(load_model("models/cartpole_reduced.toml"))
>>> loop.stable, loop.controller_proper
(True, False)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import TYPE_CHECKING, Any

import numpy as np

from gfrf._results import Result, markdown_table, short_repr
from gfrf.bounds.exact import format_roots, fractions, poles
from gfrf.bounds.majorant import linear_polynomials, written_intervals, written_polynomials
from gfrf.bounds.rational import Interval, SupResult, enclosed_sup, rational_sup
from gfrf.errors import ArgumentError
from gfrf.model.equation import Model
from gfrf.model.exact import Written, coefficient_bounds
from gfrf.model.modelfile import Controller, ModelFile

if TYPE_CHECKING:  # python-control (~1 s to import) is imported where a tf is built
    import control

__all__ = ["ClosedLoop", "linear_plant", "controller_tf", "controller_polynomials", "loop_text",
           "closed_loop", "characteristic", "characteristic_exact", "with_lags"]


def _continuous(model: Model, what: str) -> None:
    if model.is_discrete:
        raise ArgumentError(f"{what} is discrete-time: closed loops are implemented for "
                            "continuous-time models only")


def linear_plant(model: Model) -> control.TransferFunction:
    """H1 = -B/A of ``model`` as a :class:`control.TransferFunction`.

    A discrete (NARX) model gives a discrete transfer function in z = 1/q with
    ``dt = sample_time``.

    Parameters
    ----------
    model : Model
        The plant model.

    Returns
    -------
    control.TransferFunction
        Its linear part H1 (continuous in s, or discrete in z).
    """
    import control

    num, den = linear_polynomials(model)
    if model.is_discrete:
        size = max(num.size, den.size)
        pad = [np.concatenate([c, np.zeros(size - c.size)]) for c in (num, den)]
        return control.tf(pad[0], pad[1], model.sample_time)
    return control.tf(num, den)


def controller_polynomials(controller: Controller) -> tuple[np.ndarray, np.ndarray]:
    """(N_C, D_C) highest power first: the transfer function, or a polynomial
    controller's linear part.

    Parameters
    ----------
    controller : Controller
        A transfer-function controller, or a continuous polynomial controller.

    Returns
    -------
    tuple of numpy.ndarray
        Numerator and denominator coefficients, highest power of s first.
    """
    if controller.is_linear:
        return np.asarray(controller.num, dtype=float), np.asarray(controller.den, dtype=float)
    _continuous(controller.model, "the controller")  # type: ignore[arg-type]
    return linear_polynomials(controller.model)  # type: ignore[arg-type]


def loop_text(controller: Controller) -> str:
    """The loop as an equation, where the reference r enters: ``u = C(r - y), C(s) = ...``.

    Theorem 2 bounds the loop error e = r - y (r + y for positive feedback) driven by the
    reference r, so r, r* and the amplitude are in the units of y (the reference), not
    of the plant input u.

    Parameters
    ----------
    controller : Controller
        The model file's controller.

    Returns
    -------
    str
        One line describing the loop.
    """
    sign = "-" if controller.feedback == -1 else "+"
    if controller.is_linear:
        num, den = (_poly_s(np.asarray(c, dtype=float)) for c in (controller.num, controller.den))
        what = f"C(s) = {num}" if den == "1" else f"C(s) = ({num}) / ({den})"
    else:
        what = f"C: {controller.model.equation()}"  # type: ignore[union-attr]
    return f"u = C(r {sign} y), {what}; r is the reference, in units of y"


def _poly_s(c: np.ndarray) -> str:
    """Polynomial in s, highest power first, as short text (``0.001``, ``2 s + 1``)."""
    nz = np.flatnonzero(c)
    c = c[nz[0]:] if nz.size else np.zeros(1)
    degree = c.size - 1
    parts = []
    for i, v in enumerate(c):
        if v == 0:
            continue
        power = degree - i
        var = "" if power == 0 else ("s" if power == 1 else f"s^{power}")
        coef = f"{abs(v):g}" if (abs(v) != 1 or not power) else ""
        parts.append(("- " if v < 0 else "+ ") + f"{coef} {var}".strip())
    return " ".join(parts).removeprefix("+ ") if parts else "0"


def controller_tf(controller: Controller) -> control.TransferFunction:
    """The controller's linear part as a :class:`control.TransferFunction` (may be improper).

    Parameters
    ----------
    controller : Controller
        A transfer-function controller, or a continuous polynomial controller.

    Returns
    -------
    control.TransferFunction
        C(s).
    """
    import control

    num, den = controller_polynomials(controller)
    return control.tf(num, den)


def _degree(coefficients: np.ndarray) -> int:
    nz = np.flatnonzero(coefficients)
    return int(coefficients.size - 1 - nz[0]) if nz.size else 0


def _polymul(a: list[Fraction], b: list[Fraction]) -> list[Fraction]:
    """Exact product of two highest-first coefficient lists."""
    out = [Fraction(0)] * (len(a) + len(b) - 1)
    for i, x in enumerate(a):
        if x:
            for k, y in enumerate(b):
                out[i + k] += x * y
    return out


def _trimmed(c: list[Fraction]) -> list[Fraction]:
    while len(c) > 1 and c[0] == 0:
        c = c[1:]
    return c


def characteristic_exact(plant: tuple[np.ndarray, np.ndarray],
                         ctrl: tuple[np.ndarray, np.ndarray], feedback: int) -> list[Fraction]:
    """chi = D_P D_C - feedback * N_P N_C in exact rationals, highest power first.

    The float coefficients are taken at their exact values and multiplied without
    rounding; leading zeros are dropped (``[0]`` for the zero polynomial).

    Parameters
    ----------
    plant, ctrl : tuple of numpy.ndarray
        ``(N, D)`` of the plant and of the controller, highest power of s first.
    feedback : int
        -1 for negative feedback u = C(r - y), +1 for positive.

    Returns
    -------
    list of Fraction
        The characteristic polynomial, highest power first.
    """
    den = _polymul(fractions(plant[1]), fractions(ctrl[1]))
    num = _polymul(fractions(plant[0]), fractions(ctrl[0]))
    size = max(len(den), len(num))
    den = [Fraction(0)] * (size - len(den)) + den
    num = [Fraction(0)] * (size - len(num)) + num
    return _trimmed([d - feedback * n for d, n in zip(den, num, strict=True)])


def _written_den(plant: Model) -> list[Fraction] | None:
    """A(s) of the plant with its coefficients as written (None: one is irrational)."""
    written = written_polynomials(plant, normalize=False)
    return None if written is None else written[1]


def _written_characteristic(model_file: ModelFile, sign: int) -> list[Fraction] | None:
    """chi of the loop with the coefficients as written (``0.2`` is 1/5), for the exact
    stability decision; None when one is irrational or the controller is polynomial."""
    from gfrf.stability.polysys import StateFormError, exact_transfer_function

    plant = written_polynomials(model_file.plant, normalize=False)
    ctrl = model_file.controller
    if plant is None or ctrl is None or not ctrl.is_linear:
        return None
    try:
        num, den = exact_transfer_function(ctrl)
    except StateFormError:
        return None
    chi = characteristic_exact(plant, (num, den), sign)  # type: ignore[arg-type]
    return None if chi == [0] else chi


def _written_sups(model_file: ModelFile, sign: int) -> tuple[SupResult, SupResult]:
    """Proven (rho_1, lambda_1) of the loop as written (``0.2`` is 1/5; an irrational
    coefficient as its double widened by a relative 2^-50): sups over rational intervals
    of the coefficients of D_P D_C / chi and N_C / D_C (:func:`enclosed_sup`)."""
    plant = written_intervals(model_file.plant)
    ctrl = _controller_intervals(model_file.controller)  # type: ignore[arg-type]
    den = _interval_polymul(plant[1], ctrl[1])
    chi = _interval_add(den, _interval_polymul(plant[0], ctrl[0]), -sign)
    while len(chi) > 1 and chi[0] == (0, 0):
        chi = chi[1:]
    if chi == [(0, 0)]:
        raise ArgumentError("the closed-loop characteristic polynomial D_P D_C - f N_P N_C "
                            "as written is identically zero")
    return enclosed_sup(den, chi), enclosed_sup(*ctrl)


def _controller_intervals(ctrl: Controller) -> tuple[list[Interval], list[Interval]]:
    """(N_C, D_C) of the controller as rational intervals, highest power first."""
    if not ctrl.is_linear:
        return written_intervals(ctrl.model)  # type: ignore[arg-type]
    num, den = ctrl.exact_tf()
    doubles = (ctrl.num or (), ctrl.den or ())
    return tuple(  # type: ignore[return-value]
        [coefficient_bounds(c, Written(c, v)) for c, v in zip(d, w, strict=True)] or
        [(Fraction(1), Fraction(1))] for d, w in zip(doubles, (num, den), strict=True))


def _interval_polymul(a: list[Interval], b: list[Interval]) -> list[Interval]:
    """Product of polynomials with interval coefficients (exact rational interval ends)."""
    out = [(Fraction(0), Fraction(0))] * (len(a) + len(b) - 1)
    for i, (alo, ahi) in enumerate(a):
        for j, (blo, bhi) in enumerate(b):
            ends = (alo * blo, alo * bhi, ahi * blo, ahi * bhi)
            lo, hi = out[i + j]
            out[i + j] = (lo + min(ends), hi + max(ends))
    return out


def _interval_add(a: list[Interval], b: list[Interval], factor: int) -> list[Interval]:
    """a + factor * b (factor +-1) for interval polynomials, highest power first."""
    size = max(len(a), len(b))
    zero = (Fraction(0), Fraction(0))
    a = [zero] * (size - len(a)) + a
    b = [zero] * (size - len(b)) + b
    return [(x[0] + y[0], x[1] + y[1]) if factor > 0 else (x[0] - y[1], x[1] - y[0])
            for x, y in zip(a, b, strict=True)]


def characteristic(plant: tuple[np.ndarray, np.ndarray], ctrl: tuple[np.ndarray, np.ndarray],
                   feedback: int) -> np.ndarray:
    """chi = D_P D_C - feedback * N_P N_C, highest power first, leading zeros trimmed.

    The nearest floats to the exact coefficients of :func:`characteristic_exact`
    (for display and ``control`` objects; decisions use the exact polynomial).

    Parameters
    ----------
    plant, ctrl : tuple of numpy.ndarray
        ``(N, D)`` of the plant and of the controller, highest power of s first.
    feedback : int
        -1 for negative feedback u = C(r - y), +1 for positive.

    Returns
    -------
    numpy.ndarray
        Float coefficients, highest power first.
    """
    return np.array([float(c) for c in characteristic_exact(plant, ctrl, feedback)])


@dataclass(frozen=True, kw_only=True, repr=False)
class ClosedLoop(Result):
    """The linear closed loop of a plant and controller (angular frequency in rad/s).

    ``to_dict`` adds the monic characteristic polynomial and gives every pole as a
    complex number; it leaves out ``plant_poly`` and ``controller_poly`` (the
    characteristic polynomial combines them), ``sensitivity_num`` (working data of the
    sensitivity peak, which is in the dict) and ``characteristic_exact`` (exact rationals
    of ``characteristic``, which is in the dict).

    Attributes
    ----------
    plant, controller : control.TransferFunction
        H1 of the plant and the controller's linear part (properties: python-control
        is imported on first use, not by the verdict).
    reference_to_output, sensitivity : control.TransferFunction
        y/r = P C / (1 - f P C) and g1 = 1 / (1 - f P C) (properties, likewise).
    plant_poly, controller_poly : tuple of numpy.ndarray
        (numerator, denominator) of P and C, highest power first.
    sensitivity_num : numpy.ndarray
        Numerator D_P D_C of g1 (its denominator is ``characteristic``).
    characteristic : numpy.ndarray
        chi(s), highest power first.
    poles : numpy.ndarray
        Roots of chi (midpoints of rigorous enclosures, for display).
    stable : bool
        All poles in the open left half plane (exact test on the exact chi).
    sensitivity_peak : float
        sup |g1(j w)| (Theorem 2's rho_1 in the section-5 reading; midpoint of a
        proven enclosure); inf if chi has imaginary-axis roots.
    sensitivity_peak_omega : float
        Where it is attained (rad/s; inf for the limit w -> inf).
    controller_norm : float
        lambda_1 = sup |C(j w)|, inf for an improper controller.
    controller_proper, plant_stable : bool
        Plant stability decided exactly, like the loop's.
    feedback : int
    notes : tuple of str
    outside : bool
        Some closed-loop pole strictly in Re s > 0 (exact test): the loop is unstable.
    sensitivity_peak_upper, controller_norm_upper : float
        Proven upper ends of the enclosures of rho_1 and lambda_1.
    characteristic_exact : tuple of Fraction
        chi in exact rationals (highest power first) of the coefficients' doubles;
        ``stable``, ``outside`` and ``plant_stable`` are decided on the coefficients as
        written (``0.2`` is 1/5; :attr:`gfrf.model.equation.Term.exact`).
    proof : str
        Level of the sups rho_1 and lambda_1 (:func:`gfrf.bounds.rational.rational_sup`);
        stability is decided exactly at every level.
    """

    plant_poly: tuple[np.ndarray, np.ndarray]
    controller_poly: tuple[np.ndarray, np.ndarray]
    sensitivity_num: np.ndarray
    characteristic: np.ndarray
    poles: np.ndarray
    stable: bool
    sensitivity_peak: float
    sensitivity_peak_omega: float
    controller_norm: float
    controller_proper: bool
    plant_stable: bool
    feedback: int
    notes: tuple[str, ...] = field(default=())
    outside: bool = False
    sensitivity_peak_upper: float = math.nan
    controller_norm_upper: float = math.nan
    characteristic_exact: tuple[Fraction, ...] = field(default=())
    proof: str = "interval"

    _exclude = ("plant_poly", "controller_poly", "sensitivity_num", "characteristic_exact")
    _order = ("characteristic", "characteristic_monic")

    @property
    def plant(self) -> control.TransferFunction:
        """H1 of the plant."""
        return _tf(*self.plant_poly)

    @property
    def controller(self) -> control.TransferFunction:
        """The controller's linear part."""
        return _tf(*self.controller_poly)

    @property
    def reference_to_output(self) -> control.TransferFunction:
        """y/r = P C / (1 - f P C) (the loop u = C(r + f y))."""
        return _tf(np.polymul(self.plant_poly[0], self.controller_poly[0]), self.characteristic)

    @property
    def sensitivity(self) -> control.TransferFunction:
        """g1 = 1 / (1 - f P C)."""
        return _tf(self.sensitivity_num, self.characteristic)

    def __repr__(self) -> str:
        return short_repr(self, "stable", "feedback", "sensitivity_peak",
                          poles=[complex(p) for p in self.poles])

    def _repr_markdown_(self) -> str:
        rows = [("stable", self.stable), ("feedback", self.feedback),
                ("sensitivity peak", self.sensitivity_peak),
                ("controller norm", self.controller_norm),
                ("poles", ", ".join(f"{complex(p):.6g}" for p in self.poles))]
        return "**Closed loop (linear part)**\n\n" + markdown_table(("quantity", "value"), rows)

    def _computed(self) -> dict[str, Any]:
        """The monic characteristic polynomial; the poles as complex numbers."""
        monic = self.characteristic / self.characteristic[0]
        return {"characteristic_monic": monic.tolist(),
                "poles": [complex(p) for p in self.poles]}


def closed_loop(model_file: ModelFile, feedback: int | None = None,
                proof: str = "interval") -> ClosedLoop:
    """Build the linear closed loop of a model file's plant and controller.

    Parameters
    ----------
    model_file : ModelFile
        Must have a controller.
    feedback : int, optional
        Override the file's feedback sign (-1 negative, +1 positive).
    proof : {"interval", "float", "none"}
        Level of the sups rho_1 and lambda_1 (default: proven enclosures).

    Returns
    -------
    ClosedLoop

    Raises
    ------
    ArgumentError
        No controller, a discrete-time model, or a feedback sign other than +-1.
    """
    if model_file.controller is None:
        raise ArgumentError(f"{model_file.name or 'model'} has no [controller] table")
    _continuous(model_file.plant, "the plant")
    sign = model_file.controller.feedback if feedback is None else feedback
    if sign not in (-1, 1):
        raise ArgumentError(f"feedback must be -1 or +1, got {sign!r}")
    plant_poly = linear_polynomials(model_file.plant)
    ctrl_poly = controller_polynomials(model_file.controller)
    chi_exact = characteristic_exact(plant_poly, ctrl_poly, sign)
    if chi_exact == [0]:
        raise ArgumentError("the closed-loop characteristic polynomial D_P D_C - f N_P N_C is "
                            "identically zero")
    chi = np.array([float(c) for c in chi_exact])
    report = poles(_written_characteristic(model_file, sign) or chi_exact)
    sens_num = _polymul(fractions(plant_poly[1]), fractions(ctrl_poly[1]))
    if proof == "interval":  # proven for the loop as written
        peak, lam = _written_sups(model_file, sign)
    else:
        peak, lam = rational_sup(sens_num, chi_exact, proof), rational_sup(*ctrl_poly,
                                                                           proof=proof)
    notes = []
    if lam.reason:
        notes.append(f"controller norm lambda_1 "
                     f"{'= inf' if lam.lower == math.inf else 'not enclosed'}: {lam.reason}")
    if not report.stable:
        where = ("poles with Re s > 0: " + format_roots([p for p in report.roots
                                                          if p.real > 0])
                 if report.outside else "poles on the imaginary axis at "
                 + format_roots(report.boundary))
        notes.append("linear closed loop not asymptotically stable (exact test on chi): "
                     + where + ("" if np.isfinite(peak.value) else
                                "; a pole on the imaginary axis makes the sensitivity peak "
                                "infinite"))
    return ClosedLoop(plant_poly=plant_poly,
                      controller_poly=ctrl_poly,
                      sensitivity_num=np.array([float(c) for c in sens_num]),
                      characteristic=chi,
                      poles=report.roots,
                      stable=report.stable,
                      sensitivity_peak=peak.value,
                      sensitivity_peak_omega=peak.omega,
                      controller_norm=lam.value,
                      controller_proper=_degree(ctrl_poly[0]) <= _degree(ctrl_poly[1]),
                      plant_stable=poles(_written_den(model_file.plant)
                                         or plant_poly[1]).stable,
                      feedback=sign,
                      notes=tuple(notes),
                      outside=report.outside,
                      sensitivity_peak_upper=peak.upper,
                      controller_norm_upper=lam.upper,
                      characteristic_exact=tuple(chi_exact),
                      proof=proof)


def _tf(num: np.ndarray, den: np.ndarray) -> control.TransferFunction:
    """control.tf(num, den), importing python-control on first use."""
    import control

    return control.tf(num, den)


def with_lags(model_file: ModelFile, time_constants: tuple[float, ...]) -> ModelFile:
    """The model file with its transfer-function controller divided by prod (T_i s + 1).

    Restores the first-order lags of the paper's eq (15), ``(a s^2 + b s + c) /
    ((T1 s + 1)(T2 s + 1)(T3 s + 1))``, which the paper neglects; T_i in seconds.

    Parameters
    ----------
    model_file : ModelFile
        A model file with a transfer-function controller.
    time_constants : tuple of float
        The lags' time constants T_i in s, each finite and >= 0.

    Returns
    -------
    ModelFile
        A new model file; the input one is unchanged.

    Raises
    ------
    ArgumentError
        No transfer-function controller, or a negative or non-finite time constant.
    """
    controller = model_file.controller
    if controller is None or not controller.is_linear:
        raise ArgumentError("lags can only be added to a transfer-function controller")
    den = np.asarray(controller.den, dtype=float)
    for t in time_constants:
        if not (np.isfinite(t) and t >= 0):
            raise ArgumentError(f"time constants must be finite and >= 0 s, got {t!r}")
        den = np.polymul(den, [t, 1.0])
    return replace(model_file, controller=replace(controller, den=tuple(den.tolist())))
