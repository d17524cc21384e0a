"""Shared pieces of the SOS search: the result, monomial bases, the coefficient-matching
program (cvxpy + Clarabel), rounding to rationals and the exact Gram correction."""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np

from gfrf.stability.polysys import Poly
from gfrf.stability.sos_check import gram_poly

__all__ = ["SosResult"]

#: Rationals are rounded to this grid (dyadic, exact in floats).
_ROUND = 2**36


@dataclass(frozen=True, kw_only=True)
class SosResult:
    """A verified SOS certificate.

    Attributes
    ----------
    radius : float
        U (every input with sup|v| <= U), ``inf`` for a global certificate; a float at or
        below the exact rational U of the certificate.
    kind : str
        ``local-continuous``, ``local-discrete`` or ``global-continuous``.
    certificate : dict
        The certificate (exact rationals as ``"p/q"`` texts), re-checkable by
        :func:`gfrf.stability.sos_check.check_dict`.
    solves : int
        SDPs solved (the work).
    property : str
        What is proven.
    """

    radius: float
    kind: str
    certificate: dict[str, Any] = field(repr=False)
    solves: int
    property: str


def _monomials(nv: int, degrees: range, vmax: int, xonly: bool = False) -> list[tuple[int, ...]]:
    out = []
    for d in degrees:
        for combo in itertools.combinations_with_replacement(range(nv), d):
            k = [0] * nv
            for i in combo:
                k[i] += 1
            if (xonly and k[-1]) or k[-1] > vmax:
                continue
            out.append(tuple(k))
    return out


class _Program:
    """Coefficient matching: sum of blocks == constant, blocks linear maps of variables."""

    def __init__(self) -> None:
        import cvxpy as cp

        self.cp = cp
        self.index: dict[tuple[int, ...], int] = {}
        self.parts: list[tuple[dict[tuple[int, int], float], Any]] = []
        self.const: dict[int, float] = {}
        self.constraints: list[Any] = []

    def _row(self, k: tuple[int, ...]) -> int:
        return self.index.setdefault(k, len(self.index))

    def gram(self, basis: list[tuple[int, ...]], times: Poly, sign: float) -> Any:
        """A PSD Gram variable Q: adds sign * (z^T Q z) * times."""
        m = len(basis)
        Q = self.cp.Variable((m, m), PSD=True)
        entries: dict[tuple[int, int], float] = {}
        for i, a in enumerate(basis):
            for j, b in enumerate(basis):
                for t, c in times.items():
                    k = tuple(x + y + z for x, y, z in zip(a, b, t, strict=True))
                    key = (self._row(k), j * m + i)  # column-major vec
                    entries[key] = entries.get(key, 0.0) + sign * float(c)
        self.parts.append((entries, self.cp.vec(Q, order="F")))
        return Q

    def free(self, basis: list[tuple[int, ...]], times: Poly, sign: float) -> Any:
        """A free polynomial lambda over ``basis``: adds sign * lambda * times."""
        lam = self.cp.Variable(len(basis))
        entries: dict[tuple[int, int], float] = {}
        for j, a in enumerate(basis):
            for t, c in times.items():
                k = tuple(x + z for x, z in zip(a, t, strict=True))
                key = (self._row(k), j)
                entries[key] = entries.get(key, 0.0) + sign * float(c)
        self.parts.append((entries, lam))
        return lam

    def constant(self, p: Poly, sign: float) -> None:
        for k, c in p.items():
            r = self._row(k)
            self.const[r] = self.const.get(r, 0.0) + sign * float(c)

    def residual(self) -> tuple[Any, np.ndarray]:
        """The identity's coefficients as a cvxpy expression (one row per monomial) and
        its constant part: the identity holds where ``expr + b == 0``."""
        import scipy.sparse as sps

        rows = len(self.index)
        expr: Any = 0
        for entries, var in self.parts:
            keys = list(entries)
            M = sps.csr_matrix(([entries[k] for k in keys], ([k[0] for k in keys],
                                                            [k[1] for k in keys])),
                               shape=(rows, var.size))
            expr = expr + M @ var
        b = np.zeros(rows)
        for r, c in self.const.items():
            b[r] = c
        return expr, b

    def solve(self, skip: tuple[int, ...] | None = None) -> bool:
        cp = self.cp
        drop = self.index.get(skip) if skip is not None else None
        expr, b = self.residual()
        keep = np.array([r for r in range(len(self.index)) if r != drop])
        prob = cp.Problem(cp.Minimize(0), [expr[keep] + b[keep] == 0, *self.constraints])
        try:
            prob.solve(solver="CLARABEL")
        except cp.error.SolverError:
            return False
        return prob.status == "optimal"


def _r(x: float) -> Fraction:
    return Fraction(round(float(x) * _ROUND), _ROUND)


def _rgram(Q: Any) -> list[list[Fraction]]:
    A = np.asarray(Q.value, dtype=float)
    A = (A + A.T) / 2
    return [[_r(A[i, j]) for j in range(A.shape[1])] for i in range(A.shape[0])]


def _project(basis: list[tuple[int, ...]], Q: list[list[Fraction]], target: Poly,
             free_constant: bool = False) -> list[list[Fraction]] | None:
    """Q corrected so that z^T Q z == target exactly (each monomial's residual spread
    evenly over its Gram entries); None when a monomial has no entry."""
    slots: dict[tuple[int, ...], list[tuple[int, int]]] = {}
    for i, a in enumerate(basis):
        for j, b in enumerate(basis):
            slots.setdefault(tuple(x + y for x, y in zip(a, b, strict=True)), []).append((i, j))
    have = gram_poly(basis, Q)
    out = [row[:] for row in Q]
    for k in set(slots) | set(target):
        if free_constant and not any(k):
            continue
        res = target.get(k, Fraction(0)) - have.get(k, Fraction(0))
        if res == 0:
            continue
        if k not in slots:
            return None
        share = res / len(slots[k])
        for i, j in slots[k]:
            out[i][j] += share
    return out


_GLOBAL = ("bounded: every solution under every bounded input stays bounded (from any "
           "initial state); not: returns to the equilibrium")
