"""H-infinity norms of the GFRFs: ||H1|| exactly, ||Hn|| (n >= 2) as a certified bracket.

``h1_norm(model)`` is the sup over omega (rad/s) of |H1(j omega)|, H1 = -B/A, as a
proven enclosure ``[lower, upper]`` (``proof = "interval"``): exact rational algebra
on the float coefficients and ball arithmetic on the stationary points of |H1|^2
(:func:`gfrf.bounds.rational.rational_sup`), for continuous and NARX models alike.  It is
cross-checked against python-control's ``control.norm(sys, p='inf')`` (whose
tolerance is 1e-6 without slycot).  A common factor of B and A is cancelled exactly
and reported; an improper H1 or a pole on the imaginary axis (unit circle), decided
exactly, gives ``upper = inf`` with the reason in ``notes``; an unstable linear part
(a pole in the open right half plane) still has a finite sup on the axis (the
L-infinity norm, used by Theorem 2 for an unstable plant), flagged ``stable = False``.
Stability of A is decided exactly (Routh's test in rationals, :mod:`gfrf.bounds.exact`).

``kernel_norm(model, n)`` brackets ||H_n|| = sup over R^n of |H_n(j w_1..j w_n)|:

* ``upper`` is certified: the recursive majorant of :mod:`gfrf.bounds.majorant` (proven sups
  combined in ball arithmetic, :meth:`gfrf.bounds.majorant.Majorant.proven_upper`), valid for the
  symmetric and the asymmetric kernel.  For a pure-output polynomial with constant
  input gain (Duffing, the hanging pendulum) it equals |c3| ||H1||^3 sup|1/A| for H3
  and is attained at (w_r, w_r, -w_r): the gap is rounding only.  Where the majorant
  is not attained (the cart-pole's theta^3 and theta^2 u partly cancel; resonances
  that cannot coincide) a kernel of order n <= 5 is refined by the certified
  branch-and-bound of :mod:`gfrf.bounds.branch_bound` (continuous: majorant tail outside a
  box; NARX: the torus [-pi/T, pi/T]^n; third-order Taylor enclosures on sub-boxes)
  until the gap is below ``tol``
  (default 1e-3) or a work cap of about 8 s of enclosures
  (:func:`gfrf.bounds.branch_bound.default_budget`) is spent; the bracket stays open
  (honestly) where that budget is too small.
* ``lower`` is the best value found: |H_n| evaluated at all start points built from the
  resonance frequencies of the linear part (each w_i in {0, +-damped natural
  frequencies, +-peak frequencies of |H1| and |1/A|}, plus points whose sum hits a
  resonance), taken up to permutation and global sign (the symmetric kernel is
  invariant under both in modulus), then polished by Nelder-Mead on log|H_n|.  At
  ``proof = "interval"`` and ``"float"`` |H_n| is re-evaluated at that witness point in
  ball arithmetic (:mod:`gfrf.bounds.witness`: exact binary coefficients and frequencies) and
  the lower end is
  the ball's lower end rounded down, proven to be attained to its digits
  (``lower_proof = "interval"``); a ball wider than 1e-10 relative keeps the float
  value, labelled ``"float"``.  An identically zero kernel (decided symbolically) is exact.

Which kernel: the symmetric kernel by default (it is unique for the system); the
asymmetric kernel of the recursion on request (it depends on how the model is written).

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> m = parse_model("D(y,2) + 0.05*D(y) + 2.45*y - 0.41*y**3 = u")
>>> b = kernel_norm(m, 3)
>>> b.certified and b.gap < 1e-9
True
"""

from __future__ import annotations

import math
import sys
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from gfrf._results import Result, markdown_table, short_repr
from gfrf.bounds.branch_bound import (
    DEFAULT_WORK,
    MAX_OPEN,
    MAX_ORDER,
    BranchBoundResult,
    box_work,
    branch_and_bound,
    check_budget,
    default_budget,
)
from gfrf.bounds.budget import kernel_operations
from gfrf.bounds.exact import PoleReport, format_roots, poles
from gfrf.bounds.local_search import SEARCH_WORK, local_search
from gfrf.bounds.majorant import linear_polynomials, linear_sup, majorant, written_polynomials
from gfrf.bounds.rational import check_proof
from gfrf.errors import ArgumentError
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import Model

if TYPE_CHECKING:
    import control

