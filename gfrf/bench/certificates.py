"""The lower side of ``gfrf threshold``: the sum-of-squares certificate search.

Per model: the CPU time of the search (:func:`gfrf.stability.sos.sos_certificate`: the
quadratic V, its degree-4 V-lambda improvement, every proposal re-checked in exact
rational arithmetic), the proven radius U (every input with sup|u| <= U) and the
witnessed escape of ``gfrf threshold`` (upper / lower: closer to 1 is tighter), beside
the baseline a user would write first: a quadratic Lyapunov function of the
linearisation with its largest provable input bound (the same exact check, degree 2).
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
        ("PI loop", ModelFile(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"),
                              controller=Controller(num=(0.5, 0.2), den=(1.0, 0.0)))),
        ("cubic damping", parse_model("D(y,2) + 0.2*D(y) + y - 0.3*D(y)**3 = u")),
    ]
    if not quick:
        cases += [("nonlinear damping", parse_model(
            "D(y,2) + 0.4*D(y) + 2*y + 0.5*y**2*D(y) + 0.8*y**3 = u")),
            ("hanging_pendulum_damped", bundled_model("hanging_pendulum_damped.toml"))]
    return cases


def _fmt(x: float | None) -> str:
    if x is None or x == 0:
        return "-"
    return "inf" if math.isinf(x) else f"{x:.4g}"


def run(quick: bool) -> BenchSection:
    """Time the certificate search and its quadratic baseline per model; return the section.

    Parameters
    ----------
    quick : bool
        Only the third-order plant, the PI loop and the cubic-damping oscillator.

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``: per model, the search's CPU time, SDPs and
        radius, the baseline's, the witnessed upper and upper / lower.
    """
    from gfrf.model.modelfile import resolve_model
    from gfrf.stability.polysys import state_form
    from gfrf.stability.sos import sos_certificate
    from gfrf.twosided.threshold import threshold

    load = os.getloadavg()
    rows: list[list[object]] = []
    for label, source in _cases(quick):
        mf = resolve_model(source)  # type: ignore[arg-type]
        system = state_form(mf)
        t0 = time.process_time()
        res, solves = sos_certificate(system)
        cpu = time.process_time() - t0
        t0 = time.process_time()
        base, base_solves = sos_certificate(system, global_search=False, degree=2)
        base_cpu = time.process_time() - t0
        upper = threshold(mf, prove=False).upper
        lower = res.radius if res is not None else None
        blow = base.radius if base is not None else None
        rows.append([label, f"{cpu:.1f}", solves, _fmt(lower),
                     _fmt(upper / lower) if upper and lower else "-",
                     f"{base_cpu:.1f}", base_solves, _fmt(blow),
                     _fmt(upper / blow) if upper and blow else "-", _fmt(upper)])
    return BenchSection(
        title="Lower side: the sum-of-squares certificate search",
        intro=" ".join(__doc__.split("\n\n", 1)[1].split()),
        columns=["model", "search CPU (s)", "SDPs", "lower (interval)", "upper/lower",
                 "baseline CPU (s)", "baseline SDPs", "baseline lower (quadratic V)",
                 "upper/baseline", "upper (witness)"],
        rows=rows,
        notes=["CPU seconds of this process (time.process_time).",
               "Every radius is exactly re-checked (rational identity, Gram matrices PSD "
               "by their exact characteristic polynomial) before it is reported.",
               "upper: the falsifier's escaping input of `gfrf threshold` (prove=False); "
               "'-' when none was found below its cap.",
               load_note(load)])
