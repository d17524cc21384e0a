"""Newton corrector, pseudo-arclength continuation and fold location on a balance.

The branch is followed in ``z = (x / sx, p / sp)``: the coefficients x scaled by a
response size sx and the parameter p (omega, or the forcing amplitude A) by the width
of its range, so that one arclength unit is comparable in both.  Each step predicts
along the unit tangent (the null vector of ``[R_x, R_p]``, oriented to continue the
previous one) and corrects with Newton on the balance plus the arclength condition
``t . (z - z_i) = ds``.  The step length adapts to the corrector's iteration count and
to the turning of the tangent, only from counts and angles, never from the clock.
A fold (saddle-node) is where the tangent's parameter component changes sign; it is
located by Brent's method on the arclength from the point before it, each evaluation
a corrected point and its tangent.

May import: numpy, scipy and :mod:`gfrf.harmonic.balance`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from gfrf.harmonic.balance import Balance, Evaluation

__all__ = ["Point", "Tracer", "newton_fixed"]

#: Newton iterations per corrector before the step is refused.
MAX_NEWTON = 12
#: Relative tolerance of the corrector (residual against the size of the equation's terms).
TOLERANCE = 1e-12
#: Response size, in units of the scale sx, beyond which the branch is not followed
#: (an undamped resonance sends it to infinity).
UNBOUNDED = 1e3
#: Root-finder iterations of a fold location.
FOLD_ITERATIONS = 60


@dataclass(frozen=True)
class Point:
    """One corrected point: coefficients, frequency, forcing and the evaluation there."""

    x: np.ndarray
    omega: float
    amplitude: float
    evaluation: Evaluation


def _solve(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """``matrix^-1 rhs``, or the least-squares step of least norm when the matrix is
    singular (an undamped internal resonance: a harmonic left undetermined stays 0)."""
    try:
        return np.linalg.solve(matrix, rhs)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(matrix, rhs, rcond=None)[0]


def newton_fixed(balance: Balance, x: np.ndarray, omega: float, amplitude: float,
                 scale: float) -> Point | None:
    """Newton on the balance at fixed omega and A.

    Parameters
    ----------
    balance : Balance
        The harmonic-balance equations.
    x : ndarray
        Starting coefficients.
    omega, amplitude : float
        The fixed frequency and forcing amplitude.
    scale : float
        Size of the equation's terms: the residual must fall below 1e-9 of it.

    Returns
    -------
    Point or None
        The solution, or None when Newton does not converge in :data:`MAX_NEWTON` steps.
    """
    x = x.copy()
    for _ in range(MAX_NEWTON):
        e = balance.evaluate(x, omega, amplitude)
        dx = _solve(e.jac_x, -e.residual)
        if not np.isfinite(dx).all():
            return None
        x += dx
        if np.max(np.abs(dx)) <= 1e-11 * max(np.max(np.abs(x)), 1e-300):
            e = balance.evaluate(x, omega, amplitude)
            if np.max(np.abs(e.residual)) <= 1e-9 * scale:
                return Point(x, omega, amplitude, e)
    return None


class Tracer:
    """Pseudo-arclength continuation of a balance in omega or in the forcing amplitude.

    Parameters
    ----------
    balance : Balance
        The harmonic-balance equations.
    vary : {"omega", "amplitude"}
        The continuation parameter p; the other one is held.
    x_scale, p_scale : float
        sx and sp of the scaled variables (module docstring).
    term_scale : float
        Size of the equation's terms, for the residual tolerance.
    """

    def __init__(self, balance: Balance, vary: str, x_scale: float, p_scale: float,
                 term_scale: float) -> None:
        self.balance = balance
        self.vary = vary
        self.sx = x_scale
        self.sp = p_scale
        self.term_scale = term_scale
        self.size = balance.size

    def param(self, point: Point) -> float:
        """The continuation parameter of a point.

        Parameters
        ----------
        point : Point
            A point of the branch.

        Returns
        -------
        float
            Its omega (rad/s) or its amplitude A, whichever is varied.
        """
        return point.omega if self.vary == "omega" else point.amplitude

    def _state(self, point: Point) -> np.ndarray:
        return np.append(point.x / self.sx, self.param(point) / self.sp)

    def _point(self, z: np.ndarray, fixed: Point, e: Evaluation) -> Point:
        p = z[-1] * self.sp
        if self.vary == "omega":
            return Point(z[:-1] * self.sx, p, fixed.amplitude, e)
        return Point(z[:-1] * self.sx, fixed.omega, p, e)

    def _evaluate(self, z: np.ndarray, fixed: Point) -> tuple[Evaluation, np.ndarray]:
        x, p = z[:-1] * self.sx, z[-1] * self.sp
        if self.vary == "omega":
            e = self.balance.evaluate(x, p, fixed.amplitude)
            jp = e.jac_omega
        else:
            e = self.balance.evaluate(x, fixed.omega, p)
            jp = e.jac_amplitude
        return e, np.column_stack([e.jac_x * self.sx, jp * self.sp])

    def tangent(self, point: Point, previous: np.ndarray | None) -> np.ndarray:
        """Unit tangent at ``point`` in the scaled variables, oriented like ``previous``
        (or towards increasing p).

        Parameters
        ----------
        point : Point
            A corrected point (its evaluation holds the Jacobians).
        previous : numpy.ndarray or None
            The previous tangent (scaled variables), None at the first point.

        Returns
        -------
        numpy.ndarray
            The unit null vector of the scaled (2H+1, 2H+2) Jacobian, length 2H + 2.
        """
        e = point.evaluation
        jp = e.jac_omega if self.vary == "omega" else e.jac_amplitude
        k = np.column_stack([e.jac_x * self.sx, jp * self.sp])
        guide = previous if previous is not None else np.eye(self.size + 1)[-1]
        t = np.linalg.svd(k)[2][-1]  # the null vector of the (m, m + 1) Jacobian
        return -t if t @ guide < 0 else t

    def arclength(self, start: Point, tangent: np.ndarray, end: Point) -> float:
        """``tangent . (z_end - z_start)``: the arclength coordinate of ``end`` on the
        corrector's hyperplanes through ``start``.

        Parameters
        ----------
        start, end : Point
            Points of the branch.
        tangent : numpy.ndarray
            The unit tangent at ``start`` in the scaled variables.

        Returns
        -------
        float
            The arclength coordinate, in the scaled variables.
        """
        return float(tangent @ (self._state(end) - self._state(start)))

    def correct(self, start: Point, tangent: np.ndarray, ds: float
                ) -> tuple[Point, int] | None:
        """The point at arclength ``ds`` from ``start`` along ``tangent`` and the
        iterations it took, or None when Newton fails.

        Parameters
        ----------
        start : Point
            The last corrected point.
        tangent : numpy.ndarray
            The unit tangent at ``start`` in the scaled variables.
        ds : float
            Arclength step in the scaled variables.

        Returns
        -------
        tuple of (Point, int) or None
            The corrected point and the Newton iterations, or None.
        """
        z0 = self._state(start)
        z = z0 + ds * tangent
        for it in range(1, MAX_NEWTON + 1):
            e, k = self._evaluate(z, start)
            rhs = np.append(-e.residual, ds - tangent @ (z - z0))
            dz = _solve(np.vstack([k, tangent]), rhs)
            if not np.isfinite(dz).all():
                return None
            z = z + dz
            if np.max(np.abs(dz)) <= 1e-11 * max(np.max(np.abs(z)), 1.0):
                e, _ = self._evaluate(z, start)
                if np.max(np.abs(e.residual)) <= 1e-9 * self.term_scale:
                    return self._point(z, start, e), it
        return None

    def at_parameter(self, start: Point, tangent: np.ndarray, p: float) -> Point | None:
        """The point of the branch through ``start`` whose parameter is exactly p (the
        end of the range), by Newton at fixed p from the linear prediction.

        Parameters
        ----------
        start : Point
            A point of the branch near the end of the range.
        tangent : numpy.ndarray
            The unit tangent at ``start`` in the scaled variables.
        p : float
            The parameter wanted: omega in rad/s or the amplitude A.

        Returns
        -------
        Point or None
            The corrected point, or None when Newton fails.
        """
        dp = tangent[-1] * self.sp
        step = (p - self.param(start)) / dp if dp != 0 else 0.0
        x = start.x + step * tangent[:-1] * self.sx
        if self.vary == "omega":
            return newton_fixed(self.balance, x, p, start.amplitude, self.term_scale)
        return newton_fixed(self.balance, x, start.omega, p, self.term_scale)

    def fold(self, start: Point, tangent: np.ndarray, ds: float) -> Point | None:
        """The fold between ``start`` and the point at arclength ``ds``: the root of the
        tangent's parameter component in the arclength, by the Illinois (regula falsi)
        method, each evaluation a corrected point and its tangent.

        Parameters
        ----------
        start : Point
            The last corrected point before the parameter's direction turned.
        tangent : numpy.ndarray
            The unit tangent at ``start`` in the scaled variables.
        ds : float
            Arclength (scaled variables) of the corrected point past the fold.

        Returns
        -------
        Point or None
            The point nearest the fold, or None when a correction fails or the tangent's
            parameter component does not change sign on [0, ds].
        """
        def component(s: float) -> tuple[float, Point] | None:
            out = self.correct(start, tangent, s) if s > 0 else (start, 0)
            if out is None:
                return None
            return float(self.tangent(out[0], tangent)[-1]), out[0]

        left, right = component(0.0), component(ds)
        if left is None or right is None or left[0] * right[0] > 0:
            return None
        a, b = 0.0, ds
        fa, fb = left[0], right[0]
        best = right[1] if abs(fb) < abs(fa) else left[1]
        side = 0
        for _ in range(FOLD_ITERATIONS):
            s = (a * fb - b * fa) / (fb - fa)
            got = component(s)
            if got is None:
                return None
            fs, best = got
            if abs(fs) <= 1e-13 or abs(b - a) <= 1e-14 * ds:
                break
            if fs * fb > 0:
                b, fb = s, fs
                if side == -1:
                    fa /= 2
                side = -1
            else:
                a, fa = s, fs
                if side == 1:
                    fb /= 2
                side = 1
        return best

    def trace(self, first: Point, end: float, *, step: float, max_points: int,
              accept: Callable[[Point], None]) -> tuple[list[tuple[Point, np.ndarray]],
                                                         list[tuple[Point, int]], bool]:
        """Follow the branch from ``first`` until the parameter reaches ``end``.

        Returns the points with their tangents, the located folds with the sign of the
        parameter's direction just before each (+1: p was increasing), and whether the end
        was reached (False when ``max_points`` ran out or the step shrank to nothing).
        ``accept`` is called on every new point (for a progress count).

        Parameters
        ----------
        first : Point
            The corrected starting point.
        end : float
            The parameter value to reach: omega in rad/s or the amplitude A.
        step : float
            The largest arclength step, in the scaled variables (the first is a quarter of it).
        max_points : int
            Most points of the branch kept, the first included.
        accept : callable
            Called with every new point.
        """
        t = self.tangent(first, None)
        if (end - self.param(first)) * t[-1] < 0:
            t = -t
        points = [(first, t)]
        folds: list[tuple[Point, int]] = []
        ds = step / 4
        low, high = sorted((self.param(first), end))
        while len(points) < max_points:
            point, t = points[-1]
            out = self.correct(point, t, ds)
            if out is None:
                ds /= 2
                if ds < step * 1e-6:
                    return points, folds, False
                continue
            new, iterations = out
            if np.max(np.abs(new.x)) > UNBOUNDED * self.sx:
                return points, folds, False
            t_new = self.tangent(new, t)
            angle = math.acos(min(1.0, abs(float(t @ t_new))))
            if angle > 0.2 and ds > step * 1e-6:
                ds /= 2
                continue
            p = self.param(new)
            if not low <= p <= high:
                last = self.at_parameter(point, t, high if p > high else low)
                if last is not None:
                    points.append((last, self.tangent(last, t)))
                    accept(last)
                return points, folds, True
            if t[-1] * t_new[-1] < 0:
                fold = self.fold(point, t, ds)
                if fold is not None:
                    folds.append((fold, 1 if t[-1] > 0 else -1))
            points.append((new, t_new))
            accept(new)
            if iterations <= 3 and angle < 0.05:
                ds = min(ds * 1.5, step)
        return points, folds, False
