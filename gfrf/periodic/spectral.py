"""Transition orbits of eq (3)/(4) as Fourier series: collocation + Newton (the fast exact path).

An orbit on a transition curve with ``x(0) = amplitude``, ``x'(0) = 0`` is even in ``t``
(see :mod:`~gfrf.periodic.shooting`), so it is a cosine series::

    branch "0":   x(t) = sum_k a_k cos(k t),            k = 0 .. n-1  (period 2*pi)
    branch "1/4": x(t) = sum_k a_k cos((k + 1/2) t),    k = 0 .. n-1  (period 4*pi,
                                                                      x(t + 2 pi) = -x(t))

and so is the residual ``R = x'' + (delta + eps cos t) g(x)`` (``g`` odd), with the same
symmetry.  Both series are fixed by their values at the ``n`` points
``t_j = pi (j + 1/2) / n`` of ``(0, pi)``.  Collocation ``R(t_j) = 0`` plus
``sum_k a_k = amplitude`` are ``n + 1`` equations for ``(a_0 .. a_{n-1}, delta)``, solved
by Newton's method with the exact Jacobian.  The orbit is analytic, so the coefficients
decay faster than geometrically and ``delta`` converges spectrally in ``n``: ``n`` is
doubled (from 16, at most :data:`MAX_MODES`) until the last quarter of the coefficients is
below ``1e-15`` of the largest, a rule on the computed coefficients, never on time.

The orbit is continued from the linear one, the lowest eigenpair of the same collocation
operator with ``g(x) = x`` (Hill's method; the eigenvalue is the Mathieu value
``a_0(2 eps)/4`` resp. ``b_1(2 eps)/4``), in ``x(0)`` by steps of at most 0.1 (as the
shooting continuation did), or from a given neighbouring orbit (continuation in ``eps``
along a curve).  Along a continuous family ``x`` keeps its sign pattern (no zero on
``[0, pi]``, resp. one at ``t = pi``), which every accepted orbit is checked for.

:func:`gfrf.periodic.shooting.transition_delta` checks every result by an independent
integration (Fortran DOP853 at ``rtol = 1e-12``) of the initial value problem.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from gfrf.errors import ArgumentError, ConvergenceError
from gfrf.periodic.equation import nonlinearity, parse_branch

__all__ = ["MAX_MODES", "FourierOrbit", "fourier_transition"]

#: Largest number of cosine modes tried before giving up.
MAX_MODES = 256
_FIRST_MODES = 16
#: Newton stops once its step is below this (``delta`` absolute, coefficients relative to
#: the amplitude): convergence is quadratic, so the iterate is then accurate to rounding.
_STEP_TOL = 1e-9
#: The last quarter of the coefficients must be below this fraction of the largest.
_TAIL_TOL = 1e-15
_MAXITER = 30
#: During continuation the modes are doubled once the tail exceeds this.
_GROW_TAIL = 1e-8
#: Largest accepted Newton correction of a continuation step, relative to the orbit.
_MAX_CORRECTION = 0.1
#: The continuation step never falls below ``step / 2**_HALVINGS``.
_HALVINGS = 6


@dataclass(frozen=True)
class FourierOrbit:
    """A transition orbit ``x(t) = sum_k a_k cos(w_k t)`` of eq (3)/(4).

    Attributes
    ----------
    eps, delta, amplitude : float
        Excitation, transition value and ``x(0)``.
    branch : str
        ``"0"`` (``w_k = k``) or ``"1/4"`` (``w_k = k + 1/2``).
    truncation : int or None
        Taylor degree of ``sin`` (None: ``sin`` itself).
    coefficients : ndarray
        ``a_k``, ``k = 0 .. modes-1``.
    iterations : int
        Newton iterations over all mode counts tried.
    tail : float
        Largest ``|a_k|`` of the last quarter, relative to the largest ``|a_k|``.
    """

    eps: float
    delta: float
    amplitude: float
    branch: str
    truncation: int | None
    coefficients: np.ndarray
    iterations: int
    tail: float

    @property
    def modes(self) -> int:
        """Number of cosine modes."""
        return len(self.coefficients)

    def evaluate(self, t: np.ndarray) -> np.ndarray:
        """Return ``x(t)`` at the times ``t`` (any order, any sign).

        Parameters
        ----------
        t : numpy.ndarray
            Dimensionless times.

        Returns
        -------
        numpy.ndarray
            x(t).
        """
        t = np.asarray(t, dtype=float)
        w = _frequencies(self.branch, self.modes)
        return np.cos(np.multiply.outer(t, w)) @ self.coefficients


def _frequencies(branch: str, n: int) -> np.ndarray:
    return np.arange(n, dtype=float) + (0.0 if branch == "0" else 0.5)


@functools.lru_cache(maxsize=16)
def _grid(branch: str, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Collocation times, ``C[j, k] = cos(w_k t_j)`` and the second derivative ``-w_k**2 C``."""
    t = math.pi * (np.arange(n) + 0.5) / n
    w = _frequencies(branch, n)
    c = np.cos(np.outer(t, w))
    d2 = c * -(w**2)
    for arr in (t, c, d2):
        arr.flags.writeable = False
    return t, c, d2


