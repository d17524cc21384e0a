"""Formula-by-formula check of the paper: each regenerated formula against the printed one.

Printed formulas are transcribed once here, quoted with their equation numbers; every
regenerated value comes from the program (perturbation series, averaging, energy and
HAM modules, or a Lagrangian derivation).  A check with ``agrees=False`` is a misprint
or an inconsistency; ``corrected`` then holds the corrected form.  Checks of text
(captions, equation references) have ``kind="text"``.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from gfrf._results import Result
from gfrf.periodic.averaging import averaged_equations, averaging_equilibria
from gfrf.periodic.energy import energy_formulas
from gfrf.periodic.homotopy import paper_ham_first_order
from gfrf.periodic.perturbation import perturbation_series

__all__ = ["FormulaCheck", "formula_checks"]

a, c, d, e, h, tau, th, ph, B = sp.symbols("a c delta epsilon h tau theta phi B")


@dataclass(frozen=True, kw_only=True)
class FormulaCheck(Result):
    """One printed formula (or reference) against its regenerated form.

    Attributes
    ----------
    equation : str
        Equation number or place in the paper.
    quantity : str
        What is compared.
    printed, regenerated : str
        The printed form (quoted) and what the program derives.
    agrees : bool
        Mathematical agreement.
    corrected : str
        Corrected form when ``agrees`` is False (else empty).
    note : str
        Reason, conventions, or the size of the discrepancy.
    kind : str
        ``"formula"`` or ``"text"``.
    inherits : str
        For a formula that follows correctly from an earlier printed one but is wrong
        because that one is: the earlier equation (``agrees`` is then False).
    """

    equation: str
    quantity: str
    printed: str
    regenerated: str
    agrees: bool
    corrected: str = ""
    note: str = ""
    kind: str = "formula"
    inherits: str = ""


def _zero(expr: sp.Expr) -> bool:
    return sp.simplify(sp.expand(expr)) == 0


def _lagrangian_checks() -> list[FormulaCheck]:
    t, s, m, L, A, w, g = sp.symbols("t s m L A omega g", positive=True)
    q = sp.Function("theta")(t)
    y = A * sp.cos(w * t)
    V = m * g * (y + L * sp.cos(q))
    T_printed = m / 2 * (L * q.diff(t) * sp.cos(q) ** 2 + (y.diff(t) - L * q.diff(t)
                                                           * sp.sin(q)) ** 2)
    T_fixed = m / 2 * ((L * q.diff(t) * sp.cos(q)) ** 2 + (y.diff(t) - L * q.diff(t)
                                                           * sp.sin(q)) ** 2)
    eps, delta = A / L, -g / (L * w**2)

    def residual(T: sp.Expr) -> sp.Expr:
        H = T - V
        eom = sp.diff(H.diff(q.diff(t)), t) - H.diff(q)
        target = q.diff(t, 2) + w**2 * (delta + eps * sp.cos(w * t)) * sp.sin(q)
        return sp.simplify(eom / (m * L**2) - target)

    ok_fixed, res_printed = _zero(residual(T_fixed)), residual(T_printed)
    return [
        FormulaCheck(equation="(1)",
                     quantity="kinetic energy T",
                     printed="T = m/2 [L θ' cos(θ)^2 + (y' - L θ' sin θ)^2]",
                     regenerated="T = m/2 [(L θ' cos θ)^2 + (y' - L θ' sin θ)^2] gives (3) exactly",
                     agrees=_zero(res_printed),
                     corrected="T = m/2 [(L θ' cos θ)^2 + (y' - L θ' sin θ)^2]",
                     note="the printed T (square on cos only) is not even dimensionally "
                          "consistent; its Euler-Lagrange equation is not (3), the corrected T "
                          "gives (3)"),
        FormulaCheck(equation="(3)",
                     quantity="equation of motion, eps = A/L, delta = -g/(L omega^2)",
                     printed="θ'' + (δ + ε cos t) sin θ = 0",
                     regenerated="same (t = ω t_phys)",
                     agrees=ok_fixed),
    ]


def _perturbation_checks() -> list[FormulaCheck]:
    s0 = perturbation_series("0", 2, "kernel")
    s4 = perturbation_series("1/4", 2, "kernel")
    x1 = s0.harmonic_expr(1, 1)
    x2c2 = s0.harmonic_expr(2, 2)
    d0 = s0.delta_expr()
    d4 = s4.delta_expr()
    printed_x1 = -a * (a**2 - 6) / 6
    printed_x2 = a * (12 - 8 * a**2 + a**4) / 96
    printed_d4 = sp.Rational(1, 4) - e / 2 + (a**2 / 32 - sp.Rational(1, 8)) * e**2
    u1 = s4.harmonic_expr(1, 3)
    u2_5, u2_3 = s4.harmonic_expr(2, 5), s4.harmonic_expr(2, 3)
    return [
        FormulaCheck(equation="(10)", quantity="x1", printed="x1 = -(1/6) cos(t) a (a^2 - 6)",
                     regenerated=f"x1 = ({x1}) cos t", agrees=_zero(x1 - printed_x1)),
        FormulaCheck(equation="(11)",
                     quantity="x2",
                     printed="x2 = (1/96) a (12 - 8a^2 + a^4)(cos 2t - 1)",
                     regenerated=f"x2 = ({x2c2}) cos 2t + C2",
                     agrees=_zero(x2c2 - printed_x2),
                     corrected="",
                     note="the cos 2t coefficient agrees; the constant -1 (x2(0) = 0) contradicts "
                     "the rule C1 = C2 = 0 the paper applies to x1 in (10) (zero mean). Either "
                     "choice is legitimate but changes what 'a' means at O(eps^3)"),
        FormulaCheck(equation="(12)",
                     quantity="delta2",
                     printed="δ2 = (1/4)(a^2 - 2)",
                     regenerated=str(d0.coeff(e, 2)),
                     agrees=_zero(d0.coeff(e, 2) - (a**2 - 2) / 4)),
        FormulaCheck(equation="(13)",
                     quantity="transition curve through 0",
                     printed="δ = (1/4)(a^2 - 2) ε^2",
                     regenerated=str(d0),
                     agrees=_zero(d0 - (a**2 - 2) / 4 * e**2),
                     corrected="",
                     note="'a' is the mean of x (x0 = a), not x(0): by (14) "
                     "x(0) = a + ε a (1 - a^2/6) + O(ε^2); the program uses x(0)"),
        FormulaCheck(equation="(15)",
                     quantity="transition curve through 1/4",
                     printed="δ = 1/4 - ε/2 + (a^2/32 - 1/8) ε^2",
                     regenerated=str(d4),
                     agrees=_zero(d4 - printed_d4),
                     corrected="",
                     note="'a' scales with 1/eps: the orbit is x = ε a cos(t/2) + ..., so "
                     "x(0) = ε a (1 + ε/4 + O(ε^2)); the program uses a = x(0)/ε"),
        FormulaCheck(equation="(16)",
                     quantity="orbit on the 1/4 curve",
                     printed="x = a{cos(t/2)ε + (1/4)cos(3t/2)ε^2 + (1/48 cos(5t/2) - "
                     "(a^2/192 + 1/16) cos(3t/2) ε^3)}",
                     regenerated=f"u1 = ({u1}) cos(3t/2); u2 = ({u2_5}) cos(5t/2) + "
                                 f"({u2_3}) cos(3t/2)",
                     agrees=False,
                     corrected="x = a{cos(t/2)ε + (1/4)cos(3t/2)ε^2 + (1/48 cos(5t/2) - "
                     "(a^2/192 + 1/16) cos(3t/2)) ε^3}",
                     note=("all three coefficients agree"
                           if _zero(u1 - a / 4) and _zero(u2_5 - a / 48)
                           and _zero(u2_3 + a**3 / 192 + a / 16) else "COEFFICIENTS DIFFER")
                     + "; the closing parenthesis is misplaced so that ε^3 multiplies only "
                     "the cos(3t/2) term"),
        FormulaCheck(equation="Figure 2 caption",
                     quantity="equation cited",
                     printed="analytical results of Equation (24)",
                     regenerated="section 3 text: (16)",
                     agrees=False,
                     corrected="Equation (16)",
                     note="(24) is the m-th order deformation equation of the HAM",
                     kind="text"),
    ]


def _ham_checks() -> list[FormulaCheck]:
    out = paper_ham_first_order()
    printed_g0 = -d * (c**2 - 8) / 8
    printed_g1 = d**2 * (c**2 - 8) * (9 * c**2 - 8) * h / 64
    printed_x1 = h * c / 6 * (c**2 * e * sp.cos(tau) ** 5 + c**2 * (d - e) * sp.cos(tau) ** 4
                              - c**2 * d * sp.cos(tau) ** 3
                              + (6 - sp.Rational(3, 4) * c**2) * d * sp.cos(tau) ** 2
                              + (sp.Rational(3, 4) * c**2 * d + 3 * tau * e * sp.sin(tau)
                                 - 6 * d) * sp.cos(tau) + 3 * d * tau * sp.sin(tau))
    g1 = out["gamma1"]
    return [
        FormulaCheck(equation="(17)",
                     quantity="time scaling",
                     printed="γ x'' + (δ + ε cos τ)(x - x^3/6) = 0, τ = Ω t",
                     regenerated="with τ = Ω t the excitation is cos(τ/Ω), not cos τ",
                     agrees=False,
                     corrected="γ x'' + (δ + ε cos(τ/Ω))(x - x^3/6) = 0",
                     note="as printed, (17) is (4) only if Ω = 1; moreover γ0 = δ(1 - c^2/8) < 0 "
                     "for δ < 0, so Ω is imaginary and (32) is not a periodic orbit of (4)"),
        FormulaCheck(equation="(23)",
                     quantity="γ_n",
                     printed="γ(q) = γ0 + Σ γ_n(τ) q^n",
                     regenerated="γ_n are constants",
                     agrees=False,
                     corrected="γ(q) = γ0 + Σ γ_n q^n",
                     note="(23) second line itself defines constants",
                     kind="text"),
        FormulaCheck(equation="(29)",
                     quantity="x1 of the HAM",
                     printed="x1 = (1/6)hc(c^2 ε cos^5 τ + ... + 3δτ sin τ)",
                     regenerated=f"x1 = {out['x1']}",
                     agrees=_zero(printed_x1 - out["x1"]),
                     corrected=f"x1 = {out['x1']}",
                     note="the printed x1 contains secular terms τ sin τ although γ0 of (30) "
                     "removes the only resonant harmonic; regenerated with x1(0) = x1'(0) = 0"),
        FormulaCheck(equation="(30)",
                     quantity="γ0",
                     printed="γ0 = -(1/8) δ (c^2 - 8)",
                     regenerated=str(out["gamma0"]),
                     agrees=_zero(out["gamma0"] - printed_g0)),
        FormulaCheck(equation="(30)",
                     quantity="γ1",
                     printed="γ1 = (1/64) δ^2 (c^2 - 8)(9c^2 - 8) h",
                     regenerated=str(g1),
                     agrees=_zero(g1 - printed_g1),
                     corrected=str(g1),
                     note="the printed γ1 does not vanish in the linear autonomous limit "
                     "(c -> 0, ε = 0) where γ = δ exactly; the regenerated one does and, "
                     "with h = -1, δ = 1, reproduces the Lindstedt value 1 - c^2/8 - c^4/1536"),
    ]


def _energy_checks() -> list[FormulaCheck]:
    f = energy_formulas()
    a, th, ph, d, e = sp.symbols("a theta phi delta epsilon", positive=True)  # as in energy.py
    printed39 = 1 - a**2 / 16 - a**2 * sp.cos(2 * th) / 48
    printed47 = (d * (1 - a**2 / 16) * (1 - a**2 / 6)
                 + (1 - a**2 / 16) * e * sp.cos(2 * ph) * (1 - a**2 / 12) / 4)
    diff47 = sp.expand(f["47_theta"] - printed47)
    printed47e = a**2 / 4 * sp.sqrt(d) * e * (1 - a**2 / 12) * sp.sin(2 * ph) * (1 - a**2 / 16)
    diff47e = sp.expand(f["47_energy"] - printed47e)
    return [
        FormulaCheck(equation="(33)-(38)",
                     quantity="system cited",
                     printed="根据能量法, 系统(43)对应的能量坐标变换",
                     regenerated="the transformation belongs to system (33)",
                     agrees=False,
                     corrected="系统(33)",
                     note="(43) is the θ-equation derived later",
                     kind="text"),
        FormulaCheck(equation="(34)",
                     quantity="condition x g(x) > 0",
                     printed="x g(x) > 0 (x ≠ 0)",
                     regenerated="x g(x) = δ x^2 (1 - x^2/6) < 0 for δ < 0",
                     agrees=False,
                     corrected="needs δ > 0 (and |x| < √6)",
                     note="the energy method therefore cannot treat the inverted pendulum δ < 0; "
                     "sqrt(δ) in (39) is imaginary there"),
        FormulaCheck(equation="(39)",
                     quantity="velocity factor",
                     printed="1 - a^2/16 - a^2 cos(2θ)/48",
                     regenerated=str(f["39_factor"]),
                     agrees=_zero(f["39_factor"] - printed39),
                     corrected="",
                     note="first-order expansion of sqrt(1 - a^2/8 - a^2 cos(2θ)/24)"),
        FormulaCheck(equation="(44)",
                     quantity="da/dE",
                     printed="(g(-a) - g(a)) / (2 g(-a) g(a))",
                     regenerated=str(f["44"]),
                     agrees=_zero(f["44"] - 1 / (d * a * (1 - a**2 / 6))),
                     corrected="",
                     note="= 1/g(a)"),
        FormulaCheck(equation="(47) first",
                     quantity="θ-average of dE/dt",
                     printed="(a^2/4)√δ ε (1 - a^2/12) sin 2φ "
                     "(1 - a^2/16)",
                     regenerated=str(f["47_energy"]),
                     agrees=diff47e.coeff(a, 2) == 0 and diff47e.coeff(a, 4) == 0,
                     corrected="",
                     note=f"agrees to O(a^4): exact average - printed = {diff47e} (the printed "
                     "product drops this a^6 term, which is beyond the O(a^2) accuracy of the "
                     "velocity factor (39); it does not change the roots φ = 0, π/2)"),
        FormulaCheck(equation="(47) second",
                     quantity="θ-average of dθ/dt (times √δ(1 - a^2/6))",
                     printed="√δ(1 - a^2/16) + (1 - a^2/16) ε cos 2φ (1 - a^2/12)/(4√δ(1 - a^2/6))",
                     regenerated=str(f["47_theta"]),
                     agrees=_zero(diff47),
                     corrected=f"{f['47_theta']} = √δ(1 - a^2/6)/2",
                     note="the printed average keeps only part of the O(ε a^2) terms: coefficient "
                     f"of ε a^2 cos 2φ is {f['47_theta'].coeff(e).coeff(a, 2) / sp.cos(2 * ph)}"
                     f" exactly, {sp.expand(printed47).coeff(e).coeff(a, 2) / sp.cos(2 * ph)} "
                     "as printed; (48)-(49) inherit this (energy variant 'consistent' fixes it)"),
    ] + _energy_upper_checks(f, printed47)


def _energy_upper_checks(f: dict[str, sp.Expr], printed47: sp.Expr) -> list[FormulaCheck]:
    """(48)-(49) from the printed (47) at ``phi = 0, pi/2``, and (51) from (46)."""
    a, th, ph, d, e = sp.symbols("a theta phi delta epsilon", positive=True)
    bracket = {sgn: sp.sqrt(d) * (1 - a**2 / 16) * (1 + sgn * e * (1 - a**2 / 12)
                                                       / (4 * d * (1 - a**2 / 6)))
               for sgn in (1, -1)}  # printed (48) (sgn = 1) and (49) (sgn = -1)
    # (47) second times sqrt(delta)(1 - a^2/6): equal to the printed (48)/(49) times the same
    regen = {sgn: printed47.subs(ph, 0 if sgn == 1 else sp.pi / 2) for sgn in (1, -1)}
    ok = {sgn: _zero(regen[sgn] - sp.expand(bracket[sgn] * sp.sqrt(d) * (1 - a**2 / 6)))
          for sgn in (1, -1)}
    exact = {sgn: f["47_theta"].subs(ph, 0 if sgn == 1 else sp.pi / 2) for sgn in (1, -1)}
    # O(eps a^2) coefficient of (printed - exact)
    err = {sgn: sp.expand(regen[sgn] - exact[sgn]).coeff(e).coeff(a, 2) for sgn in (1, -1)}
    s39 = 1 - a**2 / 16 - a**2 * sp.cos(2 * th) / 48
    printed51_e = (a**2 / 4 * sp.sqrt(d) * e * (1 - a**2 * sp.cos(th) ** 2 / 6)
                   * (-sp.sin(4 * th)) * s39)
    printed51_t = s39 * (d * (1 - a**2 / 6) + (-1 - 2 * sp.cos(2 * th) - sp.cos(4 * th)) * e / 4
                         * (1 - a**2 * (sp.cos(2 * th) + 1) / 12))
    ok51 = (_zero(sp.expand_trig(f["46_energy"].subs(ph, sp.pi / 2) - printed51_e))
            and _zero(sp.expand_trig(f["46_theta"].subs(ph, sp.pi / 2) - printed51_t)))
    def inherited(sgn: int) -> str:
        where = "φ = 0" if sgn == 1 else "φ = π/2"
        follows = "follows exactly from" if ok[sgn] else "does NOT follow from"
        return (f"{follows} the printed (47) second line at {where}, so it inherits that "
                f"line's O(ε a^2) error: in the polynomial form (times √δ(1 - a^2/6)), "
                f"printed - exact = {err[sgn]} ε a^2; the corrected form is energy variant "
                "'consistent'")

    return [
        FormulaCheck(equation="(48)",
                     quantity="lower curve from (47), φ = 0",
                     printed="√δ(1 - a^2/16)(1 + ε(1 - a^2/12)/(4δ(1 - a^2/6))) = 1/2",
                     regenerated=f"{sp.factor(regen[1])} = √δ(1 - a^2/6)/2",
                     agrees=False,
                     corrected=f"{exact[1]} = √δ(1 - a^2/6)/2",
                     note=inherited(1), inherits="(47) second"),
        FormulaCheck(equation="(49)",
                     quantity="upper curve from (47), φ = π/2",
                     printed="√δ(1 - a^2/16)(1 - ε(1 - a^2/12)/(4δ(1 - a^2/6))) = 1/2",
                     regenerated=f"{sp.factor(regen[-1])} = √δ(1 - a^2/6)/2",
                     agrees=False,
                     corrected=f"{exact[-1]} = √δ(1 - a^2/6)/2",
                     note=inherited(-1) + "; (49) is (48) with ε -> -ε and always has a real root",
                     inherits="(47) second"),
        FormulaCheck(equation="(51)",
                     quantity="system at φ = π/2",
                     printed="(50) with sin 4θ -> -sin 4θ and 1 + 2cos 2θ + cos 4θ -> its negative",
                     regenerated="(46) at φ = π/2 = (50) with ε -> -ε",
                     agrees=ok51,
                     corrected="",
                     note="x(0) = a cos(π/2) = 0: the orbit is odd, its turning point a is "
                          "at t ≈ π"),
    ]


def _averaging_checks() -> list[FormulaCheck]:
    e58, e59 = averaged_equations()
    dphi, dB, dth, t = sp.symbols("dphi dB dtheta t")
    p58 = B * (dphi + d - sp.Rational(1, 4) - d * B**2 / 8 + e * sp.cos(2 * ph) / 2
               - e * B**2 * sp.cos(2 * ph) / 12)
    p59 = dB + B * e * sp.sin(2 * ph) / 2 - e * B**3 * sp.sin(2 * ph) / 24
    # x = B cos θ, θ = t/2 - φ: x' = -(B/2) sin θ requires B' cos θ + B φ' sin θ = 0
    constraint = sp.expand(dB * sp.cos(th) - B * (sp.Rational(1, 2) - dphi) * sp.sin(th)
                           + B / 2 * sp.sin(th))
    printed54 = dB * sp.cos(th) + B * dth * sp.sin(th)
    cases = averaging_equilibria()
    printed_case2 = d - sp.Rational(1, 4) - d * B**2 / 8 + e / 2 - e * B**2 / 12
    printed_case3 = d - sp.Rational(1, 4) - d * B**2 / 8 - e / 2 + e * B**2 / 12
    return [
        FormulaCheck(equation="(54)",
                     quantity="variation-of-constants condition",
                     printed="B' cos θ + B θ' sin θ = 0",
                     regenerated=f"{constraint} = 0",
                     agrees=_zero(constraint - printed54),
                     corrected="B' cos θ + B φ' sin θ = 0",
                     note="θ' = 1/2 - φ' appears where φ' is needed; (55)-(59) are right and use "
                     "the corrected form (with the factor 1/2 when combining (54), (55))"),
        FormulaCheck(equation="(58)",
                     quantity="averaged phase equation",
                     printed=str(p58),
                     regenerated=str(e58),
                     agrees=_zero(e58 - p58)),
        FormulaCheck(equation="(59)",
                     quantity="averaged amplitude equation",
                     printed=str(p59),
                     regenerated=str(e59),
                     agrees=_zero(e59 - p59)),
        FormulaCheck(equation="section 6, case 2", quantity="equilibrium 2φ = 0 (lower curve)",
                     printed="δ - 1/4 - δB^2/8 + ε/2 - εB^2/12 = 0",
                     regenerated=f"{cases['case2']} = 0",
                     agrees=_zero(cases["case2"] - printed_case2)),
        FormulaCheck(equation="section 6, case 3",
                     quantity="equilibrium 2φ = π (upper curve)",
                     printed="δ - 1/4 - δB^2/8 - ε/2 + εB^2/12 = 0",
                     regenerated=f"{cases['case3']} = 0",
                     agrees=_zero(cases["case3"] - printed_case3),
                     corrected="",
                     note="case 2 with ε -> -ε; orbit x = B cos(t/2 - π/2) = B sin(t/2), x(0) = 0"),
        FormulaCheck(equation="Figure 10 caption",
                     quantity="parameters",
                     printed="ε = 0.1, 0.2, x(0) = 0.5",
                     regenerated="section 6 text: ε = 0.1, 0.3",
                     agrees=False,
                     corrected="ε = 0.1, 0.3 (or the text is "
                     "wrong)",
                     note="caption and text disagree",
                     kind="text"),
    ]


def formula_checks() -> list[FormulaCheck]:
    """All checks, in the order of the paper."""
    return (_lagrangian_checks() + _perturbation_checks() + _ham_checks() + _energy_checks()
            + _averaging_checks())
