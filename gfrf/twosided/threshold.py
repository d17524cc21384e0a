"""The two-sided answer: stable below ``lower`` (proven), unstable at ``upper`` (a witness).

``lower`` is the largest radius of the proven certificates: Theorem 1's r* (Theorem 2's
for a model file with a controller; input class: sums of tones, amplitude = sum of tone
amplitudes, the L1 norm of the spectrum), the energy certificate of
:mod:`gfrf.stability.energy` (every bounded input: radius infinity when it applies) or,
for a softening oscillator, the invariant sublevel set of
:mod:`gfrf.stability.energy_local` (every input with sup|u| <= U).
``upper`` is the amplitude of the falsifier's witness (:mod:`gfrf.twosided.falsify`),
searched only when no certificate is global.  Between them: unknown (the only case
still called ``inconclusive``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from gfrf._results import markdown_table, proof_word, short_repr
from gfrf.model.equation import Model
from gfrf.model.modelfile import ModelFile, resolve_model
from gfrf.stability.energy import Certificate, energy_certificate
from gfrf.stability.energy_local import local_energy_certificate
from gfrf.twosided.falsify import (
    CAP_FACTOR,
    ESCAPE_LEVEL,
    Falsification,
    falsify,
    tones_text,
)

__all__ = ["Threshold", "threshold", "THEOREM_CLASS"]

#: Input class of Theorems 1 and 2.
THEOREM_CLASS = {
    1: "sums of tones u = sum A_i cos(omega_i t + phi_i), amplitude = sum A_i (the L1 "
       "norm of the spectrum, Theorem 1's class)",
    2: "sums of tones in the reference r, amplitude = sum A_i (the L1 norm of the "
       "spectrum, Theorem 2's class)"}
#: The level of proof of ``lower`` in the JSON contract for each certificate level.
_LOWER_PROOF = {"exact": "interval", "interval": "interval", "float": "float"}
#: The amplitude series conditions of Theorems 1 and 2 (r* is their radius).
_SERIES_CONDITIONS = ("norm series sum ||H_n|| r^n converges",
                      "sum theta_n rho_1^n r^n converges")
UPPER_METHOD = ("falsifier: sum of tones switched on at t = 0 from rest escapes "
                "(simulation witness, estimate-grade)")


@dataclass(frozen=True)
class Threshold:
    """Result of :func:`threshold` (the ``--json`` of ``gfrf threshold``: :meth:`to_dict`).

    Attributes
    ----------
    name : str
        The model's name.
    lower : float
        Largest proven radius (``inf`` for a global certificate).
    lower_method, lower_proof : str
        Its certificate, and ``"interval"`` (proven: exact or ball arithmetic),
        ``"float"`` or ``"none"``.
    upper : float or None
        Amplitude of the falsifier's witness (sum of its tone amplitudes); None when no
        escape was found up to ``cap`` or when ``lower`` is infinite.
    upper_method : str or None
    certificates : tuple of Certificate
    falsification : Falsification or None
        The search (None when not run: a global certificate).
    static_bound : float or None
        The proven upper bound on the norm series' radius (a static branch point); a
        bound on where the Volterra series converges, not on stability.
    theorem : int
        1 (open loop) or 2 (reference of the closed loop).
    """

    name: str
    lower: float
    lower_method: str
    lower_proof: str
    upper: float | None
    upper_method: str | None
    certificates: tuple[Certificate, ...]
    falsification: Falsification | None = field(default=None, repr=False)
    static_bound: float | None = None
    theorem: int = 1

    @property
    def witness(self) -> dict[str, Any] | None:
        """``{"tones": [[A, omega, phase], ...], "t_escape": t}`` or None."""
        return self.falsification.witness() if self.falsification and self.upper else None

    @property
    def answer(self) -> str:
        """The verdict in words."""
        signal = "reference amplitude" if self.theorem == 2 else "input amplitude"
        proof = proof_word(self.lower_proof)
        if math.isinf(self.lower):
            return f"stable for every {signal} ({proof}: {self.lower_method})"
        low = (f"stable below {signal} {self.lower:.6g} ({proof}: {self.lower_method})"
               if self.lower > 0 else "stability is proven at no amplitude")
        if self.upper is None:
            return f"{low}; unknown above (no escaping input found)"
        return f"{low}; unstable at {self.upper:.6g} (a witness escapes); unknown in between"

    def verdict_at(self, amplitude: float) -> str:
        """``stable`` below ``lower`` (proven), ``unstable`` at or above ``upper`` (an input
        of amplitude ``upper`` <= ``amplitude`` escapes: a simulation witness), else
        ``inconclusive`` (the gap)."""
        if amplitude < self.lower:
            return "stable"
        if self.upper is not None and amplitude >= self.upper:
            return "unstable"
        return "inconclusive"

    @property
    def witness_tones(self) -> list[tuple[float, float, float]]:
        """The witness's tones (amplitude, omega rad/s, phase rad); empty without one."""
        return list(self.falsification.tones) if self.falsification else []

    def __repr__(self) -> str:
        return short_repr(self, "lower", "upper", "lower_method")

    def _repr_markdown_(self) -> str:
        rows = [("stable below (lower)", self.lower, self.lower_proof, self.lower_method),
                ("unstable at (upper)", self.upper, "estimate" if self.upper else "-",
                 self.upper_method or "no escape found")]
        rows += [(f"certificate: {c.method}", c.radius, c.proof, c.input_class)
                 for c in self.certificates]
        title = f"**{self.name}**: " if self.name else ""
        return f"{title}{self.answer}\n\n" + markdown_table(
            ("", "amplitude", "proof", "method / inputs"), rows)

    def to_dict(self) -> dict[str, Any]:
        """The JSON contract of ``gfrf threshold --json`` (``lower`` may be ``inf``)."""
        f = self.falsification
        return {
            "lower": float(self.lower), "lower_method": self.lower_method,
            "lower_proof": self.lower_proof,
            "upper": None if self.upper is None else float(self.upper),
            "upper_method": self.upper_method, "witness": self.witness,
            # proof levels of the contract ("exact" rational checks count as "interval")
            "certificates": [{**{k: v for k, v in c.to_dict().items() if k != "detail"},
                              "proof": _LOWER_PROOF.get(c.proof, c.proof)}
                             for c in self.certificates],
            "answer": self.answer, "model": self.name, "theorem": self.theorem,
            "upper_proof": "estimate" if self.upper is not None else None,
            "static_bound": self.static_bound,
            "search": None if f is None else {
                "cap": f.cap, "t_end_s": f.t_end, "runs": f.runs, "edge": f.edge,
                "escape": f.escape},
            "certificate_details": {c.method: c.detail for c in self.certificates}}

    def text(self) -> str:
        """The short text of ``gfrf threshold``: the three regions, then the evidence."""
        f = self.falsification
        lines = [self.name] if self.name else []
        lines.append(self.answer)
        if f is not None and self.upper is not None:
            lines.append(f"witness: u = {tones_text(f.tones)}, switched on at t = 0 from "
                         f"rest, reaches |y| >= {ESCAPE_LEVEL:g} at t = {f.t_escape:.6g} s "
                         "(simulation, estimate-grade; DOP853 at two tolerances agree)")
        elif f is not None:
            lines.append(f"no sum of tones up to amplitude {f.cap:.6g} (the search cap) "
                         f"escaped within {f.t_end:g} s")
        certs = ", ".join(f"{c.method.split(' (')[0]} {c.radius:.6g} ({c.proof})"
                          for c in self.certificates)
        lines.append(f"certificates: {certs}")
        if self.static_bound is not None:
            lines.append(f"static bound {self.static_bound:.6g}: the norm series' radius, "
                         "not a stability limit")
        return "\n".join(lines)


