"""1/A(j sigma) of a continuous-time model and its derivatives, bounded over intervals.

The factors 1/A(j sigma_B) of the enclosures of :mod:`gfrf.bounds.enclosure` (sigma_B the
sum of a block's frequencies, rad/s): their values and first two derivatives at box
centres, and sups of their moduli and of their first three derivatives over intervals
of sigma.  With a(sigma) = A(j sigma) and its sigma-derivatives (formed exactly from the
float coefficients), r = 1/a and m = 1/|a| (through q = |a|^2) have derivatives whose
numerators are polynomials; each numerator's modulus is bounded over intervals by
:class:`_Modulus`: critical points of its square isolated exactly (Arb) once, endpoint
values widened by an a-priori Horner error bound.  So a box straddling a resonance is
bounded by the resonance peak, not by infinity.  The discrete-time counterpart is
:class:`gfrf.bounds.torus.InverseTrig`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["InverseA"]

#: Relative error of a centre's 1/A and Taylor terms above which its values are not used
#: (the same threshold as :mod:`gfrf.bounds.enclosure`).
_POINT_RTOL = 1e-5


def _cmul(a: tuple[Any, Any], b: tuple[Any, Any]) -> tuple[Any, Any]:
    """Product of complex polynomials given as (real part, imaginary part) fmpq_polys."""
    return a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0]


class _Modulus:
    """Bounds of |p(sigma)| over intervals, p a complex polynomial of real sigma given
    exactly by its real and imaginary parts (fmpq_polys).

    The critical points of |p|^2 are the real roots of its derivative, isolated
    rigorously (FLINT/Arb) once, and |p| is enclosed on their balls; the endpoint
    values are double-precision Horner evaluations widened by the a-priori error bound
    gamma * sum |c_k| |sigma|^k.  So ``extrema`` is a sound (min, max) even for a cluster
    of lightly damped poles, where float roots of d|p|^2 can be off by 1e-4.
    """

    def __init__(self, re: Any, im: Any) -> None:
        from flint import arb_poly

        from gfrf.bounds.exact import _PREC, _down, _precision, _real_roots, _up

        degree = max(re.degree(), im.degree(), 0)
        re_c = [float(c) for c in re.coeffs()] + [0.0] * (degree + 1 - len(re.coeffs()))
        im_c = [float(c) for c in im.coeffs()] + [0.0] * (degree + 1 - len(im.coeffs()))
        self.coef = (np.array(re_c) + 1j * np.array(im_c))[::-1]  # highest first
        self.abs_coef = np.abs(self.coef)
        self.gamma = (4 * degree + 8) * 2.0 ** -53
        squared = re * re + im * im
        slope = squared.derivative()
        lo, hi, small, large = [], [], [], []
        if slope.degree() >= 1:
            with _precision(_PREC):
                sq = arb_poly([c for c in squared.coeffs()])
                for x, _ in _real_roots(slope):
                    value = sq(x)
                    lo.append(_down(x))
                    hi.append(_up(x))
                    small.append(math.sqrt(max(_down(value), 0.0)))
                    large.append(math.sqrt(_up(value)) * (1 + 2.0 ** -52))
        self.crit_lo, self.crit_hi = np.array(lo), np.array(hi)
        self.crit_min, self.crit_max = np.array(small), np.array(large)

    def __call__(self, sigma: np.ndarray) -> np.ndarray:
        return np.polyval(self.coef, sigma)

    def error(self, sigma: np.ndarray) -> np.ndarray:
        """A-priori bound on the error of the double-precision value at sigma."""
        return self.gamma * np.polyval(self.abs_coef, np.abs(sigma))

    def extrema(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(lower bound of min, upper bound of max) of |p| over [lo, hi] (vectorised).

        Where a value overflows, the min bound is NaN (read as "no bound" by the callers,
        whose ``min > 0`` tests then fail) and the max bound inf.
        """
        with np.errstate(over="ignore", invalid="ignore"):
            a, b = np.abs(self(lo)), np.abs(self(hi))
            ea, eb = self.error(lo), self.error(hi)
            small = np.maximum(np.minimum(a - ea, b - eb), 0.0)
            large = np.maximum(a + ea, b + eb)
        if self.crit_lo.size:
            inside = (self.crit_lo <= hi[:, None]) & (self.crit_hi >= lo[:, None])
            small = np.minimum(small, np.where(inside, self.crit_min, np.inf).min(axis=1))
            large = np.maximum(large, np.where(inside, self.crit_max, -np.inf).max(axis=1))
        return small, large