__all__ = ["Bound", "h1_norm", "kernel_norm", "linear_poles", "linear_stability"]

#: Default relative gap of :func:`kernel_norm` (and ``gfrf norm --tol``).
DEFAULT_TOL = 1e-3


@dataclass(frozen=True, kw_only=True)
class Bound(Result):
    """A bracket ``lower <= ||H_n||_inf <= upper`` (angular frequencies in rad/s).

    Attributes
    ----------
    lower : float
        Best value of |H_n| actually found (attained at ``argmax``).
    upper : float
        Upper bound (``inf`` when unbounded or not bounded by the method).
    argmax : tuple of float
        Angular frequencies (rad/s) where ``lower`` is attained.
    certified : bool
        True when ``upper`` is a certified bound (see ``proof`` for how rigorous).
    method : str
        How the bracket was obtained.
    order : int
        Kernel order n.
    symmetric : bool
        Norm of the symmetric (True) or asymmetric kernel.
    stable : bool or None
        Whether the linear part A is stable (None if not determined).
    notes : tuple of str
        Reasons for infinite values, instability, an open gap.
    reference : float or None
        python-control's ``norm(sys, 'inf')`` for order 1 (cross-check), else None.
    proof : str
        The weaker of the two ends: ``"interval"``: lower and upper are proven (exact
        algebra, ball arithmetic, outward rounding); ``"float"``: a sound method
        evaluated in floating point (relative rounding ~1e-15 not accounted for, or a
        float witness point); ``"none"``: estimates only (not certified).
    upper_proof, lower_proof : str
        The level of each end ("" means ``proof``): for n >= 2 at the interval level
        the upper end is proven by the ball-arithmetic majorant (``"float"`` where the
        float branch-and-bound lowered it) and the lower end by |H_n| at ``argmax`` in
        ball arithmetic (``"float"`` if that ball is too wide, see ``notes``).
    boxes : int
        Boxes the branch-and-bound evaluated (0 when it did not run): the work spent.
    tol : float
        The relative gap the bracket was asked to reach (``kernel_norm``'s ``tol``).
    converged : bool
        Derived (in ``to_dict`` too): the bracket is certified (``proof`` is not
        ``"none"``) and its relative ``gap`` is at most ``tol``; an exact value (a zero
        kernel, a proven infinite norm) has gap 0.  ``gfrf norm`` exits 1 unless it holds
        and the linear part is stable.
    """

    _order = ("order", "lower", "upper", "gap", "argmax")

    lower: float
    upper: float
    argmax: tuple[float, ...]
    certified: bool
    method: str
    order: int
    symmetric: bool = True
    stable: bool | None = None
    notes: tuple[str, ...] = field(default=())
    reference: float | None = None
    proof: str = "float"
    upper_proof: str = ""
    lower_proof: str = ""
    boxes: int = 0
    tol: float = DEFAULT_TOL

    @property
    def converged(self) -> bool:
        """Certified and closed to ``tol``: ``proof != "none"`` and ``gap <= tol``."""
        return self.certified and self.proof != "none" and self.gap <= self.tol

    @property
    def gap(self) -> float:
        """Relative gap (upper - lower) / upper (0 for an exact value, inf if unbounded)."""
        if self.upper == self.lower:
            return 0.0
        if math.isinf(self.upper):
            return math.inf
        return (self.upper - self.lower) / self.upper

    def __repr__(self) -> str:
        return short_repr(self, "order", "lower", "upper", "certified")

    def _repr_markdown_(self) -> str:
        """The bracket as a one-row Markdown table (Jupyter)."""
        return markdown_table(("n", "lower", "upper", "gap", "lower proof", "upper proof"),
                              [(self.order, self.lower, self.upper, self.gap,
                                self.lower_proof or self.proof,
                                self.upper_proof or self.proof)])

    def _computed(self) -> dict[str, Any]:
        return {"gap": self.gap, "converged": self.converged,
                "upper_proof": self.upper_proof or self.proof,
                "lower_proof": self.lower_proof or self.proof}


