"""Notebook views of the frequency-domain results: Markdown tables and figures of a
:class:`gfrf.sim.volterra.VolterraPrediction` and of an :class:`gfrf.sim.ofrf.OFRF`.

Figures are made without pyplot (:func:`gfrf._results.new_figure`): no window opens
under any backend; matplotlib is imported on the first plot only.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gfrf._results import markdown_table, new_figure

__all__ = ["prediction_markdown", "prediction_figure", "ofrf_markdown", "ofrf_figure"]


def prediction_markdown(p: Any) -> str:
    """The components of a Volterra prediction as a Markdown table.

    Parameters
    ----------
    p : VolterraPrediction
        The prediction.

    Returns
    -------
    str
        A heading line and a table of omega (rad/s), amplitude and phase (rad).
    """
    head = (f"**Volterra prediction, order {p.order}**: input amplitude {p.amplitude:.6g}, "
            f"series radius r* = {p.radius:.6g} ({p.radius_proof})")
    if p.warning:
        head += f"\n\n*warning: {p.warning}*"
    rows = [(c.omega, c.amplitude, c.phase) for c in p.components]
    return head + "\n\n" + markdown_table(("omega (rad/s)", "amplitude", "phase (rad)"), rows)


def prediction_figure(p: Any, simulated: Any = None, *, periods: float = 20.0) -> Any:
    """Predicted amplitudes as stems against omega (rad/s), with the FFT of a simulation.

    ``simulated`` is a :class:`gfrf.sim.simulation.SimulationResult` (or ``(t, y)``) whose
    last ``periods`` periods of the slowest tone are taken as the steady state; its
    one-sided amplitude spectrum (Hann window) is drawn behind the stems.

    Parameters
    ----------
    p : VolterraPrediction
        The prediction.
    simulated : SimulationResult or tuple of array_like, optional
        A simulation, or ``(t, y)`` in s; None: the stems only.
    periods : float, optional
        Number of periods of the slowest tone taken from the end of the simulation.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    figure, axes = new_figure(1, 1, (7.0, 3.8))
    ax = axes[0][0]
    omegas = np.array([c.omega for c in p.components])
    amplitudes = np.array([c.amplitude for c in p.components])
    if simulated is not None:
        t, y = (simulated.t, simulated.y) if hasattr(simulated, "t") else simulated
        t, y = np.asarray(t, dtype=float), np.asarray(y, dtype=float)
        slowest = min(w for _, w, _ in p.tones)
        keep = t >= t[-1] - periods * 2 * np.pi / slowest
        t, y = t[keep], y[keep]
        if t.size > 8:
            window = np.hanning(t.size)
            spectrum = np.fft.rfft(y * window) * 2 / window.sum()
            spectrum[0] /= 2
            w = 2 * np.pi * np.fft.rfftfreq(t.size, t[1] - t[0])
            ax.semilogy(w, np.abs(spectrum), color="0.6", lw=1,
                        label="simulation (FFT of the last periods, Hann)")
    positive = amplitudes > 0
    ax.vlines(omegas[positive], 1e-300, amplitudes[positive], color="C0")
    ax.semilogy(omegas[positive], amplitudes[positive], "o", color="C0",
                label=f"Volterra prediction, order {p.order}")
    if positive.any():
        ax.set_ylim(amplitudes[positive].min() / 100, amplitudes[positive].max() * 3)
        ax.set_xlim(-0.05 * omegas.max() - 0.1, 1.1 * omegas.max() + 0.1)
    ax.set(xlabel="omega (rad/s)", ylabel="amplitude",
           title=f"steady state: input amplitude {p.amplitude:.4g}, r* = {p.radius:.4g}")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    return figure


def ofrf_markdown(o: Any) -> str:
    """The OFRF coefficients and NOFRFs as Markdown tables.

    Parameters
    ----------
    o : OFRF
        The output frequency response function.

    Returns
    -------
    str
        A heading line and two tables.
    """
    head = (f"**OFRF of {o.parameter}** at omega = {o.omega:.6g} rad/s, order {o.order}: "
            f"complex amplitude = sum P_k {o.parameter}^k (estimate: truncated series; "
            f"truncation error at {o.parameter} = {o.value:.6g} at most "
            f"{o.truncation_bound:.3g}, {o.truncation_proof})")
    coeffs = markdown_table(("k", "Re P_k", "Im P_k"),
                            [(k, c.real, c.imag) for k, c in enumerate(o.coefficients)])
    nofrf = markdown_table(("n", f"G_n at {o.parameter} = {o.value:.6g}"),
                           [(n, None if g is None else f"{g:.6g}")
                            for n, g in o.nofrf().items()])
    return "\n\n".join([head, coeffs, nofrf])


def ofrf_figure(o: Any, values: Any = None) -> Any:
    """|Y(jW)| (the amplitude at W) against the parameter's value.

    Parameters
    ----------
    o : OFRF
        The output frequency response function.
    values : array_like, optional
        Values of the parameter; default 201 points from ``value - |value|`` to
        ``value + |value|`` (a span of 1 each side when the file's value is 0).

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    if values is None:
        span = abs(o.value) or 1.0
        values = np.linspace(o.value - span, o.value + span, 201)
    values = np.asarray(values, dtype=float)
    figure, axes = new_figure(1, 1, (6.0, 3.6))
    ax = axes[0][0]
    ax.plot(values, [abs(o(v)) for v in values], label=f"OFRF, order {o.order}")
    ax.axvline(o.value, color="0.5", ls=":", label=f"{o.parameter} = {o.value:.4g} (file)")
    ax.set(xlabel=o.parameter, ylabel=f"amplitude at {o.omega:.4g} rad/s",
           title=f"output at omega = {o.omega:.4g} rad/s as a polynomial in {o.parameter}")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    return figure