def threshold(model: ModelFile | Model, *, order: int = 5,
              progress: Callable[[int, int], None] | None = None) -> Threshold:
    """Stable below ``lower`` (proven), unstable at ``upper`` (a witness), unknown between.

    Parameters
    ----------
    model : ModelFile or Model
        A model; a model file with a ``[controller]`` is analysed in closed loop
        (Theorem 2; amplitudes are those of the reference).
    order : int
        Order of the norms of the verdict behind Theorem 1's r*.
    progress : callable, optional
        ``progress(done, total)`` during the falsifier's search.

    Returns
    -------
    Threshold

    Examples
    --------
    >>> import gfrf
    >>> gfrf.threshold(gfrf.parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")).lower
    inf
    """
    from gfrf.stability.criteria import verdict
    from gfrf.stability.static import radius_upper

    mf = resolve_model(model)
    closed = mf.controller is not None
    v = verdict(mf, order=order, with_norms=False, proof="interval")
    # r* proves stability only with the theorem's other hypotheses (a stable linear
    # part, proper kernels, ...): a failed or open one leaves radius 0
    other = [c for c in v.conditions if c.name not in _SERIES_CONDITIONS]
    holds = all(c.passed is True for c in other)
    certs = [Certificate(f"theorem {v.theorem} (norm series radius r*)",
                         float(v.radius) if holds else 0.0,
                         v.radius_proof if v.radius_certified else "none",
                         THEOREM_CLASS[v.theorem],
                         "" if holds else "not applicable: " + "; ".join(
                             c.name for c in other if c.passed is not True))]
    if not closed:
        energy = energy_certificate(mf.plant) or local_energy_certificate(mf.plant)
        if energy is not None:
            certs.append(energy)
    proven = [c for c in certs if c.proof in _LOWER_PROOF]
    # the largest radius; of equal ones, the higher proof level
    best = max(proven, key=lambda c: (c.radius, _LOWER_PROOF[c.proof] == "interval"),
               default=None)
    lower = best.radius if best else 0.0
    static = radius_upper(mf.plant)
    static_bound = None if static is None else float(static.value)
    falsification = None
    upper = None
    if not math.isinf(lower):
        # the cap from the finite scales only (a linear model's radii are infinite)
        ref = max((x for x in (static_bound, float(v.radius))
                   if x is not None and 0 < x < math.inf), default=1.0)
        cap = CAP_FACTOR * ref
        falsification = falsify(mf, cap, closed_loop=closed, progress=progress)
        upper = falsification.upper
    return Threshold(
        name=getattr(mf, "name", "") or "", lower=lower,
        lower_method=best.method if best else "none",
        lower_proof=_LOWER_PROOF[best.proof] if best and lower > 0 else "none", upper=upper,
        upper_method=UPPER_METHOD if upper is not None else None,
        certificates=tuple(certs), falsification=falsification,
        static_bound=static_bound, theorem=v.theorem)
