"""Cost of the levels of proof: ||H1||, ||H3|| and r* at ``none``, ``float``, ``interval``.

For every bundled model with GFRFs the same quantity is computed at the three levels
of :data:`gfrf.bounds.rational.PROOF_LEVELS` in one run, and the times are reported as
ratios to the float path.  Each time is the best of a few repeats of a *cold*
computation: the memoised sups (:func:`gfrf.bounds.exact_sup.clear_caches`) are forgotten before
every call, while the symbolic kernels (the same at every level) are built once
beforehand.  Quantities:

* ``sup |H1|``: :func:`gfrf.bounds.rational.rational_sup` alone (exact decisions, then Arb
  ball enclosure of the stationary points, or numpy roots and double evaluation);
* ``||H1||``: :func:`gfrf.bounds.norms.h1_norm` as the CLI calls it (it also runs the
  python-control cross-check at every level);
* ``||H3||``: :func:`gfrf.bounds.norms.kernel_norm` (majorant, local search and, where the
  majorant is not attained, the branch-and-bound, whose cost is the same at every
  level but ``none``);
* ``r*``: :func:`gfrf.stability.criteria.verdict` at order 1 without norm brackets (majorant,
  radius and, at the interval level, the ball-arithmetic check of the supersolution;
  Theorem 2's loop radius for the cart-pole with lags).

The values agree across levels to rounding (the float path's difference from the
proven enclosure is shown); where they do not, the float path is wrong, not the proof.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from gfrf.bench import BenchSection, best_of, bundled_model

__all__ = ["run", "LEVELS"]

#: The levels timed, float (the reference of the ratios) first.
LEVELS = ("float", "none", "interval")
#: Cart-pole controller lags (s) for a loop with a proper controller (finite lambda_1).
LAGS = (0.01, 0.01, 0.01)


def _cases() -> list[tuple[str, str, Callable[[str], Any], Callable[[Any], float]]]:
    """(model label, quantity, function of the level, value of its result)."""
    from gfrf.bounds.majorant import linear_polynomials
    from gfrf.bounds.norms import h1_norm, kernel_norm
    from gfrf.bounds.rational import discrete_rational_sup, rational_sup
    from gfrf.model.modelfile import load_model
    from gfrf.stability.criteria import verdict
    from gfrf.stability.loops import with_lags

    cases: list[tuple[str, str, Callable[[str], Any], Callable[[Any], float]]] = []
    for name in ("hanging_pendulum", "hanging_pendulum_damped", "duffing", "cartpole",
                 "narx_example"):
        mf = load_model(bundled_model(f"{name}.toml"))
        plant = mf.plant
        num, den = linear_polynomials(plant)
        if plant.is_discrete:
            def sup(level: str, num: Any = num, den: Any = den, t: Any = plant.sample_time
                    ) -> Any:
                return discrete_rational_sup(num, den, t, level)
        else:
            def sup(level: str, num: Any = num, den: Any = den) -> Any:
                return rational_sup(num, den, level)
        cases.append((name, "sup |H1|", sup, lambda r: r.upper))
        cases.append((name, "||H1||", lambda level, p=plant: h1_norm(p, level),
                      lambda b: b.upper))
        cases.append((name, "||H3||", lambda level, p=plant: kernel_norm(p, 3, proof=level),
                      lambda b: b.upper))
        target = mf if name != "cartpole" else mf.plant
        cases.append((name if name != "cartpole" else "cartpole (plant)", "r*",
                      lambda level, m=target: verdict(m, 1, 0.01, False, level),
                      lambda v: v.radius))
    loop = with_lags(load_model(bundled_model("cartpole_reduced.toml")), LAGS)
    cases.append(("cart-pole loop, lags 0.01 s", "r* (Theorem 2)",
                  lambda level: verdict(loop, 1, 0.01, False, level), lambda v: v.radius))
    return cases


def run(quick: bool) -> BenchSection:
    """Time every case at every level; return the report section.

    Parameters
    ----------
    quick : bool
        Two repeats per timing instead of five.

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``.
    """
    from gfrf.bounds.exact_sup import clear_caches

    repeats = 2 if quick else 5
    rows: list[list[object]] = []
    worst: dict[str, float] = {}
    for label, quantity, f, value in _cases():
        for level in LEVELS:  # warm-up: symbolic kernels, imports, compiled code
            f(level)
        times, values = {}, {}
        for level in LEVELS:
            times[level], result = best_of(lambda lv=level, g=f: g(lv), repeats,
                                           before=clear_caches)
            values[level] = value(result)
        ratio = {lv: times[lv] / times["float"] for lv in LEVELS}
        key = quantity.split(" ")[0]
        worst[key] = max(worst.get(key, 0.0), ratio["interval"])
        proven, flt = values["interval"], values["float"]
        diff = (abs(flt - proven) / abs(proven) if proven and math.isfinite(proven)
                and math.isfinite(flt) else 0.0)
        rows.append([label, quantity.replace("|", "\\|"), f"{1e3 * times['float']:.2f}",
                     f"{1e3 * times['none']:.2f}", f"{1e3 * times['interval']:.2f}",
                     f"{ratio['none']:.2f}", f"{ratio['interval']:.2f}", f"{proven:.10g}",
                     f"{diff:.1e}"])
    goal = all(v < 3.0 for v in worst.values())
    notes = ["ratios are time / time of the float path of the same row, measured in this run; "
             "each time is the best of "
             f"{repeats} cold repeats (memoised sups cleared)",
             "largest interval/float ratio per quantity: "
             + ", ".join(f"{k} {v:.2f}" for k, v in worst.items())
             + f"; goal < 3x: {'met' if goal else 'NOT met'}, so the default level of "
             "`gfrf norm` and `gfrf verdict` is `interval`",
             "'float - proven' is the relative difference of the float path's value from the "
             "interval level's upper end (radius: its reported value)",
             "the cart-pole loop of the paper has an improper controller (lambda_1 = inf, "
             "r* = 0 at once); with lags T_i = 0.01 s the controller is proper and r* is the "
             "theta series radius (that linear loop is unstable; r* is still computed)"]
    return BenchSection(
        title="Proof levels",
        intro="Milliseconds per cold computation at the levels none, float and interval "
              "(`--proof`), and the ratios to the float path (same run).",
        columns=["model", "quantity", "float (ms)", "none (ms)", "interval (ms)",
                 "none / float", "interval / float", "proven value", "float - proven"],
        rows=rows, notes=notes)