def linear_poles(model: Model) -> PoleReport:
    """Exact location of the poles of A: Re s < 0, or |z| < 1 in z = 1/q for NARX.

    Decided on the exact rational values of the (normalised) coefficients by Routh's
    test (after the Cayley map for NARX), with exact boundary roots; see
    :func:`gfrf.bounds.exact.poles`.

    Parameters
    ----------
    model : Model
        The plant model (continuous or NARX).

    Returns
    -------
    PoleReport
        Whether every root is inside, whether some is outside, the boundary roots and
        all roots (s, or z = 1/q for NARX).
    """
    # For a NARX model den is A's coefficients, lowest power of q first; in z = 1/q the
    # polynomial z^L A(1/z) has those same coefficients, highest power of z first.
    _, den = written_polynomials(model) or linear_polynomials(model)  # as written if rational
    return poles(den, model.is_discrete)


def linear_stability(model: Model) -> tuple[bool, np.ndarray]:
    """(stable, poles) of A, stability decided exactly (see :func:`linear_poles`).

    Parameters
    ----------
    model : Model
        The plant model (continuous or NARX).

    Returns
    -------
    tuple of (bool, numpy.ndarray)
        Whether A is asymptotically stable, and its roots (s, or z = 1/q for NARX).
    """
    report = linear_poles(model)
    return report.stable, report.roots


def h1_norm(model: Model, proof: str = "interval", cross_check: bool = False) -> Bound:
    """||H1||_inf = sup over omega (rad/s) of |H1(j omega)|, as a proven enclosure.

    Parameters
    ----------
    model : Model
        The plant model (continuous or NARX).
    proof : {"interval", "float", "none"}
        Level of proof (:func:`gfrf.bounds.rational.rational_sup`); the default proves.
    cross_check : bool, optional
        Also compute python-control's ``norm(sys, 'inf')`` into ``Bound.reference``
        (imports python-control, ~2 s cold, and ~70 % of a warm call: off by default).

    Returns
    -------
    Bound
        ``[lower, upper]`` proven at the default level; ``inf`` for an improper H1
        or poles on the imaginary axis / unit circle (reason in ``notes``);
        ``stable = False`` flags an unstable linear part, whose finite value is then
        the L-infinity norm on the axis, not an H-infinity norm.
    """
    check_proof(proof)
    num, den = linear_polynomials(model)
    report = linear_poles(model)
    stable = report.stable
    notes = []
    if not stable:
        where = ("some pole strictly outside the stability region" if report.outside else
                 "poles on the stability boundary at "
                 + format_roots(report.boundary, "z" if model.is_discrete else "s"))
        notes.append(f"linear part not asymptotically stable ({where}, exact test): the value "
                     "is the L-infinity norm on the frequency axis, not an H-infinity norm")
    if model.is_discrete:
        sup = linear_sup(model, proof)  # proof "interval": the model as written
        method = ("exact rational algebra on the unit circle (Cayley map) + "
                  + _stationary_text(proof))
    else:
        sup = linear_sup(model, proof)
        method = "exact rational algebra + " + _stationary_text(proof)
    reference = None
    if cross_check and stable and math.isfinite(sup.upper):
        import control  # imported where used: nothing else here needs it

        system = (control.tf(_pad(num, den), _pad(den, num), model.sample_time)
                  if model.is_discrete else control.tf(num, den))
        reference = _control_norm(system)
        method += ", cross-checked with control.norm"
    no_upper = ("||H1|| = inf: " if sup.lower == math.inf else
                f"no finite upper end at proof level {proof!r}: ")
    notes += [no_upper + note if note == sup.reason else note for note in sup.notes]
    return Bound(lower=sup.lower,
                 upper=sup.upper,
                 argmax=(sup.omega,),
                 certified=proof != "none",
                 method=method,
                 order=1,
                 symmetric=True,
                 stable=stable,
                 notes=tuple(notes),
                 reference=reference,
                 proof=proof)


def _stationary_text(proof: str) -> str:
    if proof == "interval":
        return "ball enclosure of the stationary points of |H1|^2 (proven)"
    label = "float" if proof == "float" else "estimate"
    return f"stationary points of |H1|^2 by numpy.roots ({label})"