def _linear_start(eps: float, branch: str, n: int, amplitude: float
                  ) -> tuple[np.ndarray, float]:
    """Lowest eigenpair of the linear (Mathieu) collocation problem, scaled to ``x(0)``."""
    t, c, d2 = _grid(branch, n)
    # D2 a + eps cos(t_j) C a = -delta C a  <=>  C^-1 (D2 + eps cos C) a = -delta a
    op = np.linalg.solve(c, d2 + (eps * np.cos(t))[:, None] * c)
    vals, vecs = np.linalg.eig(op)
    i = int(np.argmax(vals.real))
    vec = vecs[:, i].real
    return vec * (amplitude / vec.sum()), float(-vals[i].real)


def _newton(eps: float, amplitude: float, branch: str, truncation: int | None,
            a: np.ndarray, delta: float) -> tuple[np.ndarray, float, int] | None:
    """Newton on the collocation equations; None if it does not converge."""
    n = len(a)
    t, c, d2 = _grid(branch, n)
    g, dg = nonlinearity(truncation)
    k_t = eps * np.cos(t)
    jac = np.empty((n + 1, n + 1))
    jac[n, :n] = 1.0
    jac[n, n] = 0.0
    f = np.empty(n + 1)
    a = a.copy()
    for it in range(1, _MAXITER + 1):
        x = c @ a
        k = delta + k_t
        gx = g(x)
        f[:n] = d2 @ a + k * gx
        f[n] = a.sum() - amplitude
        jac[:n, :n] = d2 + (k * dg(x))[:, None] * c
        jac[:n, n] = gx
        try:
            step = np.linalg.solve(jac, f)
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(step)):
            return None
        a -= step[:n]
        delta -= float(step[n])
        if abs(step[n]) <= _STEP_TOL and np.max(np.abs(step[:n])) <= _STEP_TOL * amplitude:
            return a, delta, it
    return None


def _on_branch(a: np.ndarray, branch: str) -> bool:
    """Whether ``x > 0`` on ``[0, pi]`` (branch 0) or ``[0, pi)`` (branch 1/4), sampled.

    A zero of ``x`` on a periodic orbit cannot appear or vanish along a continuous family
    of orbits (it would need ``x = x' = 0``, i.e. ``x == 0``), so the orbits continued
    from the linear ones (``ce_0 > 0``; ``cos(t/2)``-like, one zero at ``t = pi``) keep
    this sign pattern; a Newton step that lands on another family breaks it.
    """
    return bool(np.all(_samples(branch, len(a)) @ a > 0))


@functools.lru_cache(maxsize=16)
def _samples(branch: str, n: int) -> np.ndarray:
    """``cos(w_k t)`` at ``8 n + 1`` equispaced ``t`` in ``[0, pi]`` (``[0, pi)`` for 1/4)."""
    t = np.linspace(0.0, math.pi, 8 * n + 1)
    if branch == "1/4":
        t = t[:-1]
    out = np.cos(np.outer(t, _frequencies(branch, n)))
    out.flags.writeable = False
    return out


def _near(out: tuple[np.ndarray, float, int] | None, a: np.ndarray, delta: float,
          branch: str) -> bool:
    """Whether Newton converged from ``(a, delta)`` to a nearby orbit on the branch.

    "Nearby": the correction is at most :data:`_MAX_CORRECTION` of the orbit's largest
    coefficient (and of ``max(1, |delta|)``); a larger one means the predictor was poor and
    Newton may have reached another family, so the step is refused.
    """
    if out is None:
        return False
    a_new, d_new, _ = out
    return bool(np.max(np.abs(a_new - a)) <= _MAX_CORRECTION * np.max(np.abs(a_new))
                and abs(d_new - delta) <= _MAX_CORRECTION * max(1.0, abs(d_new))
                and _on_branch(a_new, branch))


def _resize(a: np.ndarray, n: int) -> np.ndarray:
    out = np.zeros(n)
    m = min(n, len(a))
    out[:m] = a[:m]
    return out


