"""Cold kernels, cached compiled kernels, tight NARX norms and prepared simulations.

Every row is timed in fresh Python processes (CPU time of the work inside the child,
``time.process_time``, imports excluded unless said), the gfrf path and its baseline
interleaved, the median of the repetitions:

* **cold kernels**: H1..H5 of every bundled model, and the cart-pole's H7 alone, built
  and evaluated at 10^5 random frequency tuples by ``kernel(model, n)(*w)`` in a process
  with a fresh, empty gfrf cache folder, against the baseline a user would write
  (:mod:`gfrf.bench.probing_baseline`, no gfrf kernel code): sympy harmonic probing for
  the explicit symmetric rational functions, ``sympy.lambdify(..., cse=True)``, called at
  s = j*w (a discrete model at q = exp(-j*w*T)); the two must agree.  The baseline of an
  order runs only when its probing sums at most :data:`BASELINE_MAX_WORK` products (the
  cart-pole's H7, 7,225, fits: about a minute of CPU, so its baseline runs once, not
  three times);
* **warm kernel**: the cart-pole's top order (H7; the quick run: H5) evaluated again
  (median of 3 calls), ``H(w)`` (the numpy path, whatever the cache holds: in the
  baseline's process, its calls interleaved with the lambdified function's) and (full
  run) ``H.compiled()(w)``, against the lambdified function called again;
* **cached compiled kernel**: ``Kernel.compiled()`` of the cart-pole's H5 in a second
  process (the machine code on disk: a shared library on Linux with ``cc``, an object
  file linked in memory by LLVM without it, else numba's cache), with and without
  ``NUMBA_CACHE_DIR`` and without ``cc``, against the first (compiling) process;
* **NARX norm**: ``gfrf.kernel_norm`` of the identified example's H3 and H5 (default
  settings) against a dense grid (72^3 points; for H5 400,000 random points) whose best
  10 points are polished by Nelder-Mead, the value found must lie in the bracket;
* **prepared simulation**: ``simulate`` of the Duffing model (1 s, dt = 0.01 s, fast
  path) called with a prepared ``OdeSystem`` and ``InputSignal``, against the same
  call with the model file and the input text (rebuilt and re-parsed every call);
* **CSV reading**: ``gfrf.identify.read_data`` of a 10^6-row file with a header (columns
  u,y written with 17 digits; columns t,u,y with 6 digits, as the README's example writes
  them) against ``np.loadtxt(path, delimiter=",", skiprows=1)`` of the same file
  (in-process, interleaved).
"""

from __future__ import annotations

import importlib.util
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from gfrf._data import MODELS_DIR
from gfrf.bench import BenchSection, bundled_model, load_note

__all__ = ["run", "BASELINE_MAX_WORK"]

#: Largest :func:`gfrf.bench.probing_baseline.probing_work` of an order whose baseline the
#: bench runs (the cart-pole's H7: 7,225 products, about a minute of CPU on this machine).
BASELINE_MAX_WORK = 8_000

_COLD = """
import json, statistics, sys, time
import numpy as np
from gfrf.model.modelfile import load_model
mode, path, top = sys.argv[1], sys.argv[2], int(sys.argv[3])
orders = [top] if sys.argv[4] == "top" else range(1, top + 1)
model = load_model(path).plant
w = np.random.default_rng(0).uniform(-20.0, 20.0, (top, 100000))
if mode == "gfrf":
    from gfrf.kernels.recursion import kernel
else:
    from gfrf.bench.probing_baseline import ProbingBaseline
start = time.process_time()
if mode == "gfrf":
    calls = [kernel(model, n) for n in orders]
else:
    probing = ProbingBaseline(model)
    calls = [probing.function(n) for n in orders]
built = time.process_time() - start
values = [np.broadcast_to(calls[i](*w[:n]), (100000,)) for i, n in enumerate(orders)]
seconds = time.process_time() - start
ours = None
if mode == "base":  # gfrf's H_top beside it, the warm calls interleaved in this process
    from gfrf.kernels.recursion import kernel
    ours = kernel(model, top)
    ours(*w[:top])
warm, warm_gfrf = [], []
for _ in range(3):
    start = time.process_time()
    calls[-1](*w[:top])
    warm.append(time.process_time() - start)
    if ours is not None:
        start = time.process_time()
        ours(*w[:top])
        warm_gfrf.append(time.process_time() - start)
check = np.asarray(values[-1])[:16]
print(json.dumps({"seconds": seconds, "built": built, "warm": statistics.median(warm),
                  "warm_gfrf": statistics.median(warm_gfrf or [0.0]),
                  "check": [[complex(v).real, complex(v).imag] for v in check]}))
"""