def _pad(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """q-polynomial (lowest first) as a z-polynomial (highest first) of the common degree."""
    return np.concatenate([a, np.zeros(max(a.size, b.size) - a.size)])


def _control_norm(system: control.TransferFunction) -> float | None:
    """python-control's H-infinity norm, or None where it fails (e.g. a zero system)."""
    import control

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            return float(control.norm(system, p="inf", print_warning=False))
        except (np.linalg.LinAlgError, ValueError):
            return None


def kernel_norm(model: Model, n: int, symmetric: bool = True, tol: float = DEFAULT_TOL,
                max_boxes: int | None = None, proof: str = "interval",
                cross_check: bool = False, searches: int | None = None,
                progress: bool | None = False) -> Bound:
    """Bracket ||H_n||_inf over R^n (rad/s): certified upper, best-found lower bound.

    Parameters
    ----------
    model : Model
        The plant model (continuous or NARX).
    n : int
        Kernel order (1 gives :func:`h1_norm`).
    symmetric : bool, optional
        Symmetric kernel (default) or the asymmetric kernel of the recursion.
    tol : float, optional
        Target relative gap (default :data:`DEFAULT_TOL` = 1e-3); more local searches
        are run, and the branch-and-bound goes on, while the gap exceeds it.
    max_boxes : int or None, optional
        Budget of the branch-and-bound (boxes evaluated, at most
        :data:`gfrf.bounds.branch_bound.BOX_LIMIT`), used when the majorant leaves a gap above
        ``tol`` (n <= 5); 0 skips it (the majorant's upper end and the
        local search only); None (default) is
        :func:`gfrf.bounds.branch_bound.default_budget`: a work cap of about 8 s of
        enclosures on one core, from the kernel's size.  The search stops on this work
        count or on ``tol``, never on time.  Measured on a 2-core 2026 machine
        (``gfrf bench``, section "Tight brackets"): ||H5|| of every bundled continuous model
        closes to ``tol = 1e-3`` within the default budget (the hanging pendulum in about
        55,000 boxes, the cart-pole plant in about 26,000; the counts may differ between
        CPUs in the last bits of floating point); of the NARX models ||H3|| closes (about
        1,300 boxes), the identified examples' ||H5|| stays open (gap about 0.49 after
        20,466 boxes; 0.035 with ``max_boxes=120_000``).
    proof : {"interval", "float", "none"}
        ``"interval"`` (default): the majorant's upper end in ball arithmetic on proven
        sups (``upper_proof = "interval"``) and the witness |H_n(argmax)| in ball
        arithmetic (``lower_proof = "interval"``).
        ``"float"``: the majorant in floating point on double-precision sups (one
        that underflows to 0 is redone in balls); the witness still in ball arithmetic
        (cheap, and a float |H_n| can be off where A(j w) cancels).
        ``"none"``: the float majorant and the local search only (no
        branch-and-bound), labelled estimates (``certified = False``).
    cross_check : bool, optional
        For n = 1, also python-control's norm (see :func:`h1_norm`).
    searches : int, optional
        Most local searches of the lower bound (default: up to 12 for n <= 4 and 2
        above, stopping once the gap is below ``tol``); fewer searches only lower it.
    progress : bool or None, optional
        Progress bar of the branch-and-bound (see
        :func:`gfrf.bounds.branch_bound.branch_and_bound`);
        None shows it on a terminal only.  Default False.

    Returns
    -------
    Bound
    """
    if not (isinstance(tol, float | int) and 0 < tol < 1):
        raise ArgumentError(f"tol must be in (0, 1), got {tol!r}")
    if searches is not None and (isinstance(searches, bool) or not isinstance(searches, int)
                                 or searches < 0):
        raise ArgumentError(f"searches must be a non-negative integer, got {searches!r}")
    if max_boxes is not None:
        max_boxes = check_budget(max_boxes, 0)
    check_proof(proof)
    k = kernel(model, n, symmetric)
    if n == 1:
        b = h1_norm(model, proof, cross_check)
        return Bound(lower=b.lower,
                     upper=b.upper,
                     argmax=b.argmax,
                     certified=b.certified,
                     method=b.method,
                     order=1,
                     symmetric=symmetric,
                     stable=b.stable,
                     notes=b.notes,
                     reference=b.reference,
                     proof=b.proof,
                     tol=tol)
    stable, _ = linear_stability(model)
    notes = [] if stable else ["linear part not asymptotically stable: L-infinity norm on the "
                               "frequency axis"]
    if k.is_zero:
        return Bound(lower=0.0,
                     upper=0.0,
                     argmax=tuple([0.0] * n),
                     certified=True,
                     method="kernel identically zero",
                     order=n,
                     symmetric=symmetric,
                     stable=stable,
                     notes=tuple(notes), proof="interval", tol=tol)
    maj = majorant(model, proof)
    upper = maj.proven_upper(n) if proof == "interval" else float(maj.coefficients(n)[n, 0])
    upper_proof = proof
    if upper == 0.0:  # a float majorant of a nonzero kernel underflowed: use balls
        upper, upper_proof = majorant(model, "interval").proven_upper(n), "interval"
    notes += list(maj.reasons)
    blowup = _axis_blowup(k, model, n)
    if blowup is not None:
        return Bound(lower=math.inf,
                     upper=math.inf,
                     argmax=blowup,
                     certified=True,
                     method="A(j w) = 0 on the axis and P_n != 0 there",
                     order=n,
                     symmetric=symmetric,
                     stable=stable,
                     notes=(*notes, "||H_n|| = inf: H_n = -P_n / A(j(w_1+..+w_n)) with A(j w0) = 0 "
                      "and P_n bounded away from 0 near the hyperplane w_1+..+w_n = w0"),
                     tol=tol)
    found = local_search(k, model, n, symmetric, upper, tol, proof,
                         kernel_operations(model, n, symmetric), searches)
    lower, argmax = found.value, found.argmax
    if found.capped:
        notes.append(f"local search stopped on its work cap ({found.evaluations} evaluations "
                     f"of H_{n}, {kernel_operations(model, n, symmetric)} operations each; "
                     "at most "
                     f"{SEARCH_WORK} evaluations x operations per search): the lower end is "
                     "the best value found")
    method = ({"interval": "recursive majorant in ball arithmetic (proven upper)",
               "float": "recursive majorant in floating point (certified upper)",
               "none": "recursive majorant in floating point (estimate)"}[proof]
              + " + resonance-start Nelder-Mead (lower: "
              + ("witness re-evaluated in ball arithmetic)" if proof != "none"
                 else "float witness)"))
    boxes = 0
    if (max_boxes != 0 and (upper == math.inf or upper - lower > tol * upper)
            and n <= MAX_ORDER and proof != "none"):
        bb, skipped = _refine(model, n, symmetric, lower, argmax, tol, max_boxes, progress,
                              upper)
        boxes = 0 if bb is None else bb.boxes
        if bb is None:
            notes.append(skipped)
        else:
            if bb.lower > lower:
                lower, argmax = bb.lower, bb.argmax
            if bb.upper < upper * (1 - 4 * 2.0 ** -52):  # not a rounding of the majorant
                upper, upper_proof = bb.upper, "float"
            notes.append(f"branch-and-bound: {bb.boxes} boxes over the torus "
                         f"[-pi/T, pi/T]^{n} (one period of every w_i)" if model.is_discrete
                         else f"branch-and-bound: {bb.boxes} boxes; |H_{n}| <= "
                         f"{bb.tail:.6g} where some |w_i| > {bb.width:.6g} rad/s (tail bound)")
            if bb.stop in ("budget", "open boxes"):
                notes.append(_stop_note(bb, max_boxes, box_work(model, n, symmetric)))
            method = (f"branch-and-bound, {bb.boxes} boxes in [-{bb.width:.4g}, "
                      f"{bb.width:.4g}]^{n} rad/s"
                      + (" (the torus)" if model.is_discrete else " + majorant tail")
                      + " (certified upper); local search (lower)")
    if upper == math.inf and not maj.reasons:  # no other note explains it
        notes.append(f"the majorant of |H_{n}| overflows double precision (above "
                     f"{sys.float_info.max:.3g}): no finite upper end")
    gap = 0.0 if upper == lower else (upper - lower) / upper
    if gap > tol:
        notes.append(f"relative gap {gap:.3g} > tol {tol:g}: the majorant is not attained "
                     "(terms of different sign or phase) and the branch-and-bound budget "
                     "did not close the gap; honest bracket")
    lower_proof = "none" if proof == "none" else "float"
    if proof != "none":  # a float |H_n| can be off where A(j w) cancels: prove the witness
        lower, lower_proof, note = _proven_witness(model, n, symmetric, lower, argmax)
        notes += [note] if note else []
    if lower > upper:  # only rounding of the float levels can do this
        upper = lower
    weakest = min(upper_proof, lower_proof, key=("none", "float", "interval").index)
    return Bound(lower=lower,
                 upper=upper,
                 argmax=argmax,
                 certified=maj.certified,
                 method=method,
                 order=n,
                 symmetric=symmetric,
                 stable=stable,
                 notes=tuple(notes),
                 proof=weakest,
                 upper_proof=upper_proof,
                 lower_proof=lower_proof,
                 boxes=boxes,
                 tol=tol)


#: Range of the majorant within which the double-precision box enclosures of the
#: branch-and-bound are trusted (beyond it their products underflow or overflow).
_FLOAT_RANGE = (1e-280, 1e280)


def _stop_note(bb: BranchBoundResult, max_boxes: int | None, work: int) -> str:
    """Why the branch-and-bound stopped before ``tol``, and how to go further (``work``:
    operations per box)."""
    if bb.stop == "open boxes":
        return (f"branch-and-bound stopped at {MAX_OPEN} open boxes (the memory cap "
                "MAX_OPEN); the bracket is sound, a larger tol closes sooner")
    which = (f"the default work cap of {DEFAULT_WORK} operations (about 8 s of enclosures "
             "on one core)" if max_boxes is None else "the budget --max-boxes / max_boxes")
    return (f"branch-and-bound stopped at {bb.boxes} boxes of {work} operations each, {which}; "
            "a larger max_boxes (gfrf norm --max-boxes N) goes further, taking about as much "
            "longer")


def _refine(model: Model, n: int, symmetric: bool, lower: float, argmax: tuple[float, ...],
            tol: float, max_boxes: int | None, progress: bool | None, upper: float
            ) -> tuple[BranchBoundResult | None, str]:
    """(branch-and-bound result, "") or (None, why it was not run)."""
    if math.isfinite(upper) and not _FLOAT_RANGE[0] < upper < _FLOAT_RANGE[1]:
        return None, (f"branch-and-bound skipped: the majorant {upper:.3g} is outside "
                      f"[{_FLOAT_RANGE[0]:g}, {_FLOAT_RANGE[1]:g}], where its double-"
                      "precision enclosures would underflow or overflow")
    try:
        budget = default_budget(model, n, symmetric) if max_boxes is None else max_boxes
        return branch_and_bound(model, n, symmetric, lower, argmax, tol,
                                max_boxes=budget, progress=progress), ""
    except OverflowError:
        return None, ("branch-and-bound skipped: the linear part's coefficients (and the "
                      "derivatives of |A(j w)|^2) overflow double precision")


def _proven_witness(model: Model, n: int, symmetric: bool, lower: float,
                    argmax: tuple[float, ...]) -> tuple[float, str, str]:
    """(lower, lower_proof, note): |H_n| at the witness ``argmax`` re-evaluated in balls.

    The proven lower end is the ball's lower end rounded down (at most an ulp or two
    below the float value); a ball wider than :data:`gfrf.bounds.witness.WIDTH` relative keeps
    the float value, labelled "float", with a note.
    """
    from gfrf.bounds.witness import WIDTH, witness_bound

    if lower == 0.0:  # |H_n| >= 0 needs no witness
        return 0.0, "interval", ""
    ball = witness_bound(model, n, argmax, symmetric)
    if ball.relative_width > WIDTH:
        return lower, "float", (f"witness |H_{n}| at {list(argmax)} enclosed only to relative "
                                f"width {ball.relative_width:.3g} in ball arithmetic "
                                f"({ball.precision} bits): the lower end stays a float value")
    return ball.lower, "interval", ""


def _axis_blowup(k: Any, model: Model, n: int) -> tuple[float, ...] | None:
    """A point near which |H_n| is unbounded because A(j w0) = 0, or None.

    On the hyperplane w_1 + .. + w_n = w0 the denominator A(j w0) vanishes; if the
    numerator P_n = -H_n A is nonzero at a generic point of it (|H_n A| evaluated at
    distances 1e-6 and 1e-8 from the hyperplane agree and are not tiny), H_n is
    unbounded there.  Continuous models only.
    """
    if model.is_discrete:
        return None
    _, den = linear_polynomials(model)
    axis = sorted({abs(p.imag) for p in linear_poles(model).boundary})
    rng = np.random.default_rng(0)
    for w0 in axis:
        base = rng.uniform(-1.0, 1.0, n - 1) * (1 + w0) + 0.123
        products = []
        for eps in (1e-6, 1e-8):
            point = (*base, w0 + eps - float(np.sum(base)))
            value = complex(k(*point))
            products.append(abs(value * np.polyval(den, 1j * (w0 + eps))))
        if products[1] > 1e-12 and abs(products[0] - products[1]) <= 1e-3 * products[1]:
            return (*(float(b) for b in base), w0 - float(np.sum(base)))
    return None
