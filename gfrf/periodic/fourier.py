"""Truncated cosine-series arithmetic on coefficient arrays (exact or floating point).

A :class:`CosSeries` is an even, ``2*pi``-periodic function of ``tau`` whose Fourier
coefficients are polynomials in one parameter ``a``::

    f(tau, a) = sum_{k=-H..H} sum_{j=0..P-1} c[k + H, j] * a**j * exp(i k tau),

stored two-sided with ``c[k] = c[-k]``, so the cosine coefficient of ``cos(k tau)`` is
``2 c[k]`` for ``k > 0`` and ``c[0]`` for ``k = 0``.  Products are 2-D convolutions,
which is exact and fast; entries are :class:`fractions.Fraction` (``dtype=object``)
for exact formulas or ``float`` for numerical work.  No symbolic trigonometric
simplification is ever needed.
"""

from __future__ import annotations

from collections.abc import Callable
from fractions import Fraction

import numpy as np
from scipy.signal import convolve2d

__all__ = ["CosSeries", "poly_divide", "poly_eval", "poly_mul"]


def _zeros(shape: tuple[int, ...], exact: bool) -> np.ndarray:
    if exact:
        out = np.empty(shape, dtype=object)
        out.fill(Fraction(0))
        return out
    return np.zeros(shape)