_WARM_COMPILED = """
import json, statistics, sys, time
import numpy as np
from gfrf.model.modelfile import load_model
from gfrf.kernels.recursion import kernel
top = int(sys.argv[2])
w = np.random.default_rng(0).uniform(-20.0, 20.0, (top, 100000))
f = kernel(load_model(sys.argv[1]).plant, top).compiled()
f(*w[:, :4])
warm = []
for _ in range(3):
    start = time.process_time()
    f(*w)
    warm.append(time.process_time() - start)
print(json.dumps({"seconds": statistics.median(warm)}))
"""

_LOAD = """
import json, sys, time
import numpy as np
from gfrf.model.modelfile import load_model
from gfrf.kernels.recursion import kernel
k = kernel(load_model(sys.argv[1]).plant, 5)
start = time.process_time()
f = k.compiled()
f(*np.ones((5, 4)))
print(json.dumps({"seconds": time.process_time() - start}))
"""

_NORM = """
import json, math, sys, time
import numpy as np
from scipy.optimize import minimize
from gfrf.model.modelfile import load_model
from gfrf.bounds.norms import kernel_norm
from gfrf.kernels.recursion import kernel
model, order = load_model(sys.argv[2]).plant, int(sys.argv[3])
start = time.process_time()
if sys.argv[1] == "gfrf":
    b = kernel_norm(model, order)
    out = {"lower": b.lower, "upper": b.upper, "gap": b.gap}
else:
    k, t = kernel(model, order), model.sample_time
    if order == 3:
        axis = np.linspace(-math.pi / t, math.pi / t, 72, endpoint=False)
        grid = np.meshgrid(axis, axis, axis, indexing="ij")
    else:  # 72^5 points are too many: 400,000 random ones
        grid = np.random.default_rng(0).uniform(-math.pi / t, math.pi / t, (order, 400000))
    values = np.abs(k(*grid))
    best = 0.0
    for i in np.argsort(values.ravel())[::-1][:10]:
        x0 = np.array([g.flat[i] for g in grid])
        res = minimize(lambda x: -abs(complex(k(*x))), x0, method="Nelder-Mead",
                       options={"xatol": 1e-10, "fatol": 1e-15, "maxiter": 4000})
        best = max(best, -float(res.fun))
    out = {"value": best}
out["seconds"] = time.process_time() - start
print(json.dumps(out))
"""

_SIMULATE = """
import json, statistics, sys, time
from gfrf.model.modelfile import load_model
from gfrf.model.signals import parse_input
from gfrf.sim.simulation import simulate
from gfrf.sim.system import build_system
model = load_model(sys.argv[2])
if sys.argv[1] == "prepared":
    source, signal = build_system(model), parse_input("0.1*sin(t)")
else:
    source, signal = model, "0.1*sin(t)"
simulate(source, signal, t_end=1.0, method="fast", dt=0.01, n_out=11)
times = []
for _ in range(50):
    start = time.process_time()
    simulate(source, signal, t_end=1.0, method="fast", dt=0.01, n_out=11)
    times.append(time.process_time() - start)
print(json.dumps({"seconds": statistics.median(times)}))
"""


def _csv_rows(repeat: int) -> list[list[object]]:
    import time

    import numpy as np

    from gfrf.identify.data import read_data

    rng = np.random.default_rng(0)
    n = 1_000_000
    u = rng.standard_normal(n)
    y = np.tanh(u) + 0.1 * rng.standard_normal(n)
    rows: list[list[object]] = []
    with tempfile.TemporaryDirectory(prefix="gfrf-bench-csv-") as scratch:
        for label, columns, header, fmt in (
                ("u,y, 17 digits", np.c_[u, y], "u,y", "%.17g"),
                ("t,u,y, 6 digits", np.c_[0.1 * np.arange(n), u, y], "t,u,y", "%.6g")):
            path = Path(scratch) / "data.csv"
            np.savetxt(path, columns, fmt=fmt, delimiter=",", header=header, comments="")
            ours, base = [], []
            for _ in range(max(repeat, 3)):  # interleaved; a second each
                start = time.process_time()
                np.loadtxt(path, delimiter=",", skiprows=1)
                base.append(time.process_time() - start)
                start = time.process_time()
                read_data(path, "y", "u")
                ours.append(time.process_time() - start)
            mine, theirs = statistics.median(ours), statistics.median(base)
            rows.append([f"read_data, 10^6 rows ({label})", f"{mine:.3f} s",
                         f"{theirs:.3f} s (np.loadtxt)", f"{mine / theirs:.2f}",
                         "target <= 1.5"])
    return rows


