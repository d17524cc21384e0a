"""The cart-pole loop of paper 001 (section 5) told straight: the linear-loop findings.

Code that exists only for this paper; the general library is :mod:`gfrf.stability.loops` and
:mod:`gfrf.stability.theorem2`.  Four findings, each a function returning a result object with
``to_dict``:

* :func:`inertia_reversal` - with the model's own signs (eq (16), negative feedback
  ``u = -(a s^2 + b s + c) theta``) the closed-loop theta'' coefficient is
  ``1 - 39.3185 a < 0``: the linear loop looks stable only because the improper
  controller's ``a s^2`` term reverses the sign of the inertia.
* :func:`lagged_loops` - any realisable version, the controller times ``1/(tau s + 1)^k``,
  has a right-half-plane pole near ``(39.3185 a - 1)/tau`` (python-control
  ``feedback``/``poles``).
* :func:`sign_margin` - with the physically right sign (``u = +K theta`` for this plant)
  the paper's ``c = 0.1331`` leaves a right-half-plane pole; the loop is stable exactly
  for ``c > c* = 67.578/39.3185`` (Routh-Hurwitz on the characteristic polynomial).
* :func:`theorem2_obstruction` - no proper, stable linear controller lets Theorem 2
  certify this plant (proof in the docstring), with a small search over PD-with-filter
  gains through :func:`gfrf.stability.theorem2.theorem2` that agrees.

The time-domain trials (the lagged *nonlinear* loop integrated until it diverges, the
closed loop driven at its own corner frequency) are in :mod:`gfrf.papers.cartpole_trials`.

Angular frequencies are in rad/s, times in s, angles in rad unless a name says deg.

Examples
--------
>>> from gfrf.model.modelfile import load_model
>>> mf = load_model("models/cartpole_reduced.toml")
>>> round(inertia_reversal(mf).coefficient, 4)
-612.3686
>>> sign_margin(mf).c_min
Fraction(135156, 78637)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from fractions import Fraction
from typing import Any

import numpy as np

from gfrf._results import Result, short_repr
from gfrf.bounds.majorant import linear_polynomials
from gfrf.errors import ArgumentError
from gfrf.model.modelfile import ModelFile
from gfrf.stability.loops import characteristic, closed_loop, controller_polynomials

__all__ = ["InertiaReversal", "LagRow", "SignMargin", "ControllerTrial",
           "Theorem2Obstruction", "inertia_reversal", "lagged_loops", "sign_margin",
           "theorem2_obstruction", "LAG_TIME_CONSTANTS", "PD_GRID"]

#: Lag time constants tau (s) of the realisable controllers (the paper: "T_i << 1").
LAG_TIME_CONSTANTS = (1e-3, 3e-3, 1e-2)

#: PD-with-filter gains (K_p, K_d, tau_f) tried by :func:`theorem2_obstruction`:
#: u = +(K_d s + K_p)/(tau_f s + 1) theta.  No point has K_d = tau_f K_p (the zero would
#: cancel the filter pole and leave closed-loop poles on the imaginary axis).
PD_GRID = tuple((kp, kd, tf) for kp in (1.8, 2.5, 4.0, 20.0) for kd in (0.05, 0.5, 5.0)
                for tf in (1e-3, 1e-2, 1e-1))


def _exact(x: float) -> Fraction:
    """The decimal a model file prints (shortest repr) as an exact rational."""
    return Fraction(repr(float(x)))


def _loop_parts(mf: ModelFile) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]:
    if mf.controller is None or not mf.controller.is_linear:
        raise ArgumentError(f"{mf.name or 'model'}: needs a transfer-function [controller]")
    num_p, den_p = linear_polynomials(mf.plant)
    num_c, den_c = controller_polynomials(mf.controller)
    if num_p.size != 1 or den_p.size != 3 or den_c.size != 1 or num_c.size != 3:
        raise ArgumentError("the cart-pole checks need a plant k/(s^2 + a1 s + a0) and a "
                            "controller a s^2 + b s + c")
    return num_p, den_p, num_c, den_c, mf.controller.feedback


def _poles(num_p: np.ndarray, den_p: np.ndarray, num_c: np.ndarray, den_c: np.ndarray,
           feedback: int) -> np.ndarray:
    """Closed-loop poles by python-control (``feedback`` sign as in the model file)."""
    import control

    loop = control.feedback(control.tf(num_p, den_p), control.tf(num_c, den_c),
                            sign=feedback)
    return np.sort_complex(np.asarray(control.poles(loop), dtype=complex))


@dataclass(frozen=True, kw_only=True)
class InertiaReversal(Result):
    """The ideal loop's theta'' coefficient with the model's own signs.

    Attributes
    ----------
    input_gain : float
        Coefficient of u in the plant equation (39.3185 in eq (16)).
    a : float
        The controller's s^2 coefficient.
    feedback : int
    coefficient : float
        theta'' coefficient of the closed loop, D_P[0] D_C[0] - f N_P[0] a (unnormalised).
    characteristic : tuple of float
        chi(s) = D_P D_C - f N_P N_C, highest power first, unnormalised.
    poles : tuple of complex
        Roots of chi (python-control).
    plant_leading : float
        theta'' coefficient of the plant alone (1); not in :meth:`to_dict` (``reversed``
        compares the two signs).
    """

    _exclude = ("plant_leading",)
    _order = ("input_gain", "a", "feedback", "coefficient", "reversed")

    input_gain: float
    a: float
    feedback: int
    coefficient: float
    characteristic: tuple[float, ...]
    poles: tuple[complex, ...]
    plant_leading: float

    @property
    def reversed(self) -> bool:
        """The closed loop's theta'' coefficient has the opposite sign of the plant's."""
        return (self.coefficient > 0) != (self.plant_leading > 0)

    @property
    def linear_stable(self) -> bool:
        return all(p.real < 0 for p in self.poles)

    def __repr__(self) -> str:
        return short_repr(self, "coefficient", "reversed")

    def _computed(self) -> dict[str, Any]:
        return {"reversed": self.reversed, "linear_stable": self.linear_stable}


def inertia_reversal(mf: ModelFile) -> InertiaReversal:
    """The closed-loop theta'' coefficient of the ideal loop (model's signs, file's feedback).

    With ``u = f (a s^2 + b s + c) theta`` and eq (16) ``theta'' - 67.578 theta + ... +
    39.3185 u = 0`` the closed loop is ``(1 + 39.3185 f a) theta'' + ...``; for
    ``f = -1`` this is ``1 - 39.3185 a``.

    Parameters
    ----------
    mf : ModelFile
        The cart-pole model file, with its controller.

    Returns
    -------
    InertiaReversal
        The coefficient and the gains it is formed from.
    """
    num_p, den_p, num_c, den_c, f = _loop_parts(mf)
    chi = characteristic((num_p, den_p), (num_c, den_c), f)
    lead = float(den_p[0] * den_c[0] - f * num_p[0] * num_c[0])
    return InertiaReversal(input_gain=float(-num_p[0] / den_p[0]),
                           a=float(num_c[0] / den_c[0]),
                           feedback=f,
                           coefficient=lead,
                           characteristic=tuple(float(x) for x in chi),
                           poles=tuple(complex(p) for p in _poles(num_p, den_p, num_c, den_c, f)),
                           plant_leading=float(den_p[0] * den_c[0]))


@dataclass(frozen=True, kw_only=True)
class LagRow(Result):
    """The loop with the controller divided by (tau s + 1)^lags.

    Attributes
    ----------
    tau : float
        Lag time constant (s).
    lags : int
        1 (a first-order filter) or 3 (the paper's eq (15) with T1 = T2 = T3 = tau).
    poles : tuple of complex
        Closed-loop poles (python-control).
    predicted : float or None
        For one lag, the large-pole estimate (input_gain * a - 1)/tau (rad/s).
    """

    _order = ("tau", "lags", "poles", "unstable")

    tau: float
    lags: int
    poles: tuple[complex, ...]
    predicted: float | None

    @property
    def unstable(self) -> tuple[complex, ...]:
        """Poles with Re s > 0."""
        return tuple(p for p in self.poles if p.real > 0)

    def _computed(self) -> dict[str, Any]:
        return {"unstable": self.unstable}


def lagged_loops(mf: ModelFile, taus: tuple[float, ...] = LAG_TIME_CONSTANTS,
                 lags: tuple[int, ...] = (1, 3), feedback: int | None = None) -> list[LagRow]:
    """Closed-loop poles with the controller times 1/(tau s + 1)^k (python-control).

    Parameters
    ----------
    mf : ModelFile
        Plant and ideal controller a s^2 + b s + c.
    taus : tuple of float
        Time constants (s), positive.
    lags : tuple of int
        Numbers k of equal first-order lags.
    feedback : int, optional
        Override the file's sign (+1: ``u = +C theta``).

    Returns
    -------
    list of LagRow
    """
    num_p, den_p, num_c, den_c, f = _loop_parts(mf)
    f = f if feedback is None else feedback
    rows = []
    for k in lags:
        for tau in taus:
            if not (math.isfinite(tau) and tau > 0) or k < 1:
                raise ArgumentError(f"lags need tau > 0 and k >= 1, got tau={tau!r}, k={k!r}")
            den = den_c
            for _ in range(k):
                den = np.polymul(den, [tau, 1.0])
            gain = -f * num_p[0] / den_p[0] * num_c[0] / den_c[0]
            predicted = float(-(1.0 + gain) / tau) if k == 1 else None
            rows.append(LagRow(tau=float(tau), lags=k,
                               poles=tuple(complex(p) for p in
                                           _poles(num_p, den_p, num_c, den, f)),
                               predicted=predicted))
    return rows


@dataclass(frozen=True, kw_only=True)
class SignMargin(Result):
    """The loop with ``u = +(a s^2 + b s + c) theta`` (feedback +1) and its threshold on c.

    Attributes
    ----------
    c_file : float
        The paper's c.
    poles_file : tuple of complex
        Ideal loop poles at ``c_file`` with feedback +1 (python-control).
    c_min : Fraction
        Routh-Hurwitz threshold: stable iff c > c_min (ideal and one-lag loops).
    poles_below, poles_above : tuple of complex
        Ideal loop poles at c_min (1 - step) and c_min (1 + step).
    step : float
    c_max : dict
        tau -> upper limit of c for the one-lag loop (cubic Hurwitz condition).
    lag_poles_above : dict
        tau -> poles of the one-lag loop at c_min (1 + step).
    """

    _order = ("c_file", "poles_file", "c_min", "c_min_exact")

    c_file: float
    poles_file: tuple[complex, ...]
    c_min: Fraction
    poles_below: tuple[complex, ...]
    poles_above: tuple[complex, ...]
    step: float
    c_max: dict[float, float]
    lag_poles_above: dict[float, tuple[complex, ...]]

    def __repr__(self) -> str:
        return short_repr(self, "c_file", c_min=float(self.c_min))

    def _computed(self) -> dict[str, Any]:
        return {"c_min": float(self.c_min),
                "c_min_exact": f"{self.c_min.numerator}/{self.c_min.denominator}"}


def sign_margin(mf: ModelFile, taus: tuple[float, ...] = LAG_TIME_CONSTANTS,
                step: float = 1e-3) -> SignMargin:
    """The physically signed loop (feedback +1): poles at the paper's c and the threshold.

    chi(s; c) = D_P D_C - N_P N_C depends on c only through its constant term
    chi(0) = D_P(0) - N_P(0) c (D_C = 1 or tau s + 1).  For the ideal loop chi has
    degree 2 and is Hurwitz iff its three coefficients are positive; the s^2 and s
    coefficients (1 - N_P a, -N_P b) are positive for a, b > 0, so the loop is stable iff
    c > c_min = D_P(0)/N_P(0).  With one lag, chi = tau s^3 + A2 s^2 + A1 s + A0 is
    Hurwitz iff all A_i > 0 and A2 A1 > tau A0: the same c_min and an upper limit c_max.

    Parameters
    ----------
    mf : ModelFile
        The cart-pole model file, with its controller.
    taus : tuple of float, optional
        Time constants (s) of the one-lag loops examined.
    step : float, optional
        Relative offset of c from c_min at which the poles are reported.

    Returns
    -------
    SignMargin
        c_min, c_max per lag and the poles on either side.
    """
    num_p, den_p, num_c, den_c, _ = _loop_parts(mf)
    a, b, c = (_exact(x) / _exact(den_c[0]) for x in num_c)
    k, d2, d1, d0 = _exact(num_p[0]), _exact(den_p[0]), _exact(den_p[1]), _exact(den_p[2])
    if (d2 - k * a) <= 0 or (d1 - k * b) <= 0:
        raise ArgumentError("the s^2 or s coefficient of the ideal loop is not positive: "
                            "no c stabilises it")
    if k >= 0:
        raise ArgumentError("with u = +C theta the plant's input coefficient must oppose its "
                            "instability (N_P < 0): no smallest c")
    c_min = d0 / k

    def poles(cc: float, den: list[float] | None = None) -> tuple[complex, ...]:
        dc = np.array([1.0]) if den is None else np.array(den)
        return tuple(complex(p) for p in
                     _poles(num_p, den_p, np.array([float(a), float(b), cc]), dc, 1))

    c_max, lag_poles = {}, {}
    for tau in taus:
        t = _exact(tau)
        # chi = (d2 s^2 + d1 s + d0)(t s + 1) - k (a s^2 + b s + c)
        a2, a1 = d2 + d1 * t - k * a, d1 + d0 * t - k * b
        # A0 = d0 - k c > 0 and A2 A1 > d2 t A0  ->  c < (d0 - A2 A1 / (d2 t)) / k
        c_max[float(tau)] = float((d0 - a2 * a1 / (d2 * t)) / k) if a2 > 0 and a1 > 0 \
            else float(c_min)
        lag_poles[float(tau)] = poles(float(c_min) * (1 + step), [float(tau), 1.0])
    return SignMargin(c_file=float(c),
                      poles_file=poles(float(c)),
                      c_min=c_min,
                      poles_below=poles(float(c_min) * (1 - step)),
                      poles_above=poles(float(c_min) * (1 + step)),
                      step=step,
                      c_max=c_max,
                      lag_poles_above=lag_poles)


def _static_series(mf: ModelFile) -> tuple[Fraction, Fraction, Fraction]:
    """c1, c2, c3 of the static branch theta = c1 u + c2 u^2 + c3 u^3 + ... (exact).

    At zero frequency only the underived terms remain: F(theta, u) = sum a_ij theta^i u^j
    = 0; the coefficients follow order by order.  They equal H_n(0, .., 0) (the GFRF
    recursion evaluated at zero frequencies is this expansion).
    """
    a: dict[tuple[int, int], Fraction] = {}
    for r in mf.plant.coefficient_table():
        if any(r["y_orders"]) or any(r["u_orders"]):
            continue
        key = (len(r["y_orders"]), len(r["u_orders"]))
        a[key] = a.get(key, Fraction(0)) + _exact(r["coefficient"])

    def g(i: int, j: int) -> Fraction:
        return a.get((i, j), Fraction(0))

    if g(1, 0) == 0:
        raise ArgumentError("the static equation has no linear theta term")
    c1 = -g(0, 1) / g(1, 0)
    c2 = -(g(2, 0) * c1 ** 2 + g(1, 1) * c1 + g(0, 2)) / g(1, 0)
    c3 = -(2 * g(2, 0) * c1 * c2 + g(3, 0) * c1 ** 3 + g(2, 1) * c1 ** 2 + g(1, 1) * c2
           + g(1, 2) * c1 + g(0, 3)) / g(1, 0)
    return c1, c2, c3


@dataclass(frozen=True, kw_only=True)
class ControllerTrial(Result):
    """One PD-with-filter controller u = +(K_d s + K_p)/(tau_f s + 1) theta in Theorem 2.

    ``bound`` is the proof's ceiling on the certifiable amplitude for this controller,
    (2/(3 sqrt 3)) (lambda_1 rho_1)^(-3/2) |c3|^(-1/2); ``radius`` is gfrf's certified r*.
    """

    kp: float
    kd: float
    tau_f: float
    stable: bool
    lambda1: float
    rho1: float
    radius: float
    verdict: str
    bound: float


@dataclass(frozen=True, kw_only=True)
class Theorem2Obstruction(Result):
    """Why Theorem 2 cannot certify the cart-pole with a proper, stable linear controller.

    Attributes
    ----------
    beta1_floor : Fraction
        |h1(0)| (exact), a lower bound of beta_1 = ||h1||.
    c3 : Fraction
        h3(0, 0, 0) (exact), so beta_3 >= |c3|.
    kernel_h1_0, kernel_h3_0 : float
        The same two values from :func:`gfrf.kernels.recursion.kernel` (cross-check).
    ceiling : float
        sup over y > 0 of beta1_floor y - |c3| y^3 = (2/(3 sqrt 3)) beta1^(3/2) |c3|^(-1/2):
        no stabilising controller's theta-series converges at a reference size r at or
        above it.
    holds : bool
        The exact test 4 beta1^3 < 27 |c3| (ceiling < 1).
    trials : tuple of ControllerTrial
        The PD-with-filter search.
    """

    beta1_floor: Fraction
    c3: Fraction
    kernel_h1_0: float
    kernel_h3_0: float
    ceiling: float
    holds: bool
    trials: tuple[ControllerTrial, ...]

    @property
    def stabilising(self) -> tuple[ControllerTrial, ...]:
        return tuple(t for t in self.trials if t.stable)

    @property
    def best(self) -> ControllerTrial | None:
        """The stabilising trial with the largest certified r*."""
        return max(self.stabilising, key=lambda t: t.radius, default=None)

    def __repr__(self) -> str:
        return short_repr(self, "ceiling", "holds", trials=len(self.trials))

    def _computed(self) -> dict[str, Any]:
        return {"beta1_floor": float(self.beta1_floor), "c3": float(self.c3),
                "stabilising": len(self.stabilising),
                "certified_at_r1": sum(t.verdict == "stable" for t in self.trials),
                "best": self.best}


def theorem2_obstruction(mf: ModelFile, grid: tuple[tuple[float, float, float], ...] = PD_GRID
                         ) -> Theorem2Obstruction:
    """Prove that Theorem 2 cannot certify the cart-pole, and search PD-with-filter gains.

    **Claim.**  For the plant of eq (12) or (16) and *any* proper, stable, linear
    controller s1 = N_C/D_C for which the linear closed loop is stable, the series
    sum theta_n rho_1^n of Theorem 2 diverges; more generally it converges for no
    reference size r >= (2/(3 sqrt 3)) beta^(3/2) |c3|^(-1/2) (= :attr:`ceiling`,
    about 0.67), where beta = |h1(0)| = 39.3185/67.578 and c3 = h3(0, 0, 0).

    **Proof.**  (i) Take D_C monic; it is Hurwitz, so D_C(0) > 0.  As deg N_C <= deg D_C,
    chi = D_P D_C - f N_P N_C has leading coefficient 1, and Hurwitz chi has chi(0) > 0:
    -67.578 D_C(0) + 39.3185 f N_C(0) > 0, i.e. |s1(0)| > 67.578/39.3185 = 1/beta.
    Hence lambda_1 = sup|s1(jw)| >= |s1(0)| > 1/beta.  (ii) rho_1 >= 1: the sensitivity
    1/(1 + h1 s1) tends to 1 as w -> inf (h1 strictly proper, s1 proper); the literal
    sup|(1 + h1) s1| >= (1 + beta)|s1(0)| > 1 as well.  (iii) beta_3 = ||h3|| >= |h3(0,0,0)|
    = |c3|, the cubic Taylor coefficient of the static branch theta(u) (exact rationals
    in :func:`_static_series`), and phi_3 >= beta_3 alpha_1^3 = beta_3 (alpha_1 = 1),
    every phi_m >= 0.  (iv) With T(x) = sum theta_n x^n, Theorem 2's recursion is
    T = x + rho_1 Psi(lambda_1 T), Psi(y) = sum_{m>=2} phi_m y^m (non-negative
    coefficients).  If sum theta_n (rho_1 r)^n converges, its value T* solves it
    (Tonelli), and y = lambda_1 T* > 0 gives
    r = y/(lambda_1 rho_1) - Psi(y) < beta y - |c3| y^3 <= ceiling.
    With beta = 0.5818 and c3 = -0.0657 the exact test 4 beta^3 < 27 |c3| gives
    ceiling < 1: at the paper's r = 1 the series diverges.  QED.  (The first series,
    sum phi_m lambda_1^m, need not diverge: its lower bound sum |c_m| lambda_1^m
    converges for lambda_1 below the static branch's radius.)

    The search builds u = +(K_d s + K_p)/(tau_f s + 1) theta for each point of ``grid``,
    keeps those with a stable linear loop and runs :func:`gfrf.stability.theorem2.theorem2`
    (order 3, majorant only); each certified r* must lie below that controller's own
    ceiling (2/(3 sqrt 3)) (lambda_1 rho_1)^(-3/2) |c3|^(-1/2).

    Parameters
    ----------
    mf : ModelFile
        ``models/cartpole_reduced.toml`` or ``models/cartpole.toml``.
    grid : tuple of (K_p, K_d, tau_f)

    Returns
    -------
    Theorem2Obstruction
    """
    from gfrf.kernels.recursion import kernel
    from gfrf.stability.theorem2 import theorem2

    c1, c2, c3 = _static_series(mf)
    if c2 != 0 or c3 == 0:
        raise ArgumentError("the obstruction argument needs an odd static branch with c3 != 0")
    beta = abs(c1)
    holds = 4 * beta ** 3 < 27 * abs(c3)
    ceiling = 2.0 / (3.0 * math.sqrt(3.0)) * float(beta) ** 1.5 / math.sqrt(float(abs(c3)))
    h1_0 = float(np.real(kernel(mf.plant, 1)(0.0)))
    h3_0 = float(np.real(kernel(mf.plant, 3)(0.0, 0.0, 0.0)))
    trials = []
    ctrl = mf.controller
    if ctrl is None:
        raise ArgumentError(f"{mf.name or 'model'}: needs a [controller] table")
    for kp, kd, tf in grid:
        trial_mf = replace(mf, controller=replace(ctrl, num=(kd, kp), den=(tf, 1.0),
                                                  feedback=1))
        loop = closed_loop(trial_mf)
        lam, rho = loop.controller_norm, loop.sensitivity_peak
        bound = (2.0 / (3.0 * math.sqrt(3.0)) * (lam * rho) ** -1.5
                 / math.sqrt(float(abs(c3))))
        if loop.stable:
            v = theorem2(trial_mf, order=3, with_norms=False)
            trials.append(ControllerTrial(kp=kp,
                                          kd=kd,
                                          tau_f=tf,
                                          stable=True,
                                          lambda1=lam,
                                          rho1=rho,
                                          radius=v.radius,
                                          verdict=v.verdict,
                                          bound=bound))
        else:
            trials.append(ControllerTrial(kp=kp,
                                          kd=kd,
                                          tau_f=tf,
                                          stable=False,
                                          lambda1=lam,
                                          rho1=rho,
                                          radius=0.0,
                                          verdict="unstable",
                                          bound=bound))
    return Theorem2Obstruction(beta1_floor=beta,
                               c3=c3,
                               kernel_h1_0=h1_0,
                               kernel_h3_0=h3_0,
                               ceiling=ceiling,
                               holds=holds,
                               trials=tuple(trials))
