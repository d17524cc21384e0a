"""The lower side of the two-sided answer: every certificate tried, with its input class.

The top-level ``lower`` of :func:`gfrf.twosided.threshold.threshold` is the largest
radius proven for *every input with sup|u| <= lower* (L-infinity; the reference r of a
loop u = C(r - y)): the energy certificates (:mod:`gfrf.stability.energy`,
:mod:`gfrf.stability.energy_local`) and the sum-of-squares certificate
(:mod:`gfrf.stability.sos`, exactly re-verified).  Theorem 1's (2's) r* covers a smaller
class (sums of tones, amplitude = the L1 norm of the spectrum): it is listed beside it,
never as it.  A linear part (or linear closed loop) with a pole in the unstable region,
decided exactly, answers ``lower = upper = 0``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from gfrf._results import Result
from gfrf.model.modelfile import ModelFile
from gfrf.stability.energy import Certificate, energy_certificate
from gfrf.stability.energy_local import local_energy_certificate

__all__ = ["LowerSide", "lower_side", "LINF_LOWER_CLASS", "SOS_METHOD"]

#: The input class of the top-level ``lower``.
LINF_LOWER_CLASS = ("every input u(t) with sup|u| <= lower (L-infinity, any shape and "
                    "duration), from rest")
LOOP_LOWER_CLASS = ("every reference r(t) with sup|r| <= lower (L-infinity), loop "
                    "u = C(r - y), from rest")
SOS_METHOD = "sum-of-squares storage function V (exact rational check)"
#: The class of a loop with an improper polynomial controller: d = C r enters the plant
#: exactly as a plant-input signal, so the bound is on C r, not on r.
IMPROPER_LOWER_CLASS = ("every reference r(t) with sup|C(s) r| <= lower (equivalently every "
                        "plant-input signal d = C r with sup|d| <= lower), loop u = C(r - y) "
                        "= d - C y, from rest")
REGION_METHOD = "invariant polygon of the implicit loop (exact rational check)"
#: Classes that count for the top-level lower.
_LINF_PROOFS = ("exact", "interval")


@dataclass(frozen=True, kw_only=True, repr=False)
class LowerSide(Result):
    """The certificates of the lower side (``to_dict``: ``certificates`` and ``unstable``;
    ``best`` is left out as one of the certificates, ``sos`` as the search object behind
    the sos certificate, which is in ``certificates``, and ``files`` as the re-checkable
    files that ``--certificate-out`` writes).

    Attributes
    ----------
    certificates : tuple of Certificate
        Every method tried (radius 0 and proof ``none`` when it did not apply).
    best : Certificate or None
        The largest proven L-infinity radius.
    unstable : str or None
        Why the equilibrium is unstable (an exact pole location), or None.
    sos : Any
        The :class:`gfrf.stability.sos.SosResult` behind the SOS certificate, or None.
    files : dict
        The re-checkable file (exact rationals, ``gfrf certificate check``) of each
        verified certificate that has one, by method.
    input_class : str or None
        The class of the top-level lower when it is not the model's usual one (a loop
        with an improper controller: :data:`IMPROPER_LOWER_CLASS`).
    implicit : Any
        The implicit form (:class:`gfrf.stability.implicit.ImplicitLoop`) behind it.
    """

    _exclude = ("best", "sos", "files", "implicit")

    certificates: tuple[Certificate, ...]
    best: Certificate | None
    unstable: str | None = None
    sos: Any = None
    files: dict[str, dict[str, Any]] = field(default_factory=dict, repr=False)
    input_class: str | None = None
    implicit: Any = field(default=None, repr=False)

    @property
    def best_file(self) -> dict[str, Any] | None:
        """The file of the headline certificate (``best``), or None when it has none."""
        return None if self.best is None else self.files.get(self.best.method)



def _unstable(mf: ModelFile, system: Any) -> str | None:
    """The exact reason the equilibrium is unstable, or None."""
    from flint import fmpq, fmpq_mat

    from gfrf.bounds.exact import format_roots, poles

    if system is not None:
        A = system.jacobian()
        n = len(A)
        M = fmpq_mat(n, n, [fmpq(x.numerator, x.denominator) for row in A for x in row])
        coeffs = [c for c in reversed(M.charpoly().coeffs())]
        from fractions import Fraction

        chi = [Fraction(int(c.p), int(c.q)) for c in coeffs]
        report = poles(chi, discrete=system.discrete)
        what = "linear closed loop" if mf.controller is not None else "linear part"
    elif mf.controller is not None and not mf.plant.is_discrete:
        from gfrf.stability.loops import closed_loop

        loop = closed_loop(mf)
        if not loop.outside:
            return None
        return ("the linear closed loop has a pole with Re s > 0 (exact test on its "
                "characteristic polynomial): " + "; ".join(loop.notes))
    else:
        from gfrf.bounds.majorant import linear_polynomials

        _, den = linear_polynomials(mf.plant)
        report = poles(den, discrete=mf.plant.is_discrete)
        what = "linear part"
    if not report.outside:
        return None
    region = "|z| > 1" if (system.discrete if system is not None
                           else mf.plant.is_discrete) else "Re s > 0"
    bad = [p for p in report.roots
           if (abs(p) > 1 if region == "|z| > 1" else p.real > 0)]
    return (f"the {what} has a pole in {region} (decided exactly): {format_roots(bad)}; "
            "the equilibrium is unstable, so no input amplitude keeps the response near it")


def lower_side(mf: ModelFile, theorem_certificate: Certificate) -> LowerSide:
    """Every lower-side certificate of a model (file), and the best L-infinity one.

    Parameters
    ----------
    mf : ModelFile
        The model; with a ``[controller]`` the closed loop u = C(r - y) is analysed.
    theorem_certificate : Certificate
        Theorem 1's (2's) r*, listed first (tone class).

    Returns
    -------
    LowerSide
    """
    from gfrf.stability.polysys import StateFormError, state_form
    from gfrf.stability.sos import MAX_GRAM_SEARCH, search_size, sos_certificate

    certs = [theorem_certificate]
    closed = mf.controller is not None
    try:
        system = state_form(mf)
        why_not = ""
    except StateFormError as exc:
        system, why_not = None, f"no polynomial state form: {exc}"
        implicit = _implicit_lower(mf, theorem_certificate)
        if implicit is not None:
            return implicit
    unstable = _unstable(mf, system)
    if unstable is not None:
        return LowerSide(certificates=tuple(certs), best=None, unstable=unstable)
    linf = LOOP_LOWER_CLASS if closed else LINF_LOWER_CLASS
    files: dict[str, dict[str, Any]] = {}
    if not closed:
        energy = energy_certificate(mf.plant) or local_energy_certificate(mf.plant)
        if energy is not None:
            certs.append(energy)
    if system is not None and system.discrete:
        from gfrf.twosided.lower_narx import narx_lower

        narx, narx_files = narx_lower(system, linf)
        certs.extend(narx)
        files.update(narx_files)
    sos = None
    if not any(c.radius == float("inf") or (c.radius > 0 and system is not None
                                            and system.discrete) for c in certs[1:]):
        if system is not None and search_size(system) > MAX_GRAM_SEARCH:
            why_not = (f"Gram size {search_size(system)} above the search bound "
                       f"MAX_GRAM_SEARCH = {MAX_GRAM_SEARCH}")
        elif system is not None:
            sos, solves = sos_certificate(system)
            why_not = "" if sos is not None else (
                f"no proposal passed the exact check ({solves} SDPs)")
        if sos is not None:
            kind = sos.kind
            detail = (f"{kind}: {system.map_text() if system else ''}; V of degree "
                      f"{max(sum(k) for k, _ in sos.certificate['V'])}; "
                      + ("V radially unbounded, dV/dt < 0 outside a compact set for every "
                         "bounded input" if sos.radius == float("inf") else
                         f"{{V <= {sos.certificate['c']}}} invariant for |v| <= "
                         f"{sos.certificate['U']}")
                      + f"; {sos.solves} SDPs (Clarabel), identity and Gram matrices "
                      "re-checked in exact rational arithmetic")
            files[SOS_METHOD] = sos.certificate
            certs.append(Certificate(method=SOS_METHOD, radius=sos.radius, proof="exact",
                                     input_class=linf if sos.radius != float("inf") else
                                     "every bounded input (L-infinity, any size)",
                                     detail=detail, property=sos.property))
        else:
            certs.append(Certificate(method=SOS_METHOD, radius=0.0, proof="none", input_class=linf,
                                     detail="not applicable: " + why_not))
    proven = [c for c in certs[1:] if c.proof in _LINF_PROOFS and c.radius > 0]
    best = max(proven, key=lambda c: c.radius, default=None)
    return LowerSide(certificates=tuple(certs), best=best, sos=sos, files=files)


def _implicit_lower(mf: ModelFile, theorem_certificate: Certificate) -> LowerSide | None:
    """The lower side of a loop with no polynomial state form but an implicit one
    (:mod:`gfrf.stability.implicit`: the highest derivative with a polynomial
    coefficient, an improper polynomial controller): an exactly checked invariant
    polygon, in the class of bounded plant-input signals d (d = C r for a loop)."""
    from gfrf.stability.implicit import implicit_form
    from gfrf.stability.implicit_check import polygon_parts
    from gfrf.stability.implicit_region import region_certificate
    from gfrf.stability.polysys import StateFormError

    try:
        form = implicit_form(mf)
        polygon_parts(form)  # the polygon needs 2 states, D of y alone, R affine in d
    except (StateFormError, ValueError):
        return None
    linf = IMPROPER_LOWER_CLASS if form.loop else LINF_LOWER_CLASS
    cap = _static_cap(form)
    cert, work = region_certificate(form, cap) if cap is not None else (None, 0)
    if cert is None:
        c = Certificate(method=REGION_METHOD, radius=0.0, proof="none", input_class=linf,
                        detail=f"not applicable: no polygon passed the exact check ({work} built)")
        return LowerSide(certificates=(theorem_certificate, c), best=None,
                         input_class=linf, implicit=form)
    from fractions import Fraction

    from gfrf.stability.implicit_check import bound

    U = Fraction(cert["U"])
    radius = float(U) if Fraction(float(U)) <= U else math.nextafter(float(U), 0.0)
    ymax, vmax = bound(cert)
    detail = (f"D(x) y'' + R(x, d) = 0 with x = ({', '.join(form.states)}), d = "
              f"{form.input_name}; a polygon of {len(cert['vertices'])} vertices with "
              f"|y| <= {ymax:.6g}, |y'| <= {vmax:.6g} is invariant for every |d| <= {cert['U']}"
              f" and |D| stays above {cert.get('level', 0)} |D(0)| on it ({work} polygons "
              "built; edges, simplicity "
              "and D re-checked in exact rational arithmetic)")
    c = Certificate(method=REGION_METHOD, radius=radius, proof="exact", input_class=linf,
                    detail=detail,
                    property="bounded: every solution from rest stays in the invariant polygon "
                    "(not: returns to the equilibrium)")
    return LowerSide(certificates=(theorem_certificate, c), best=c,
                     files={REGION_METHOD: cert}, input_class=linf, implicit=form)


def _static_cap(form: Any) -> float | None:
    """The search cap: the constant input whose equilibrium reaches the singular set
    (no polygon can hold beyond it), or None when the form does not fit."""
    from gfrf.stability.implicit_region import LoopField

    try:
        fl = LoopField(form)
    except ValueError:
        return None
    ys = fl.singular()[1]
    if not math.isfinite(ys):
        return None
    y = ys * (1 - 1e-9)
    g1 = fl.g1(y, 0.0)
    return abs(fl.g0(y, 0.0) / g1) if g1 else None