def _child(code: str, args: list[str], env: dict[str, str] | None = None) -> dict:
    done = subprocess.run([sys.executable, "-c", code, *args], capture_output=True,
                          text=True, timeout=600, env={**os.environ, **(env or {})},
                          check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def _median(code: str, args: list[str], repeat: int, env: dict[str, str] | None = None
            ) -> tuple[float, dict]:
    runs = [_child(code, args, env) for _ in range(repeat)]
    return statistics.median(r["seconds"] for r in runs), runs[-1]


def _agreement(ours: dict, base: dict) -> float:
    """Largest relative difference of the two children's check values."""
    a = [complex(*v) for v in ours["check"]]
    b = [complex(*v) for v in base["check"]]
    return max(abs(x - y) / max(abs(y), 1e-300) for x, y in zip(a, b, strict=True))


def _cold_child(args: list[str]) -> dict:
    """One cold run: a fresh process with a fresh, empty gfrf cache folder."""
    with tempfile.TemporaryDirectory(prefix="gfrf-bench-cold-") as scratch:
        return _child(_COLD, args, {"GFRF_CACHE_DIR": scratch})


#: The models of the quick run's cold rows: the smallest, the largest and a NARX model.
QUICK_MODELS = ("duffing.toml", "cartpole.toml", "identified_example.toml")


def _cold_rows(repeat: int, quick: bool, numba: bool) -> list[list[object]]:
    """Cold H1..H5 of every bundled GFRF model; cold and warm H7 of the cart-pole."""
    from gfrf.bench.probing_baseline import probing_work
    from gfrf.model.modelfile import load_model

    rows: list[list[object]] = []
    warm: list[tuple[int, float, float]] = []
    if quick:  # three models and no order 7 (its baseline alone takes a minute)
        cases = [(name, 5, "all", "1.5") for name in QUICK_MODELS]
    else:
        cases = [(name, 5, "all", "1.5") for name in _gfrf_models()]
        cases.append(("cartpole.toml", 7, "top", "2"))
    for name, top, which, goal in cases:
        args = [bundled_model(name), str(top), which]
        what = f"H1..H{top}" if which == "all" else f"H{top}"
        work = probing_work(load_model(args[0]).plant, top)
        if work > BASELINE_MAX_WORK:
            rows.append([f"cold {what} of {name}, 10^5 points", "", f"not run: probing "
                         f"sums {work} products > BASELINE_MAX_WORK", "", f"target <= {goal}"])
            continue
        ours: list[dict] = []
        base: list[dict] = []
        for i in range(repeat):  # interleaved; an order-7 baseline once (a minute)
            ours.append(_cold_child(["gfrf", *args]))
            if top < 7 or i == 0:
                base.append(_cold_child(["base", *args]))
        mine = statistics.median(r["seconds"] for r in ours)
        theirs = statistics.median(r["seconds"] for r in base)
        built = statistics.median(r["built"] for r in base)
        agree = _agreement(ours[-1], base[-1])
        rows.append([f"cold {what} of {name}, 10^5 points", f"{mine:.3f} s",
                     f"{theirs:.3f} s (probing + lambdify cse, {built:.3f} s of it building; "
                     f"agree to {agree:.1e})", f"{mine / theirs:.2f}", f"target <= {goal}"])
        if name == "cartpole.toml":  # the warm numpy path, interleaved with the baseline
            warm.append((top, statistics.median(r["warm_gfrf"] for r in base),
                         statistics.median(r["warm"] for r in base)))
    for top, mine, theirs in warm:
        rows.append([f"warm H{top} of cartpole.toml, 10^5 points, H(w) (numpy path)",
                     f"{mine:.3f} s", f"{theirs:.3f} s (the lambdified function called again)",
                     f"{mine / theirs:.2f}", "target <= 0.3" if top == 7 else ""])
    if numba and not quick:  # the compile takes 15-25 s
        with tempfile.TemporaryDirectory(prefix="gfrf-bench-warm-") as scratch:
            compiled = _child(_WARM_COMPILED, [bundled_model("cartpole.toml"), "7"],
                              {"GFRF_CACHE_DIR": scratch})["seconds"]
        theirs = warm[-1][2]  # the H7 baseline called again
        rows.append(["warm H7 of cartpole.toml, 10^5 points, H.compiled()(w)",
                     f"{compiled:.3f} s", f"{theirs:.3f} s (the lambdified function called "
                     "again)", f"{compiled / theirs:.2f}", "target <= 0.3"])
    return rows


def _cache_rows(repeat: int) -> list[list[object]]:
    """The cart-pole's cached compiled H5 in a second process against the first."""
    rows: list[list[object]] = []
    with tempfile.TemporaryDirectory(prefix="gfrf-bench-cache-") as scratch:
        numba_dir = {"NUMBA_CACHE_DIR": str(Path(scratch) / "numba")}
        no_cc = {"PATH": str(Path(sys.executable).parent)}  # no C compiler driver
        for i, (label, extra) in enumerate((("", {}), (", NUMBA_CACHE_DIR set", numba_dir),
                                            (", no cc on the PATH", no_cc))):
            env = {"GFRF_CACHE_DIR": str(Path(scratch) / f"gfrf{i}"), **extra}
            first = _child(_LOAD, [bundled_model("cartpole.toml")], env)["seconds"]
            second, _ = _median(_LOAD, [bundled_model("cartpole.toml")], repeat, env)
            rows.append([f"cached compiled cart-pole H5, second process{label}",
                         f"{second:.3f} s", f"{first:.3f} s (first process, compiling)",
                         f"{second / first:.2f}", "target <= 0.3 s"])
    return rows


def _gfrf_models() -> list[str]:
    """File names of the bundled models that have GFRFs (not the parametric ones)."""
    import tomllib

    return sorted(path.name for path in MODELS_DIR.glob("*.toml")
                  if tomllib.loads(path.read_text()).get("kind", "gfrf") != "parametric")


def run(quick: bool) -> BenchSection:
    """Time the cold, cached, NARX-norm and prepared-simulation paths against baselines.

    Parameters
    ----------
    quick : bool
        One timing per row instead of the median of three, the cold rows of
        three models (``QUICK_MODELS``) without order 7, and no compiled warm row
        (its compile takes 15-25 s).

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``: rows of times and ratios to the baselines.
    """
    load = os.getloadavg()
    repeat = 1 if quick else 3
    rows: list[list[object]] = []
    numba = importlib.util.find_spec("numba") is not None  # the extra gfrf[fast]
    notes = [] if numba else ["numba (gfrf[fast]) is not installed: the compiled-kernel, "
                              "cached-kernel and fast-simulation rows were skipped"]
    rows += _cold_rows(repeat, quick, numba)
    rows += _cache_rows(repeat) if numba else []
    narx = bundled_model("identified_example.toml")
    for order, search in (("3", "72^3 grid"), ("5", "4e5 random points")):
        ours, bracket = _median(_NORM, ["gfrf", narx, order], repeat)
        base, grid = _median(_NORM, ["grid", narx, order], repeat)
        inside = (bracket["lower"] * (1 - 1e-9) <= grid["value"]
                  <= bracket["upper"] * (1 + 1e-12))
        rows.append([f"‖H{order}‖ of identified_example: gap {bracket['gap']:.2g} "
                     f"[{bracket['lower']:.4g}, {bracket['upper']:.4g}]", f"{ours:.2f} s",
                     f"{base:.2f} s ({search} + Nelder-Mead from the best 10: "
                     f"{grid['value']:.6g}, {'inside' if inside else 'OUTSIDE'} the bracket)",
                     f"{ours / base:.2f}", "target gap <= 1e-3, <= 10 s"])
    if numba:
        duffing = bundled_model("duffing.toml")
        prepared, _ = _median(_SIMULATE, ["prepared", duffing], repeat)
        text, _ = _median(_SIMULATE, ["text", duffing], repeat)
        rows.append(["simulate(method='fast'), 1 s at dt = 0.01 s, per call",
                     f"{prepared * 1e3:.2f} ms (prepared OdeSystem, InputSignal)",
                     f"{text * 1e3:.2f} ms (model file and input text)",
                     f"{prepared / text:.2f}", "target <= 1 ms"])
    rows += _csv_rows(repeat)
    return BenchSection(
        title="Cold kernels, cached kernels, NARX norms, prepared simulations",
        intro=" ".join(__doc__.split("\n\n", 1)[1].split()),
        columns=["what", "gfrf (CPU)", "baseline (CPU)", "ratio", "goal"],
        rows=rows, notes=[*notes, load_note(load)])
