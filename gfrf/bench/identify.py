"""Timings of identification: ``run(quick) -> BenchSection`` for ``gfrf bench``.

Data: the worked example's true model (:mod:`gfrf.identify.example`) driven by
uniform white noise, output measurement noise 0.02, 10^4 and 10^5 samples (2*10^3
and 10^4 when quick), written to a CSV file.  Timed: :func:`gfrf.identify.fit.identify`
(FROLS fit, exact conversion, held-out free run), the whole ``gfrf identify DATA.csv
--json`` command in-process (CSV read, fit, model file text checked by re-reading,
verdict of Theorem 1 with norms up to order 5), and, as the baseline, sysidentpy's
FROLS alone on the same training samples (least squares, with its constant
candidate).  Errors beside the times: the largest relative error of the identified
H1 and H2 against the true kernels, and the held-out free-run RRSE.  Full runs add
the whole command ``gfrf identify DATA.csv --order 2 --json`` in a fresh process on
200,000 rows of the README's offset data (:func:`measure_cli`): its CPU seconds (user +
system, imports included) and peak memory.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from gfrf.identify import example as ex
from gfrf.identify.fit import identify

__all__ = ["run", "measure", "measure_cli"]


def _write_csv(path: Path, u: np.ndarray, y: np.ndarray) -> None:
    rows = ["u,y"] + [f"{a:.6g},{b:.6g}" for a, b in zip(u, y, strict=True)]
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")


def measure(n: int, folder: Path) -> dict[str, Any]:
    """Time identification and CSV -> verdict on ``n`` samples of the example model.

    Parameters
    ----------
    n : int
        Number of samples of the example model's data set.
    folder : pathlib.Path
        Scratch folder for the CSV and model files.

    Returns
    -------
    dict
        ``samples``, ``identify_s``, ``csv_to_verdict_s``, ``sysidentpy_s`` (seconds; None
        without sysidentpy),
        ``terms``, ``h1_error``, ``h2_error``, ``free_run_rrse``, ``verdict``.
    """
    from gfrf.identify.data import read_csv
    from gfrf.identify.output import load_text, model_file_text
    from gfrf.stability.criteria import verdict

    u, y, _ = ex.generate(n, seed=ex.SEED + n)
    csv_path = folder / f"bench_{n}.csv"
    _write_csv(csv_path, u, y)
    start = time.perf_counter()
    result = identify(y, u, ex.SAMPLE_TIME)
    identify_s = time.perf_counter() - start

    start = time.perf_counter()  # the work of `gfrf identify DATA.csv`, in-process
    y_read, u_read = read_csv(csv_path, "y", "u")
    fit = identify(y_read, u_read, ex.SAMPLE_TIME)
    pipeline_verdict = verdict(load_text(model_file_text(fit, str(csv_path)), ""))
    pipeline_s = time.perf_counter() - start

    baseline_s = _sysidentpy_seconds(u[:result.n_train], y[:result.n_train])
    errors = ex.kernel_errors(result.model, ex.true_model())
    return {"samples": n, "identify_s": identify_s, "csv_to_verdict_s": pipeline_s,
            "sysidentpy_s": baseline_s, "terms": len(result.regressors),
            "h1_error": errors["H1"], "h2_error": errors["H2"],
            "free_run_rrse": result.free_run_error,
            "verdict": pipeline_verdict.verdict}


def _sysidentpy_seconds(u: np.ndarray, y: np.ndarray) -> float | None:
    """Seconds of sysidentpy's FROLS on the training samples; None without sysidentpy
    (the optional extra ``gfrf[identify]``)."""
    import importlib.util

    if importlib.util.find_spec("sysidentpy") is None:
        return None
    from sysidentpy.basis_function import Polynomial
    from sysidentpy.model_structure_selection import FROLS
    from sysidentpy.parameter_estimation import LeastSquares

    baseline = FROLS(ylag=2, xlag=2, order_selection=True, info_criteria="bic",
                     n_info_values=15, estimator=LeastSquares(),
                     basis_function=Polynomial(degree=3))
    start = time.perf_counter()
    baseline.fit(X=u[:, None], y=y[:, None])
    return time.perf_counter() - start


def measure_cli(n: int, folder: Path) -> dict[str, Any]:
    """CPU time and peak memory of ``gfrf identify`` in a fresh process on ``n`` rows.

    The data are the README's: the example model, seed 5, output offset 0.5.

    Parameters
    ----------
    n : int
        Number of rows.
    folder : pathlib.Path
        Scratch folder for the CSV file.

    Returns
    -------
    dict
        ``samples``, ``cpu_s`` (user + system of the child process), ``peak_mb``,
        ``terms``, ``free_run_rrse``, ``verdict``.
    """
    import json
    import resource
    import subprocess
    import sys

    u, y, _ = ex.generate(n, seed=5)
    path = folder / f"cli_{n}.csv"
    rows = ["t,u,y"] + [f"{k * ex.SAMPLE_TIME:.10g},{a:.6g},{b + 0.5:.6g}"
                        for k, (a, b) in enumerate(zip(u, y, strict=True))]
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run([sys.executable, "-c", "import sys; from gfrf.cli import main; "
                           "sys.exit(main(sys.argv[1:]))", "identify", str(path), "--order",
                           "2", "--json"], capture_output=True, text=True, check=False)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = json.loads(done.stdout)
    fit = out["identification"]
    return {"samples": n, "cpu_s": after.ru_utime - before.ru_utime + after.ru_stime
            - before.ru_stime, "peak_mb": after.ru_maxrss / 1024.0,
            "terms": len(fit["regressors"]), "free_run_rrse": fit["free_run_error"],
            "verdict": (out["verdict"] or {}).get("verdict", "none")}


def run(quick: bool = False) -> Any:
    """The bench section: identification and CSV -> verdict times at two data sizes.

    Parameters
    ----------
    quick : bool
        Data sets of 2,000 and 10,000 samples instead of 10,000 and 100,000.

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``.
    """
    from gfrf.bench import BenchSection

    sizes = (2_000, 10_000) if quick else (10_000, 100_000)
    with tempfile.TemporaryDirectory() as tmp:
        measure(500, Path(tmp))  # warm-up: imports, first kernel generation
        rows = [measure(n, Path(tmp)) for n in sizes]
        cli = None if quick else measure_cli(200_000, Path(tmp))
    table = [[f"{r['samples']:,}", f"{r['identify_s']:.2f}", f"{r['csv_to_verdict_s']:.2f}",
              "not installed" if r["sysidentpy_s"] is None else f"{r['sysidentpy_s']:.2f}",
              r["terms"], f"{r['h1_error']:.2e}",
              f"{r['h2_error']:.2e}", f"{r['free_run_rrse']:.4f}", r["verdict"]]
             for r in rows]
    if cli is not None:
        table.append([f"{cli['samples']:,} (`gfrf identify --order 2`, fresh process)", "-",
                      f"{cli['cpu_s']:.2f} CPU s, {cli['peak_mb']:.0f} MB", "-", cli["terms"],
                      "-", "-", f"{cli['free_run_rrse']:.4f}", cli["verdict"]])
    return BenchSection(
        title="Identification: CSV to verdict (gfrf identify, sysidentpy FROLS)",
        intro="Data from the worked example's true NARX model (uniform white input, output "
              "measurement noise 0.02, 25 % held out); ylag = ulag = 2, degree 3, BIC over "
              "up to 15 of 34 candidate terms. `identify` = FROLS fit without the constant, "
              "exact conversion and held-out free run; `CSV -> verdict` = the whole "
              "work of `gfrf identify DATA.csv` in-process (read, fit, model file, verdict); "
              "baseline = sysidentpy's FROLS "
              "alone (with its constant candidate) on the same training samples. Errors: "
              "largest relative error of the identified H1, H2 against the true kernels.",
        columns=["samples", "identify (s)", "CSV -> verdict (s)", "sysidentpy FROLS alone (s)",
                 "terms", "H1 rel. error", "H2 rel. error", "held-out free-run RRSE",
                 "verdict at r = 1"],
        rows=table,
        notes=["The verdict's cost does not grow with the data: it depends on the identified "
               "model only.",
               "The fresh-process row (full runs only): the README's offset data (noise 0.02, "
               "output offset 0.5, lags and degree searched), CPU seconds user + system "
               "with the imports, and peak memory; the target is at most 10 s and 1 GB."])
