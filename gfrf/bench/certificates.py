"""The lower side of ``gfrf threshold``: the certificate search.

Per model: the CPU time of the search (:func:`gfrf.stability.sos.sos_certificate`: the
quadratic V, its degree-4 V-lambda improvement, every proposal re-checked in exact
rational arithmetic), the proven radius U (every input with sup|u| <= U) and the
witnessed escape of ``gfrf threshold`` (upper / lower: closer to 1 is tighter), beside
the baseline a user would write first: a quadratic Lyapunov function of the
linearisation with its largest provable input bound (the same exact check, degree 2).
For a NARX model the search is the invariant box then the invariant paving of its
recursion (:func:`gfrf.twosided.lower_narx.narx_lower`, both checked exactly) and the
baseline is the invariant box alone.  A loop with an improper controller (the cart-pole)
has no polynomial state form: its row times the whole ``gfrf threshold`` (the invariant
polygon of the implicit loop, checked exactly, and the witness search; no baseline), in
its class sup|d| with d = C r.
"""

from __future__ import annotations

import math
import os
import time

from gfrf.bench import BenchSection, bundled_model, load_note

__all__ = ["run"]


def _cases(quick: bool) -> list[tuple[str, object]]:
    import control

    from gfrf.model.equation import parse_model
    from gfrf.model.from_control import from_tf
    from gfrf.model.modelfile import Controller, ModelFile

    cases: list[tuple[str, object]] = [
        ("third-order plant", from_tf(control.tf([2], [1, 1.2, 3, 1]), {2: 0.3, 3: 0.5})),
        ("PI loop", ModelFile(plant=parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"),
                              controller=Controller(num=(0.5, 0.2), den=(1.0, 0.0)))),
        ("cubic damping", parse_model("D(y,2) + 0.2*D(y) + y - 0.3*D(y)**3 = u")),
    ]
    if not quick:
        cases += [("nonlinear damping", parse_model(
            "D(y,2) + 0.4*D(y) + 2*y + 0.5*y**2*D(y) + 0.8*y**3 = u")),
            ("hanging_pendulum_damped", bundled_model("hanging_pendulum_damped.toml"))]
        third = "D(y,3) + 1.2*D(y,2) + 3*D(y) + y + 0.6*y**2 + y**3 = 2*u"
        cases += [(f"third-order plant + {name} (four states)",
                   ModelFile(plant=parse_model(third), controller=Controller(num=num, den=den)))
                  for name, num, den in (("PI", (0.5, 0.2), (1.0, 0.0)),
                                         ("lead-lag", (1.0, 0.5), (1.0, 2.0)))]
    cases.append(("cartpole_reduced (input d = C r; whole threshold)",
                  bundled_model("cartpole_reduced.toml")))
    if not quick:
        cases.append(("cartpole (input d = C r; whole threshold)",
                      bundled_model("cartpole.toml")))
    cases.append(("narx_example", bundled_model("narx_example.toml")))
    if not quick:
        cases += [("identified_example", bundled_model("identified_example.toml")),
                  ("NARX with y^3 and y*u", parse_model(
                      "y[k] = 1.2*y[k-1] - 0.5*y[k-2] + 0.3*u[k-1] + 0.1*u[k-2] "
                      "- 0.15*y[k-1]**3 + 0.1*y[k-1]*u[k-1]", sample_time=0.05))]
    return cases


def _narx(system: object) -> tuple[float, float | None, float, float | None]:
    """(CPU s, radius) of the box-then-paving search and of the box alone."""
    from gfrf.stability.narx_box import box_certificate
    from gfrf.twosided.lower_narx import narx_lower

    t0 = time.process_time()
    certs, _ = narx_lower(system, "every input with sup|u| <= U")  # type: ignore[arg-type]
    cpu = time.process_time() - t0
    lower = max((c.radius for c in certs if c.proof == "exact"), default=None)
    t0 = time.process_time()
    box = box_certificate(system)  # type: ignore[arg-type]
    return cpu, lower, time.process_time() - t0, box.radius if box is not None else None


def _fmt(x: float | None) -> str:
    if x is None or x == 0:
        return "-"
    return "inf" if math.isinf(x) else f"{x:.4g}"


def run(quick: bool) -> BenchSection:
    """Time the certificate search and its quadratic baseline per model; return the section.

    Parameters
    ----------
    quick : bool
        Only the third-order plant, the PI loop, the cubic-damping oscillator, the
        reduced cart-pole loop and the NARX example.

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``: per model, the search's CPU time, SDPs and
        radius, the baseline's, the witnessed upper and upper / lower.
    """
    from gfrf.model.modelfile import resolve_model
    from gfrf.stability.polysys import StateFormError, state_form
    from gfrf.stability.sos import sos_certificate
    from gfrf.twosided.threshold import threshold

    load = os.getloadavg()
    rows: list[list[object]] = []
    for label, source in _cases(quick):
        mf = resolve_model(source)  # type: ignore[arg-type]
        try:
            system = state_form(mf)
        except StateFormError:  # an improper controller: the implicit loop's polygon
            t0 = time.process_time()
            answer = threshold(mf, prove=False)
            cpu = time.process_time() - t0
            rows.append([label, f"{cpu:.1f}", "-", _fmt(answer.lower),
                         _fmt(answer.upper / answer.lower) if answer.upper and answer.lower
                         else "-", "-", "-", "-", "-", _fmt(answer.upper)])
            continue
        solves: object = "-"
        base_solves: object = "-"
        if system.discrete:
            cpu, lower, base_cpu, blow = _narx(system)
        else:
            t0 = time.process_time()
            res, solves = sos_certificate(system)
            cpu = time.process_time() - t0
            t0 = time.process_time()
            base, base_solves = sos_certificate(system, global_search=False, degree=2)
            base_cpu = time.process_time() - t0
            lower = res.radius if res is not None else None
            blow = base.radius if base is not None else None
        upper = threshold(mf, prove=False).upper
        rows.append([label, f"{cpu:.1f}", solves, _fmt(lower),
                     _fmt(upper / lower) if upper and lower else "-",
                     f"{base_cpu:.1f}", base_solves, _fmt(blow),
                     _fmt(upper / blow) if upper and blow else "-", _fmt(upper)])
    return BenchSection(
        title="Lower side: the sum-of-squares certificate search",
        intro=" ".join(__doc__.split("\n\n", 1)[1].split()),
        columns=["model", "search CPU (s)", "SDPs", "lower (interval)", "upper/lower",
                 "baseline CPU (s)", "baseline SDPs",
                 "baseline lower (quadratic V; NARX: invariant box)",
                 "upper/baseline", "upper (witness)"],
        rows=rows,
        notes=["CPU seconds of this process (time.process_time).",
               "Every radius is exactly re-checked (rational identity, Gram matrices PSD "
               "by their exact characteristic polynomial) before it is reported.",
               "upper: the falsifier's escaping input of `gfrf threshold` (prove=False); "
               "'-' when none was found below its cap.",
               load_note(load)])
