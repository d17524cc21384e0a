"""Limits in seconds: hard inputs, each answered or refused, beside its baseline.

Each input runs as a fresh ``gfrf`` process on one core (BLAS and numba thread pools set
to 1); CPU is user + system time of that process (imports included), wall time from
launch to exit, memory its peak resident set.  An input is *answered* (exit 0 or 1: a
result) or *refused* (exit 2 with a ``gfrf: error:`` line naming the limit, before the
work).  The baselines are the wall times of the same inputs without the work caps
(measured once on a loaded 2-core machine; the record is in reports/).
"""

from __future__ import annotations

import os
import resource
import subprocess
import time

from gfrf.bench import BenchSection, bundled_model, gfrf_command, load_note

__all__ = ["run"]

_ONE_CORE = {name: "1" for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                    "MKL_NUM_THREADS", "NUMBA_NUM_THREADS")}
_INLINE = "D(y,2)+0.2*D(y)+y+0.3*y**2+0.1*D(y)**2+0.2*y*D(y)+0.1*y**3 = u"
_VERDICT = "D(y,2) + 0.3*D(y) + y + 0.4*y**2 + 0.2*D(y)**2 + 0.3*y*D(y) + 0.1*y**3 = u"
_TONES = " + ".join(f"0.001*sin({1 + 0.01 * k:.4f}*t)" for k in range(2000))
#: Most wall seconds an input may run here (a bench never hangs).
_TIMEOUT = 900.0


def _cases(quick: bool) -> list[tuple[str, list[str], str]]:
    """(label, gfrf arguments, baseline without the work caps)."""
    pendulum, cartpole = bundled_model("hanging_pendulum.toml"), bundled_model("cartpole.toml")
    cases = [
        ("kernel, pendulum, order 11",
         ["kernel", pendulum, "--order", "11", "--at", "1,1,1,1,1,1,1,1,1,1,-1"], "42.5 s"),
        ("kernel, inline quadratic+cubic, order 12",
         ["kernel", _INLINE, "--order", "12", "--at", "1,1,1,1,1,1,1,1,1,1,1,-1"],
         "killed after 600 s"),
    ]
    if quick:
        return cases
    return cases + [
        ("verdict, inline quadratic+cubic", ["verdict", _VERDICT], "27.6 s"),
        ("norm order 4 without branch-and-bound, same model",
         ["norm", _VERDICT, "--order", "4", "--max-boxes", "0"], "80 s"),
        ("simulate, 2,000-tone input", ["simulate", bundled_model("duffing.toml"), "--input",
                                        _TONES, "--t-end", "1"], "33-43 s to parse"),
        ("norm, cart-pole, order 5 (defaults)", ["norm", cartpole, "--order", "5"],
         "gap 4.7e-1 in 19 s"),
        ("norm, pendulum, order 5, tol 1e-12, 2e7 boxes",
         ["norm", pendulum, "--order", "5", "--tol", "1e-12", "--max-boxes", "20000000"],
         "> 645 MB after 8 min"),
    ]


def _measure(args: list[str]) -> tuple[int, str, float, float, float]:
    """(exit code, last stderr/stdout line, CPU s, wall s, peak MB) of one gfrf process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    try:
        out = subprocess.run(gfrf_command(args), capture_output=True, text=True,
                             timeout=_TIMEOUT, env={**os.environ, **_ONE_CORE})
        code, text = out.returncode, (out.stderr.strip() or out.stdout.strip())
    except subprocess.TimeoutExpired:
        code, text = -1, f"stopped after {_TIMEOUT:g} s"
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    last = text.splitlines()[-1] if text else ""
    return code, last, cpu, wall, after.ru_maxrss / 1024


def run(quick: bool) -> BenchSection:
    """Run every input; return the report section.

    Parameters
    ----------
    quick : bool
        Only the two kernel cases, not the verdict and norm ones.

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``.
    """
    load = os.getloadavg()
    rows: list[list[object]] = []
    for label, args, baseline in _cases(quick):
        code, last, cpu, wall, peak = _measure(args)
        outcome = {0: "answered", 1: "answered", 2: "refused"}.get(code, f"exit {code}")
        rows.append([label, baseline, outcome, f"{cpu:.1f}", f"{wall:.1f}", f"{peak:.0f}",
                     "yes" if code in (0, 1, 2) and cpu <= 10.0 else "no",
                     last[:160]])
    notes = ["Peak memory is the largest resident set of any child process so far (getrusage "
             "reports the maximum over children, so it never decreases down the table).",
             "Refusals name the estimate and the flag that goes on anyway (gfrf kernel "
             "--max-work, gfrf norm --max-boxes).", load_note(load)]
    return BenchSection(
        title="Limits in seconds: hard inputs answered or refused",
        intro=" ".join(__doc__.split("\n\n", 1)[1].split()),
        columns=["input", "baseline (no caps)", "now", "CPU (s)", "wall (s)", "peak MB",
                 "within 10 s CPU", "last line"],
        rows=rows, notes=notes)
