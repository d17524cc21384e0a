"""Harmonic balance of a polynomial model under ``u = A cos(omega t)``.

The periodic steady state is written with H harmonics,

    y(t) = a0 + sum_{k=1..H} (a_k cos(k omega t) + b_k sin(k omega t)),

and the unknowns are ``x = (a0, a1, b1, ..., aH, bH)``.  Every factor of a term,
``D^l y`` (continuous) or ``y[k-l]`` (discrete, sample time T), multiplies the complex
amplitude of harmonic k by ``(j k omega)^l`` or ``exp(-j k omega l T)``: a 2 x 2 block
on ``(a_k, b_k)``.  The residual of the equation is evaluated on N equally spaced
samples of one period (alternating frequency-time) and projected back on the
harmonics 0..H.  A term of degree d is a trigonometric polynomial of degree at most
d H in the phase, so with ``N >= (degree + 1) H + 1`` samples no product aliases onto
a kept harmonic: the projection is the exact Galerkin projection, and so are the
analytic Jacobians (with respect to x, omega and A) assembled from the same samples.

A discrete model is balanced as the continuous-time trigonometric polynomial whose
samples at ``t = kT`` are the sequence; its frequencies run up to Nyquist, pi / T.

May import: :mod:`gfrf.model` (the terms of a model) and numpy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gfrf.errors import ArgumentError
from gfrf.model.equation import Term

__all__ = ["Balance", "Evaluation", "MAX_HARMONICS", "samples_needed"]

#: Largest number of harmonics accepted (the Newton systems are dense, 2H + 2 square,
#: and Hill's eigenproblem d (2H + 1) square).
MAX_HARMONICS = 100


def samples_needed(degree: int, harmonics: int) -> int:
    """Samples per period that make the projection exact.

    Parameters
    ----------
    degree : int
        The model's largest total degree.
    harmonics : int
        H.

    Returns
    -------
    int
        ``(degree + 1) H + 1``.
    """
    return (degree + 1) * harmonics + 1


@dataclass(frozen=True, kw_only=True)
class Evaluation:
    """Residual and Jacobians of the balance at one point.

    Attributes
    ----------
    residual : ndarray
        The projections on harmonics 0..H, ordered as x.
    jac_x, jac_omega, jac_amplitude : ndarray
        Derivatives of ``residual`` with respect to x, omega and A.
    partials : dict
        ``{l: samples of dF/d(D^l y)}`` (or dF/dy[k-l]): the coefficients of the
        linearised equation along the orbit, for Hill's method.
    """

    residual: np.ndarray
    jac_x: np.ndarray
    jac_omega: np.ndarray
    jac_amplitude: np.ndarray
    partials: dict[int, np.ndarray]


class Balance:
    """The harmonic-balance equations of ``terms = 0`` with ``harmonics`` harmonics.

    Parameters
    ----------
    terms : sequence of Term
        The polynomial's monomials (a model's ``terms`` or a subset of them).
    harmonics : int
        H, the highest harmonic kept (1 <= H <= :data:`MAX_HARMONICS`).
    sample_time : float or None
        T of a discrete model (lags instead of derivatives), None if continuous.
    samples : int, optional
        Samples per period; default and minimum :func:`samples_needed`.
    """

    def __init__(self, terms: tuple[Term, ...], harmonics: int, *,
                 sample_time: float | None = None, samples: int | None = None) -> None:
        if isinstance(harmonics, bool) or not isinstance(harmonics, int) \
                or not 1 <= harmonics <= MAX_HARMONICS:
            raise ArgumentError(f"harmonics must be an integer from 1 to MAX_HARMONICS = "
                                f"{MAX_HARMONICS}, got {harmonics!r}")
        self.terms = tuple(terms)
        self.harmonics = harmonics
        self.sample_time = sample_time
        self.degree = max(t.degree for t in self.terms)
        need = samples_needed(self.degree, harmonics)
        self.samples = max(need, samples or 0)
        self.size = 2 * harmonics + 1
        self.y_orders = sorted({o for t in self.terms for o in t.y_orders})
        self.u_orders = sorted({o for t in self.terms for o in t.u_orders})
        tau = 2.0 * math.pi * np.arange(self.samples) / self.samples
        k = np.arange(1, harmonics + 1)
        basis = np.ones((self.samples, self.size))
        basis[:, 1::2] = np.cos(np.outer(tau, k))
        basis[:, 2::2] = np.sin(np.outer(tau, k))
        self.basis = basis
        self.projection = basis.T * (2.0 / self.samples)
        self.projection[0] /= 2.0
        self.tau = tau
        self._k = np.arange(harmonics + 1, dtype=float)
        self._ones = np.ones(harmonics + 1, dtype=complex)
        self._zeros = np.zeros(harmonics + 1, dtype=complex)
        self._cache: dict[int, np.ndarray] = {}
        span = np.arange(-2 * harmonics, 2 * harmonics + 1)
        #: exp(-j n tau) / N for n = -2H..2H: complex Fourier coefficients of samples.
        self.analysis = np.exp(-1j * np.outer(span, tau)) / self.samples

    def multipliers(self, order: int, omega: float) -> tuple[np.ndarray, np.ndarray]:
        """Complex factors of harmonics 0..H for ``D^order`` (or lag ``order``) and their
        derivative with respect to omega.

        Parameters
        ----------
        order : int
            l: the derivative order (continuous) or the lag (discrete).
        omega : float
            The fundamental angular frequency in rad/s.

        Returns
        -------
        tuple of numpy.ndarray
            The H + 1 complex factors and their H + 1 derivatives with respect to omega.
        """
        k = self._k
        if self.sample_time is not None:
            m = np.exp(-1j * k * omega * order * self.sample_time)
            return m, -1j * k * order * self.sample_time * m
        if order == 0:
            return self._ones, self._zeros
        m = self._powers(order) * omega ** order
        return m, m * (order / omega)

    def _powers(self, order: int) -> np.ndarray:
        """(j k)^order for k = 0..H, computed once per order."""
        if order not in self._cache:
            self._cache[order] = (1j * self._k) ** order
        return self._cache[order]

    def operator(self, factors: np.ndarray) -> np.ndarray:
        """The real (2H+1)-square matrix multiplying harmonic k's amplitude by ``factors[k]``.

        Parameters
        ----------
        factors : numpy.ndarray
            H + 1 complex factors, one per harmonic 0..H (the imaginary part of the first is
            ignored).

        Returns
        -------
        numpy.ndarray
            The real matrix acting on ``x = (a0, a1, b1, ..., aH, bH)``.
        """
        out = np.zeros((self.size, self.size))
        out[0, 0] = factors[0].real
        idx = np.arange(1, self.size, 2)
        out[idx, idx] = out[idx + 1, idx + 1] = factors[1:].real
        out[idx, idx + 1] = factors[1:].imag
        out[idx + 1, idx] = -factors[1:].imag
        return out

    def _apply(self, factors: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``operator(factors) @ x`` in O(H)."""
        out = np.empty(self.size)
        out[0] = factors[0].real * x[0]
        re, im = factors[1:].real, factors[1:].imag
        a, b = x[1::2], x[2::2]
        out[1::2] = re * a + im * b
        out[2::2] = re * b - im * a
        return out

    def _columns(self, factors: np.ndarray) -> np.ndarray:
        """``basis @ operator(factors)``: samples of each coefficient's image."""
        out = np.empty_like(self.basis)
        out[:, 0] = factors[0].real
        re, im = factors[1:].real, factors[1:].imag
        cos, sin = self.basis[:, 1::2], self.basis[:, 2::2]
        out[:, 1::2] = cos * re - sin * im
        out[:, 2::2] = cos * im + sin * re
        return out

    def multiplication(self, samples: np.ndarray) -> np.ndarray:
        """The (2H+1)-square matrix of multiplication by a trigonometric polynomial of
        degree <= (degree - 1) H given by its samples, projected on harmonics 0..H.

        Parameters
        ----------
        samples : numpy.ndarray
            The trigonometric polynomial's values at the :attr:`samples` points of one period.

        Returns
        -------
        numpy.ndarray
            The real (2H+1)-square matrix acting on ``x``.
        """
        return (self.projection * samples) @ self.basis

    def evaluate(self, x: np.ndarray, omega: float, amplitude: float) -> Evaluation:
        """Residual and Jacobians at coefficients ``x``, frequency omega, forcing A.

        Parameters
        ----------
        x : numpy.ndarray
            The 2H + 1 coefficients ``(a0, a1, b1, ..., aH, bH)``.
        omega : float
            The forcing's angular frequency in rad/s.
        amplitude : float
            A, the forcing's amplitude.

        Returns
        -------
        Evaluation
            The projected residual, its Jacobians and the partial derivatives along the orbit.
        """
        mult: dict[int, np.ndarray] = {}
        ys: dict[int, np.ndarray] = {}
        dys: dict[int, np.ndarray] = {}
        for order in self.y_orders:
            m, dm = self.multipliers(order, omega)
            mult[order] = m
            ys[order] = self.basis @ self._apply(m, x)
            dys[order] = self.basis @ self._apply(dm, x)
        cos, sin = self.basis[:, 1], self.basis[:, 2]
        units: dict[int, np.ndarray] = {}
        dunits: dict[int, np.ndarray] = {}
        for order in self.u_orders:
            m, dm = self.multipliers(order, omega)
            units[order] = cos * m[1].real - sin * m[1].imag
            dunits[order] = cos * dm[1].real - sin * dm[1].imag
        n = self.samples
        r = np.zeros(n)
        r_omega = np.zeros(n)
        r_amp = np.zeros(n)
        gy = {order: np.zeros(n) for order in self.y_orders}
        gu = {order: np.zeros(n) for order in self.u_orders}
        for term in self.terms:
            q = len(term.u_orders)
            factors = [ys[o] for o in term.y_orders] + [units[o] for o in term.u_orders]
            scale = term.coefficient * amplitude ** q
            value = scale * _product(factors)
            r += value
            for i, order in enumerate(term.y_orders):
                gy[order] += scale * _product(factors[:i] + factors[i + 1:])
            for i, order in enumerate(term.u_orders):
                gu[order] += scale * _product(factors[:len(term.y_orders) + i]
                                              + factors[len(term.y_orders) + i + 1:])
            if q:
                r_amp += term.coefficient * q * amplitude ** (q - 1) * _product(factors)
        jac = np.zeros((self.size, self.size))
        for order in self.y_orders:
            jac += (self.projection * gy[order]) @ self._columns(mult[order])
            r_omega += gy[order] * dys[order]
        for order in self.u_orders:
            r_omega += gu[order] * dunits[order]
        return Evaluation(residual=self.projection @ r, jac_x=jac,
                          jac_omega=self.projection @ r_omega,
                          jac_amplitude=self.projection @ r_amp, partials=gy)

    def residual_samples(self, x: np.ndarray, omega: float, amplitude: float,
                         samples: int) -> tuple[np.ndarray, np.ndarray]:
        """The residual of the equation and the largest term, on ``samples`` points of
        one period (the full residual, harmonics above H included).

        Parameters
        ----------
        x : numpy.ndarray
            The 2H + 1 coefficients ``(a0, a1, b1, ..., aH, bH)``.
        omega : float
            The forcing's angular frequency in rad/s.
        amplitude : float
            A, the forcing's amplitude.
        samples : int
            Number of equally spaced points of the period.

        Returns
        -------
        tuple of numpy.ndarray
            The residual and the largest absolute value of a single term, at each point.
        """
        tau = 2.0 * math.pi * np.arange(samples) / samples
        k = np.arange(self.harmonics + 1)
        phase = np.exp(1j * np.outer(tau, k))
        amp = np.concatenate([[x[0]], x[1::2] - 1j * x[2::2]])
        r = np.zeros(samples)
        biggest = np.zeros(samples)
        for term in self.terms:
            value = np.full(samples, term.coefficient * amplitude ** len(term.u_orders))
            for order in term.y_orders:
                value = value * (phase @ (self.multipliers(order, omega)[0] * amp)).real
            for order in term.u_orders:
                value = value * (self.multipliers(order, omega)[0][1] * phase[:, 1]).real
            r += value
            biggest = np.maximum(biggest, np.abs(value))
        return r, biggest

    def linear_guess(self, omega: float, amplitude: float) -> np.ndarray:
        """Coefficients of the linear part's steady state (H1 times the forcing), or
        zeros where H1 is undefined.

        Parameters
        ----------
        omega : float
            The forcing's angular frequency in rad/s.
        amplitude : float
            A, the forcing's amplitude.

        Returns
        -------
        numpy.ndarray
            The 2H + 1 coefficients, nonzero only at ``a1, b1``.
        """
        den = 0j
        num = 0j
        for term in self.terms:
            if term.degree != 1:
                continue
            order = (term.y_orders or term.u_orders)[0]
            factor = term.coefficient * self.multipliers(order, omega)[0][1]
            if term.y_orders:
                den += factor
            else:
                num += factor
        x = np.zeros(self.size)
        if abs(den) > 0:
            y1 = -num * amplitude / den
            x[1], x[2] = y1.real, -y1.imag
        return x

    def linear_factor(self, k: int, omega: float) -> complex:
        """The linear output part at harmonic k: sum_l a_l (j k omega)^l, or with lags
        sum_l a_l exp(-j k omega l T).

        Parameters
        ----------
        k : int
            The harmonic, >= 0.
        omega : float
            The fundamental angular frequency in rad/s.

        Returns
        -------
        complex
            The factor multiplying the complex amplitude of harmonic k of y.
        """
        return sum((t.coefficient * _factor(t.y_orders[0], k, omega, self.sample_time)
                    for t in self.terms if t.is_linear_output), 0j)


def _factor(order: int, k: int, omega: float, sample_time: float | None) -> complex:
    if sample_time is not None:
        return complex(np.exp(-1j * k * omega * order * sample_time))
    return complex((1j * k * omega) ** order)


def _product(factors: list[np.ndarray]) -> np.ndarray | float:
    out: np.ndarray | float = 1.0
    for f in factors:
        out = out * f
    return out
