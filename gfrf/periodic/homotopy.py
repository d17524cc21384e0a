"""Homotopy analysis method (HAM, eqs (17)-(32)), set up so that it yields transition curves.

The paper's HAM (17)-(32) keeps ``delta`` fixed and treats ``gamma = Omega**2`` as the
unknown, which (a) replaces ``cos(t)`` by ``cos(tau)`` although ``tau = Omega t``, and
(b) gives ``gamma_0 = delta (1 - c**2/8) < 0`` for ``delta < 0``: ``Omega`` is imaginary,
so (32) is not a periodic orbit of (4) in real time.  :func:`paper_ham_first_order`
regenerates (29)-(30) for the formula check.

Here the same deformation equations are used with the frequency fixed by the branch and
``delta`` as the unknown eigenvalue (expanded ``delta = sum delta_m q**m`` like
``gamma`` in (23)):

* branch ``"1/4"``: ``tau = t/2``, ``x_0 = c cos(tau)``, ``L = d2/dt2 + 1/4``
  (``(1/4)(d2/dtau2 + 1)``, the paper's (27) up to a factor); the ``cos(tau)`` harmonic
  of each ``R_m`` fixes ``delta_{m-1}``;
* branch ``"0"``: ``tau = t``, ``x_0 = c``, ``L = d2/dt2``; the mean of ``R_m`` fixes
  ``delta_{m-1}``.

``x_m(0) = 0`` for ``m >= 1`` so ``x(0) = c`` (the API amplitude).  The order-``M``
approximation is ``x_0 + ... + x_M`` and ``delta_0 + ... + delta_M``.  The
convergence-control parameter ``h`` minimises the mean squared residual of (4) over a
period (computed exactly from the Fourier coefficients), unless given.
Eq (3) is handled through ``truncation`` (a high Taylor degree of ``sin``): nothing in the
deformation equations needs the cubic.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp
from scipy.optimize import minimize_scalar

from gfrf._results import Result
from gfrf.errors import ArgumentError
from gfrf.periodic.equation import parse_branch, sin_taylor_coefficients
from gfrf.periodic.fourier import CosSeries

__all__ = ["HamResult", "ham", "ham_optimal", "paper_ham_first_order"]


@dataclass(frozen=True, kw_only=True, repr=False)
class HamResult(Result):
    """HAM approximation of the periodic orbit on a transition curve.

    Attributes
    ----------
    branch : str
    eps, amplitude, h : float
        Excitation, ``x(0) = c`` and the convergence-control parameter.
    order : int
        ``M``: terms ``x_0..x_M``, ``delta_0..delta_M``.
    delta : float
        Sum ``delta_0 + ... + delta_M``.
    residual : float
        RMS of ``x'' + (delta + eps cos t) g(x)`` over a period.
    series : CosSeries
        The orbit as a function of ``tau`` (``t`` or ``t/2``); not in :meth:`to_dict`
        (its coefficients are a solver's internals; :meth:`solution` evaluates it).
    """

    _exclude = ("series",)

    branch: str
    eps: float
    amplitude: float
    h: float
    order: int
    delta: float
    residual: float
    series: CosSeries

    def solution(self, t: np.ndarray) -> np.ndarray:
        """``x(t)`` of the HAM approximation.

        Parameters
        ----------
        t : numpy.ndarray
            Dimensionless times.

        Returns
        -------
        numpy.ndarray
            x(t).
        """
        tau = np.asarray(t, dtype=float) / (1 if self.branch == "0" else 2)
        return self.series.evaluate(tau)


def _g(x: CosSeries, coeffs: dict[int, float]) -> CosSeries:
    out = CosSeries.zero(False)
    power = x
    for k in range(1, max(coeffs) + 1):
        if k > 1:
            power = power * x
        if k in coeffs:
            out = out + power * coeffs[k]
    return out


def ham(eps: float, amplitude: float, branch: str = "1/4", order: int = 4, h: float = -1.0,
        truncation: int = 3) -> HamResult:
    """HAM to ``order`` with a given ``h`` (see module docstring).

    Parameters
    ----------
    eps, amplitude : float
        Excitation and ``x(0) = c > 0``.
    branch : {"0", "1/4"}
    order : int
        Highest deformation order ``M >= 0``.
    h : float
        Convergence-control parameter (non-zero).
    truncation : int
        Odd Taylor degree of ``sin`` (3: eq (4)).
    """
    b = parse_branch(branch)
    if order < 0 or h == 0 or amplitude <= 0:
        raise ArgumentError(f"need order >= 0, h != 0, amplitude > 0 (got {order}, {h}, "
                            f"{amplitude})")
    cf = {k: float(v) for k, v in sin_taylor_coefficients(truncation).items()}
    p, kappa, lam0 = (1, 0, 0.0) if b == "0" else (2, 1, 0.25)
    x0 = CosSeries.cos(kappa, amplitude, exact=False)
    xs = [x0]
    gs: list[CosSeries] = []  # q**j coefficients of g(X): found from partial sums
    partial = x0
    deltas: list[float] = []
    g0 = _g(x0, cf)
    g0k = float(g0.harmonic(kappa)[0])
    if g0k == 0:
        raise ArgumentError(f"amplitude {amplitude} makes g(x_0) vanish on the kernel")

    def d2(s: CosSeries) -> CosSeries:  # d^2/dt^2 in terms of tau = t/p
        return s.map_harmonics(lambda k: -(k * k) / (p * p))

    for m in range(1, order + 2):
        gs.append(_q_coefficient(xs, cf, m - 1))
        rest = d2(xs[m - 1]) + gs[m - 1].mul_cos(p) * eps
        for i in range(m - 1):
            rest = rest + gs[m - 1 - i] * deltas[i]
        delta_m1 = -float(rest.harmonic(kappa)[0]) / g0k
        deltas.append(delta_m1)
        if m == order + 1:
            break
        R = rest + g0 * delta_m1
        xm = R.map_harmonics(lambda k: 0.0 if k == kappa else h / (lam0 - k * k / (p * p)))
        if m > 1:
            xm = xm + xs[m - 1]
        xm = xm - CosSeries.cos(kappa, float(xm.at_zero()[0]), exact=False)
        xs.append(xm)
        partial = partial + xm
    delta = float(sum(deltas))
    res = d2(partial) + _g(partial, cf) * delta + _g(partial, cf).mul_cos(p) * eps
    return HamResult(branch=b,
                     eps=eps,
                     amplitude=amplitude,
                     h=h,
                     order=order,
                     delta=delta,
                     residual=float(np.sqrt(res.mean_square())),
                     series=partial)


def _q_coefficient(xs: list[CosSeries], cf: dict[int, float], j: int) -> CosSeries:
    """``q**j`` coefficient of ``g(sum_i x_i q**i)`` (only ``x_0..x_j`` matter)."""
    out = CosSeries.zero(False)
    for k, c in cf.items():
        # coefficient of q^j in (sum x_i q^i)^k via repeated truncated products
        pw = [xs[i] if i < len(xs) else CosSeries.zero(False) for i in range(j + 1)]
        acc = pw
        for _ in range(k - 1):
            acc = [sum((acc[i] * pw[n - i] for i in range(n + 1)), CosSeries.zero(False))
                   for n in range(j + 1)]
        out = out + acc[j] * c
    return out


def ham_optimal(eps: float, amplitude: float, branch: str = "1/4", order: int = 4,
                truncation: int = 3, h_bounds: tuple[float, float] = (-2.0, -0.05)
                ) -> HamResult:
    """HAM with ``h`` minimising the squared residual on ``h_bounds`` (bounded Brent).

    At ``order = 0`` the approximation does not depend on ``h``; ``h = -1`` is reported.

    Parameters
    ----------
    eps : float
        The dimensionless forcing amplitude.
    amplitude : float
        x(0) of the orbit.
    branch : str, optional
        ``"0"`` or ``"1/4"``.
    order : int, optional
        The HAM order, >= 0.
    truncation : int, optional
        Odd Taylor degree of ``sin``.
    h_bounds : tuple of float, optional
        The interval of the convergence-control parameter h searched.

    Returns
    -------
    HamResult
        The approximation at the best h.
    """
    if order == 0:
        return ham(eps, amplitude, branch, 0, -1.0, truncation)
    opt = minimize_scalar(lambda h: ham(eps, amplitude, branch, order, h, truncation).residual,
                          bounds=h_bounds, method="bounded", options={"xatol": 1e-4})
    return ham(eps, amplitude, branch, order, float(opt.x), truncation)


def paper_ham_first_order() -> dict[str, sp.Expr]:
    """Regenerate (30) and (29) of the paper's own HAM formulation (17)-(28).

    ``N = gamma x'' + (delta + eps cos tau)(x - x**3/6)``, ``L = x'' + x``,
    ``x_0 = c cos tau``, ``x(0) = c``, ``x'(0) = 0``; ``gamma_m`` removes the ``cos tau``
    harmonic (the only secular one) from ``R_{m+1}``.

    Returns
    -------
    dict
        ``gamma0``, ``gamma1`` and ``x1`` (a sympy function of ``tau``).
    """
    from gfrf.periodic.fourier import trig_harmonic

    tau, c, d, e, h, g0, g1 = sp.symbols("tau c delta epsilon h gamma0 gamma1")
    x0 = c * sp.cos(tau)

    def nl(x: sp.Expr) -> sp.Expr:
        return (d + e * sp.cos(tau)) * (x - x**3 / 6)

    R1 = sp.expand(g0 * sp.diff(x0, tau, 2) + nl(x0))
    gamma0 = sp.solve(trig_harmonic(R1, tau, 1), g0)[0]
    R1 = sp.expand(R1.subs(g0, gamma0))
    # x'' + x = h R1 with x(0) = 0, x'(0) = 0: harmonic by harmonic (no cos tau left);
    # sin tau harmonics are absent because R1 is even in tau
    part = sum(h * trig_harmonic(R1, tau, k) * sp.cos(k * tau) / (1 - k * k)
               for k in (0, 2, 3, 4, 5))
    x1 = sp.expand(part - part.subs(tau, 0) * sp.cos(tau))
    R2 = sp.expand(gamma0 * sp.diff(x1, tau, 2) + g1 * sp.diff(x0, tau, 2)
                   + (d + e * sp.cos(tau)) * (x1 - x0**2 * x1 / 2))
    gamma1 = sp.solve(trig_harmonic(R2, tau, 1), g1)[0]
    return {"gamma0": sp.factor(gamma0), "gamma1": sp.factor(gamma1), "x1": x1}
