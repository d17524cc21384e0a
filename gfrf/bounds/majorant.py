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

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gfrf.bounds.exact import arb_upper
from gfrf.bounds.rational import SupResult, check_proof, discrete_rational_sup, rational_sup
from gfrf.model.equation import Model
from gfrf.model.scaling import normalized

__all__ = ["Majorant", "MajorantTerm", "Radius", "majorant", "radius", "plant_radius",
           "linear_polynomials"]


@dataclass(frozen=True)
class MajorantTerm:
    """One nonlinear model term as the majorant sees it: |c| U r^q prod X_{l_i}."""

    weight: float
    q: int
    y_orders: tuple[int, ...]
    text: str


@dataclass(frozen=True)
class Majorant:
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
        """Right-hand side of (*): r v_l + K_l G(x, a) with a = amplitude or r."""
        a = r if amplitude is None else amplitude
        g = _nonlinear_sum(self, x, a)
        return np.array([r * self.linear[ell] + _mul(self.gains[ell], g)
                         for ell in self.powers])

    def nonlinear(self, x: np.ndarray, amplitude: float) -> float:
        """G(x, a) = sum_terms |c| U a^q prod x_{l_i} (the part of order >= 2)."""
        return _nonlinear_sum(self, x, amplitude)

    def coefficients(self, n_max: int) -> np.ndarray:
        """Array M[n, i] = M_{n, powers[i]} for n = 0..n_max (row 0 is zero).

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
        """
        if not (self.finite and np.all(np.isfinite(x)) and np.all(x >= 0)):
            return False
        from flint import arb

        xs = [arb(float(v)) for v in x]
        new = self.rhs_ball(xs, arb(r), arb(r))
        return all(v <= xs[i] for i, v in enumerate(new))

    def nonlinear_ball(self, xs: list[Any], amplitude: Any) -> Any:
        """G(x, a) of :meth:`nonlinear` in Arb ball arithmetic (x, a: arb balls)."""
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
        """:meth:`rhs` in Arb ball arithmetic: r v_l + K_l G(x, amplitude) as arb balls."""
        from flint import arb

        g = self.nonlinear_ball(xs, amplitude)
        return [r * arb(self.linear[ell]) + arb(self.gains[ell]) * g for ell in self.powers]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description."""
        return {"powers": list(self.powers), "linear": {str(k): v for k, v in self.linear.items()},
                "gains": {str(k): v for k, v in self.gains.items()},
                "terms": [{"term": t.text, "weight": t.weight, "q": t.q,
                           "y_orders": list(t.y_orders)} for t in self.terms],
                "exact": self.exact, "reasons": list(self.reasons), "proof": self.proof}


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
    """
    model = normalized(model)
    a, b = model.linear_output, model.linear_input
    den = np.array([a.get(k, 0.0) for k in range(max(a) + 1)])
    num = np.array([-b.get(k, 0.0) for k in range(max(b, default=0) + 1)])
    if model.is_discrete:
        return num, den
    return num[::-1], den[::-1]


def _sup(model: Model, num: np.ndarray, den: np.ndarray, proof: str) -> SupResult:
    if model.is_discrete:
        return discrete_rational_sup(num, den, model.sample_time, proof)  # type: ignore[arg-type]
    return rational_sup(num, den, proof)


def _shift(coefficients: np.ndarray, ell: int, discrete: bool) -> np.ndarray:
    """Multiply by s^ell (continuous, highest first) or q^ell (discrete, lowest first)."""
    if discrete:
        return np.concatenate([np.zeros(ell), coefficients])
    return np.concatenate([coefficients, np.zeros(ell)])


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
    num, den = linear_polynomials(model)
    discrete = model.is_discrete
    nonlinear = model.nonlinear_terms
    powers = tuple(sorted({0, *(ell for t in nonlinear for ell in t.y_orders)}))
    reasons: list[str] = []
    linear, gains = {}, {}
    exact = True
    for ell in powers:
        h1 = _sup(model, _shift(num, ell, discrete), den, proof)
        inv_a = _sup(model, _shift(np.ones(1), ell, discrete), den, proof)
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
        terms.append(MajorantTerm(math.inf if unbounded else abs(t.coefficient),
                                  len(t.u_orders), t.y_orders, str(t)))
    return Majorant(powers, linear, gains, tuple(terms), exact, tuple(reasons), proof)


@dataclass(frozen=True)
class Radius:
    """Radius of convergence r* of a positive fixed-point system.

    Attributes
    ----------
    value : float
        r* (``inf`` when the system is linear in x, 0 when some entry is infinite).
    certified_below : float
        An amplitude at which convergence is certified (a supersolution exists);
        within ``rel_tol`` of :func:`radius` (default 1e-10) relative of ``value``.
    solution : numpy.ndarray or None
        The fixed point at ``certified_below``.
    proof : str
        ``"interval"`` when convergence at ``certified_below`` was re-checked in ball
        arithmetic (:meth:`Majorant.proves`), else ``"float"``.
    """

    value: float
    certified_below: float
    solution: np.ndarray | None = None
    proof: str = "float"


