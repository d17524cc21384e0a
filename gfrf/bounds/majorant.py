"""Certified majorants of the GFRF norms and the radius of convergence of their series.

The recursion H_n = -P_n / A(s_1 + ... + s_n) (see :mod:`gfrf.kernels.recursion`) is bounded
term by term.  For every derivative power ell that multiplies an output factor keep

    M_{n,ell} >= sup over omega in R^n of |(s_1 + ... + s_n)^ell H_n|,   s_i = j*omega_i.

Then M_{1,ell} = v_l = sup|(j w)^ell H1(j w)| and for n >= 2

    M_{n,ell} = K_l * sum_terms |c| * U * sum_{n - q = n_1 + ... + n_p} prod_i M_{n_i, l_i},

with K_l = sup|(j w)^ell / A(j w)|, U = prod_j sup|(j w)^{k_j}| over the term's input
factors (1 when every k_j = 0, infinite otherwise) and the inner sum over ordered
compositions.  The symmetric kernel's sum over ordered set partitions with weights
prod|B_i|!/n! has total weight one per composition, so M_{n,0} bounds the symmetric
and the asymmetric H_n alike.  Every sup is the upper end of a proven enclosure
from :func:`gfrf.bounds.rational.rational_sup` (exact rational algebra and ball arithmetic),
so M_{n,0} is a certified upper bound on ||H_n|| (the products and sums of the
recursion are then done in floating point, ~1e-15 relative).  For a discrete (NARX)
model |q| = 1, so U = 1 and K_l = sup|1/A| on the unit circle, proven the same way.
The model is normalised first (:func:`gfrf.model.scaling.normalized`), so the majorant and
r* do not change when the equation is multiplied by a constant.

Generating function.  With X_l(r) = sum_n M_{n,ell} r^n the recursion is the polynomial
fixed-point system

    X_l = r v_l + K_l * sum_terms |c| U r^q prod_i X_{l_i}            (*)

with nonnegative coefficients.  The norm series sum_n ||H_n|| r^n is dominated by
X_0(r), which converges exactly when (*) has a nonnegative solution (the monotone
iteration from 0 is then bounded).  The radius r* is the branch point where the
Jacobian of (*) reaches spectral radius 1 (for a pure cubic, X = beta1 r + g X^3
gives r* = 2 / (3 beta1 sqrt(3 g))).  :func:`radius` brackets it with the certificate
``rhs(X', r) <= X'`` for the solution X' at a slightly larger r, which proves
convergence at r: certified at the reported lower end, not found at the upper end.
The bracket is placed by Newton on the branch point itself (X = rhs(X, r) together
with (I - d rhs/dX) v = 0, v >= 0), started from a certified solution at a smaller r;
bisection on r with Newton continuation is the fallback.

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> maj = majorant(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"))
>>> float(round(maj.coefficients(3)[3, 0] / (0.5 * maj.linear[0] ** 3 * maj.gains[0]), 12))
1.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np

from gfrf._results import Result
from gfrf.bounds.exact import arb_upper
from gfrf.bounds.fixed_point import Radius, certify, radius
from gfrf.bounds.radius_scaling import scaled_plant_radius
from gfrf.bounds.rational import (
    SupResult,
    check_proof,
    discrete_rational_sup,
    enclosed_sup,
    rational_sup,
)
from gfrf.model.equation import Model
from gfrf.model.scaling import normalized

__all__ = ["Majorant", "MajorantTerm", "Radius", "majorant", "radius", "plant_radius",
           "linear_polynomials", "written_polynomials", "written_intervals", "linear_sup",
           "certify"]


@dataclass(frozen=True, kw_only=True, repr=False)
class MajorantTerm(Result):
    """One nonlinear model term as the majorant sees it: |c| U r^q prod X_{l_i}
    (``to_dict`` names ``text`` ``term`` and puts it first)."""

    _keys = {"text": "term"}
    _order = ("term",)

    weight: float
    q: int
    y_orders: tuple[int, ...]
    text: str


@dataclass(frozen=True, kw_only=True, repr=False)
class Majorant(Result):
    """The certified majorant data of a model.

    Attributes
    ----------
    powers : tuple of int
        Derivative powers ell tracked (0 first).
    linear : dict
        v_l = sup |(j w)^ell H1(j w)|.
    gains : dict
        K_l = sup |(j w)^ell / A(j w)|.
    terms : tuple of MajorantTerm
        Nonlinear terms (weight = |c| U, possibly infinite).
    exact : bool
        Every sup is a proven enclosure (:attr:`gfrf.bounds.rational.SupResult.exact`).
    reasons : tuple of str
        Why some entry is infinite.
    proof : str
        Level of the sups: ``"interval"`` (proven upper ends), ``"float"`` (double
        precision stationary points) or ``"none"`` (estimates).
    """

    powers: tuple[int, ...]
    linear: dict[int, float]
    gains: dict[int, float]
    terms: tuple[MajorantTerm, ...]
    exact: bool = True
    reasons: tuple[str, ...] = field(default=())
    proof: str = "interval"

    @property
    def certified(self) -> bool:
        """Whether the sups come from a sound method (``proof`` interval or float)."""
        return self.proof == "interval" and self.exact or self.proof == "float"

    @property
    def finite(self) -> bool:
        """Whether every quantity the recursion uses is finite."""
        values = [*self.linear.values(), *self.gains.values(), *(t.weight for t in self.terms)]
        return all(math.isfinite(v) for v in values)

    def rhs(self, x: np.ndarray, r: float, amplitude: float | None = None) -> np.ndarray:
        """Right-hand side of (*): r v_l + K_l G(x, a) with a = amplitude or r.

        Parameters
        ----------
        x : numpy.ndarray
            One value x_l >= 0 per entry of :attr:`powers`.
        r : float
            The amplitude in the linear part.
        amplitude : float, optional
            The amplitude a in G; None: r.

        Returns
        -------
        numpy.ndarray
            One value per entry of :attr:`powers` (float arithmetic).
        """
        a = r if amplitude is None else amplitude
        g = _nonlinear_sum(self, x, a)
        return np.array([r * self.linear[ell] + _mul(self.gains[ell], g)
                         for ell in self.powers])

    def nonlinear(self, x: np.ndarray, amplitude: float) -> float:
        """G(x, a) = sum_terms |c| U a^q prod x_{l_i} (the part of order >= 2).

        Parameters
        ----------
        x : numpy.ndarray
            One value x_l >= 0 per entry of :attr:`powers`.
        amplitude : float
            The amplitude a.

        Returns
        -------
        float
            G(x, a) (float arithmetic).
        """
        return _nonlinear_sum(self, x, amplitude)

    def coefficients(self, n_max: int) -> np.ndarray:
        """Array M[n, i] = M_{n, powers[i]} for n = 0..n_max (row 0 is zero).

        Parameters
        ----------
        n_max : int
            Highest order, >= 0.

        Returns
        -------
        numpy.ndarray of float, shape (n_max + 1, len(powers))
        """
        idx = {ell: i for i, ell in enumerate(self.powers)}
        m = np.zeros((n_max + 1, len(self.powers)))
        if n_max >= 1:
            m[1] = [self.linear[ell] for ell in self.powers]
        for n in range(2, n_max + 1):
            total = 0.0
            for t in self.terms:
                rest = n - t.q
                if rest < len(t.y_orders) or (not t.y_orders and rest != 0):
                    continue
                series = [m[:, idx[ell]] for ell in t.y_orders]
                total += _mul(t.weight, _product_coefficient(series, rest))
            m[n] = [_mul(self.gains[ell], total) for ell in self.powers]
        return m

    def proven_upper(self, n: int) -> float:
        """Upper bound on M_{n,0} with every product and sum rounded outward (Arb balls).

        The inputs (sups, |c|) are the proven upper ends of :func:`majorant`; the result
        is then a proven upper bound on ||H_n|| (``inf`` when some input is infinite).

        Parameters
        ----------
        n : int
            Kernel order >= 1.

        Returns
        -------
        float
        """
        if not self.finite:
            return float(self.coefficients(n)[n, 0])
        from flint import arb

        idx = {ell: i for i, ell in enumerate(self.powers)}
        zero = arb(0)
        m = [[zero] * len(self.powers) for _ in range(n + 1)]
        m[1] = [arb(self.linear[ell]) for ell in self.powers]
        for order in range(2, n + 1):
            total = zero
            for t in self.terms:
                rest = order - t.q
                if t.weight == 0.0 or rest < len(t.y_orders) or (not t.y_orders and rest != 0):
                    continue
                acc = [arb(1)] + [zero] * rest  # product of the series, truncated
                for ell in t.y_orders:
                    col = [m[k][idx[ell]] for k in range(rest + 1)]
                    acc = [sum((acc[i] * col[k - i] for i in range(k + 1)), zero)
                           for k in range(rest + 1)]
                total += arb(t.weight) * acc[rest]
            m[order] = [arb(self.gains[ell]) * total for ell in self.powers]
        return arb_upper(m[n][0])

    def proves(self, x: np.ndarray, r: float) -> bool:
        """Whether rhs(x, r) <= x holds in ball arithmetic (outward rounding).

        For x >= 0 this proves that the monotone iteration from 0 stays below x, so
        the majorant series (hence the norm series) converges at amplitude r.

        Parameters
        ----------
        x : numpy.ndarray
            The candidate supersolution, one value per entry of :attr:`powers`.
        r : float
            The amplitude.

        Returns
        -------
        bool
            True when the check passes (False for a negative, non-finite or estimated input).
        """
        if not (self.finite and np.all(np.isfinite(x)) and np.all(x >= 0)):
            return False
        from flint import arb

        xs = [arb(float(v)) for v in x]
        new = self.rhs_ball(xs, arb(r), arb(r))
        return all(v <= xs[i] for i, v in enumerate(new))

    def nonlinear_ball(self, xs: list[Any], amplitude: Any) -> Any:
        """G(x, a) of :meth:`nonlinear` in Arb ball arithmetic (x, a: arb balls).

        Parameters
        ----------
        xs : list of flint.arb
            One ball per entry of :attr:`powers`.
        amplitude : flint.arb
            The amplitude a.

        Returns
        -------
        flint.arb
            A ball containing G(x, a).
        """
        from flint import arb

        idx = {ell: i for i, ell in enumerate(self.powers)}
        g = arb(0)
        for t in self.terms:
            if t.weight == 0.0:
                continue
            value = arb(t.weight) * amplitude ** t.q
            for ell in t.y_orders:
                value *= xs[idx[ell]]
            g += value
        return g

    def rhs_ball(self, xs: list[Any], r: Any, amplitude: Any) -> list[Any]:
        """:meth:`rhs` in Arb ball arithmetic: r v_l + K_l G(x, amplitude) as arb balls.

        Parameters
        ----------
        xs : list of flint.arb
            One ball per entry of :attr:`powers`.
        r : flint.arb
            The amplitude in the linear part.
        amplitude : flint.arb
            The amplitude a in G.

        Returns
        -------
        list of flint.arb
            One ball per entry of :attr:`powers`.
        """
        from flint import arb

        g = self.nonlinear_ball(xs, amplitude)
        return [r * arb(self.linear[ell]) + arb(self.gains[ell]) * g for ell in self.powers]


def _mul(a: float, b: float) -> float:
    """Product with 0 * inf = 0 (a structurally absent contribution stays absent)."""
    return 0.0 if a == 0.0 or b == 0.0 else a * b


def _nonlinear_sum(maj: Majorant, x: np.ndarray, a: float) -> float:
    idx = {ell: i for i, ell in enumerate(maj.powers)}
    total = 0.0
    for t in maj.terms:
        value = t.weight * a ** t.q
        for ell in t.y_orders:
            value = _mul(value, float(x[idx[ell]]))
        total += value
    return total


def _product_coefficient(series: list[np.ndarray], n: int) -> float:
    """Coefficient of r^n in the product of the given power series."""
    acc = np.zeros(n + 1)
    acc[0] = 1.0
    for s in series:
        new = np.zeros(n + 1)
        for k in range(n + 1):
            if acc[k] == 0.0:
                continue
            tail = s[: n + 1 - k]
            with np.errstate(invalid="ignore", over="ignore"):  # inf: no bound
                finite = np.where(tail == 0.0, 0.0, acc[k] * tail)
            new[k:k + tail.size] += finite
        acc = new
    return float(acc[n])


def linear_polynomials(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """(num, den) of H1 = -B/A, highest power first for a continuous model.

    For a discrete model the arrays are lowest power of q first.  Both are taken from
    the normalised model (:func:`gfrf.model.scaling.normalized`): H1 is unchanged, A's
    leading coefficient lies in [1, 2).

    Parameters
    ----------
    model : Model
        The plant model.

    Returns
    -------
    tuple of numpy.ndarray
        ``(num, den)``.
    """
    model = normalized(model)
    a, b = model.linear_output, model.linear_input
    den = np.array([a.get(k, 0.0) for k in range(max(a) + 1)])
    num = np.array([-b.get(k, 0.0) for k in range(max(b, default=0) + 1)])
    if model.is_discrete:
        return num, den
    return num[::-1], den[::-1]


def written_intervals(model: Model, *, normalize: bool = True
                      ) -> tuple[list[tuple[Fraction, Fraction]], list[tuple[Fraction, Fraction]]]:
    """(num, den) of H1 = -B/A of the normalised model as rational intervals containing
    the coefficients as written (:meth:`gfrf.model.equation.Term.bounds`), in the order
    of :func:`linear_polynomials`.

    Parameters
    ----------
    model : Model
        The plant model.
    normalize : bool
        Take the normalised model (:func:`gfrf.model.scaling.normalized`, the same H1);
        False: the coefficients exactly as the model has them.

    Returns
    -------
    tuple of list of tuple of Fraction
        ``(num, den)``, each coefficient as ``(lo, hi)`` (equal for a rational one).
    """
    if normalize:
        model = normalized(model)
    a: dict[int, tuple[Fraction, Fraction]] = {}
    b: dict[int, tuple[Fraction, Fraction]] = {}
    for t in model.terms:
        if t.is_linear_output:
            part, k, sign = a, t.y_orders[0], 1
        elif not t.y_orders and len(t.u_orders) == 1:
            part, k, sign = b, t.u_orders[0], -1
        else:
            continue
        lo, hi = t.bounds()
        lo, hi = (lo, hi) if sign > 0 else (-hi, -lo)
        old = part.get(k, (Fraction(0), Fraction(0)))
        part[k] = (old[0] + lo, old[1] + hi)
    zero = (Fraction(0), Fraction(0))
    den = [a.get(k, zero) for k in range(max(a, default=0) + 1)]
    num = [b.get(k, zero) for k in range(max(b, default=0) + 1)]
    if model.is_discrete:
        return num, den
    return num[::-1], den[::-1]


def written_polynomials(model: Model, *, normalize: bool = True
                        ) -> tuple[list[Fraction], list[Fraction]] | None:
    """(num, den) of H1 = -B/A of the normalised model with the coefficients as written
    (``0.2`` is 1/5), in the order of :func:`linear_polynomials`.

    Parameters
    ----------
    model : Model
        The plant model.
    normalize : bool
        Take the normalised model (the same H1); False: the coefficients exactly as the
        model has them.

    Returns
    -------
    tuple of list of Fraction, or None
        None when a linear coefficient as written is irrational.
    """
    num, den = written_intervals(model, normalize=normalize)
    if any(lo != hi for lo, hi in (*num, *den)):
        return None
    return [lo for lo, _ in num], [lo for lo, _ in den]


def linear_sup(model: Model, proof: str = "interval", ell: int = 0,
               inverse: bool = False) -> SupResult:
    """sup |s^ell H1| (or sup |s^ell / A| with ``inverse``) over the axis or the circle.

    At ``proof = "interval"`` it is proven for the model as written (decimals as exact
    rationals, an irrational coefficient as an interval: :func:`enclosed_sup`); the
    float and estimate levels use the doubles.

    Parameters
    ----------
    model : Model
        The plant model.
    proof : {"interval", "float", "none"}
        Level of proof (:func:`gfrf.bounds.rational.rational_sup`).
    ell : int, optional
        The power of s (of q for a NARX model) multiplying the numerator.
    inverse : bool, optional
        1/A instead of H1 = -B/A.

    Returns
    -------
    SupResult
    """
    discrete = model.is_discrete
    if check_proof(proof) == "interval":
        num_w, den_w = written_intervals(model)
        one = (Fraction(1), Fraction(1))
        top = _shift([one] if inverse else num_w, ell, discrete, (Fraction(0), Fraction(0)))
        return enclosed_sup(top, den_w, model.sample_time if discrete else None)
    num, den = linear_polynomials(model)
    shifted = _shift([1.0] if inverse else list(num), ell, discrete, 0.0)
    if discrete:
        return discrete_rational_sup(np.array(shifted), den, model.sample_time,  # type: ignore[arg-type]
                                     proof)
    return rational_sup(np.array(shifted), den, proof)


def _shift(coefficients: list[Any], ell: int, discrete: bool, zero: Any) -> list[Any]:
    """Multiply by s^ell (continuous, highest first) or q^ell (discrete, lowest first)."""
    if discrete:
        return [zero] * ell + coefficients
    return coefficients + [zero] * ell


def _weight_upper(term: Any) -> float:
    """The smallest float >= |c| for every value c of the term's coefficient as written."""
    lo, hi = term.bounds()
    top = max(abs(lo), abs(hi))
    value = float(top)
    return math.nextafter(value, math.inf) if Fraction(value) < top else value


