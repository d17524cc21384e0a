"""Identification targets on data sets of known systems, through ``gfrf identify --json``.

Each data set is simulated here from a known system: the hardening oscillator
``D(y,2) + 0.6D(y) + y + 0.5y**3 = u`` and the asymmetric one ``D(y,2) + 0.5D(y) + y +
0.3y**2 + 0.5y**3 = u`` (sampled at T = 0.1 with a zero-order-hold input, scipy's DOP853,
input uniform in +-3), and the NARX model with a cross term ``y[k] = 1.2y[k-1] -
0.5y[k-2] + 0.3u[k-1] + 0.1u[k-2] - 0.15y[k-1]**3 + 0.1y[k-1]u[k-1]`` (T = 0.05, input
uniform in +-1); 4,000 samples, the input from ``default_rng(seed)``, white output noise
of sd ``level * sd(y)`` from ``default_rng(1000 + seed)``, an offset added to y.  Each set
is written with columns ``t,u,y`` and identified in a fresh process by the command a user
(or a checker) runs, ``gfrf identify DATA.csv --amplitude R --json`` with R = 0.7 r*_true
(``default``: the lags and degree searched), and with the fixed structure ``--ylag 2
--ulag 2 --degree 3`` (``fixed``).  The targets: adequate; the identified (pruned) r*
within 15 % of r*_true (``gfrf verdict`` on the true equation); the verdict ``stable``.
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["DataSet", "SYSTEMS", "data_sets", "simulate", "true_radius", "run_set", "run"]

#: name -> (true equation, sample time, input amplitude)
SYSTEMS: dict[str, tuple[str, float, float]] = {
    "hardening": ("D(y,2) + 0.6*D(y) + y + 0.5*y**3 = u", 0.1, 3.0),
    "asymmetric": ("D(y,2) + 0.5*D(y) + y + 0.3*y**2 + 0.5*y**3 = u", 0.1, 3.0),
    "narx": ("y[k] = 1.2*y[k-1] - 0.5*y[k-2] + 0.3*u[k-1] + 0.1*u[k-2] - 0.15*y[k-1]**3 "
             "+ 0.1*y[k-1]*u[k-1]", 0.05, 1.0),
}

#: the structure options of the ``fixed`` runs
FIXED = ("--ylag", "2", "--ulag", "2", "--degree", "3")


@dataclass(frozen=True, kw_only=True)
class DataSet:
    """One data set: system name, output noise level (fraction of sd(y)), offset on y, seed."""

    system: str
    noise: float
    offset: float
    seed: int
    n: int = 4000


def _oscillator(u: np.ndarray, step: float, damping: float, square: float) -> np.ndarray:
    from scipy.integrate import solve_ivp

    x = np.zeros(2)
    y = np.empty(u.size)
    for k, value in enumerate(u):
        y[k] = x[0]
        sol = solve_ivp(lambda _t, z, v=value: [z[1], v - damping * z[1] - z[0]
                                                 - square * z[0] ** 2 - 0.5 * z[0] ** 3],
                        (0.0, step), x, method="DOP853", rtol=1e-10, atol=1e-12)
        x = sol.y[:, -1]
    return y


def _narx(u: np.ndarray) -> np.ndarray:
    y = np.zeros(u.size)
    for k in range(2, u.size):
        y[k] = (1.2 * y[k - 1] - 0.5 * y[k - 2] + 0.3 * u[k - 1] + 0.1 * u[k - 2]
                - 0.15 * y[k - 1] ** 3 + 0.1 * y[k - 1] * u[k - 1])
    return y


def simulate(ds: DataSet) -> tuple[np.ndarray, np.ndarray, float]:
    """Input, noisy output with offset, and sample time of a data set.

    Parameters
    ----------
    ds : DataSet
        The data set.

    Returns
    -------
    tuple
        ``(u, y, T)``.
    """
    _, step, amp = SYSTEMS[ds.system]
    u = amp * np.random.default_rng(ds.seed).uniform(-1, 1, ds.n)
    if ds.system == "narx":
        x = _narx(u)
    else:
        x = _oscillator(u, step, 0.6 if ds.system == "hardening" else 0.5,
                        0.0 if ds.system == "hardening" else 0.3)
    noise = ds.noise * np.std(x) * np.random.default_rng(1000 + ds.seed).standard_normal(ds.n)
    return u, x + noise + ds.offset, step


def true_radius(system: str) -> float:
    """r* of the true equation (Theorem 1, proven).

    Parameters
    ----------
    system : str
        A key of :data:`SYSTEMS`.
    """
    from gfrf.model.equation import parse_model
    from gfrf.stability.criteria import verdict

    equation, step, _ = SYSTEMS[system]
    sample_time = step if "[k]" in equation else None
    return verdict(parse_model(equation, sample_time=sample_time), 1, 1.0,
                   with_norms=False).radius


def data_sets(seeds: tuple[int, ...] = (21, 31, 3), noises: tuple[float, ...] = (0.0, 0.02, 0.05),
              systems: tuple[str, ...] = ("hardening", "narx")) -> list[DataSet]:
    """Every combination of system, noise level, offset 0 and 0.5, and seed.

    Parameters
    ----------
    seeds : tuple of int
        Seeds of the input (the noise uses ``1000 + seed``).
    noises : tuple of float
        Output noise levels.
    systems : tuple of str
        Keys of :data:`SYSTEMS`.
    """
    return [DataSet(system=s, noise=z, offset=o, seed=seed) for s in systems for seed in seeds
            for z in noises for o in (0.0, 0.5)]


def run_set(ds: DataSet, folder: Path, r_true: float, fixed: bool,
            extra: tuple[str, ...] = ("--order", "1")) -> dict[str, Any]:
    """Identify one data set with ``gfrf identify`` in a fresh process.

    Parameters
    ----------
    ds : DataSet
        The data set.
    folder : pathlib.Path
        Scratch folder for its CSV file (written once, reused).
    r_true : float
        r* of the true system; the verdict is asked at 0.7 of it.
    fixed : bool
        Add :data:`FIXED` (otherwise the lags and degree are searched).
    extra : tuple of str
        Further options (default ``--order 1``: the verdict and r* do not depend on it).

    Returns
    -------
    dict
        ``adequate``, ``ratio`` (identified r* / r*_true), ``low`` (lower end / r*_true),
        ``verdict``, ``terms``, ``structure``, ``reason``, ``cpu_s``, ``peak_mb``, ``exit``.
    """
    path = folder / f"{ds.system}_{ds.seed}_{ds.noise:g}_{ds.offset:g}.csv"
    if not path.exists():
        u, y, step = simulate(ds)
        from gfrf._atomic import atomic_open

        with atomic_open(path) as fh:
            np.savetxt(fh, np.c_[step * np.arange(u.size), u, y], fmt="%.10g",
                       delimiter=",", header="t,u,y", comments="")
    args = [str(path), "--amplitude", repr(0.7 * r_true), *extra, "--json"]
    if fixed:
        args += FIXED
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run([sys.executable, "-c", "import sys; from gfrf.cli import main; "
                           "sys.exit(main(sys.argv[1:]))", "identify", *args],
                          capture_output=True, text=True, check=False)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    if not done.stdout.strip():
        return {"adequate": None, "ratio": None, "low": None, "verdict": "error",
                "reason": done.stderr.strip()[-300:], "cpu_s": cpu, "exit": done.returncode}
    out = json.loads(done.stdout)
    ident = out["identification"]
    radius = ident.get("radius") or {}
    settings = ident.get("settings", {})
    return {"adequate": ident["adequate"],
            "ratio": None if radius.get("radius") is None else radius["radius"] / r_true,
            "low": None if radius.get("low") is None else radius["low"] / r_true,
            "verdict": (out.get("verdict") or {}).get("verdict", "none"),
            "terms": len(ident.get("regressors", [])),
            "structure": f"{settings.get('ylag')},{settings.get('ulag')},{settings.get('degree')}",
            "reason": ident.get("reason", ""), "cpu_s": cpu,
            "peak_mb": after.ru_maxrss / 1024.0, "exit": done.returncode}


def met(row: dict[str, Any]) -> bool:
    """The three targets of one row: adequate, within 15 % of r*_true, ``stable``.

    Parameters
    ----------
    row : dict
        What :func:`run_set` returned.
    """
    return bool(row["adequate"]) and row["ratio"] is not None and \
        abs(row["ratio"] - 1) <= 0.15 and row["verdict"] == "stable"


def run(quick: bool = False) -> Any:
    """The bench section: every data set, with the searched and the fixed structure.

    Parameters
    ----------
    quick : bool
        Seed 21 only (12 data sets) instead of seeds 21, 31 and 3 (36).

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``.
    """
    import tempfile

    from gfrf.bench import BenchSection

    sets = data_sets(seeds=(21,) if quick else (21, 31, 3))
    radii = {s: true_radius(s) for s in {d.system for d in sets}}
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for ds in sets:
            cells = [ds.system, f"{ds.noise:.0%}", f"{ds.offset:g}", ds.seed]
            for fixed in (False, True):
                r = run_set(ds, Path(tmp), radii[ds.system], fixed)
                cells.append(_cell(r))
            rows.append(cells)
    return BenchSection(
        title="Identification targets on data sets of known systems (gfrf identify --json)",
        intro=__doc__.split("\n\n", 1)[1].replace("\n", " "),
        columns=["system", "noise", "offset on y", "seed",
                 "searched lags: r*/r*true, lower end, verdict, CPU s",
                 "--ylag 2 --ulag 2 --degree 3: same"],
        rows=rows,
        notes=[f"r*_true: {', '.join(f'{k} {v:.4f}' for k, v in sorted(radii.items()))}."])


def _cell(r: dict[str, Any]) -> str:
    cpu = f"{r['cpu_s']:.1f} s"
    if not r["adequate"]:
        return f"not adequate ({cpu})"
    return (f"{r['ratio']:.3f} / {r['low']:.3f} `{r['verdict']}` ({r['structure']}, {cpu})"
            + ("" if met(r) else " **missed**"))
