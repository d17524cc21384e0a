"""Lohner's QR step: interval Taylor enclosures without the wrapping effect.

A box carried from step to step by interval arithmetic grows each step by the absolute
value of the flow's Jacobian (the wrapping effect): an oscillator rotates the box, and
its axis-aligned hull grows like exp(t |J|) even when the true set of solutions does
not grow at all.  Lohner's method carries the set as

    {c + B r : r in R}

with c a point (a ball of zero or tiny radius), B an exact float matrix and R an
interval vector, and advances it by the mean-value form of the flow phi over one step:

    phi(c + B r) in phi(c) + J B r,   J = D phi(X)  (X the hull of c + B R),

where phi(c) is the interval Taylor method from the point c (Taylor coefficients plus
the Lagrange remainder over an a priori enclosure) and J the enclosure of the flow's
Jacobian: the Taylor series of the variational equation V' = DF(z) V from (X, I),
plus its own Lagrange remainder over an a priori enclosure of (z, V).  The next set is
c' = mid(phi(c)), B' = Q from the QR factorisation of mid(J B) (columns ordered by
their share of the width, so the widest direction is kept exactly), and

    R' = (Q^-1 J B) R + Q^-1 (phi(c) - c'),

with Q^-1 the Arb enclosure of the exact inverse of the float matrix Q.  The
derivatives DF are taken by forward differentiation (:class:`_Dual`) of the same
polynomial field, so the variational equation needs no second description of the
model.
"""

from __future__ import annotations

from typing import Any

__all__ = ["LohnerSet", "lohner_step", "JACOBIAN_ORDER"]

#: Taylor order of the Jacobian enclosure (its radius multiplies the set's tiny width).
JACOBIAN_ORDER = 10


class _Dual:
    """A value with its derivatives along each initial state (forward differentiation)."""

    __slots__ = ("v", "d")

    def __init__(self, v: Any, d: list[Any]):
        self.v, self.d = v, d

    def __add__(self, o: Any) -> _Dual:
        if isinstance(o, _Dual):
            return _Dual(self.v + o.v, [a + b for a, b in zip(self.d, o.d, strict=True)])
        return _Dual(self.v + o, self.d)

    __radd__ = __add__

    def __neg__(self) -> _Dual:
        return _Dual(-self.v, [-a for a in self.d])

    def __sub__(self, o: Any) -> _Dual:
        return self + (-o)

    def __rsub__(self, o: Any) -> _Dual:
        return (-self) + o

    def __mul__(self, o: Any) -> _Dual:
        if isinstance(o, _Dual):
            return _Dual(self.v * o.v, [self.v * b + o.v * a
                                        for a, b in zip(self.d, o.d, strict=True)])
        return _Dual(self.v * o, [a * o for a in self.d])

    __rmul__ = __mul__


class _Variational:
    """(z, V)' = (F(z), DF(z) V) on the flat state z_0..z_{d-1}, then V row by row."""

    def __init__(self, field: Any):
        self.field = field
        self.dim = field.dim * (field.dim + 1)

    def __call__(self, flat: list[Any]) -> list[Any]:
        d = self.field.dim
        z = [_Dual(flat[i], flat[d + i * d:d + (i + 1) * d]) for i in range(d)]
        out = self.field(z)
        values: list[Any] = []
        rows: list[Any] = []
        for o in out:
            if isinstance(o, _Dual):
                values.append(o.v)
                rows += o.d
            else:  # a component that does not depend on the state
                values.append(o)
                rows += [0] * d
        return values + rows


class LohnerSet:
    """The set {c + B r : r in R} (c: balls, B: an exact ``arb_mat``, R: balls).

    Parameters
    ----------
    c : list
        The centre (Arb balls, at most rounding-sized).
    B : flint.arb_mat
        The basis, a matrix of exact floats.
    R : list
        The coefficient box (Arb balls).
    """

    __slots__ = ("c", "B", "R")

    def __init__(self, c: list[Any], B: Any, R: list[Any]):
        self.c, self.B, self.R = c, B, R

    @classmethod
    def of_box(cls, X: list[Any]) -> LohnerSet:
        """The box X itself: c = its midpoints, B = I, R = its radii.

        Parameters
        ----------
        X : list
            Arb balls.

        Returns
        -------
        LohnerSet
        """
        from flint import arb, arb_mat

        d = len(X)
        eye = arb_mat([[1 if i == j else 0 for j in range(d)] for i in range(d)])
        return cls([x.mid() for x in X], eye, [arb(0, x.rad()) for x in X])

    def hull(self) -> list[Any]:
        """The interval hull: a ball per state holding every point of the set."""
        d = len(self.c)
        out = []
        for i in range(d):
            total = self.c[i]
            for j in range(d):
                total = total + self.B[i, j] * self.R[j]
            out.append(total)
        return out


def _horner(coeffs: list[Any], rem: Any, h: Any, K: int) -> Any:
    total: Any = 0
    for k in range(K - 1, -1, -1):
        total = total * h + coeffs[k]
    return total + rem * h**K


def lohner_step(field: Any, S: LohnerSet, h: Any, K: int, apriori: Any, series: Any
                ) -> LohnerSet | None:
    """The set at t + h holding every solution from the set ``S`` at t, or None.

    Parameters
    ----------
    field : callable
        The polynomial field z' = F(z) on lists of balls, series or :class:`_Dual`
        values, with its dimension in ``field.dim``.
    S : LohnerSet
        The set at t.
    h : flint.arb
        The step (exact).
    K : int
        Taylor order of the point part.
    apriori : callable
        ``apriori(field, X, h)``: a box holding every solution from the box X over
        [0, h] (Picard-Lindelof), or None.
    series : callable
        ``series(field, z0, K)``: Taylor coefficients 0..K of the solution from the
        balls z0, or None.

    Returns
    -------
    LohnerSet or None
        None when an a priori enclosure or a finite series was not found (the caller
        halves the step).
    """
    import numpy as np
    from flint import arb, arb_mat

    d = len(S.c)
    X = S.hull()
    box = apriori(field, X, h)
    if box is None:
        return None
    coeffs, rem = series(field, S.c, K - 1), series(field, box, K)
    if coeffs is None or rem is None:
        return None
    y = [_horner(c, r[K], h, K) for c, r in zip(coeffs, rem, strict=True)]
    ext = _Variational(field)
    start = list(X) + [arb(1 if i == j else 0) for i in range(d) for j in range(d)]
    ebox = apriori(ext, start, h)
    if ebox is None:
        return None
    L = JACOBIAN_ORDER
    jc, jr = series(ext, start, L - 1), series(ext, ebox, L)
    if jc is None or jr is None:
        return None
    J = arb_mat([[_horner(jc[d + i * d + j], jr[d + i * d + j][L], h, L) for j in range(d)]
                 for i in range(d)])
    A = J * S.B
    mid = np.array([[float(A[i, j].mid()) for j in range(d)] for i in range(d)])
    size = np.array([float(abs(r).upper()) for r in S.R])
    weight = np.linalg.norm(mid, axis=0) * size
    order = sorted(range(d), key=lambda j: (-weight[j], j))
    q, _ = np.linalg.qr(mid[:, order])
    if not np.all(np.isfinite(q)):
        return None
    Q = arb_mat(q.tolist())
    Qi = Q.inv()
    M = Qi * A
    c = [v.mid() for v in y]
    R = []
    for i in range(d):
        total = arb(0)
        for j in range(d):
            total = total + M[i, j] * S.R[j] + Qi[i, j] * (y[j] - c[j])
        R.append(total)
    return LohnerSet(c, Q, R)