def majorant(model: Model, proof: str = "interval") -> Majorant:
    """Build the majorant data of ``model``.

    Parameters
    ----------
    model : Model
    proof : {"interval", "float", "none"}
        How the sups are computed (:func:`gfrf.bounds.rational.rational_sup`): proven upper
        ends of ball enclosures (default), or double-precision values.

    Returns
    -------
    Majorant
    """
    check_proof(proof)
    model = normalized(model)
    discrete = model.is_discrete
    nonlinear = model.nonlinear_terms
    powers = tuple(sorted({0, *(ell for t in nonlinear for ell in t.y_orders)}))
    reasons: list[str] = []
    linear, gains = {}, {}
    exact = True
    for ell in powers:
        h1 = linear_sup(model, proof, ell)
        inv_a = linear_sup(model, proof, ell, inverse=True)
        linear[ell], gains[ell] = h1.upper, inv_a.upper
        exact = exact and h1.exact and inv_a.exact
        for name, res in ((f"sup|s^{ell} H1|", h1), (f"sup|s^{ell}/A|", inv_a)):
            if res.reason:
                what = "infinite" if res.lower == math.inf else "has no finite upper bound"
                reasons.append(f"{name} {what}: {res.reason}")
    terms = []
    for t in nonlinear:
        unbounded = not discrete and any(k > 0 for k in t.u_orders)
        if unbounded:
            reasons.append(f"term {t}: an input derivative factor has sup |j w|^k = inf")
        weight = _weight_upper(t) if proof == "interval" else abs(t.coefficient)
        terms.append(MajorantTerm(weight=math.inf if unbounded else weight,
                                  q=len(t.u_orders), y_orders=t.y_orders, text=str(t)))
    return Majorant(powers=powers,
                    linear=linear,
                    gains=gains,
                    terms=tuple(terms),
                    exact=exact,
                    reasons=tuple(reasons),
                    proof=proof)


def plant_radius(maj: Majorant) -> Radius:
    """r* of the plant majorant (the radius of the norm series, used by the verdict and by
    the Volterra prediction), computed on an O(1) rescaled system and scaled back exactly
    (:func:`gfrf.bounds.radius_scaling.scaled_plant_radius`); ``proof = "interval"`` when
    the sups are proven and the supersolution passes the ball-arithmetic check
    rhs(x, r) <= x, ``"none"`` for an estimated majorant.

    Parameters
    ----------
    maj : Majorant
        The plant's majorant (:func:`majorant`).

    Returns
    -------
    Radius
        r*, the amplitude at which convergence is certified, and the proof level.
    """
    return scaled_plant_radius(maj)
