"""The figures 3-6 section of ``paper-gfrf.md``: eq (16)'s plant kernels, then the text.

:func:`figure_facts` draws the figures and gathers the numbers into a
:class:`FigureFacts`; :func:`figures_text` writes the section from them (whether the
plant is unstable, H3's sign on the slice, whether the paper's beta_3 lies in our
bracket are read from the facts).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gfrf._results import Result
from gfrf.bounds.majorant import linear_polynomials
from gfrf.kernels.recursion import kernel
from gfrf.papers.gfrf_paper import CheckRow
from gfrf.report._figures import frequency_scale, h1_figure, h3_slice_figure
from gfrf.report._format import bracket_cells, cell, code, num
from gfrf.report.analysis import MODELS_DIR, analyse
from gfrf.stability.loops import closed_loop

__all__ = ["FigureFacts", "figure_facts", "figures_text"]

#: The cart-pole files: eq (16) (the figures' plant) and eq (12) (the paper's constants).
REDUCED, FULL = "cartpole_reduced.toml", "cartpole.toml"


@dataclass(frozen=True, kw_only=True, repr=False)
class FigureFacts(Result):
    """The numbers of the figures 3-6 section (eq (16)'s plant kernels).

    ``to_dict`` leaves out ``names`` (the PNGs' file names, not results).

    Attributes
    ----------
    names : tuple of str
        File names of figures 3-4, 5 and 6.
    stiff : float
        The paper's linear coefficient in eq (13) (its printed h1's pole is sqrt of it).
    unstable : bool
        Whether the plant has a right-half-plane pole.
    real : bool
        Whether H3 is real on the slice f3 = 0.
    sign : str
        H3's sign on the slice: ``negative``, ``positive`` or ``of both signs``.
    points : int
        Grid points per axis.
    d0 : float
        The plant denominator's constant coefficient.
    b3 : tuple of float
        The largest |H3| found and its certified upper bound.
    argmax : tuple of float
        Where the largest |H3| was found (rad/s).
    beta3_paper : float
        The paper's printed beta_3.
    """

    names: tuple[str, str, str]
    stiff: float
    unstable: bool
    real: bool
    sign: str
    points: int
    d0: float
    b3: tuple[float, float]
    argmax: tuple[float, ...]
    beta3_paper: float

    _exclude = ("names",)

    def beta3_in_bracket(self) -> bool:
        """Whether the paper's beta_3 lies in our bracket of ||H3||."""
        return self.b3[0] <= self.beta3_paper <= self.b3[1]


def figure_facts(out_dir: Path, quick: bool, rows: list[CheckRow]) -> FigureFacts:
    """Draw figures 3-6 into ``out_dir`` and gather the numbers the section states.

    Parameters
    ----------
    out_dir : Path
        The report folder.
    quick : bool
        Coarser grid (151 points per axis instead of 301).
    rows : list of CheckRow
        The reproduction table (the paper's printed beta_3 is taken from it).

    Returns
    -------
    FigureFacts
        The facts :func:`figures_text` writes.
    """
    a = analyse(str(MODELS_DIR / REDUCED), quick)
    paper = analyse(str(MODELS_DIR / FULL), quick).model_file.paper
    plant = a.model_file.plant
    loop = closed_loop(a.model_file)
    gain, stiff = paper["input_gain"], paper["linear_coefficient_in_eq13"]

    def printed(w: np.ndarray) -> np.ndarray:
        return (gain / (-w ** 2 + stiff)).astype(complex)

    def reference(w: np.ndarray) -> np.ndarray:
        return np.asarray(loop.reference_to_output(1j * w), dtype=complex)

    plant_den = linear_polynomials(plant)[1]
    plant_poles = np.roots(plant_den)
    unstable = bool(np.any(plant_poles.real > 0))
    fig34 = h1_figure(plant, out_dir / "paper-gfrf-fig3-4.png", hz=True,
                      extra=[(f"paper's printed h1 = {gain:g}/(-w^2 + {stiff:g})", printed),
                             ("linear closed loop y/r (for comparison)", reference)],
                      title="Figs 3-4: H1 of eq (16)" + (
                          ": L-inf gain of an unstable plant (pole at s = "
                          f"{max(plant_poles.real):.4g})" if unstable else ""))
    half = 2.5 * frequency_scale(plant)
    points = 151 if quick else 301
    fig5 = h3_slice_figure(plant, out_dir / "paper-gfrf-fig5.png", 0.0, half, hz=True,
                           points=points, title="Fig 5: |H3(f1, f2, f3 = 0)|, eq (16)")
    grid = 2 * np.pi * np.linspace(-half, half, points)
    w1, w2 = np.meshgrid(grid, grid)
    h3 = np.asarray(kernel(plant, 3)(w1, w2, np.zeros_like(w1)), dtype=complex)
    real = bool(np.all(np.abs(h3.imag) <= 1e-12 * np.abs(h3)))
    sign = ("negative" if np.all(h3.real < 0) else "positive" if np.all(h3.real > 0)
            else "of both signs")
    fig6 = h3_slice_figure(plant, out_dir / "paper-gfrf-fig6.png", 0.0, half, hz=True,
                           points=points, phase=True,
                           title="Fig 6: phase of H3(f1, f2, f3 = 0), eq (16)" + (
                               f"; H3 real, {sign}" if real else ""))
    b3 = a.verdict.norms[2]
    beta3 = next(r.paper for r in rows if r.section == "5 (cart-pole, eq (16))"
                 and r.quantity.startswith("beta_3"))
    return FigureFacts(names=(fig34, fig5, fig6), stiff=float(stiff), unstable=unstable,
                       real=real, sign=sign, points=points, d0=float(plant_den[-1]),
                       b3=(float(b3.lower), float(b3.upper)),
                       argmax=tuple(float(w) for w in b3.argmax), beta3_paper=float(beta3))


def figures_text(f: FigureFacts) -> list[str]:
    """The section's lines from its facts.

    Parameters
    ----------
    f : FigureFacts
        The facts (:func:`figure_facts`).

    Returns
    -------
    list of str
        The lines.
    """
    fig34, fig5, fig6 = f.names
    flat = (" H3 is real on this slice (no damping term: A(jw) = -w^2 "
            f"{'+' if f.d0 >= 0 else '-'} {abs(f.d0):g} is real) and {f.sign} at every one "
            f"of the {f.points}^2 grid points, so figure 6 is one flat colour (phase 180 deg "
            "where H3 < 0, 0 where H3 > 0): the phase plot shows only the sign."
            if f.real else "")
    lower, upper, _ = bracket_cells(*f.b3)
    return ["## Figures 3-6 regenerated", "",
            "**What is drawn.** Section 5 prints the plant kernels h1 and h3 of the reduced "
            "model eq (16) just before the figures, so \"first order\" and \"third order\" are "
            "read as the *plant* GFRFs H1 and H3 of eq (16) (open loop, no controller), in Hz "
            "as in the paper, with f3 = 0. For comparison figure 3-4 also shows the paper's "
            "printed h1 formula (its sign slip puts a pole at "
            f"{num(float(np.sqrt(f.stiff)) / (2 * np.pi), 4)} Hz) and the linear closed loop "
            "y/r. Eq (12)'s extra terms theta theta'^2 and theta^2 theta'' change H3 only "
            "(see [cartpole](models/cartpole.md))."
            + (" The plant is unstable, so |H1(jw)| in figure 3-4 is the L-inf gain on the "
               "frequency axis, not a response that could be measured; it only looks like a "
               "stable low-pass." if f.unstable else "") + flat, "",
            f"![Figs 3-4]({fig34})", "",
            f"![Fig 5]({fig5}) ![Fig 6]({fig6})", "",
            f"The largest |H3| found is {lower} at "
            f"{cell([w / (2 * np.pi) for w in f.argmax])} Hz, with certified upper bound "
            f"{upper} ({code('gfrf norm models/cartpole_reduced.toml --order 3')}); "
            f"the paper's beta_3 = {num(f.beta3_paper)} is "
            + ("" if f.beta3_in_bracket() else "not ") + "in this bracket (see the table).", ""]
