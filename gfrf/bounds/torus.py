"""1/A(q) and its derivatives over intervals of frequency for a discrete-time (NARX) model.

The discrete counterpart of :class:`gfrf.bounds.inverse.InverseA`: with
a(sigma) = A(exp(-j sigma T)) = sum_l a_l exp(-j l sigma T) (a trigonometric polynomial
of the block's frequency sum sigma, rad/s) the branch-and-bound of
:mod:`gfrf.bounds.branch_bound` needs r = 1/a and m = 1/|a| with their first two
derivatives at box centres, and bounds of them and of their third derivatives over the
interval [sigma - rho, sigma + rho] of a block's sum.

Bounds.  The k-th derivative a^(k)(sigma) = sum_l a_l (-j l T)^k exp(-j l sigma T) is
bounded everywhere by ``S_k = sum_l |a_l| (l T)^k``.  Over an interval of half-width rho
about c, |a^(k)| <= |a^(k)(c)| + |a^(k+1)(c)| rho + S_(k+2) rho^2 / 2, and
min |a| >= |a(c)| - |a'(c)| rho - |a''(c)| rho^2 / 2 - S_3 rho^3 / 6 (Taylor with the
global bound of the remainder), never below ``1 / sup |1/A|`` on the whole circle (the
proven sup of :func:`gfrf.bounds.rational.discrete_rational_sup`), so a box whose sum
spans a whole period still gets a finite bound.  Derivatives of 1/a and of 1/|a| then
follow from the quotient rule with the numerators bounded by products of those sups
(for |a|^2 the first two derivatives use their values at the centre too, so near a
resonance peak, where (|a|^2)' vanishes, the bound is second order in rho).

Tables of sups.  Those Taylor bounds grow fast with rho, and a block's sum spans up to n
times a box's width (half a period and more at the start of a search).  All these sups
are of functions of one periodic variable, so they are also tabulated once per model:
the same bounds on each of ``_CELLS`` cells of one period (each cell widened by 1/64
of its width, which covers the rounding of the cell index), and the sup over an
interval is the largest cell bound it meets (a sparse table of maxima: O(1) per
interval).  A cell's bounds are also taken from the Taylor series of r and m at its
centre (degree 11, exact recurrences) with Cauchy's bound of the twelfth derivative on a
strip |Im sigma| <= Y where |a| stays away from 0 (:meth:`InverseTrig._strip`): within
0.2 % of the true sups, where the quotient-rule bounds of the third derivatives are
1.5-6x above them.  Every interval gets the smaller of the two bounds.

Soundness.  Values at the centre are double-precision sums; the a-priori error bound
``gamma * S_k`` (gamma a few units of rounding per term) is added to every bound, and
subtracted from the lower bound of |a|.  As in the continuous case the result is
certified in floating point, not proven.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

__all__ = ["InverseTrig"]

#: Relative error of a centre's 1/a above which the centre's values are not used
#: (the same threshold as :mod:`gfrf.bounds.enclosure`).
_POINT_RTOL = 1e-5
#: Cells per period of the tables of sups (see the module docstring).
_CELLS = 4096
#: Degree of the Taylor series of r and m at a cell's centre (``InverseTrig._series_bounds``).
_SERIES_DEGREE = 12
#: Relative margin for the rounding of those series' coefficients (double precision, a
#: few dozen operations each).
_SERIES_RTOL = 1e-9


class _SupTable:
    """Sups of periodic functions over intervals, from bounds over the cells of a period.

    Parameters
    ----------
    cell_bounds : callable
        ``cell_bounds(lo, hi) -> (N, k)`` array: valid upper bounds over the intervals.
    period : float
        The common period of the functions bounded.
    """

    def __init__(self, cell_bounds: Callable[[np.ndarray, np.ndarray], np.ndarray],
                 period: float) -> None:
        self.period = period
        self.width = period / _CELLS
        edges = -0.5 * period + self.width * np.arange(_CELLS + 1)
        pad = self.width / 64
        cells = cell_bounds(edges[:-1] - pad, edges[1:] + pad)
        self.top = cells.max(axis=0)
        self.levels = [np.vstack([cells, cells])]  # two periods: no wrap-around in a query
        span = 1
        while 2 * span <= _CELLS:  # levels[k][i]: max over cells i .. i + 2^k - 1
            last = self.levels[-1]
            self.levels.append(np.maximum(last[:-span], last[span:]))
            span *= 2

    def __call__(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Upper bounds over the intervals [lo, hi], shape (N, k).

        Parameters
        ----------
        lo, hi : numpy.ndarray
            Ends of the N intervals, ``lo <= hi``.

        Returns
        -------
        numpy.ndarray
            The largest bound of the cells each interval meets (the top of all cells
            for an interval of a period or more).
        """
        with np.errstate(invalid="ignore"):
            first = np.floor((lo + 0.5 * self.period) / self.width)
            count = np.floor((hi + 0.5 * self.period) / self.width) - first + 1
            whole = ~(count < _CELLS)  # a period or more (or not a number)
        count = np.where(whole, 1.0, count).astype(np.int64)
        start = np.where(whole, 0.0, first % _CELLS).astype(np.int64)
        level = np.floor(np.log2(count)).astype(np.int64)
        out = np.empty((np.size(lo), self.top.size))
        for k in np.unique(level):
            rows = level == k
            table = self.levels[int(k)]
            out[rows] = np.maximum(table[start[rows]],
                                   table[start[rows] + count[rows] - (1 << int(k))])
        out[whole] = self.top
        return out


