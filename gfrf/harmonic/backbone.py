"""The backbone: free periodic oscillations of the unforced, undamped system.

The conservative part of a continuous model keeps the terms without the input and
with even derivatives of y only (``y'' + y + 0.3 y^3`` of a Duffing oscillator).  It is
reversible in time, so its free oscillations are even: cosine series.  With the
first-harmonic amplitude a1 held, the cosine projections 0..H are H + 1 equations in
``(a0, a2, ..., aH, omega)``, solved by Newton while a1 is raised in equal steps from
the linear resonance ``omega0`` (the smallest positive root of the conservative linear
part) up to the largest amplitude asked for.  The march stops where Newton fails (a
softening backbone bends to omega = 0).

May import: numpy and :mod:`gfrf.harmonic.balance`.
"""

from __future__ import annotations

import numpy as np

from gfrf.harmonic.balance import Balance
from gfrf.model.equation import Model

__all__ = ["backbone_curve", "BACKBONE_STEPS"]

#: Amplitude steps of the backbone march.
BACKBONE_STEPS = 60


def _linear_resonance(terms: tuple) -> float | None:
    """Smallest positive omega where sum_l a_l (j omega)^l of the even linear terms vanishes."""
    coeffs: dict[int, float] = {}
    for t in terms:
        if t.is_linear_output:
            coeffs[t.y_orders[0]] = coeffs.get(t.y_orders[0], 0.0) + t.coefficient
    if not coeffs or max(coeffs) == 0:
        return None
    poly = np.zeros(max(coeffs) + 1)
    for order, c in coeffs.items():
        poly[order] = c * (-1) ** (order // 2)
    roots = np.roots(poly[::-1])
    positive = [r.real for r in roots if abs(r.imag) <= 1e-9 * abs(r) and r.real > 0]
    return min(positive) if positive else None


def backbone_curve(model: Model, harmonics: int, top: float
                   ) -> tuple[tuple[float, float, float], ...]:
    """The backbone of the unforced, undamped part of ``model``.

    Parameters
    ----------
    model : Model
        A continuous model; its terms without the input and with even derivatives only
        are kept.
    harmonics : int
        Harmonics of the cosine balance.
    top : float
        Largest first-harmonic amplitude a1 of the march.

    Returns
    -------
    tuple of (float, float, float)
        (omega, a1, peak) from a1 = 0 up to ``top`` (or where Newton fails), peak =
        y(0) = a0 + a1 + ... + aH the turning point; empty if there is no backbone.
    """
    terms = tuple(t for t in model.terms
                  if not t.u_orders and all(o % 2 == 0 for o in t.y_orders))
    if not terms or not any(t.is_linear_output for t in terms) or not top > 0:
        return ()
    omega0 = _linear_resonance(terms)
    if omega0 is None:
        return ()
    balance = Balance(terms, harmonics)
    cos = [0] + [2 * k - 1 for k in range(1, harmonics + 1)]
    free = [i for i in cos if i != 1]
    out = [(omega0, 0.0, 0.0)]
    x = np.zeros(balance.size)
    omega = omega0
    previous: tuple[np.ndarray, float] | None = None
    for i in range(1, BACKBONE_STEPS + 1):
        a1 = top * i / BACKBONE_STEPS
        guess_x, guess_w = x.copy(), omega
        if previous is not None:
            guess_x = 2 * x - previous[0]
            guess_w = 2 * omega - previous[1]
        guess_x[1] = a1
        solved = _newton(balance, guess_x, guess_w, cos, free)
        if solved is None:
            break
        previous = (x, omega)
        x, omega = solved
        if not omega > 0:
            break
        out.append((float(omega), float(a1), float(np.sum(x[cos]))))
    return tuple(out)


def _newton(balance: Balance, x: np.ndarray, omega: float, rows: list[int],
            free: list[int]) -> tuple[np.ndarray, float] | None:
    x = x.copy()
    for _ in range(20):
        e = balance.evaluate(x, omega, 0.0)
        jac = np.column_stack([e.jac_x[np.ix_(rows, free)], e.jac_omega[rows]])
        try:
            step = np.linalg.solve(jac, -e.residual[rows])
        except np.linalg.LinAlgError:
            return None
        if not np.isfinite(step).all():
            return None
        x[free] += step[:-1]
        omega += float(step[-1])
        if np.max(np.abs(step)) <= 1e-12 * max(float(np.max(np.abs(x))), abs(omega)):
            return x, omega
    return None
