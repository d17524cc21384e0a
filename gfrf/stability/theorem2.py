"""Theorem 2 of the GFRF stability paper (closed loop), with a rigorous series decision.

Theorem 2 (closed loop, plant kernels h_n, controller kernels s_n, reference r).
The tracking loop is internally L2 stable if
  1) all h_n and s_n are proper rational functions,
  2) the linear closed loop is L2 stable,
  3) with beta_n = ||h_n||, lambda_1 = ||s_1|| > 0, lambda_n = ||s_n|| <= alpha_n lambda_1^n,
     phi_1 = beta_1, phi_n = sum_{m=1}^n beta_m sum_{k_1+..+k_m=n} alpha_{k_1}..alpha_{k_m},
     rho_1 = ||g_1||, theta_1 = 1,
     theta_n = rho_1 sum_{m=2}^n phi_m lambda_1^m sum_{k_1+..+k_m=n} theta_{k_1}..theta_{k_m},
     the series sum phi_m lambda_1^m and sum theta_n rho_1^n converge,
  4) the reference spectrum is absolutely integrable.

The plant's norm series, its brackets and radii, and what "converges" means are those
of Theorem 1 (:mod:`gfrf.stability.theorem1`); the loop radius is the branch point of
the loop majorant's generating function, re-checked in ball arithmetic.

How the ambiguous symbols are read
----------------------------------
* rho_1.  Theorem 2 prints ||g_1|| = sup|(1 + h_1) s_1|; section 5 computes
  rho_1 = sup|(1 + h_1 s_1)^{-1}|, the sensitivity peak.  Only the latter makes the
  theta recursion a bound: the loop error e solves (1 + h_1 s_1) e_1 = r at first
  order and e_n = -g_1 [sum_{m>=2} N_m(e, .., e)]_n with ||N_m|| <= phi_m lambda_1^m, so
  ||e_n|| <= theta_n rho_1^n by induction.  We use the sensitivity peak
  (:attr:`gfrf.stability.loops.ClosedLoop.sensitivity_peak`) and report the literal reading too.
* alpha_1.  Undefined in the paper; lambda_1 = alpha_1 lambda_1 forces alpha_1 = 1.  A
  linear controller has lambda_n = alpha_n = 0 for n >= 2 ("<" read as "<="), so
  phi_n = beta_n.
* beta_n for an unstable plant (the inverted pendulum) is the sup of |h_n| on the
  frequency axis (an L-infinity, not H-infinity, norm), as the paper's beta_1 = 0.58 is.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gfrf.bounds.majorant import Majorant, Radius, certify, majorant, plant_radius, radius
from gfrf.bounds.radius_scaling import scaled_majorant
from gfrf.bounds.rational import check_proof, rational_sup
from gfrf.errors import ArgumentError
from gfrf.model.modelfile import ModelFile
from gfrf.stability.theorem1 import (
    _check_amplitude,
    _norm_level,
    _norms_and_series,
    _proper_condition,
    _radii,
    _series_condition,
    _summary,
)
from gfrf.stability.verdicts import Condition, Verdict

__all__ = ["theorem2", "theta_series", "phi_series"]


def theta_series(phi: list[float], lambda1: float, rho1: float, order: int) -> list[float]:
    """theta_1..theta_order of Theorem 2 from phi_1..phi_order (index 0 is phi_1).

    theta_1 = 1, theta_n = rho_1 sum_{m=2}^n phi_m lambda_1^m [x^n] Theta(x)^m, with
    Theta(x) = sum theta_k x^k (the sum over compositions k_1 + .. + k_m = n).
    An infinite rho_1 (a closed-loop pole on the axis) or phi_m bounds nothing:
    theta_n = inf for n >= 2.

    Parameters
    ----------
    phi : list of float
        phi_1..phi_order of :func:`phi_series` (index 0 is phi_1).
    lambda1 : float
        lambda_1, the H-infinity norm of the controller's linear part.
    rho1 : float
        rho_1, the sensitivity peak sup|(1 + h_1 s_1)^-1| of the linear closed loop.
    order : int
        Number of terms.

    Returns
    -------
    list of float
        theta_1..theta_order.
    """
    if not (math.isfinite(rho1) and all(math.isfinite(p) for p in phi[:order])):
        return [1.0] + [math.inf] * (order - 1)
    theta = np.zeros(order + 1)
    theta[1] = 1.0
    for n in range(2, order + 1):
        total = 0.0
        power = theta.copy()  # Theta^1, truncated
        for m in range(2, n + 1):
            power = np.convolve(power, theta)[: order + 1]
            if phi[m - 1]:
                total += phi[m - 1] * lambda1 ** m * power[n]
        theta[n] = rho1 * total
    return theta[1:].tolist()


def phi_series(beta: list[float], alpha: list[float], order: int) -> list[float]:
    """phi_1..phi_order: phi_n = sum_m beta_m sum_{k_1+..+k_m=n} alpha_{k_1}..alpha_{k_m}.

    ``beta[0]`` is beta_1 and ``alpha[0]`` is alpha_1 (= 1); phi_1 = beta_1.

    Parameters
    ----------
    beta : list of float
        beta_n = ||H_n||, the plant's kernel norms, index 0 is beta_1 (0: no such term).
        At least ``order`` entries.
    alpha : list of float
        alpha_1.. (``alpha[0]`` = 1); entries past ``order`` are ignored.
    order : int
        Number of terms.

    Returns
    -------
    list of float
        phi_1..phi_order.
    """
    a = np.zeros(order + 1)
    a[1:len(alpha) + 1] = alpha[:order]
    phi = np.zeros(order + 1)
    power = np.zeros(order + 1)
    power[0] = 1.0
    for m in range(1, order + 1):
        power = np.convolve(power, a)[: order + 1]
        if beta[m - 1]:
            with np.errstate(invalid="ignore"):  # 0 * inf: an absent term adds nothing
                phi += np.where(power > 0, beta[m - 1] * power, 0.0)
    return phi[1:].tolist()


def theorem2(model_file: ModelFile, order: int = 5, amplitude: float = 1.0,
             with_norms: bool = True, proof: str = "interval", *,
             norms: str | None = None) -> Verdict:
    """Theorem 2 (closed loop) for a model file with a controller.

    A transfer-function controller has lambda_n = alpha_n = 0 (n >= 2).  A polynomial
    controller (``[controller] equation``) gets its own certified majorant M^c_n >=
    lambda_n, and alpha_n = M^c_n / lambda_1^n; then sum_n phi_n lambda_1^n is the plant
    majorant evaluated at the controller majorant C(1), and the theta series has the
    generating function E = rho_1 r + rho_1 [B(C(E)) - beta_1 lambda_1 E].

    Parameters
    ----------
    model_file : ModelFile
        Plant and controller.
    order, amplitude, with_norms, proof, norms
        As in :func:`theorem1` (default ``norms="fast"``); the amplitude scales the
        reference r.  At the interval level the loop radius is re-checked in ball
        arithmetic with the proven upper ends of rho_1 and lambda_1.

    Returns
    -------
    Verdict
    """
    _check_amplitude(amplitude, order)
    check_proof(proof)
    level = _norm_level(with_norms, norms)
    controller = model_file.controller
    if controller is None:
        raise ArgumentError("Theorem 2 needs a controller; use theorem1 for an open loop")
    plant = model_file.plant
    from gfrf.stability.loops import closed_loop  # imports python-control: Theorem 2 only

    loop = closed_loop(model_file, proof=proof)
    maj = majorant(plant, proof)
    cmaj = (None if controller.is_linear else
            majorant(controller.model, proof))  # type: ignore[arg-type]
    lam, rho1 = loop.controller_norm, loop.sensitivity_peak
    plant_proper = _proper_condition(plant, maj, "plant h_n")
    ctrl_ok = loop.controller_proper and math.isfinite(lam) and (cmaj is None or cmaj.finite)
    c1 = Condition(name="plant h_n and controller s_n proper rational",
                   passed=(False if not ctrl_ok or plant_proper.passed is False
                           else plant_proper.passed),
                   value={"lambda_1": lam},
                   detail=("controller improper or unbounded: lambda_1 = "
                           f"{lam:g}; " if not ctrl_ok else "controller proper; ")
                   + plant_proper.detail)
    c2 = Condition(name="linear closed loop L2 stable", passed=loop.stable,
                   value=[complex(p) for p in loop.poles],
                   detail="characteristic polynomial " + _poly_text(loop.characteristic)
                   + ("" if loop.stable else "; " + "; ".join(loop.notes)))
    alpha = ([1.0] + [0.0] * (order - 1) if cmaj is None or not ctrl_ok else
             [float(m) / lam ** n for n, m in
              enumerate(cmaj.coefficients(order)[1:, 0], start=1)])
    c3 = Condition(name="lambda_1 > 0 finite, lambda_n <= alpha_n lambda_1^n",
                   passed=ctrl_ok and lam > 0,
                   value={"lambda_1": lam, "alpha": alpha},
                   detail="linear controller: lambda_n = alpha_n = 0 for n >= 2, phi_n = beta_n"
                   if cmaj is None else "alpha_n = M^c_n / lambda_1^n from the controller's "
                   "certified majorant M^c_n >= lambda_n")
    plant_rad = plant_radius(maj)
    norms, rows = _norms_and_series(plant, maj, order, amplitude, level)
    radii = _radii(plant, maj, plant_rad.value if maj.certified else 0.0, level != "none",
                   proof)
    exact = maj.certified and (cmaj is None or cmaj.certified)
    lam_up, rho1_up = loop.controller_norm_upper, loop.sensitivity_peak_upper
    if ctrl_ok:
        c_at_1 = lam_up if cmaj is None else _controller_output(cmaj)
        phi_ok = c_at_1 < plant_rad.certified_below
        c4 = Condition(name="sum phi_m lambda_1^m converges", passed=phi_ok if exact else None,
                       value={"controller_majorant_at_1": c_at_1, "plant_radius": plant_rad.value},
                       detail=f"the series is the plant majorant at amplitude C(1) = {c_at_1:.6g} "
                       f"(C = controller majorant; lambda_1 for a linear controller), "
                       f"plant radius {plant_rad.value:.6g} (units of the plant input u)")
        rad = _loop_radius(maj, lam_up, rho1_up, cmaj)
    else:
        c4 = Condition(name="sum phi_m lambda_1^m converges", passed=False, value={"lambda_1": lam},
                       detail="lambda_1 = inf: the series diverges from its second term")
        rad = Radius(0.0, 0.0, None, proof=proof)  # r* = 0: a trivially valid lower end
    c5 = _series_condition("sum theta_n rho_1^n r^n converges", rad, amplitude, exact)
    literal = _literal_rho(loop)
    c5 = Condition(name=c5.name, passed=c5.passed if ctrl_ok else False,
                   value={"rho_1": rho1, "rho_1_literal": literal, "radius": rad.value},
                   detail=f"rho_1 = sup|(1 + h1 s1)^-1| = {rho1:.6g} at w = "
                   f"{loop.sensitivity_peak_omega:.4g} rad/s (the literal sup|(1 + h1) s1| "
                   f"= {literal:.4g}); " + c5.detail)
    c6 = Condition(name="reference spectrum absolutely integrable", passed=True, value=None,
                   detail="hypothesis on the input, assumed; its size is the amplitude r")
    if ctrl_ok:
        phi = phi_series([row["majorant"] for row in rows], alpha, order)
        theta = theta_series(phi, lam, rho1, order)
        for row, ph, th in zip(rows, phi, theta, strict=True):
            row["phi"] = ph
            row["theta"] = th
            row["theta_term"] = th * (rho1 * amplitude) ** row["order"]
    conditions = (c1, c2, c3, c4, c5, c6)
    result = ("stable" if all(c.passed for c in conditions) else
              "unstable" if loop.outside else "inconclusive")
    summary = _summary(result, 2, rad, amplitude, conditions, exact)
    from gfrf.stability.loops import loop_text

    loop_upper, loop_detail = _loop_upper(model_file, level != "none" and proof == "interval",
                                          maj)
    if loop_upper is not None:
        summary += (f" In units of the reference r (loop {loop_text(controller)}): the loop's "
                    f"true radius is proven <= {loop_upper:.6g} ({loop_detail}).")
    if radii.upper is not None or radii.estimate is not None:
        summary += (" The plant's own norm series sum ||h_n|| u^n, in units of the plant "
                    "input u (not the loop):" + radii.text().lstrip(";") + ".")
    return Verdict(verdict=result,
                   theorem=2,
                   radius=rad.value,
                   radius_certified=exact,
                   amplitude=float(amplitude),
                   conditions=conditions,
                   norms=norms,
                   series=rows,
                   radius_estimate=radii.estimate,
                   summary=summary,
                   radius_proof=rad.proof,
                   radius_upper=radii.upper,
                   radius_upper_detail=radii.detail,
                   estimate_of="plant's own norm series sum ||h_n|| u^n, in units of u "
                               "(not the loop)",
                   estimate_lower=radii.lower if level != "none" else None,
                   loop=loop_text(controller),
                   loop_radius_upper=loop_upper,
                   loop_radius_upper_detail=loop_detail)


def _loop_upper(model_file: ModelFile, wanted: bool,
                maj: Majorant) -> tuple[float | None, str]:
    """The loop's proven upper radius in reference units (static fold of the loop's static
    map, :func:`gfrf.stability.static.loop_radius_upper`, on the plant's O(1) amplitude
    scale), or None with the reason."""
    from fractions import Fraction

    from gfrf.bounds.radius_scaling import amplitude_shift
    from gfrf.stability.static import loop_radius_upper

    controller = model_file.controller
    if not wanted or controller is None:
        return None, "not computed (proof level 'interval' and norms on only)"
    if not controller.is_linear:
        return None, "not computed for a polynomial controller"
    num, den = controller.exact_tf()
    num, den = num or (Fraction(1),), den or (Fraction(1),)
    if den[-1] == 0:
        return None, "C(0) is infinite (integral action): statically y = r, no fold"
    if num[-1] is None or den[-1] is None:
        return None, "C(0) as written is irrational: not computed"
    bound = loop_radius_upper(model_file.plant, num[-1] / den[-1],
                              controller.feedback, amplitude_shift(maj))
    if bound is None:
        return None, "no static branch point of the loop's static map proven"
    return bound.value, bound.detail


def _controller_output(cmaj: Majorant) -> float:
    """C(1) = sum_n M^c_n, the controller majorant at unit amplitude (inf if divergent,
    or, at the interval level, if the supersolution fails the ball-arithmetic check)."""
    x = certify(lambda z, r: cmaj.rhs(z, r), len(cmaj.powers), 1.0)
    if x is None or (cmaj.proof == "interval" and not cmaj.proves(x, 1.0)):
        return math.inf
    return float(x[0])


def _poly_text(coefficients: np.ndarray) -> str:
    """Monic polynomial in s as text, e.g. ``s^2 + 24.3538 s + 0.118901``."""
    monic = coefficients / coefficients[0]
    degree = monic.size - 1
    parts = []
    for i, c in enumerate(monic):
        power = degree - i
        var = "" if power == 0 else ("s" if power == 1 else f"s^{power}")
        coef = "" if (abs(c) == 1 and power) else f"{abs(c):.6g}"
        parts.append(("- " if c < 0 else "+ ") + (f"{coef} {var}".strip()))
    return " ".join(parts).lstrip("+ ")


def _literal_rho(loop: Any) -> float:
    """Theorem 2's printed sup|(1 + h1(jw)) s1(jw)| (reported, not used)."""
    num_p, den_p = loop.plant_poly  # the polynomials, not python-control objects
    num_c, den_c = loop.controller_poly
    return rational_sup(np.polymul(np.polyadd(den_p, num_p), num_c),
                        np.polymul(den_p, den_c)).value


