"""The lower side of a NARX model: an invariant box of its recursion.

:func:`gfrf.stability.narx_box.box_certificate` finds a box of the lagged state that the
recursion maps into itself for every input with sup|u| <= U, checked in exact rational
arithmetic; here it becomes a :class:`gfrf.stability.energy.Certificate` of the lower side.
"""

from __future__ import annotations

from gfrf.stability.energy import Certificate
from gfrf.stability.polysys import PolySystem

__all__ = ["BOX_METHOD", "narx_box_lower"]

BOX_METHOD = "invariant box of the NARX recursion (exact rational check)"
_PROPERTY = ("bounded: from rest the lagged state stays in the invariant box "
             "(not: returns to the equilibrium)")


def narx_box_lower(system: PolySystem, input_class: str) -> Certificate:
    """The invariant-box certificate of a NARX state form (radius 0 when none is found).

    Parameters
    ----------
    system : PolySystem
        The discrete state form (:func:`gfrf.stability.polysys.state_form`).
    input_class : str
        The input class of the radius (every input with sup|u| <= radius).

    Returns
    -------
    Certificate
        Proof ``"exact"`` with the box in ``detail``, or radius 0 and proof ``"none"``.
    """
    from gfrf.stability.narx_box import box_certificate

    res = box_certificate(system)
    if res is None:
        return Certificate(BOX_METHOD, 0.0, "none", input_class,
                           "not found: the box iteration escapes for every U tried")
    c = res.certificate
    coords = "; ".join(f"s{i} in [{lo}, {hi}]"
                       for i, (lo, hi) in enumerate(zip(c["lo"], c["hi"], strict=True)))
    detail = (f"{system.map_text()}; coordinates s = T(x) with exact inverse "
              f"(s0 = y[k-1] minus its input-only terms where that helps); box {coords} "
              f"maps into itself for every |u| <= {c['U']} (image enclosed on "
              f"{'x'.join(map(str, c['splits']))} cells in exact rational arithmetic); "
              f"every output stays within |y| <= {res.bound:.6g}; {res.work} box iterations")
    return Certificate(BOX_METHOD, res.radius, "exact", input_class, detail, _PROPERTY)