_MARGIN = 1e-9
"""Relative step of :func:`certify`: it solves the system at r (1 + _MARGIN)."""


def certify(step: Callable[[np.ndarray, float], np.ndarray], dim: int, r: float,
            start: np.ndarray | None = None) -> np.ndarray | None:
    """A nonnegative supersolution of ``x = step(x, r)``, or None if none was found.

    Newton's method from ``start`` (or 0) solves x = step(x, r') at r' = r (1 + 1e-9).
    A nonnegative solution x' satisfies step(x', r) <= step(x', r') = x' (monotone in
    r), so the monotone iteration from 0 at amplitude r stays below x' and converges:
    that is the certificate, checked componentwise up to 1e-12 relative rounding.
    """
    r_up = r * (1 + _MARGIN)
    x = np.zeros(dim) if start is None else start.copy()
    for _ in range(100):
        f = step(x, r_up) - x
        if not np.all(np.isfinite(f)):
            return None
        jac = np.empty((dim, dim))
        # finite-difference step relative to the solution's own scale (it may be ~1e-5)
        scale = max(float(np.max(np.abs(x))), float(np.max(np.abs(f))), 1e-300)
        for i in range(dim):
            h = 1e-7 * max(abs(x[i]), scale)
            e = x.copy()
            e[i] += h
            jac[:, i] = (step(e, r_up) - e - f) / h
        try:
            dx = np.linalg.solve(jac, -f)
        except np.linalg.LinAlgError:
            return None
        x = x + dx
        if np.any(x < -1e-12 * (1 + np.max(np.abs(x)))) or not np.all(np.isfinite(x)):
            return None
        if np.max(np.abs(dx)) <= 1e-15 * (1 + np.max(np.abs(x))):
            break
    x = np.maximum(x, 0.0)
    residual = np.abs(step(x, r_up) - x)
    if np.all(residual <= 1e-12 * (x + 1e-300)) and np.all(step(x, r) <= x * (1 + 1e-12)):
        return x
    return None