def _loop_radius(maj: Majorant, lam: float, rho1: float,
                 cmaj: Majorant | None = None) -> Radius:
    """Radius in r of E = rho_1 r + rho_1 [B(C(E)) - beta_1 lambda_1 E] (certified).

    B is the plant majorant, C(E) the controller majorant (lambda_1 E for a linear
    controller); unknowns: plant majorant vector at amplitude C(E), controller majorant
    vector at amplitude E, and E.  ``proof`` of the result: ``"interval"`` when the
    majorants are proven and the supersolution at the certified end passes
    :func:`_loop_proves`; ``"none"`` for estimated majorants; else ``"float"``.
    """
    dim = len(maj.powers)
    cdim = 0 if cmaj is None else len(cmaj.powers)
    # A linear controller: solve on the plant's O(1) amplitude scale (x = alpha X,
    # e = 2^b E, r = 2^b R; :mod:`gfrf.bounds.radius_scaling`), exact powers of two.
    found = scaled_majorant(maj) if cmaj is None else None
    work, shift, alpha = (maj, 0, {ell: 0 for ell in maj.powers}) if found is None else found
    factor = math.ldexp(1.0, alpha[0] - shift)  # K_0 G(x, y) / 2^b in the scaled units
    beta1 = work.linear[0]

    def step(z: np.ndarray, r: float) -> np.ndarray:
        x, xc, e = z[:dim], z[dim:dim + cdim], z[-1]
        y = lam * e if cmaj is None else xc[0]
        x_new = work.rhs(x, y)
        xc_new = np.zeros(0) if cmaj is None else cmaj.rhs(xc, e)
        e_new = rho1 * r + rho1 * (beta1 * (y - lam * e)
                                   + factor * work.gains[0] * work.nonlinear(x, y))
        return np.concatenate([x_new, xc_new, [e_new]])

    rad = radius(step, dim + cdim + 1)
    proof = rad.proof
    levels = {maj.proof} | ({cmaj.proof} if cmaj is not None else set())
    if "none" in levels:
        proof = "none"
    elif levels == {"interval"} and rad.solution is not None and 0 < rad.certified_below < math.inf:
        for z in _slack_candidates(step, rad.solution, rad.certified_below):
            if _loop_proves(work, lam, rho1=rho1, cmaj=cmaj, z=z, r=rad.certified_below,
                            factor=factor):
                proof = "interval"
                break
    solution = None
    if rad.solution is not None:
        solution = np.array([*(math.ldexp(float(v), alpha[ell]) for v, ell in
                               zip(rad.solution[:dim], work.powers, strict=True)),
                             *rad.solution[dim:-1], math.ldexp(float(rad.solution[-1]), shift)])
    return Radius(math.ldexp(rad.value, shift), math.ldexp(rad.certified_below, shift),
                  solution, proof)


