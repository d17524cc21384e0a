"""What escape means for a model: a certified escape region, or a level from its scale.

**Escape region of an oscillator.**  For ``a2 y'' + c y' + g(y) + b u = 0`` write
y'' = -k y' - f(y) + w with k = c/a2, f = g/a2, |w| <= W = |b/a2| U.  If
p(y) = -f(y) - W > 0 for every y >= y+, the set R+ = {y >= y+, y' >= 0} is forward
invariant for every input with sup|u| <= U (on y' = 0, y'' >= p(y) > 0; on y = y+,
y' >= 0 points inward), and in it y'' >= m - k y' with m = min p > 0 on [y+, inf),
so y' is eventually at least m / (2 max(k, 0) + m) > 0 and y grows without bound:
every solution that enters R+ escapes, whatever input of size U follows.  The same with
q(y) = f(y) - W on R- = {y <= -y-, y' <= 0}.  The positivity on the half-line is
checked exactly: every coefficient of p(y+ + t) (a Taylor shift in rationals) is
positive, so p(y+ + t) > 0 for t >= 0.

**A level from the model's scale.**  Otherwise escape is |z_j| >= level_j for some state
(any state: a velocity can blow up while y stays bounded): level_0 is
:data:`LEVEL_FACTOR` times the largest nonzero real equilibrium of the unforced
model (the potential barrier or separatrix of a softening restoring force), or
:data:`DEFAULT_LEVEL` when the model has none; level_j = level_0 * max(1, |lambda|)^j
for the j-th derivative (|lambda|: the largest linear eigenvalue modulus).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from gfrf.model.equation import Model

__all__ = ["EscapeRegion", "escape_region", "escape_levels", "LEVEL_FACTOR", "DEFAULT_LEVEL"]

#: Escape level: this many times the largest nonzero real equilibrium.
LEVEL_FACTOR = 100.0
#: Escape level of a model without a nonzero real equilibrium.
DEFAULT_LEVEL = 1e6


@dataclass(frozen=True)
class EscapeRegion:
    """R+ = {y >= y_plus, y' >= 0} and R- = {y <= -y_minus, y' <= 0} for sup|u| <= U.

    A side that does not exist (the restoring force does not soften that way) is
    ``inf``.  ``k``, ``f``, ``w`` describe y'' = -k y' - f(y) + w with |w| <= w_max.
    """

    amplitude: float
    y_plus: float
    y_minus: float
    k: Fraction
    f: dict[int, Fraction]
    gain: Fraction  # b / a2: w = -gain * u

    def flags(self) -> tuple[float, float, float]:
        """(1, y_plus, y_minus) for the compiled loop (inf sides never hit)."""
        return (1.0, self.y_plus, self.y_minus)

    def text(self) -> str:
        """The region in words."""
        sides = []
        if math.isfinite(self.y_plus):
            sides.append(f"y >= {self.y_plus:.6g} with y' >= 0")
        if math.isfinite(self.y_minus):
            sides.append(f"y <= {-self.y_minus:.6g} with y' <= 0")
        return " or ".join(sides)


def _structure(model: Model) -> tuple[Fraction, Fraction, dict[int, Fraction], Fraction] | None:
    from gfrf.stability.energy import _structure as structure

    s = structure(model)
    return None if isinstance(s, str) else s


def _shift(coeffs: list[Fraction], x: Fraction) -> list[Fraction]:
    """Coefficients of p(x + t) from those of p (ascending), exactly (Horner shifts)."""
    out = list(coeffs)
    n = len(out)
    for i in range(n - 1):
        for j in range(n - 2, i - 1, -1):
            out[j] += x * out[j + 1]
    return out


def _side(p: list[Fraction]) -> float:
    """Smallest float y0 found with every coefficient of p(y0 + t) > 0 (inf: none)."""
    while p and p[-1] == 0:
        p = p[:-1]
    if len(p) < 2 or p[-1] <= 0:
        return math.inf
    roots = [0.0]
    q = np.array([float(c) for c in p][::-1])
    while q.size > 1:
        r = np.roots(q)
        roots += [float(z.real) for z in r if abs(z.imag) <= 1e-9 * max(1.0, abs(z))]
        q = np.polyder(q)
    y0 = max(roots)
    for bump in (1e-9, 1e-6, 1e-3, 1e-1):
        y = y0 + bump * max(1.0, abs(y0))
        if all(c > 0 for c in _shift(p, Fraction(y))):
            return y
    return math.inf


def escape_region(model: Model, amplitude: float) -> EscapeRegion | None:
    """The certified escape region of an oscillator for inputs sup|u| <= ``amplitude``.

    Parameters
    ----------
    model : Model
        A continuous polynomial model.
    amplitude : float
        U.

    Returns
    -------
    EscapeRegion or None
        None when the model is not ``a2 y'' + c y' + g(y) + b u = 0`` or neither side
        exists.
    """
    s = _structure(model)
    if s is None or not math.isfinite(amplitude) or amplitude < 0:
        return None
    a2, c, g, b = s
    f = {n: q / a2 for n, q in g.items()}
    gain = b / a2
    w = abs(gain) * Fraction(amplitude)
    deg = max(f, default=1)
    fc = [f.get(i, Fraction(0)) for i in range(deg + 1)]
    plus = [-x for x in fc]
    plus[0] -= w
    # q(y) = f(-x) - W as a polynomial in x = -y >= y_minus
    minus = [fc[i] * (-1) ** i for i in range(deg + 1)]
    minus[0] -= w
    yp, ym = _side(plus), _side(minus)
    if math.isinf(yp) and math.isinf(ym):
        return None
    return EscapeRegion(amplitude=amplitude, y_plus=yp, y_minus=ym, k=c / a2, f=f, gain=gain)


def escape_levels(model: Model, eigenvalues: np.ndarray, n_states: int) -> np.ndarray:
    """The escape level of each state (y, y', ...; see the module docstring).

    Parameters
    ----------
    model : Model
        The model; its static terms (no input, no derivative) give the equilibria.
    eigenvalues : numpy.ndarray
        Eigenvalues of the Jacobian at rest (``OdeSystem.linear_eigenvalues``); the
        largest modulus, at least 1, scales the levels of the derivatives.
    n_states : int
        Number of states: y, y', ..., y^(n-1) (or the lags of y).

    Returns
    -------
    numpy.ndarray
        The n_states escape levels, each at most 1e300.
    """
    static: dict[int, float] = {}
    for term in model.terms:
        # at an equilibrium, every lag of a NARX model is y and every derivative is 0
        if not term.u_orders and (model.is_discrete or all(o == 0 for o in term.y_orders)):
            static[len(term.y_orders)] = static.get(len(term.y_orders), 0.0) + term.coefficient
    scale = 0.0
    if static:
        deg = max(static)
        poly = np.array([static.get(i, 0.0) for i in range(deg, -1, -1)])
        if deg >= 2 and np.all(np.isfinite(poly)) and poly[0] != 0:
            with np.errstate(all="ignore"):
                roots = np.roots(poly)
            real = [abs(z.real) for z in roots
                    if abs(z.imag) <= 1e-9 * abs(z) and abs(z) > 0 and math.isfinite(abs(z))]
            scale = max(real, default=0.0)
    level = LEVEL_FACTOR * scale if scale > 0 else DEFAULT_LEVEL
    rate = max(1.0, float(np.max(np.abs(eigenvalues)))) if eigenvalues.size else 1.0
    with np.errstate(over="ignore"):
        return np.array([min(level * rate**j, 1e300) for j in range(n_states)])