class InverseA:
    """r(sigma) = 1 / a(sigma), a(sigma) = A(j sigma), with derivatives and their bounds.

    With a's sigma-derivatives a', a'', a''' (formed exactly from the float
    coefficients, highest power first):
    r' = -a'/a^2, r'' = (2a'^2 - a a'')/a^3, r''' = -(6a'^3 - 6a a' a'' + a^2 a''')/a^4;
    each numerator's modulus is bounded over intervals by :class:`_Modulus`.

    Parameters
    ----------
    den : numpy.ndarray
        A's coefficients, highest power of s first (float, read as exact binary rationals).
    """

    def __init__(self, den: np.ndarray) -> None:
        from flint import fmpq, fmpq_poly

        from gfrf.bounds.exact import fractions

        low = [fmpq(c.numerator, c.denominator) for c in reversed(fractions(den))]
        unit = [(1, 0), (0, 1), (-1, 0), (0, -1)]  # j^k
        a = (fmpq_poly([c * unit[k % 4][0] for k, c in enumerate(low)]),
             fmpq_poly([c * unit[k % 4][1] for k, c in enumerate(low)]))
        da = (a[0].derivative(), a[1].derivative())
        dda = (da[0].derivative(), da[1].derivative())
        ddda = (dda[0].derivative(), dda[1].derivative())
        sq, prod = _cmul(da, da), _cmul(a, dda)
        cube, mixed, last = _cmul(sq, da), _cmul(prod, da), _cmul(_cmul(a, a), ddda)
        self.a, self.da, self.dda = _Modulus(*a), _Modulus(*da), _Modulus(*dda)
        self.ddda = _Modulus(*ddda)
        self.second = _Modulus(2 * sq[0] - prod[0], 2 * sq[1] - prod[1])
        self.third = _Modulus(6 * cube[0] - 6 * mixed[0] + last[0],
                              6 * cube[1] - 6 * mixed[1] + last[1])
        # m = 1/|a| = q^(-1/2) with q = |a|^2 and its derivatives q1, q2, q3:
        # m1 = -q1 / (2 q^(3/2)), m2 = (3 q1^2 - 2 q q2) / (4 q^(5/2)),
        # m3 = (-15 q1^3 + 18 q q1 q2 - 4 q^2 q3) / (8 q^(7/2))
        q = a[0] * a[0] + a[1] * a[1]
        q1 = q.derivative()
        q2 = q1.derivative()
        q3 = q2.derivative()
        zero = fmpq_poly([])
        self.mod_slopes = [_Modulus(q1, zero), _Modulus(3 * q1 * q1 - 2 * q * q2, zero),
                           _Modulus(-15 * q1 * q1 * q1 + 18 * q * q1 * q2 - 4 * q * q * q3,
                                    zero)]
        self.q_coef = [np.array([float(c) for c in p.coeffs()][::-1] or [0.0])
                       for p in (q1, q2)]

    def centre_error(self, sigma: np.ndarray, slack: np.ndarray, rho: np.ndarray
                     ) -> np.ndarray:
        """Relative error of 1/a and of its Taylor terms r' rho, r'' rho^2 at sigma.

        The Horner errors of a, a', a'' and the moves of a, a', a'' over ``slack`` are
        divided by |a|.

        Parameters
        ----------
        sigma : numpy.ndarray
            The centres, angular frequencies in rad/s.
        slack : numpy.ndarray or float
            Bound of the rounding error of ``sigma`` itself (rad/s).
        rho : numpy.ndarray or float
            Half-widths of the intervals around the centres (rad/s).

        Returns
        -------
        numpy.ndarray
            The relative error bound per centre (inf or NaN where a is 0 there).
        """
        a = np.abs(self.a(sigma))
        moved = (np.abs(self.da(sigma)) + np.abs(self.dda(sigma)) * rho
                 + np.abs(self.ddda(sigma)) * rho * rho) * slack
        with np.errstate(divide="ignore", invalid="ignore"):
            return (self.a.error(sigma) + self.da.error(sigma) * rho
                    + self.dda.error(sigma) * rho * rho + moved) / a

    def point(self, sigma: np.ndarray, error: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """r, r' and r'' at points (NaN where ``error`` exceeds _POINT_RTOL).

        Parameters
        ----------
        sigma : numpy.ndarray
            Angular frequencies in rad/s.
        error : numpy.ndarray
            Relative error of each point (from :meth:`centre_error`).

        Returns
        -------
        tuple of numpy.ndarray
            r, r' and r'' (complex) at ``sigma``.
        """
        a, da, dda = self.a(sigma), self.da(sigma), self.dda(sigma)
        with np.errstate(divide="ignore", invalid="ignore"):
            bad = ~(error <= _POINT_RTOL)
            value = 1.0 / a
            slope = -da * value * value
            curve = (2 * da * da - a * dda) * value ** 3
        return (np.where(bad, np.nan, value), np.where(bad, np.nan, slope),
                np.where(bad, np.nan, curve))

    def modulus_point(self, sigma: np.ndarray, error: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """m = 1/|a|, m1 and m2 (its first two derivatives) at points (NaN where
        ``error`` exceeds _POINT_RTOL).

        Parameters
        ----------
        sigma : numpy.ndarray
            Angular frequencies in rad/s.
        error : numpy.ndarray
            Relative error of each point (from :meth:`centre_error`).

        Returns
        -------
        tuple of numpy.ndarray
            m, m1 and m2 (real) at ``sigma``.
        """
        a = self.a(sigma)
        with np.errstate(divide="ignore", invalid="ignore"):
            bad = ~(error <= _POINT_RTOL)
            q = (a * np.conj(a)).real
            q1, q2 = (np.polyval(c, sigma) for c in self.q_coef)
            m = 1.0 / np.sqrt(q)
            slope = -0.5 * q1 * m ** 3
            curve = (3 * q1 * q1 - 2 * q * q2) * m ** 5 / 4
        return (np.where(bad, np.nan, m), np.where(bad, np.nan, slope),
                np.where(bad, np.nan, curve))

    def modulus_bounds(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Sups over [lo, hi] of |m| and of its first three derivatives, shape (N, 4).

        Parameters
        ----------
        lo, hi : numpy.ndarray
            Ends of the N intervals of sigma (rad/s), ``lo <= hi``.
        """
        a_min, _ = self.a.extrema(lo, hi)
        sups = [modulus.extrema(lo, hi)[1] for modulus in self.mod_slopes]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            inv = np.where(a_min > 0, 1.0 / a_min, np.inf)
            return _safe(np.stack([inv, sups[0] * inv ** 3 / 2, sups[1] * inv ** 5 / 4,
                                   sups[2] * inv ** 7 / 8], axis=1))

    def bounds(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Sups over [lo, hi] of |r|, |r'|, |r''|, |r'''|, shape (N, 4).

        Parameters
        ----------
        lo, hi : numpy.ndarray
            Ends of the N intervals of sigma (rad/s), ``lo <= hi``.
        """
        a_min, _ = self.a.extrema(lo, hi)
        _, d1 = self.da.extrema(lo, hi)
        _, d2 = self.second.extrema(lo, hi)
        _, d3 = self.third.extrema(lo, hi)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            inv = np.where(a_min > 0, 1.0 / a_min, np.inf)
            return _safe(np.stack([inv, d1 * inv ** 2, d2 * inv ** 3, d3 * inv ** 4], axis=1))


def _safe(x: np.ndarray) -> np.ndarray:
    """NaN (0 * inf) becomes inf: an undetermined bound is no bound."""
    return np.where(np.isnan(x), np.inf, x)