def _slack_candidates(step: Any, z: np.ndarray, r: float) -> list[np.ndarray]:
    """Points near the supersolution z to try the ball check at.

    The majorant components of the loop solution are exact fixed points given E (their
    step does not involve r), so step(z, r) <= z is an equality there that balls cannot
    confirm; only E has the slack rho_1 (r' - r).  z + t d with (I - J) d = z (J the
    Jacobian of the step, by finite differences; (I - J)^-1 >= 0 below the radius)
    has step(z + t d) ~ z + t d - t z: slack in every component.  Any candidate that
    passes the ball check is a proof, whatever produced it.
    """
    n = z.size
    jac = np.empty((n, n))
    base = step(z, r)
    for i in range(n):
        h = 1e-7 * max(abs(z[i]), float(np.max(np.abs(z))), 1e-300)
        e = z.copy()
        e[i] += h
        jac[:, i] = (step(e, r) - base) / h
    candidates = [z]
    try:
        d = np.linalg.solve(np.eye(n) - jac, z)
    except np.linalg.LinAlgError:
        return candidates
    if np.all(np.isfinite(d)) and np.all(d >= 0):
        candidates += [z + t * d for t in (1e-13, 1e-12, 1e-11, 1e-10, 1e-9)]
    return candidates


def _loop_proves(maj: Majorant, lam: float, rho1: float, cmaj: Majorant | None,
                 z: np.ndarray, r: float, factor: float = 1.0) -> bool:
    """Whether step(z, r) <= z holds for the loop system in Arb ball arithmetic.

    The same step as :func:`_loop_radius` with every operation rounded outward
    (lam, rho1 the proven upper ends): it proves the monotone iteration from 0 stays
    below z, so the theta series converges at amplitude r.
    """
    if not (np.all(np.isfinite(z)) and np.all(z >= 0) and math.isfinite(lam)
            and math.isfinite(rho1) and maj.finite and (cmaj is None or cmaj.finite)):
        return False
    from flint import arb

    dim = len(maj.powers)
    cdim = 0 if cmaj is None else len(cmaj.powers)
    zs = [arb(float(v)) for v in z]
    x, xc, e = zs[:dim], zs[dim:dim + cdim], zs[-1]
    lam_b, rho_b = arb(lam), arb(rho1)
    y = lam_b * e if cmaj is None else xc[0]
    new = maj.rhs_ball(x, y, y)
    if cmaj is not None:
        new += cmaj.rhs_ball(xc, e, e)
    extra = arb(0) if cmaj is None else arb(maj.linear[0]) * (y - lam_b * e)
    new.append(rho_b * arb(r) + rho_b * (extra + arb(factor) * arb(maj.gains[0])
                                         * maj.nonlinear_ball(x, y)))
    return all(a <= b for a, b in zip(new, zs, strict=True))