class InverseTrig:
    """r(sigma) = 1 / A(exp(-j sigma T)) and m = 1/|A|, with derivatives and their bounds.

    Parameters
    ----------
    den : numpy.ndarray
        A's coefficients, lowest power of q first (as
        :func:`gfrf.bounds.majorant.linear_polynomials` gives them for a NARX model).
    sample_time : float
        T in seconds.
    floor : float
        A lower bound of |a(sigma)| over the whole circle (0 when unknown).
    """

    def __init__(self, den: np.ndarray, sample_time: float, floor: float) -> None:
        self.coef = np.asarray(den, dtype=float)
        self.step = float(sample_time)
        self.lags = np.arange(self.coef.size) * self.step
        self.floor = float(floor)
        magnitude = np.abs(self.coef)
        #: S_k = sum |a_l| (l T)^k, k = 0..5: global sups of |a^(k)|
        self.sups = np.array([float(np.sum(magnitude * self.lags ** k)) for k in range(6)])
        self.gamma = (4 * self.coef.size + 16) * 2.0 ** -53
        self._tables: tuple[_SupTable, _SupTable] | None = None

    def _table(self, kind: int) -> _SupTable:
        """The table of the sups of :meth:`bounds` (kind 0) or of :meth:`modulus_bounds`
        (kind 1), both built on first use."""
        if self._tables is None:
            period = 2 * math.pi / self.step
            self._tables = (
                _SupTable(lambda lo, hi: np.minimum(self._taylor_bounds(lo, hi),
                                                    self._series_bounds(lo, hi, 0)), period),
                _SupTable(lambda lo, hi: np.minimum(self._taylor_modulus_bounds(lo, hi),
                                                    self._series_bounds(lo, hi, 1)), period))
        return self._tables[kind]

    def _strip(self) -> tuple[float, float, float]:
        """(Y, bound of |r| and bound of |m| on the strip |Im sigma| <= Y), or Y = 0.

        For real s and |y| <= Y, |a(s + jy) - a(s)| <= eps = sum |a_l| (exp(l T Y) - 1),
        so |a| >= floor - eps there; b(z) = sum conj(a_l) exp(j l T z) (b = conj(a) on the
        real axis) moves as little, so a b stays within eta = eps (2 S_0 + eps) of
        |a(s)|^2 >= floor^2: where eta < floor^2, m = (a b)^(-1/2) (principal root) is
        analytic and at most (floor^2 - eta)^(-1/2).
        """
        top = len(self.coef) - 1
        if self.floor <= 0 or top == 0:
            return 0.0, 0.0, 0.0
        magnitude = np.abs(self.coef)

        def eps(y: float) -> float:
            return float(sum(m * math.expm1(lag * self.step * y)
                             for lag, m in enumerate(magnitude))) * (1 + 1e-12)

        y = 1.0 / (top * self.step)  # exp(l T Y) - 1 <= e - 1: then halve to the target
        while eps(y) * (2 * self.sups[0] + eps(y)) > 0.5 * self.floor ** 2:
            y *= 0.5
        e = eps(y)
        floor = self.floor * (1 - 1e-12)
        return (y, 1.0 / (floor - e) * (1 + 1e-12),
                1.0 / math.sqrt(floor * floor - e * (2 * self.sups[0] + e)) * (1 + 1e-12))

    def _series_bounds(self, lo: np.ndarray, hi: np.ndarray, kind: int) -> np.ndarray:
        """Sups over [lo, hi] of |f| and of its first three derivatives (f = r for
        ``kind`` 0, m for 1), shape (N, 4), from the Taylor coefficients of f at the
        centre below degree :data:`_SERIES_DEGREE` and Cauchy's bound of the higher
        derivatives on the strip of :meth:`_strip` (inf where that strip is empty).  For
        the short cells of the tables: there the third derivatives come out about 5x
        below the Taylor bounds (the identified example).
        """
        y, r_top, m_top = self._strip()
        out = np.full((np.size(lo), 4), np.inf)
        if y <= 0:
            return out
        degree = _SERIES_DEGREE
        c = 0.5 * (lo + hi)
        delta = np.nextafter(np.maximum(hi - c, c - lo), np.inf)
        # Taylor coefficients of a about c (those of b are their conjugates)
        z = np.exp(-1j * self.step * np.asarray(c, float))
        a = np.zeros((degree + 1, c.size), complex)
        power = np.ones(c.size, complex)
        for lag, coef in enumerate(self.coef):
            if coef != 0.0:
                for p in range(degree + 1):
                    a[p] += coef * (-1j * lag * self.step) ** p / math.factorial(p) * power
            power = power * z
        if kind == 0:  # 1/a: r_p = -(sum_{i=1..p} a_i r_{p-i}) / a_0
            series = np.zeros_like(a)
            series[0] = 1.0 / a[0]
            for p in range(1, degree + 1):
                series[p] = -sum(a[i] * series[p - i] for i in range(1, p + 1)) / a[0]
            top = r_top
        else:  # g = a conj(a), g^(-1/2) by the recurrence of g^alpha
            g = np.array([sum(a[i] * np.conj(a[p - i]) for i in range(p + 1))
                          for p in range(degree + 1)]).real
            series = np.zeros(g.shape)
            series[0] = g[0] ** -0.5
            for p in range(1, degree + 1):
                series[p] = sum((0.5 * i - p) * g[i] * series[p - i]
                                for i in range(1, p + 1)) / (p * g[0])
            top = m_top
        magnitude = np.abs(series)
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            for k in range(4):  # Taylor's formula for f^(k) about c, Cauchy's bound of
                # the degree-th derivative (|f^(d)| <= d! top / y^d) in its remainder
                total = sum(math.factorial(p) / math.factorial(p - k) * magnitude[p]
                            * delta ** (p - k) for p in range(k, degree))
                tail = (top * math.factorial(degree) / math.factorial(degree - k)
                        * delta ** (degree - k) / y ** degree)
                out[:, k] = (total * (1 + _SERIES_RTOL) + tail
                             + _SERIES_RTOL * top * math.factorial(k) / y ** k)
        return np.where(np.isnan(out), np.inf, out)

    def derivatives(self, sigma: np.ndarray, count: int) -> np.ndarray:
        """a, a', .., a^(count-1) at the points ``sigma``, shape (count, N).

        Parameters
        ----------
        sigma : numpy.ndarray
            Angular frequencies in rad/s, any shape.
        count : int
            Number of derivatives, the value included.

        Returns
        -------
        numpy.ndarray
            Complex, shape ``(count, *sigma.shape)``: the k-th derivative with respect to sigma
            in row k (double-precision sums, error at most ``gamma * S_k``).
        """
        sigma = np.asarray(sigma, dtype=float)
        z = np.exp(-1j * self.step * sigma)
        out = np.zeros((count, *sigma.shape), dtype=complex)
        power = np.ones(sigma.shape, dtype=complex)
        for lag, c in enumerate(self.coef):  # a few lags: plain vector operations
            if c != 0.0:
                for k in range(count):
                    out[k] += (c * (-1j * lag * self.step) ** k) * power
            power = power * z
        return out

    def _local(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(lower bound of min |a|, sups of |a|, |a'|, |a''|, |a'''| shape (4, N)) over
        the intervals [lo, hi]."""
        c = 0.5 * (lo + hi)
        rho = np.nextafter(np.maximum(hi - c, c - lo), np.inf)
        d = np.abs(self.derivatives(c, 5))
        err = self.gamma * self.sups[:, None]
        s = self.sups[:, None]
        with np.errstate(over="ignore", invalid="ignore"):
            upper = np.minimum(d[:4] + err[:4] + (d[1:5] + err[1:5]) * rho
                               + s[2:6] * rho * rho / 2, s[:4])
            small = (d[0] - err[0] - (d[1] + err[1]) * rho - (d[2] + err[2]) * rho * rho / 2
                     - s[3] * rho ** 3 / 6)
        small = np.maximum(np.nan_to_num(small, nan=0.0, neginf=0.0), self.floor)
        return small, upper

    def centre_error(self, sigma: np.ndarray, slack: np.ndarray, rho: np.ndarray
                     ) -> np.ndarray:
        """Relative error of 1/a and of its Taylor terms r' rho, r'' rho^2 at sigma
        (``slack`` bounds the rounding of sigma itself).

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
        d = np.abs(self.derivatives(sigma, 4))
        err = self.gamma * self.sups
        moved = (d[1] + d[2] * rho + d[3] * rho * rho) * slack
        with np.errstate(divide="ignore", invalid="ignore"):
            return (err[0] + err[1] * rho + err[2] * rho * rho + moved) / d[0]

    def point(self, sigma: np.ndarray, error: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """r, r' and r'' at points (NaN where ``error`` exceeds the accepted error).

        Parameters
        ----------
        sigma : numpy.ndarray
            Angular frequencies in rad/s.
        error : numpy.ndarray
            Relative error of each point (from :meth:`centre_error`); points above 1e-5 get NaN.

        Returns
        -------
        tuple of numpy.ndarray
            r, r' and r'' (complex) at ``sigma``.
        """
        a, da, dda = self.derivatives(sigma, 3)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            bad = ~(error <= _POINT_RTOL)
            value = 1.0 / a
            slope = -da * value * value
            curve = (2 * da * da - a * dda) * value ** 3
        return (np.where(bad, np.nan, value), np.where(bad, np.nan, slope),
                np.where(bad, np.nan, curve))

    def bounds(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Sups over [lo, hi] of |r|, |r'|, |r''|, |r'''|, shape (N, 4): the smaller of the
        Taylor bounds and the table's (module docstring).

        Parameters
        ----------
        lo, hi : numpy.ndarray
            Ends of the N intervals of sigma (rad/s), ``lo <= hi``.

        Returns
        -------
        numpy.ndarray
            Upper bounds, shape (N, 4), ``inf`` where |a| may vanish on the interval.
        """
        return np.minimum(self._taylor_bounds(lo, hi), self._table(0)(lo, hi))

    def _taylor_bounds(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """:meth:`bounds` from the Taylor bounds only."""
        small, (u0, u1, u2, u3) = self._local(lo, hi)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            inv = np.where(small > 0, 1.0 / small, np.inf)
            out = np.stack([inv, u1 * inv ** 2, (2 * u1 * u1 + u0 * u2) * inv ** 3,
                            (6 * u1 ** 3 + 6 * u0 * u1 * u2 + u0 * u0 * u3) * inv ** 4],
                           axis=1)
        return np.where(np.isnan(out), np.inf, out)

    def _squared(self, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """q = |a|^2 and its first two derivatives at points."""
        a, da, dda = self.derivatives(sigma, 3)
        q = (a * np.conj(a)).real
        q1 = 2 * (np.conj(a) * da).real
        q2 = 2 * ((da * np.conj(da)).real + (np.conj(a) * dda).real)
        return q, q1, q2

    def modulus_point(self, sigma: np.ndarray, error: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """m = 1/|a|, m' and m'' at points (NaN where ``error`` exceeds the accepted error).

        Parameters
        ----------
        sigma : numpy.ndarray
            Angular frequencies in rad/s.
        error : numpy.ndarray
            Relative error of each point (from :meth:`centre_error`); points above 1e-5 get NaN.

        Returns
        -------
        tuple of numpy.ndarray
            m, m' and m'' (real) at ``sigma``.
        """
        q, q1, q2 = self._squared(sigma)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            bad = ~(error <= _POINT_RTOL)
            m = 1.0 / np.sqrt(q)
            slope = -0.5 * q1 * m ** 3
            curve = (3 * q1 * q1 - 2 * q * q2) * m ** 5 / 4
        return (np.where(bad, np.nan, m), np.where(bad, np.nan, slope),
                np.where(bad, np.nan, curve))

    def modulus_bounds(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Sups over [lo, hi] of |m| and of its first three derivatives, shape (N, 4): the
        smaller of the Taylor bounds and the table's (module docstring).

        With q = |a|^2: m' = -q'/(2 q^(3/2)), m'' = (3 q'^2 - 2 q q'')/(4 q^(5/2)),
        m''' = (-15 q'^3 + 18 q q' q'' - 4 q^2 q''')/(8 q^(7/2)); q' = 2 Re(conj(a) a'),
        q'' = 2 (|a'|^2 + Re(conj(a) a'')), q''' = 2 Re(3 conj(a') a'' + conj(a) a''').

        Parameters
        ----------
        lo, hi : numpy.ndarray
            Ends of the N intervals of sigma (rad/s), ``lo <= hi``.

        Returns
        -------
        numpy.ndarray
            Upper bounds, shape (N, 4), ``inf`` where |a| may vanish on the interval.
        """
        return np.minimum(self._taylor_modulus_bounds(lo, hi), self._table(1)(lo, hi))

    def _taylor_modulus_bounds(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """:meth:`modulus_bounds` from the Taylor bounds only."""
        small, (u0, u1, u2, u3) = self._local(lo, hi)
        c = 0.5 * (lo + hi)
        rho = np.nextafter(np.maximum(hi - c, c - lo), np.inf)
        _, q1c, q2c = self._squared(c)
        slack = 8 * self.gamma * self.sups[0] * (self.sups[0] + self.sups[1]
                                                 + self.sups[2])
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            s3 = 2 * (3 * u1 * u2 + u0 * u3)
            s2 = np.minimum(2 * (u1 * u1 + u0 * u2), np.abs(q2c) + slack + s3 * rho)
            s1 = np.minimum(2 * u0 * u1, np.abs(q1c) + slack + (np.abs(q2c) + slack) * rho
                            + s3 * rho * rho / 2)
            q_top = u0 * u0
            inv = np.where(small > 0, 1.0 / small, np.inf)
            out = np.stack([inv, s1 * inv ** 3 / 2,
                            (3 * s1 * s1 + 2 * q_top * s2) * inv ** 5 / 4,
                            (15 * s1 ** 3 + 18 * q_top * s1 * s2 + 4 * q_top * q_top * s3)
                            * inv ** 7 / 8], axis=1)
        return np.where(np.isnan(out), np.inf, out)
