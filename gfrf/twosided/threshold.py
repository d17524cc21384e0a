"""The two-sided answer: stable below ``lower`` (proven), unstable at ``upper`` (a witness).

``lower`` is the largest radius proven for every input with sup|u| <= lower
(:mod:`gfrf.twosided.lower`): the energy certificates of :mod:`gfrf.stability.energy`
and :mod:`gfrf.stability.energy_local` and the exactly re-checked sum-of-squares
certificate of :mod:`gfrf.stability.sos`.  Theorem 1's r* (Theorem 2's for a model file
with a controller; input class: sums of tones, amplitude = the L1 norm of the spectrum)
is listed beside it in ``certificates``, never as it.  An unstable equilibrium (a pole
of the linear part in the unstable region, decided exactly) answers lower = upper = 0.
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
from gfrf.model.safetext import markdown_text
from gfrf.stability.energy import Certificate
from gfrf.twosided.falsify import CAP_FACTOR, Falsification, falsify
from gfrf.twosided.lower import (
    IMPROPER_LOWER_CLASS,
    LINF_LOWER_CLASS,
    LOOP_LOWER_CLASS,
    lower_side,
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
#: ``upper_method`` per witness kind of an open-loop model (the witness is the input u).
UPPER_METHOD = {
    "switching": "falsifier: switching input u = +-U (sup|u| = U) from rest escapes",
    "chirp": "falsifier: chirp A cos(w0 t + k t^2) (sup|u| = A) from rest escapes",
    "tones": "falsifier: sum of tones switched on at t = 0 from rest escapes "
             "(amplitude = sum of tone amplitudes)"}
#: ``upper_method`` per witness kind of a loop u = C(r - y) (the witness is the reference
#: r; ``implicit``: the plant-input signal d = C r of a loop with an improper controller).
LOOP_UPPER_METHOD = {
    "switching": "falsifier: switching reference r = +-U (sup|r| = U) from rest escapes",
    "chirp": "falsifier: chirp A cos(w0 t + k t^2) (sup|r| = A) from rest escapes",
    "tones": UPPER_METHOD["tones"],
    "implicit": "falsifier: switching plant-input signal d = +-U (sup|d| = U; d = C r) from "
                "rest reaches the loop's breakdown level |D(y)| <= 1e-6 |D(0)|, where "
                "y'' = -R/D is 1e6 times its scale"}


@dataclass(frozen=True, kw_only=True)
class Threshold:
    """Result of :func:`threshold` (the ``--json`` of ``gfrf threshold``: :meth:`to_dict`).

    ``to_dict`` stays written out: the contract is mostly derived values (the regions'
    ends, the answer, the proof words), a summary of the falsification search and the
    certificates with their proof levels mapped to the contract's, not the fields.  Left
    out: ``sos`` (summarised in ``certificates``), ``certificate_file`` (what
    ``--certificate-out`` writes) and ``d_witness`` (given as ``witness``).

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
    lower_class : str
        The inputs ``lower`` covers: every input (reference) with sup|u| <= lower.
    unstable : str or None
        The exact reason the equilibrium is unstable (then lower = upper = 0).
    sos : SosResult or None
        The verified sum-of-squares certificate, if any.
    certificate_file : dict or None
        The re-checkable file of the certificate behind ``lower`` (sum-of-squares, NARX
        invariant box or paving; exact rationals), written by ``--certificate-out``;
        None when ``lower``'s method has none (energy, Theorem 1/2).
    d_witness : ImplicitWitness or None
        For a loop with an improper controller: the escaping plant-input signal d = C r
        (its ``witness()`` is the JSON ``witness``), or None.
    """

    name: str
    lower: float
    lower_method: str
    lower_proof: str
    upper: float | None
    upper_method: str | None
    certificates: tuple[Certificate, ...]
    falsification: Falsification | None = field(default=None, repr=False)
    enclosure: Any = field(default=None, repr=False)
    static_bound: float | None = None
    theorem: int = 1
    lower_class: str = LINF_LOWER_CLASS
    unstable: str | None = None
    sos: Any = field(default=None, repr=False)
    certificate_file: dict[str, Any] | None = field(default=None, repr=False)
    d_witness: Any = field(default=None, repr=False)

    @property
    def tone_radius(self) -> float:
        """Theorem 1's (2's) r*: proven for sums of tones of that L1 spectrum norm only."""
        return float(self.certificates[0].radius) if self.certificates else 0.0

    @property
    def witness(self) -> dict[str, Any] | None:
        """The witness (``kind`` ``"tones"``, ``"switching"`` or ``"chirp"``, see
        :meth:`~gfrf.twosided.falsify.Falsification.witness`), ``{"kind":
        "unstable-pole", "reason": ...}`` for an unstable equilibrium, or None."""
        if self.unstable is not None:
            return {"kind": "unstable-pole", "reason": self.unstable}
        if self.d_witness is not None and self.upper:
            return dict(self.d_witness.witness())
        return self.falsification.witness() if self.falsification and self.upper else None

    @property
    def answer(self) -> str:
        """The verdict in words."""
        signal = "reference amplitude" if self.theorem == 2 else "input amplitude"
        proof = proof_word(self.lower_proof)
        if self.unstable is not None:
            return f"unstable at every {signal}: {self.unstable}"
        what = "every reference with sup|r|" if self.theorem == 2 else "every input with sup|u|"
        if self.lower_class == IMPROPER_LOWER_CLASS:
            what = "every reference with sup|C r| (a plant-input signal d = C r)"
        if math.isinf(self.lower):
            return f"bounded for every bounded input ({proof}: {self.lower_method})"
        low = (f"stable for {what} below {self.lower:.6g} ({proof}: {self.lower_method})"
               if self.lower > 0 else "stability is not proven at any amplitude")
        if self.tone_radius > self.lower:
            low += (f"; for sums of tones (L1 spectrum norm, Theorem {self.theorem}'s class "
                    f"only) below {self.tone_radius:.6g}")
        if self.upper is None:
            return f"{low}; unknown above (no escaping input found)"
        if self.d_witness is not None:
            return (f"{low}; breaks down at {self.upper:.6g} (sup|d| = sup|C r|: a witness "
                    f"reaches the loop's breakdown level |D(y)| <= 1e-6 |D(0)|, "
                    f"{self.upper_proof_words}); unknown in between")
        measure = (("sup|r|" if self.lower_class == LOOP_LOWER_CLASS else "sup|u|")
                   if self.falsification and self.falsification.kind in ("switching", "chirp")
                   else "sum of tone amplitudes")
        return (f"{low}; unstable at {self.upper:.6g} ({measure}: a witness escapes, "
                f"{self.upper_proof_words}); unknown in between")

    @property
    def upper_proof(self) -> str | None:
        """``"interval"`` (the escape is enclosed in ball arithmetic), ``"estimate"``
        (a simulation witness) or None (no witness)."""
        if self.upper is None:
            return None
        if self.unstable is not None:
            return "interval"
        return "interval" if self.enclosure is not None and self.enclosure.proven \
            else "estimate"

    @property
    def answered(self) -> bool:
        """Both sides closed (``gfrf threshold`` exits 0 exactly then): an exactly decided
        unstable equilibrium, or a proven lower side (``lower > 0`` with ``lower_proof``
        ``"interval"`` or ``"float"``) that is global (``lower`` infinite) or met by a
        witness (``upper``, proven or simulated: ``upper_proof`` says which).  Nothing
        proven below (``lower = 0``) is never an answer, whatever the witness."""
        if self.unstable is not None:
            return True
        proven = self.lower > 0 and self.lower_proof in ("interval", "float")
        return proven and (math.isinf(self.lower) or self.upper is not None)

    @property
    def upper_proof_words(self) -> str:
        """How the witness's escape was shown, in words."""
        if self.upper_proof == "interval":
            return proof_word("interval")
        if self.falsification is not None and self.falsification.discrete:
            return "witnessed by the NARX recursion"
        return "witnessed"

    def verdict_at(self, amplitude: float) -> str:
        """``stable`` below ``lower`` (proven), ``unstable`` at or above ``upper`` (an input
        of amplitude ``upper`` <= ``amplitude`` escapes: a simulation witness), else
        ``inconclusive`` (the gap).

        Parameters
        ----------
        amplitude : float
            The input amplitude sup|u| (for a loop: sup|r| of the reference).

        Returns
        -------
        str
            ``"stable"``, ``"unstable"`` or ``"inconclusive"``.
        """
        if amplitude < self.lower:  # every input with sup|u| < lower
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
                ("unstable at (upper)", self.upper, self.upper_proof or "-",
                 self.upper_method or "no escape found")]
        rows += [(f"certificate: {c.method}", c.radius, c.proof, c.input_class)
                 for c in self.certificates]
        title = f"**{markdown_text(self.name)}**: " if self.name else ""
        return f"{title}{self.answer}\n\n" + markdown_table(
            ("", "amplitude", "proof", "method / inputs"), rows)

    def to_dict(self) -> dict[str, Any]:
        """The JSON contract of ``gfrf threshold --json`` (``lower`` may be ``inf``)."""
        f = self.falsification
        return {
            "lower": float(self.lower), "lower_method": self.lower_method,
            "lower_proof": self.lower_proof, "lower_class": self.lower_class,
            "unstable": self.unstable,
            "upper": None if self.upper is None else float(self.upper),
            "upper_method": self.upper_method, "witness": self.witness,
            # proof levels of the contract ("exact" rational checks count as "interval")
            "certificates": [{**{k: v for k, v in c.to_dict().items() if k != "detail"},
                              "proof": _LOWER_PROOF.get(c.proof, c.proof)}
                             for c in self.certificates],
            "answer": self.answer, "answered": self.answered, "model": self.name,
            "theorem": self.theorem,
            "upper_proof": self.upper_proof,
            "static_bound": self.static_bound,
            "search": None if f is None else {
                "cap": f.cap, "t_end_s": f.t_end, "runs": f.runs, "edge": f.edge,
                "escape": f.escape, "escape_levels": f.levels,
                "escape_region": None if f.region is None else {
                    "y_plus": f.region.y_plus if math.isfinite(f.region.y_plus) else "inf",
                    "y_minus": f.region.y_minus if math.isfinite(f.region.y_minus)
                    else "inf"}},
            "enclosure": None if self.enclosure is None else self.enclosure.to_dict(),
            "certificate_details": {c.method: c.detail for c in self.certificates}}

    def text(self) -> str:
        """The short text of ``gfrf threshold``: the three regions, then the evidence."""
        f = self.falsification
        lines = [self.name] if self.name else []
        lines.append(self.answer)
        if self.d_witness is not None and self.upper is not None:
            w = self.d_witness
            e = self.enclosure
            how = (f"proven: {e.method}, to t <= {e.t_proven:.6g} s, where the enclosure "
                   f"has {e.reason}" if self.upper_proof == "interval" else
                   "simulation, estimate-grade; DOP853 at two tolerances agree")
            lines.append(f"witness (switching, the plant-input signal d = C r of the loop): "
                         f"{w.text('d')}, from rest at t = 0, reaches the loop's breakdown "
                         f"level |D(y)| <= 1e-6 |D(0)| at t = {w.t_escape:.6g} s ({how})")
        if f is not None and self.upper is not None:
            where = (f"enters the escape region {f.region.text()}" if f.region is not None
                     else "leaves the escape levels")
            how = ("the NARX recursion" if f.discrete else
                   "simulation, estimate-grade; DOP853 at two tolerances agree")
            if self.upper_proof == "interval":
                e = self.enclosure
                how = (f"proven: {e.method} to t = {e.t_proven:.6g} s, where the enclosure "
                       f"has {e.reason}")
            loop = self.lower_class == LOOP_LOWER_CLASS
            of = ", the reference r of the loop u = C(r - y)" if loop else ""
            lines.append(f"witness ({f.kind}{of}): {f.input_text('r' if loop else 'u')}, "
                         f"from rest at t = 0, "
                         f"{where} at t = {f.t_escape:.6g} s ({how})")
        elif f is not None:
            lines.append(f"no switching input or sum of tones up to amplitude {f.cap:.6g} "
                         f"(the search cap) escaped within {f.t_end:g} s")
        certs = ", ".join(f"{c.method.split(' (')[0]} {c.radius:.6g} ({c.proof})"
                          for c in self.certificates)
        lines.append(f"certificates: {certs}")
        if self.static_bound is not None:
            lines.append(f"static bound {self.static_bound:.6g}: the norm series' radius, "
                         "not a stability limit")
        return "\n".join(lines)


