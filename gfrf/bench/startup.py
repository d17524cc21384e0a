"""Start-up and first call: what a new user waits for, in fresh processes.

Each command runs in a new Python process (``subprocess``, wall time from launch to
exit, best and median of several runs, output discarded), side by side in this run
with the reference it is judged against: ``gfrf --help`` against ``python -c "import
numpy"``, ``gfrf norm models/hanging_pendulum.toml --order 3`` against ``python -c
"import sympy"``, and the first fast simulation in a fresh process (the hanging
pendulum, 200 s at dt = 0.01 s, after one untimed run that fills the compile cache)
both as the whole ``gfrf simulate --method fast`` command and as the first
``gfrf.simulate(..., method="fast")`` call timed inside the process.  The heavy
modules each gfrf command leaves imported are listed, from ``sys.modules`` at exit.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

from gfrf._data import MODELS_DIR
from gfrf.bench import BenchSection, gfrf_command, load_note

__all__ = ["run"]

_ROOT = Path(__file__).resolve().parents[2]
_MODEL = str(MODELS_DIR / "hanging_pendulum.toml")
_HEAVY = ("control", "matplotlib", "numba", "dask", "distributed", "sympy", "scipy", "mpmath",
          "flint", "pandas")
_SIMULATE = ["simulate", _MODEL, "--input", "0.05*sin(1.565*t)", "--t-end", "200",
             "--method", "fast", "--dt", "0.01"]
#: Goals (ratios to the reference command, and seconds).
_HELP_GOAL, _NORM_GOAL, _FIRST_FAST_GOAL = 3.0, 3.0, 0.5

_FIRST_CALL = f"""
import json, time
from gfrf.model.modelfile import load_model
from gfrf.model.signals import parse_input
from gfrf.sim.simulation import simulate
model, signal = load_model({_MODEL!r}), parse_input("0.05*sin(1.565*t)")
start = time.perf_counter()
result = simulate(model, signal, t_end=200.0, method="fast", dt=0.01)
print(json.dumps({{"first": time.perf_counter() - start, "compile": result.compile_time,
                  "status": result.status}}))
"""

_MODULES = f"""
import contextlib, io, json, sys
from gfrf.cli import main
with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
    try:
        main(sys.argv[1:])
    except SystemExit:
        pass
print(json.dumps(sorted(m for m in {_HEAVY!r} if m in sys.modules)))
"""


def _wall(cmd: list[str], repeat: int) -> tuple[float, float]:
    """Best and median wall time (s) of ``cmd`` in fresh processes."""
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True,
                       cwd=_ROOT)
        times.append(time.perf_counter() - start)
    return min(times), statistics.median(times)


def _json_out(cmd: list[str]) -> object:
    out = subprocess.run(cmd, capture_output=True, text=True, check=True, cwd=_ROOT)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _heavy_modules(args: list[str]) -> str:
    loaded = _json_out([sys.executable, "-c", _MODULES, *args])
    return ", ".join(loaded) if loaded else "none"  # type: ignore[arg-type]


def _met(value: float, goal: float) -> str:
    return "yes" if value <= goal else "NO"


def run(quick: bool) -> BenchSection:
    """Time the fresh-process commands; return the report section.

    Parameters
    ----------
    quick : bool
        Two repeats per timing instead of seven.

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``.
    """
    load = os.getloadavg()
    repeat = 2 if quick else 7
    py = sys.executable
    subprocess.run(gfrf_command(_SIMULATE), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   check=True, cwd=_ROOT)  # fills the compile cache: not timed
    timed = {
        "numpy": _wall([py, "-c", "import numpy"], repeat),
        "sympy": _wall([py, "-c", "import sympy"], repeat),
        "control": _wall([py, "-c", "import control"], repeat),
        "help": _wall(gfrf_command(["--help"]), repeat),
        "norm": _wall(gfrf_command(["norm", _MODEL, "--order", "3"]), repeat),
        "simulate": _wall(gfrf_command(_SIMULATE), repeat),
    }
    firsts, walls = [], []
    for _ in range(repeat):
        start = time.perf_counter()
        firsts.append(_json_out([py, "-c", _FIRST_CALL]))
        walls.append(time.perf_counter() - start)
    timed["api"] = (min(walls), statistics.median(walls))
    first = min(f["first"] for f in firsts)  # type: ignore[index]
    compile_load = min(f["compile"] for f in firsts)  # type: ignore[index]
    help_ratio = timed["help"][0] / timed["numpy"][0]
    norm_ratio = timed["norm"][0] / timed["sympy"][0]

    def row(what: str, key: str, ratio: str, goal: str, met: str) -> list[object]:
        best, median = timed[key]
        return [what, f"{best:.3f}", f"{median:.3f}", ratio, goal, met]

    rows = [row('python -c "import numpy"', "numpy", "reference", "", ""),
            row("gfrf --help", "help", f"{help_ratio:.2g}x numpy",
                f"<= {_HELP_GOAL:g}x numpy", _met(help_ratio, _HELP_GOAL)),
            row('python -c "import sympy"', "sympy", "reference", "", ""),
            row("gfrf norm hanging_pendulum.toml --order 3", "norm",
                f"{norm_ratio:.2g}x sympy", f"<= {_NORM_GOAL:g}x sympy",
                _met(norm_ratio, _NORM_GOAL)),
            row('python -c "import control" (for scale)', "control",
                f"{timed['control'][0] / timed['numpy'][0]:.2g}x numpy", "", ""),
            row("gfrf simulate hanging_pendulum.toml --method fast --dt 0.01 (200 s), "
                "cache warm", "simulate", f"{timed['simulate'][0] / timed['numpy'][0]:.2g}x "
                "numpy", "", ""),
            row("python script: import gfrf, load the model, one fast simulate (whole "
                "process)", "api", f"{timed['api'][0] / timed['numpy'][0]:.2g}x numpy", "", ""),
            ["first gfrf.simulate(..., method='fast') call in a fresh process, cache warm",
             f"{first:.3f}", "", f"of which {compile_load:.3f} s cache load / compile",
             f"< {_FIRST_FAST_GOAL:g} s", _met(first, _FIRST_FAST_GOAL)]]
    notes = [f"Heavy modules imported by `gfrf --help`: {_heavy_modules(['--help'])}; by "
             f"`gfrf norm MODEL --order 3`: {_heavy_modules(['norm', _MODEL, '--order', '3'])}; "
             f"by `gfrf simulate ... --method fast`: {_heavy_modules(_SIMULATE)}.",
             f"Best of {repeat} fresh processes each (median beside it); every ratio divides "
             f"two best times measured in this run.",
             load_note(load)]
    return BenchSection(
        title="Start-up and first call (fresh processes)",
        intro=" ".join(__doc__.split("\n\n", 1)[1].split()),
        columns=["command", "best (s)", "median (s)", "ratio", "goal", "met"],
        rows=rows, notes=notes)
