"""Parameter perturbation (eqs (5)-(16)) to any order in ``eps``, exactly.

Expanding ``delta = sum eps**n delta_n`` and the orbit in powers of ``eps`` and removing
secular terms order by order gives the transition curves and their periodic orbits.
The algebra is done on :class:`~gfrf.periodic.fourier.CosSeries` with rational
coefficients that are polynomials in the amplitude parameter ``a``.

Branch ``"0"`` (``delta_0 = 0``, period ``2*pi``): ``tau = t``, ``x = sum eps**n x_n``,
``x_0 = a``; the constant (kernel) harmonic of each order fixes ``delta_n``.

Branch ``"1/4"`` (``delta_0 = 1/4``, period ``4*pi``): ``tau = t/2``, the paper's scaling
``x = eps*u`` with ``u = sum eps**n u_n`` and ``u_0 = a*cos(tau)`` (so the nonlinearity
``x**k`` enters at order ``eps**(k-1)``); the ``cos(tau)`` harmonic fixes ``delta_n``.

Normalisation of the free kernel component of each correction (``n >= 1``):

* ``"initial"`` (API default): ``x_n(0) = 0``, so ``x(0) = a`` (branch 0) and
  ``x(0) = eps*a`` (branch 1/4): the amplitude ``x(0)`` converts exactly to ``a``;
* ``"kernel"``: no kernel harmonic in ``x_n`` -- the rule the paper states for (10) and
  uses in (16); there ``a`` is the mean (branch 0) or the ``cos(t/2)`` amplitude / eps.

Eq (3) (``sin x``): ``truncation`` is the Taylor degree of ``sin``.  On branch ``1/4``
``x**k`` enters at ``eps**(k-1)``, so degree ``order + 1`` gives the exact eq (3) series
to ``eps**order``; on branch ``0`` every power enters at every order (``x_0 = a``) and a
high degree (``SIN_DEGREE`` in :mod:`~gfrf.periodic.compare`) stands for ``sin``.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import sympy as sp

from gfrf._results import Result
from gfrf.errors import ArgumentError
from gfrf.periodic.equation import parse_branch, sin_taylor_coefficients
from gfrf.periodic.fourier import CosSeries, poly_divide, poly_eval

__all__ = ["PerturbationSeries", "perturbation_series"]


@dataclass(frozen=True, kw_only=True, repr=False)
class PerturbationSeries(Result):
    """Transition curve and periodic orbit of one branch as exact series in ``eps``.

    ``to_dict`` gives ``delta_coeffs`` as ``delta_n``, exact polynomials in ``a`` as text,
    and leaves out ``x_coeffs`` (the orbit's cosine series: exact rationals for
    evaluation).

    Attributes
    ----------
    branch : str
        ``"0"`` or ``"1/4"``.
    order : int
        Highest power of ``eps`` kept.
    normalization : str
        ``"initial"`` or ``"kernel"`` (see module docstring).
    truncation : int
        Taylor degree of ``sin`` in the equation (3: eq (4)).
    delta_coeffs : list of ndarray
        ``delta_n(a)`` as ascending Fraction vectors, ``n = 0..order``.
    x_coeffs : list of CosSeries
        ``x_n`` (branch 0) or ``u_n`` (branch 1/4) as functions of ``tau``.
    """

    branch: str
    order: int
    normalization: str
    truncation: int
    delta_coeffs: list[np.ndarray]
    x_coeffs: list[CosSeries]

    _exclude = ("delta_coeffs", "x_coeffs")

    def paper_a(self, eps: float, amplitude: float) -> float:
        """Series parameter ``a`` for the orbit with ``x(0) = amplitude`` ("initial" only).

        Parameters
        ----------
        eps : float
            The dimensionless forcing amplitude.
        amplitude : float
            x(0) of the orbit.

        Returns
        -------
        float
            a.
        """
        if self.normalization != "initial":
            raise ArgumentError("amplitude = x(0) converts to a only with 'initial' normalisation")
        return amplitude if self.branch == "0" else amplitude / eps

    def delta(self, eps: float, amplitude: float, order: int | None = None) -> float:
        """``delta`` on the transition curve for ``x(0) = amplitude``, truncated at ``order``.

        Parameters
        ----------
        eps : float
            The dimensionless forcing amplitude.
        amplitude : float
            x(0) of the orbit.
        order : int, optional
            Highest power of eps kept; None: every computed order.

        Returns
        -------
        float
            delta.
        """
        return self.delta_at(eps, self.paper_a(eps, amplitude), order)

    def amplitude_of(self, eps: float, a: float, order: int | None = None) -> float:
        """``x(0)`` of the orbit with series parameter ``a``: converts the paper's ``a``.

        With ``normalization="kernel"`` this is the paper's convention of (10) and (16):
        branch 0 gives ``x(0) = a + eps a (1 - a**2/6) + ...``, branch 1/4 gives
        ``x(0) = eps a (1 + eps/4 + ...)``.

        Parameters
        ----------
        eps : float
            The dimensionless forcing amplitude.
        a : float
            The series parameter.
        order : int, optional
            Highest power of eps kept; None: every computed order.

        Returns
        -------
        float
            x(0).
        """
        return float(self.evaluate(eps, a, np.array([0.0]), order)[0])

    def delta_at(self, eps: float, a: float, order: int | None = None) -> float:
        """``delta`` at the series parameter ``a`` (any normalisation).

        Parameters
        ----------
        eps : float
            The dimensionless forcing amplitude.
        a : float
            The series parameter.
        order : int, optional
            Highest power of eps kept; None: every computed order.

        Returns
        -------
        float
            delta.
        """
        k = self.order if order is None else order
        return float(sum(poly_eval(d, a) * eps**n for n, d in enumerate(self.delta_coeffs[:k + 1])))

    def solution(self, eps: float, amplitude: float, t: np.ndarray,
                 order: int | None = None) -> np.ndarray:
        """Periodic orbit ``x(t)`` with ``x(0) = amplitude`` (terms up to ``eps**order``).

        Parameters
        ----------
        eps : float
            The dimensionless forcing amplitude.
        amplitude : float
            x(0) of the orbit.
        t : numpy.ndarray
            Dimensionless times.
        order : int, optional
            Highest power of eps kept; None: every computed order.

        Returns
        -------
        numpy.ndarray
            x(t).
        """
        return self.evaluate(eps, self.paper_a(eps, amplitude), t, order)

    def evaluate(self, eps: float, a: float, t: np.ndarray,
                 order: int | None = None) -> np.ndarray:
        """Orbit ``x(t)`` at the series parameter ``a`` (any normalisation).

        Parameters
        ----------
        eps : float
            The dimensionless forcing amplitude.
        a : float
            The series parameter.
        t : numpy.ndarray
            Dimensionless times.
        order : int, optional
            Highest power of eps kept; None: every computed order.

        Returns
        -------
        numpy.ndarray
            x(t).
        """
        k = self.order if order is None else order
        tau = np.asarray(t, dtype=float) / (1 if self.branch == "0" else 2)
        x = sum(s.evaluate(tau, a) * eps**n for n, s in enumerate(self.x_coeffs[:k + 1]))
        return x if self.branch == "0" else eps * x

    def delta_expr(self) -> sp.Expr:
        """``delta`` as a sympy polynomial in ``eps`` and ``a`` (exact rationals)."""
        eps, a = sp.symbols("epsilon a")
        return sp.expand(sum(eps**n * sum(sp.Rational(c.numerator, c.denominator) * a**j
                                          for j, c in enumerate(d))
                             for n, d in enumerate(self.delta_coeffs)))

    def harmonic_expr(self, n: int, k: int) -> sp.Expr:
        """Coefficient (polynomial in ``a``) of ``cos(k tau)`` in ``x_n`` (or ``u_n``).

        Parameters
        ----------
        n : int
            The order in eps, 0 <= n <= ``order``.
        k : int
            The harmonic, >= 0.

        Returns
        -------
        sympy.Expr
            The exact polynomial in ``a``.
        """
        a = sp.Symbol("a")
        return sp.expand(sum(sp.Rational(c.numerator, c.denominator) * a**j
                             for j, c in enumerate(self.x_coeffs[n].harmonic(k))))

    def _computed(self) -> dict[str, object]:
        """delta_n as strings of exact polynomials in a."""
        a = sp.Symbol("a")
        return {"delta_n": [str(sp.expand(sum(sp.Rational(c.numerator, c.denominator) * a**j
                                                  for j, c in enumerate(d))))
                            for d in self.delta_coeffs]}


def _frac_vec(values: list[Fraction]) -> np.ndarray:
    out = np.empty(len(values), dtype=object)
    out[:] = values
    return out


def perturbation_series(branch: str = "0", order: int = 2, normalization: str = "initial",
                        truncation: int = 3) -> PerturbationSeries:
    """Compute the perturbation series of one branch to ``eps**order``.

    Parameters
    ----------
    branch : {"0", "1/4"}
        Transition curve through ``delta = 0`` or ``delta = 1/4``.
    order : int
        Highest power of ``eps`` (>= 1).
    normalization : {"initial", "kernel"}
        How the free kernel component of each correction is fixed.
    truncation : int
        Odd Taylor degree of ``sin`` (3 for eq (4)).

    Returns
    -------
    PerturbationSeries
    """
    b = parse_branch(branch)
    if order < 1:
        raise ArgumentError(f"perturbation order must be >= 1, got {order}")
    if normalization not in ("initial", "kernel"):
        raise ArgumentError(f"unknown normalization {normalization!r}")
    coeffs = sin_taylor_coefficients(truncation)
    one = Fraction(1)
    if b == "0":
        p, kappa, delta0 = 1, 0, Fraction(0)
        shift = {k: 0 for k in coeffs}
        x0 = CosSeries.cos(0, [0, 1])
    else:
        p, kappa, delta0 = 2, 1, Fraction(1, 4)
        shift = {k: k - 1 for k in coeffs}
        x0 = CosSeries.cos(1, [0, 1])

    xs: list[CosSeries] = [x0]
    pw: dict[int, list[CosSeries]] = {1: [x0]}  # pw[k][m] = eps**m coefficient of x**k
    for k in range(2, truncation + 1):
        pw[k] = [pw[k - 1][0] * x0]

    def G(m: int, skip_linear: bool = False) -> CosSeries:
        """eps**m coefficient of the (scaled) nonlinearity sum c_k eps**shift x**k."""
        total = CosSeries.zero()
        for k, c in coeffs.items():
            idx = m - shift[k]
            if (k == 1 and skip_linear) or idx < 0:
                continue
            total = total + pw[k][idx] * c
        return total

    g0 = G(0)
    g0_kernel = g0.harmonic(kappa)
    deltas = [_frac_vec([delta0])]
    for n in range(1, order + 1):
        rest = G(n - 1).mul_cos(p)
        if delta0:
            rest = rest + G(n, skip_linear=True) * delta0
        for i in range(1, n):
            rest = rest + G(n - i).mul_poly(deltas[i])
        delta_n = -poly_divide(rest.harmonic(kappa), g0_kernel)
        deltas.append(delta_n)
        forcing = rest + g0.mul_poly(delta_n)  # L x_n = -forcing
        xn = forcing.map_harmonics(
            lambda k: 0 if k == kappa else -one / (delta0 - Fraction(k * k, p * p)))
        if normalization == "initial":
            xn = xn - CosSeries.cos(kappa, xn.at_zero())
        xn = xn.trimmed()
        xs.append(xn)
        pw[1].append(xn)
        for k in range(2, truncation + 1):
            term = CosSeries.zero()
            for i in range(n + 1):
                term = term + pw[k - 1][i] * xs[n - i]
            pw[k].append(term.trimmed())
    return PerturbationSeries(branch=b, order=order, normalization=normalization,
                              truncation=truncation, delta_coeffs=deltas, x_coeffs=xs)