def threshold(model: ModelFile | Model, *, order: int = 5, prove: bool = True,
              progress: Callable[[int, int], None] | None = None) -> Threshold:
    """Stable below ``lower`` (proven), unstable at ``upper`` (a witness), unknown between.

    Parameters
    ----------
    model : ModelFile or Model
        A model; a model file with a ``[controller]`` is analysed in closed loop
        (Theorem 2; amplitudes are those of the reference).
    order : int
        Order of the norms of the verdict behind Theorem 1's r*.
    prove : bool
        Enclose the witness's escape in ball arithmetic (:mod:`gfrf.twosided.enclose`):
        ``upper_proof`` ``"interval"`` when it succeeds.
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
    theorem_cert = Certificate(method=f"theorem {v.theorem} (norm series radius r*)",
                               radius=float(v.radius) if holds else 0.0,
                               proof=v.radius_proof if v.radius_certified else "none",
                               input_class=THEOREM_CLASS[v.theorem],
                               detail="" if holds else "not applicable: " + "; ".join(
                                   c.name for c in other if c.passed is not True),
                               property="the Volterra series converges (bounded, returns to the "
                               "equilibrium with the input)")
    side = lower_side(mf, theorem_cert)
    certs = list(side.certificates)
    # the top-level lower: every input with sup|u| <= lower (never the tone class)
    best = side.best
    lower = best.radius if best else 0.0
    static = radius_upper(mf.plant)
    static_bound = None if static is None else float(static.value)
    falsification = None
    upper = 0.0 if side.unstable is not None else None
    enclosure = None
    d_witness = None
    if side.implicit is not None and not math.isinf(lower):
        from gfrf.twosided.implicit_upper import implicit_witness

        d_witness = implicit_witness(side.implicit, lower) if lower > 0 else None
        upper = d_witness.amplitude if d_witness is not None else None
        if d_witness is not None and prove:
            from gfrf.twosided.implicit_enclose import enclose_implicit_witness

            enclosure = enclose_implicit_witness(
                side.implicit, d_witness.amplitude, d_witness.first_sign,
                d_witness.switch_times, d_witness.t_escape)
    elif not math.isinf(lower) and side.unstable is None:
        # the cap from the finite scales only (a linear model's radii are infinite)
        ref = max((x for x in (static_bound, float(v.radius))
                   if x is not None and 0 < x < math.inf), default=1.0)
        cap = CAP_FACTOR * ref
        falsification = falsify(mf, cap, closed_loop=closed, floor=lower,
                                progress=progress)
        upper = falsification.upper
        if upper is not None and upper < lower:
            # a witness inside the proven region contradicts a proof: not reported
            upper = None
        if upper is not None and prove:
            from gfrf.twosided.enclose import enclose_witness

            enclosure = enclose_witness(mf if closed else mf.plant, falsification)
    methods = LOOP_UPPER_METHOD if closed else UPPER_METHOD
    return Threshold(
        name=getattr(mf, "name", "") or "", lower=lower,
        lower_method=best.method if best else "none",
        lower_proof=_LOWER_PROOF[best.proof] if best and lower > 0 else "none", upper=upper,
        upper_method=(None if upper is None
                      else "unstable equilibrium (exact pole location)"
                      if side.unstable is not None
                      else LOOP_UPPER_METHOD["implicit"] if d_witness is not None
                      else methods.get(falsification.kind or "")
                      if falsification is not None else None),
        certificates=tuple(certs), falsification=falsification, enclosure=enclosure,
        static_bound=static_bound, theorem=v.theorem,
        lower_class=side.input_class or (LOOP_LOWER_CLASS if closed else LINF_LOWER_CLASS),
        unstable=side.unstable, sos=side.sos, certificate_file=side.best_file,
        d_witness=d_witness)
