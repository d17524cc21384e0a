"""Re-verification of an invariant-box or invariant-paving file of a NARX model.

``gfrf threshold MODEL --certificate-out FILE`` writes the headline certificate; for a
NARX model that is an invariant box (:mod:`gfrf.stability.narx_box`, format
``gfrf-narx-box``) or an invariant paving (:mod:`gfrf.stability.narx_paving`, format
``gfrf-narx-paving``) of the recursion x[k+1] = f(x[k], u[k]) of the lagged outputs and
inputs.  The file holds U, the coordinates s = T(x) and their inverse X, and the box
(``lo``, ``hi``, ``splits``) or the grid (``R``, ``N``, ``pieces``, ``cells``), every
number an exact rational ``"p/q"``, and, for the record, the recursion it was found for.

:func:`check_narx` re-derives f from the model (never from the file), refuses a file
that is malformed, above a stated limit, or recorded for another recursion
(:class:`gfrf.errors.ArgumentError`: exit 2) before any enclosure is computed, then runs
:func:`gfrf.stability.narx_box.check_box` or
:func:`gfrf.stability.narx_paving.check_paving` (exact rational arithmetic, no search).
"""

from __future__ import annotations

import math
import re
from fractions import Fraction
from typing import Any

from gfrf.errors import ArgumentError
from gfrf.stability.narx_box import MAX_CELLS, box_map, check_box
from gfrf.stability.narx_paving import GRID, MAX_OUTPUT_LAGS, PIECES, check_paving
from gfrf.stability.polysys import Poly, PolySystem, pdegree

__all__ = ["check_narx", "FORMATS", "PROPERTY", "MAX_DIGITS", "MAX_TERMS",
           "MAX_MAP_MONOMIALS", "MAX_CHECK_WORK", "MAX_PAVING_CELLS"]

#: ``format`` of a file -> its ``kind``.
FORMATS = {"gfrf-narx-box": "narx-box", "gfrf-narx-paving": "narx-paving"}
#: What a valid file proves.
PROPERTY = ("bounded: from rest the lagged state stays in the invariant set "
            "(not: returns to the equilibrium)")
#: Digits of a numerator, and of a denominator, of one rational.
MAX_DIGITS = 200
#: Terms of one coordinate polynomial (T or X).
MAX_TERMS = 200
#: Monomials the recursion in the file's coordinates may have (counted from the degrees
#: of T, f and X before it is composed).
MAX_MAP_MONOMIALS = 5000
#: Exact enclosure work: cells (times input pieces) times terms of the recursion.
MAX_CHECK_WORK = 8_000_000
#: Cells of a paving.
MAX_PAVING_CELLS = GRID**MAX_OUTPUT_LAGS

_RATIONAL = re.compile(r"-?([0-9]+)(?:/([0-9]+))?")
_KEY = re.compile(r"[0-9]{1,3}(?:,[0-9]{1,3})*")


def _bad(what: str) -> ArgumentError:
    return ArgumentError(f"malformed NARX certificate: {what}")


def _rational(text: Any, what: str) -> Fraction:
    """A rational from its text ``"p/q"``: ASCII digits, at most :data:`MAX_DIGITS` each."""
    m = _RATIONAL.fullmatch(text) if isinstance(text, str) else None
    if m is None:
        raise _bad(f"{what} must be a rational written as a string 'p/q', got "
                   f"{str(text)[:40]!r}")
    if len(m.group(1)) > MAX_DIGITS or len(m.group(2) or "") > MAX_DIGITS:
        raise _bad(f"{what} has a numerator or denominator above MAX_DIGITS = {MAX_DIGITS} "
                   "digits")
    if m.group(2) is not None and int(m.group(2)) == 0:
        raise _bad(f"{what} has a zero denominator")
    return Fraction(text)


def _int(x: Any, what: str, low: int, high: int) -> int:
    if isinstance(x, bool) or not isinstance(x, int) or not low <= x <= high:
        raise _bad(f"{what} must be an integer in [{low}, {high}], got {str(x)[:40]!r}")
    return x


def _poly(table: Any, nv: int, max_degree: int, what: str) -> Poly:
    if not isinstance(table, dict) or len(table) > MAX_TERMS:
        raise _bad(f"{what} must be a table of at most MAX_TERMS = {MAX_TERMS} terms "
                   "{'e_1,..,e_n,e_v': 'p/q'}")
    out: Poly = {}
    for key, value in table.items():
        if _KEY.fullmatch(key) is None or key.count(",") != nv - 1:
            raise _bad(f"{what}: bad exponent key {key[:40]!r} ({nv} exponents expected)")
        exps = tuple(int(e) for e in key.split(","))
        if sum(exps) > max_degree:
            raise _bad(f"{what}: a term of degree {sum(exps)}, above {max_degree} (the "
                       "recursion's degree)")
        c = _rational(value, f"{what}[{key}]")
        if c:
            out[exps] = c
    return out


def _list(x: Any, size: int, what: str) -> list[Any]:
    if not isinstance(x, list) or len(x) != size:
        raise _bad(f"{what} must be a list of {size} entries")
    return x


