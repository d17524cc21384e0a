"""The lower side of a NARX model: an invariant box, then an invariant paving, of its recursion.

:func:`gfrf.stability.narx_box.box_certificate` finds a box of the lagged state that the
recursion maps into itself for every input with sup|u| <= U;
:func:`gfrf.stability.narx_paving.paving_certificate` then looks above that U for a union of
grid cells that is invariant (thinner than a box where consecutive outputs are
correlated).  Both are checked in exact rational arithmetic; here they become
:class:`gfrf.stability.energy.Certificate` entries of the lower side.
"""

from __future__ import annotations

from typing import Any

from gfrf.stability.energy import Certificate
from gfrf.stability.narx_check import PROPERTY as _PROPERTY
from gfrf.stability.polysys import PolySystem

__all__ = ["BOX_METHOD", "PAVING_METHOD", "narx_lower"]

BOX_METHOD = "invariant box of the NARX recursion (exact rational check)"
PAVING_METHOD = "invariant paving of the NARX recursion (exact rational check)"


def narx_lower(system: PolySystem, input_class: str
               ) -> tuple[tuple[Certificate, ...], dict[str, dict[str, Any]]]:
    """The invariant-box certificate of a NARX state form and, above it, the paving one.

    Parameters
    ----------
    system : PolySystem
        The discrete state form (:func:`gfrf.stability.polysys.state_form`).
    input_class : str
        The input class of the radius (every input with sup|u| <= radius).

    Returns
    -------
    tuple of Certificate
        The box (radius 0 and proof ``"none"`` when none is found) and, when one is
        verified, the paving (searched from the box's radius up); proof ``"exact"``.
    dict
        The re-checkable file (exact rationals) of each verified one, by method.
    """
    from gfrf.stability.narx_box import box_certificate
    from gfrf.stability.narx_paving import paving_certificate

    res = box_certificate(system)
    if res is None:
        box = Certificate(method=BOX_METHOD, radius=0.0, proof="none", input_class=input_class,
                          detail="not found: the box iteration escapes for every U tried")
    else:
        c = res.certificate
        coords = "; ".join(f"s{i} in [{lo}, {hi}]"
                           for i, (lo, hi) in enumerate(zip(c["lo"], c["hi"], strict=True)))
        box = Certificate(
            method=BOX_METHOD, radius=res.radius, proof="exact", input_class=input_class,
            detail=f"{system.map_text()}; coordinates s = T(x) with an exact inverse; box {coords} "
            f"maps into itself for every |u| <= {c['U']} (image enclosed on "
            f"{'x'.join(map(str, c['splits']))} cells in exact rational arithmetic); "
            + (f"every output stays within |y| <= {res.bound:.6g}; "
               if res.bound < float("inf") else "")
            + f"{res.work} box iterations",
            property=_PROPERTY)
    files = {} if res is None else {BOX_METHOD: res.certificate}
    if res is not None and res.radius == float("inf"):
        return (Certificate(method=BOX_METHOD, radius=res.radius, proof="exact",
                            input_class="every bounded input (L-infinity, any size)",
                            detail=box.detail + "; the recursion is linear, so the box scaled by t "
                            "is invariant for every t * U", property=_PROPERTY),), files
    pav = paving_certificate(system, res.radius if res is not None else 0.0)
    if pav is None:
        return (box,), files
    p = pav.certificate
    files[PAVING_METHOD] = p
    return (box, Certificate(
        method=PAVING_METHOD, radius=pav.radius, proof="exact", input_class=input_class,
        detail=f"{system.map_text()}; {pav.cells} cells of a {p['N']}-per-lag grid of the output "
        f"coordinates times [-U, U] for the lagged inputs; the image of every cell for "
        f"every |u| <= {p['U']} is enclosed in exact rational arithmetic and covered by "
        f"cells of the paving; every output stays within |y| <= {pav.bound:.6g}",
        property=_PROPERTY)), files