def _continue(eps: float, amplitude: float, branch: str, truncation: int | None,
              step: float) -> tuple[np.ndarray, float, int]:
    """Continuation in ``x(0)`` from the linear orbit, in steps of at most ``step``.

    The shape ``a / x(0)`` and ``delta`` are extrapolated linearly in ``x(0)**2`` from the
    last two orbits (the linear one first); a step where Newton fails or corrects the
    prediction by more than :data:`_MAX_CORRECTION` is halved (never below
    ``step / 2**_HALVINGS``), the modes are doubled when the tail grows, and every
    accepted orbit must keep the branch's sign pattern.
    """
    n = _FIRST_MODES
    shape, lin = _linear_start(eps, branch, n, 1.0)
    prev = (0.0, shape, lin)  # (x(0)**2, a / x(0), delta)
    cur = prev
    h = min(step, amplitude)
    min_h = h / 2**_HALVINGS
    done, total = 0.0, 0
    while done < amplitude:
        nxt = min(amplitude, done + h)
        if cur is prev:
            guess_shape, guess_d = cur[1], cur[2]
        else:
            w = (nxt * nxt - cur[0]) / (cur[0] - prev[0])
            guess_shape, guess_d = cur[1] + w * (cur[1] - prev[1]), cur[2] + w * (cur[2] - prev[2])
        guess = nxt * guess_shape / guess_shape.sum()
        out = _newton(eps, nxt, branch, truncation, guess, guess_d)
        if not _near(out, guess, guess_d, branch):
            if h <= min_h:
                why = ("did not converge" if out is None else
                       f"left the branch or moved more than {_MAX_CORRECTION:.0%} in one step")
                raise ConvergenceError(
                    f"Fourier collocation for the {branch} transition orbit (eps={eps}, x(0)="
                    f"{amplitude:g}) {why} at x(0) = {nxt:.6g} (Newton, {_MAXITER} steps, "
                    f"{n} modes, continuation in x(0) down to steps of {h:.3g}); no "
                    f"transition orbit found along this path")
            h /= 2
            continue
        a, d_new, it = out
        total += it
        prev, cur = cur, (nxt * nxt, a / nxt, d_new)
        done, h = nxt, min(step, 2 * h)
        if np.max(np.abs(a[-(n // 4):])) > _GROW_TAIL * np.max(np.abs(a)) \
                and 2 * n <= MAX_MODES:
            n *= 2
            prev = (prev[0], _resize(prev[1], n), prev[2])
            cur = (cur[0], _resize(cur[1], n), cur[2])
    return cur[1] * amplitude, cur[2], total


def fourier_transition(eps: float, amplitude: float, branch: str = "0",
                       truncation: int | None = 3, start: FourierOrbit | None = None,
                       step: float = 0.1) -> FourierOrbit:
    """Transition value and orbit with ``x(0) = amplitude`` by Fourier collocation.

    Parameters
    ----------
    eps : float
        Excitation amplitude (negative: the upper ``1/4`` side, see
        :mod:`~gfrf.periodic.equation`).
    amplitude : float
        ``x(0) > 0`` (``x'(0) = 0``).
    branch : {"0", "1/4"}
        Which transition curve.
    truncation : int or None
        3 for eq (4), None for eq (3).
    start : FourierOrbit, optional
        Newton start (e.g. the neighbour on a curve); without it, or if Newton fails
        from it, continuation in ``x(0)`` from the linear orbit.
    step : float
        Largest amplitude step of that continuation.

    Returns
    -------
    FourierOrbit

    Raises
    ------
    ArgumentError
        Non-positive or non-finite amplitude, or non-finite ``eps``.
    ConvergenceError
        No convergence, or the coefficients still not decayed at :data:`MAX_MODES` modes.

    Examples
    --------
    >>> from scipy.special import mathieu_a
    >>> orbit = fourier_transition(0.3, 1e-6, "0")  # small x(0): the linear (Mathieu) value
    >>> bool(abs(orbit.delta - mathieu_a(0, 0.6) / 4) < 1e-12)
    True
    >>> orbit.modes, round(fourier_transition(0.3, 0.5, "1/4").delta, 10)
    (16, 0.0992144701)
    """
    b = parse_branch(branch)
    if not (math.isfinite(amplitude) and amplitude > 0):
        raise ArgumentError(f"amplitude must be positive, got {amplitude}")
    if not math.isfinite(eps):
        raise ArgumentError(f"eps must be finite, got {eps}")
    out = None
    if start is not None:
        a = _resize(start.coefficients, max(_FIRST_MODES, start.modes))
        a *= amplitude / a.sum()
        out = _newton(eps, amplitude, b, truncation, a, start.delta)
        if not _near(out, a, start.delta, b):
            out = None
    a, delta, total = out if out is not None else _continue(eps, amplitude, b, truncation,
                                                            step)
    while True:
        n = len(a)
        tail = float(np.max(np.abs(a[-(n // 4):]))) / float(np.max(np.abs(a)))
        if tail <= _TAIL_TOL:
            return FourierOrbit(eps=float(eps),
                                delta=float(delta),
                                amplitude=float(amplitude),
                                branch=b,
                                truncation=truncation,
                                coefficients=a,
                                iterations=total,
                                tail=tail)
        if 2 * n > MAX_MODES:
            raise ConvergenceError(
                f"the {b} transition orbit (eps={eps}, x(0)={amplitude:g}) needs more than "
                f"{MAX_MODES} Fourier modes (tail {tail:.1e} of the largest coefficient)")
        out = _newton(eps, amplitude, b, truncation, _resize(a, 2 * n), delta)
        if out is None:
            raise ConvergenceError(
                f"Fourier collocation for the {b} transition orbit (eps={eps}, x(0)="
                f"{amplitude:g}) did not converge at {2 * n} modes from the {n}-mode orbit")
        a, delta, it = out
        total += it
