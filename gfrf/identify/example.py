"""The worked example of :mod:`gfrf.identify`: data from a known NARX model, identified back.

:func:`generate` simulates :data:`TRUE_EQUATION` (a cross term ``y[k-1]*u[k-1]``, a
square ``u[k-1]**2`` and a cube ``y[k-1]**3``) driven by uniform white noise in
[-1, 1], and adds white Gaussian measurement noise of standard deviation
:data:`NOISE` to the output, with the fixed seed :data:`SEED`.  :func:`write_example`
writes, into ``models/``:

* ``identified_example.csv`` -- columns ``t, u, y`` (measured output), 6 digits;
* ``identified_example_true.toml`` -- the true model;
* ``identified_example.toml`` -- the model ``gfrf identify`` finds in the CSV.

Regenerate with ``python -m gfrf.identify.example`` (same bytes on every run).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from gfrf._data import MODELS_DIR
from gfrf.identify.data import read_csv
from gfrf.identify.fit import free_run, identify
from gfrf.identify.output import model_file_text, write_atomic
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import Model, parse_model

__all__ = ["TRUE_EQUATION", "SAMPLE_TIME", "SEED", "NOISE", "N_SAMPLES", "STEM",
           "true_model", "generate", "write_example", "kernel_errors", "MODELS_DIR"]

#: The model that generates the data (y = u = 0 is an equilibrium; poles |z| = 0.447).
TRUE_EQUATION = ("y[k] = 0.6*y[k-1] - 0.2*y[k-2] + 0.5*u[k-1] + 0.3*u[k-2] "
                 "+ 0.15*y[k-1]*u[k-1] - 0.1*u[k-1]**2 - 0.05*y[k-1]**3")
#: Sample time in s.
SAMPLE_TIME = 0.1
#: Seed of the input and the noise.
SEED = 14
#: Standard deviation of the measurement noise added to the output.
NOISE = 0.02
#: Samples in the example data file.
N_SAMPLES = 4000
#: File stem of the example in ``models/``.
STEM = "identified_example"
#: The repository's model folder.


def true_model() -> Model:
    """The model of :data:`TRUE_EQUATION` at :data:`SAMPLE_TIME`."""
    return parse_model(TRUE_EQUATION, sample_time=SAMPLE_TIME)


def generate(n: int = N_SAMPLES, seed: int = SEED, noise: float = NOISE,
             model: Model | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Input, measured output and noise-free output of ``model`` (default the true one).

    The input is uniform white noise in [-1, 1]; the output starts from rest and
    ``noise`` is the standard deviation of the Gaussian noise added to it.

    Parameters
    ----------
    n : int, optional
        Number of samples.
    seed : int, optional
        Seed of :func:`numpy.random.default_rng`.
    noise : float, optional
        Standard deviation of the output noise.
    model : Model, optional
        A NARX model; None: the example's true model.

    Returns
    -------
    tuple of numpy.ndarray
        u, the measured y and the noise-free y, each of length ``n``.
    """
    model = model or true_model()
    rng = np.random.default_rng(seed)
    u = rng.uniform(-1.0, 1.0, n)
    y, blowup = free_run(model, u, np.zeros(model.max_order))
    if blowup is not None:
        raise RuntimeError(f"the example model blew up at sample {blowup}")
    return u, y + noise * rng.standard_normal(n), y


def kernel_errors(identified: Model, true: Model, points: int = 400) -> dict[str, float]:
    """Largest |H_id - H_true| / max |H_true| of H1 (0..pi/T) and H2 (grid on [-pi/T, pi/T]^2).

    Parameters
    ----------
    identified, true : Model
        The identified and the true NARX model.
    points : int, optional
        Points of the H1 grid (the H2 grid has about sqrt(40 points) per axis).

    Returns
    -------
    dict of str to float
        ``{"H1": ..., "H2": ...}``.
    """
    nyquist = math.pi / float(true.sample_time)  # type: ignore[arg-type]
    w = np.linspace(0.0, nyquist, points)
    out = {}
    h1_true, h1_id = kernel(true, 1)(w), kernel(identified, 1)(w)
    out["H1"] = float(np.max(np.abs(h1_id - h1_true)) / np.max(np.abs(h1_true)))
    g = np.linspace(-nyquist, nyquist, int(math.sqrt(points * 40)))
    w1, w2 = np.meshgrid(g, g)
    h2_true, h2_id = kernel(true, 2)(w1, w2), kernel(identified, 2)(w1, w2)
    out["H2"] = float(np.max(np.abs(h2_id - h2_true)) / np.max(np.abs(h2_true)))
    return out


def write_example(models_dir: str | Path = MODELS_DIR) -> list[Path]:
    """Write the example's CSV, true model file and identified model file.

    Parameters
    ----------
    models_dir : str or Path, optional
        The folder the files are written to.

    Returns
    -------
    list of Path
        The paths written.
    """
    folder = Path(models_dir)
    u, y, _ = generate()
    t = np.arange(u.size) * SAMPLE_TIME
    rows = ["t,u,y"] + [f"{a:.10g},{b:.6g},{c:.6g}" for a, b, c in zip(t, u, y, strict=True)]
    csv_path = write_atomic(folder / f"{STEM}.csv", "\n".join(rows) + "\n")
    true_text = "\n".join([
        "# The NARX model that generated identified_example.csv "
        "(python -m gfrf.identify.example).",
        'name = "Identified example: the true NARX model"',
        f'equation = "{TRUE_EQUATION}"',
        f"sample_time = {SAMPLE_TIME!r}",
        f'source = "gfrf/identify/example.py: uniform white input in [-1, 1], {N_SAMPLES} '
        f'samples, output measurement noise N(0, {NOISE}^2), seed {SEED}"',
        'description = "Compare with identified_example.toml, the model gfrf identify '
        'finds in the noisy data."', ""])
    true_path = write_atomic(folder / f"{STEM}_true.toml", true_text)
    data = f"models/{STEM}.csv" if folder.resolve() == MODELS_DIR else str(csv_path)
    y_read, u_read = read_csv(csv_path, "y", "u")
    result = identify(y_read, u_read, SAMPLE_TIME)
    text = model_file_text(result, data, name="Identified example: NARX identified from "
                           "noisy data", description="The true model is "
                           "identified_example_true.toml.")
    return [csv_path, true_path, write_atomic(folder / f"{STEM}.toml", text)]


def main() -> None:  # pragma: no cover - the command-line wrapper
    """``python -m gfrf.identify.example [--models DIR]``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", default=str(MODELS_DIR), help="output folder")
    for path in write_example(parser.parse_args().models):
        print(f"wrote {path} ({path.stat().st_size} bytes)")


if __name__ == "__main__":  # pragma: no cover
    main()