def _fold_residual(step: Callable[[np.ndarray, float], np.ndarray], dim: int,
                   z: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Residual of the fold system in z = (x, v, r).

    x - step(x, r) = 0, (I - J) v = 0 with J = d step / dx (J v by a central difference)
    and c . v = 1.
    """
    x, v, r = z[:dim], z[dim:2 * dim], float(z[-1])
    h = 1e-5 * max(float(np.max(np.abs(x))), 1e-300) / max(float(np.max(np.abs(v))), 1e-300)
    jv = (step(x + h * v, r) - step(x - h * v, r)) / (2 * h)
    return np.concatenate([x - step(x, r), v - jv, [float(c @ v) - 1.0]])


def _fold(step: Callable[[np.ndarray, float], np.ndarray], dim: int, r0: float,
          x0: np.ndarray) -> tuple[float, np.ndarray] | None:
    """Branch point (r*, x*) of ``x = step(x, r)`` by Newton from a solution at r0 < r*.

    Solves x = step(x, r) together with (I - J(x, r)) v = 0, J = d step / dx, v the
    Perron vector (start: the Perron vector of J(x0, r0)).  Returns None when Newton
    does not converge to a nonnegative x with a nonnegative v.
    """
    jac = np.empty((dim, dim))
    f0 = step(x0, r0)
    for i in range(dim):
        h = 1e-7 * (abs(x0[i]) + float(np.max(np.abs(x0))) + 1e-300)
        e = x0.copy()
        e[i] += h
        jac[:, i] = (step(e, r0) - f0) / h
    values, vectors = np.linalg.eig(jac)
    if not np.all(np.isfinite(values)):
        return None
    v = np.abs(np.real(vectors[:, int(np.argmax(np.real(values)))]))
    v /= float(np.linalg.norm(v))
    z = np.concatenate([x0, v, [r0]])
    n = 2 * dim + 1
    for _ in range(50):
        f = _fold_residual(step, dim, z, v)
        if not np.all(np.isfinite(f)):
            return None
        jz = np.empty((n, n))
        scale = (float(np.max(np.abs(z[:dim]))), 1.0, 0.0)
        for i in range(n):
            h = 1e-7 * (abs(z[i]) + scale[min(i // dim, 2)] + 1e-300)
            e = z.copy()
            e[i] += h
            jz[:, i] = (_fold_residual(step, dim, e, v) - f) / h
        try:
            dz = np.linalg.solve(jz, -f)
        except np.linalg.LinAlgError:
            return None
        for _ in range(30):  # halve steps that leave r > 0, x >= 0
            if np.all(np.isfinite(dz)) and z[-1] + dz[-1] > 0 and np.all(z[:dim] + dz[:dim] >= 0):
                break
            dz = 0.5 * dz
        else:
            return None
        z = z + dz
        if abs(dz[-1]) <= 1e-13 * z[-1]:
            x, v_end = z[:dim], z[dim:2 * dim]
            tiny = 1e-9 * float(np.max(np.abs(z[:2 * dim])))
            if np.any(x < -tiny) or np.any(v_end < -tiny):
                return None
            return float(z[-1]), np.maximum(x, 0.0)
    return None


def _fold_bracket(step: Callable[[np.ndarray, float], np.ndarray], dim: int, lo: float,
                  x_lo: np.ndarray, hi: float, rel_tol: float
                  ) -> tuple[float, np.ndarray, float]:
    """The bisection bracket (lo, x_lo, hi) narrowed around the branch point.

    The branch point r_b from :func:`_fold` predicts where :func:`certify` stops
    succeeding, r_b / (1 + 1e-9).  Each end is then decided exactly as the bisection
    decides it: a certificate at 0.8 rel_tol below the prediction (else 10 and 100
    times as far) moves ``lo``, a failure at 0.1 rel_tol above it (else 10, 100, 1000
    times as far) moves ``hi``.  When both first tries succeed the bracket is already
    narrower than ``rel_tol``; otherwise the bisection finishes it.
    """
    fold = _fold(step, dim, lo, x_lo)
    if fold is None:
        return lo, x_lo, hi
    edge = fold[0] / (1 + _MARGIN)
    for k in range(3):
        r = edge * (1 - 0.8 * rel_tol * 10.0 ** k)
        if not lo < r < hi:
            break
        x = certify(step, dim, r, x_lo)
        if x is not None:
            lo, x_lo = r, x
            break
        hi = r
    for k in range(4):
        r = edge * (1 + 0.1 * rel_tol * 10.0 ** k)
        if not lo < r < hi:
            break
        x = certify(step, dim, r, x_lo)
        if x is None:
            hi = r
            break
        lo, x_lo = r, x
    return lo, x_lo, hi


def _entire(step: Callable[[np.ndarray, float], np.ndarray], dim: int) -> bool:
    """Whether the least solution of x = step(x, r) is a polynomial in r (r* = inf).

    Decided exactly from the structure of a polynomial with nonnegative coefficients:
    either nothing forces x (step(0, 1) = 0, so x = 0 for every r), or step does not
    depend on x at all (the same floats at x = 0 and at x = 1e100: an x-dependent
    monomial with a positive coefficient would change them).
    """
    zero = step(np.zeros(dim), 1.0)
    if not np.any(zero):
        return True
    with np.errstate(over="ignore", invalid="ignore"):
        big = step(np.full(dim, 1e100), 1.0)
    return bool(np.array_equal(zero, big))


def radius(step: Callable[[np.ndarray, float], np.ndarray], dim: int,
           rel_tol: float = 1e-10, fold: bool = True) -> Radius:
    """Radius of convergence in r of the positive system ``x = step(x, r)``.

    Parameters
    ----------
    step : callable
        ``step(x, r)``, nonnegative coefficients, monotone in x and r, step(0, 0) = 0.
    dim : int
        Length of x.
    rel_tol : float
        Relative width of the final bracket.
    fold : bool
        Locate the branch point directly (Newton on x = step(x, r) with
        det(I - d step/dx) = 0) and check the bracket around it; bisection is the
        fallback when that fails.  False: bisection only.

    Returns
    -------
    Radius
    """
    probe = step(np.ones(dim), 1.0)
    if not np.all(np.isfinite(probe)):
        return Radius(0.0, 0.0, None)
    if _entire(step, dim):
        return Radius(math.inf, math.inf, None)
    lo, x_lo = 0.0, np.zeros(dim)
    hi = 1.0
    while True:  # no cap: a finite radius is found in any magnitude
        x = certify(step, dim, hi, x_lo)
        if x is None:
            break
        lo, x_lo = hi, x
        hi *= 4.0
        if not math.isfinite(hi):  # certified beyond the float range
            return Radius(math.inf, lo, x_lo)
    while lo == 0.0:
        x = certify(step, dim, hi / 4.0)
        if x is None:
            hi /= 4.0
            if hi < 1e-300:
                return Radius(0.0, 0.0, None)
        else:
            lo, x_lo = hi / 4.0, x
    if fold and hi - lo > rel_tol * hi:
        lo, x_lo, hi = _fold_bracket(step, dim, lo, x_lo, hi, rel_tol)
    while hi - lo > rel_tol * hi:
        mid = 0.5 * (lo + hi)
        x = certify(step, dim, mid, x_lo)
        if x is None:
            hi = mid
        else:
            lo, x_lo = mid, x
    return Radius(hi, lo, x_lo)


def plant_radius(maj: Majorant) -> Radius:
    """r* of the plant majorant (the radius of the norm series, used by the verdict and by
    the Volterra prediction), computed on an O(1) rescaled system and scaled back exactly
    (:func:`gfrf.bounds.radius_scaling.scaled_plant_radius`); ``proof = "interval"`` when
    the sups are proven and the supersolution passes the ball-arithmetic check
    rhs(x, r) <= x, ``"none"`` for an estimated majorant."""
    from gfrf.bounds.radius_scaling import scaled_plant_radius

    return scaled_plant_radius(maj)