def _validate(system: PolySystem, cert: dict[str, Any]) -> str:
    """The file's kind after every structural check and limit; raises ArgumentError."""
    kind = FORMATS.get(str(cert.get("format")))
    if kind is None or cert.get("kind", kind) != kind:
        raise _bad("format and kind are not a NARX box or paving")
    if cert.get("version") != 1:
        raise _bad("only version 1 is known")
    if not system.discrete or not system.bounded_states:
        raise ArgumentError("the certificate is for another model: a NARX recursion, and "
                            "this model is not one")
    n, nv = system.n, system.n + 1
    if cert.get("states") != list(system.states):
        raise ArgumentError(f"the certificate is for another model: its states "
                            f"{str(cert.get('states'))[:120]} differ from the model's "
                            f"{list(system.states)}")
    deg = max(1, max(pdegree(p) for p in system.f))
    recorded = [_poly(p, nv, deg, "recursion") for p in _list(cert.get("recursion"), n,
                                                               "recursion")]
    if recorded != [dict(p) for p in system.f]:
        raise ArgumentError("the certificate is for another model: the recursion it records "
                            "differs from the one derived from MODEL")
    U = _rational(cert.get("U"), "U")
    if U <= 0:
        raise _bad("U must be positive")
    T = [_poly(p, nv, deg, "T") for p in _list(cert.get("T"), n, "T")]
    X = [_poly(p, nv, deg, "X") for p in _list(cert.get("X"), n, "X")]
    top = max(1, max(map(pdegree, T))) * deg * max(1, max(map(pdegree, X)))
    if math.comb(nv + top, top) > MAX_MAP_MONOMIALS:
        raise _bad(f"the recursion in the file's coordinates has degree {top}: up to "
                   f"{math.comb(nv + top, top)} monomials, above MAX_MAP_MONOMIALS = "
                   f"{MAX_MAP_MONOMIALS}")
    ny = min(system.bounded_states)
    terms = [len(p) for p in box_map(system, T, X)]
    if kind == "narx-box":
        for side in ("lo", "hi"):
            [_rational(x, side) for x in _list(cert.get(side), n, side)]
        splits = [_int(s, "splits", 1, MAX_CELLS)
                  for s in _list(cert.get("splits"), nv, "splits")]
        cells = math.prod(splits)
        if cells > MAX_CELLS:
            raise _bad(f"{cells} cells, above MAX_CELLS = {MAX_CELLS}")
        work = cells * sum(terms)
    else:
        if ny > MAX_OUTPUT_LAGS:
            raise _bad(f"a paving covers at most MAX_OUTPUT_LAGS = {MAX_OUTPUT_LAGS} output "
                       "lags")
        if any(_rational(x, "R") <= 0 for x in _list(cert.get("R"), ny, "R")):
            raise _bad("every half-width in R must be positive")
        N = _int(cert.get("N"), "N", 1, GRID)
        pieces = [_int(p, "pieces", 1, PIECES) for p in _list(cert.get("pieces"), nv,
                                                               "pieces")]
        cells_in = cert.get("cells")
        if not isinstance(cells_in, list) or not 1 <= len(cells_in) <= MAX_PAVING_CELLS:
            raise _bad(f"cells must be a list of 1 to MAX_PAVING_CELLS = {MAX_PAVING_CELLS}")
        for c in cells_in:
            [_int(i, "a cell index", 0, N - 1) for i in _list(c, ny, "a cell")]
        work = len(cells_in) * math.prod(pieces) * sum(terms[:ny])
    if work > MAX_CHECK_WORK:
        raise _bad(f"the exact check would evaluate {work} cell terms, above MAX_CHECK_WORK "
                   f"= {MAX_CHECK_WORK}")
    return kind


def check_narx(system: PolySystem, cert: dict[str, Any]) -> tuple[str, str, float]:
    """Re-verify an invariant-box or invariant-paving file against a model's recursion.

    Parameters
    ----------
    system : PolySystem
        The model's own NARX state form (:func:`gfrf.stability.polysys.state_form`).
    cert : dict
        The file's content (format ``gfrf-narx-box`` or ``gfrf-narx-paving``).

    Returns
    -------
    kind : str
        ``"narx-box"`` or ``"narx-paving"``.
    reason : str
        ``""`` when it holds, else the first condition that fails.
    radius : float
        When it holds: a float at or below U (``inf`` when the recursion in the box's
        coordinates is linear: the box scaled by t is invariant for t * U); else 0.

    Raises
    ------
    ArgumentError
        A malformed file, a number or a size above a stated limit, or a file recorded
        for another model (its states or its recursion differ from MODEL's).
    """
    from gfrf.stability.narx_box import _below

    kind = _validate(system, cert)
    reason = check_box(system, cert) if kind == "narx-box" else check_paving(system, cert)
    if reason:
        return kind, reason, 0.0
    nv = system.n + 1
    g = box_map(system, [_poly(p, nv, 12, "T") for p in cert["T"]],
                [_poly(p, nv, 12, "X") for p in cert["X"]])
    if kind == "narx-box" and all(sum(k) == 1 for p in g for k in p):
        return kind, "", math.inf
    return kind, "", _below(Fraction(cert["U"]))