def poly_mul(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Product of two coefficient vectors (ascending powers); exact for object arrays.

    Parameters
    ----------
    p, q : numpy.ndarray
        Coefficient vectors, ascending powers (float, or object arrays of Fractions).

    Returns
    -------
    numpy.ndarray
        The product.
    """
    if p.dtype != object and q.dtype != object:
        return np.convolve(p, q)
    out = _zeros((len(p) + len(q) - 1,), True)
    for i, c in enumerate(p):
        if c:
            out[i:i + len(q)] += c * q
    return out


def poly_divide(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Exact quotient ``p / q`` of ascending coefficient vectors.

    Parameters
    ----------
    p, q : numpy.ndarray
        Coefficient vectors, ascending powers; ``q`` not zero.

    Returns
    -------
    numpy.ndarray
        The quotient, an object array of Fractions.

    Raises
    ------
    ArithmeticError
        If ``q`` does not divide ``p``.
    """
    p = np.array(p, dtype=object)
    qd = [Fraction(c) for c in q]
    while qd and qd[-1] == 0:
        qd.pop()
    low = next(i for i, c in enumerate(qd) if c != 0)
    quot = _zeros((max(len(p) - len(qd) + 1, 1),), True)
    rem = p.copy()
    for i in range(len(quot)):  # divide from the lowest power up
        c = rem[i + low] / qd[low] if i + low < len(rem) else Fraction(0)
        quot[i] = c
        if c:
            for j, qc in enumerate(qd):
                if i + j < len(rem):
                    rem[i + j] -= c * qc
    if any(rem):
        raise ArithmeticError("polynomial division leaves a remainder")
    return quot


def poly_eval(p: np.ndarray, a: float | np.ndarray) -> float | np.ndarray:
    """Evaluate an ascending coefficient vector at ``a`` (as floats).

    Parameters
    ----------
    p : numpy.ndarray
        Coefficient vector, ascending powers.
    a : float or numpy.ndarray
        The point(s).

    Returns
    -------
    float or numpy.ndarray
        The values.
    """
    return np.polynomial.polynomial.polyval(a, np.asarray(p, dtype=float))


class CosSeries:
    """Even trigonometric series with polynomial coefficients; see module docstring.

    Parameters
    ----------
    coef : ndarray, shape (2H+1, P)
        Two-sided coefficients; row ``H + k`` holds harmonic ``k``.
    """

    def __init__(self, coef: np.ndarray) -> None:
        self.coef = coef

    @property
    def exact(self) -> bool:
        """True when the coefficients are Fractions."""
        return self.coef.dtype == object

    @property
    def order(self) -> int:
        """Highest stored harmonic ``H``."""
        return (self.coef.shape[0] - 1) // 2

    @classmethod
    def cos(cls, k: int, poly: object = 1, exact: bool = True) -> CosSeries:
        """The series ``poly(a) * cos(k tau)`` (``poly``: number or ascending vector).

        Parameters
        ----------
        k : int
            The harmonic, >= 0.
        poly : number or sequence, optional
            The coefficient: a number or an ascending coefficient vector in ``a``.
        exact : bool, optional
            Fractions (object array) instead of floats.

        Returns
        -------
        CosSeries
            The series.
        """
        p = np.atleast_1d(np.array(poly, dtype=object if exact else float))
        if exact:
            p = np.array([Fraction(c) for c in p], dtype=object)
        coef = _zeros((2 * k + 1, len(p)), exact)
        if k == 0:
            coef[0] = p
        else:
            coef[0] = coef[2 * k] = p / 2
        return cls(coef)

    @classmethod
    def zero(cls, exact: bool = True) -> CosSeries:
        """The zero series.

        Parameters
        ----------
        exact : bool, optional
            Fractions (object array) instead of floats.

        Returns
        -------
        CosSeries
            The series.
        """
        return cls(_zeros((1, 1), exact))

    def _padded(self, h: int, p: int) -> np.ndarray:
        out = _zeros((2 * h + 1, p), self.exact)
        H = self.order
        out[h - H:h + H + 1, :self.coef.shape[1]] = self.coef
        return out

    def __add__(self, other: CosSeries) -> CosSeries:
        h = max(self.order, other.order)
        p = max(self.coef.shape[1], other.coef.shape[1])
        return CosSeries(self._padded(h, p) + other._padded(h, p))

    def __neg__(self) -> CosSeries:
        return CosSeries(-self.coef)

    def __sub__(self, other: CosSeries) -> CosSeries:
        return self + (-other)

    def __mul__(self, other: CosSeries | float | Fraction) -> CosSeries:
        if not isinstance(other, CosSeries):
            return CosSeries(self.coef * other)
        if not (self.exact or other.exact):
            return CosSeries(convolve2d(self.coef, other.coef))
        a, b = self.coef, other.coef
        out = _zeros((a.shape[0] + b.shape[0] - 1, a.shape[1] + b.shape[1] - 1), True)
        for i, j in zip(*np.nonzero(a), strict=True):
            out[i:i + b.shape[0], j:j + b.shape[1]] += a[i, j] * b
        return CosSeries(out).trimmed()

    __rmul__ = __mul__

    def mul_poly(self, poly: np.ndarray) -> CosSeries:
        """Multiply every coefficient by the polynomial ``poly(a)``.

        Parameters
        ----------
        poly : numpy.ndarray
            Ascending coefficient vector in ``a``.

        Returns
        -------
        CosSeries
            The product.
        """
        rows = [poly_mul(row, np.asarray(poly)) for row in self.coef]
        return CosSeries(np.array(rows, dtype=self.coef.dtype))

    def trimmed(self) -> CosSeries:
        """Drop vanishing outer harmonics and trailing zero powers of ``a``."""
        c = self.coef
        nz_rows = [i for i in range(c.shape[0]) if any(c[i])]
        nz_cols = [j for j in range(c.shape[1]) if any(c[:, j])]
        if not nz_rows:
            return CosSeries.zero(self.exact)
        H = self.order
        h = max(abs(i - H) for i in nz_rows)
        return CosSeries(c[H - h:H + h + 1, :max(nz_cols) + 1])

    def harmonic(self, k: int) -> np.ndarray:
        """Polynomial coefficient vector of ``cos(k tau)``.

        Parameters
        ----------
        k : int
            The harmonic, >= 0.

        Returns
        -------
        numpy.ndarray
            Coefficients in powers of ``a``, lowest first (zeros above the series' order).
        """
        if k > self.order:
            return _zeros((1,), self.exact)
        row = self.coef[self.order + k]
        return row.copy() if k == 0 else row * 2

    def map_harmonics(self, factor: Callable[[int], object]) -> CosSeries:
        """Apply a diagonal operator: harmonic ``k`` is multiplied by ``factor(k)``.

        Parameters
        ----------
        factor : callable
            ``factor(k)`` for k = 0..order, a number (Fraction in an exact series).

        Returns
        -------
        CosSeries
            The new series.
        """
        H = self.order
        out = self.coef.copy()
        for i in range(out.shape[0]):
            out[i] = out[i] * factor(abs(i - H))
        return CosSeries(out)

    def mul_cos(self, p: int) -> CosSeries:
        """Multiply by ``cos(p tau)``.

        Parameters
        ----------
        p : int
            The harmonic, >= 0.

        Returns
        -------
        CosSeries
            The product.
        """
        return self * CosSeries.cos(p, 1, self.exact)

    def at_zero(self) -> np.ndarray:
        """Polynomial ``f(0, a)``."""
        return self.coef.sum(axis=0)

    def mean_square(self) -> float:
        """``(1/2pi) int f**2 dtau`` for a float series without ``a`` (Parseval)."""
        return float(np.sum(np.asarray(self.coef, dtype=float)[:, 0] ** 2))

    def evaluate(self, tau: np.ndarray, a: float = 0.0) -> np.ndarray:
        """Numerical values at the points ``tau`` for the parameter value ``a``.

        Parameters
        ----------
        tau : numpy.ndarray
            The phases (rad).
        a : float, optional
            The parameter's value.

        Returns
        -------
        numpy.ndarray
            Float values, the shape of ``tau``.
        """
        tau = np.asarray(tau, dtype=float)
        powers = a ** np.arange(self.coef.shape[1])
        cks = np.asarray(self.coef, dtype=float) @ powers
        H = self.order
        out = np.full(tau.shape, cks[H])
        for k in range(1, H + 1):
            out = out + 2 * cks[H + k] * np.cos(k * tau)
        return out


def trig_harmonic(expr: object, theta: object, k: int = 0, kind: str = "cos") -> object:
    """Exact ``(1/pi) int_0^{2pi} expr * cos(k theta) dtheta`` (``1/2pi`` for ``k=0``).

    For a trigonometric polynomial in ``theta`` (sympy expression).  Works by writing
    ``exp(i theta) = z`` and reading off Laurent coefficients, so no symbolic
    integration or trigonometric simplification is involved.  ``kind="sin"`` gives the
    ``sin(k theta)`` coefficient.

    Parameters
    ----------
    expr : sympy expression or float
        A trigonometric polynomial in ``theta``.
    theta : sympy.Symbol
        The angle.
    k : int, optional
        The harmonic.
    kind : {"cos", "sin"}, optional
        Which coefficient.
    """
    import sympy as sp

    z = sp.Symbol("_z")
    trig = sp.Float(expr) if isinstance(expr, float) else expr
    e = sp.expand(sp.expand(trig.rewrite(sp.exp)).subs(sp.exp(sp.I * theta), z))
    if e.has(theta):
        raise ArithmeticError(f"{expr} is not a trigonometric polynomial in {theta}")
    terms = sp.collect(e, z, evaluate=False)

    def coeff(n: int) -> object:
        return terms.get(z**n if n else sp.S.One, sp.S.Zero)

    if k == 0:
        return sp.simplify(sp.expand(coeff(0)).rewrite(sp.cos))
    cp, cm = coeff(k), coeff(-k)
    val = cp + cm if kind == "cos" else sp.I * (cp - cm)
    return sp.simplify(sp.expand(val).rewrite(sp.cos))
