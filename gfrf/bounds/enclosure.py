"""Third-order Taylor enclosures of |H_n(j w)| over boxes of frequencies (rad/s).

The box arithmetic of :mod:`gfrf.bounds.branch_bound`.  Every quantity q of the straight-line
recursion of H_n (the code of :func:`gfrf.kernels.compiled.kernel_source`, evaluated with
:class:`Jet` numbers) carries, for a batch of boxes with centres c and half-widths r:

* its value, gradient and Hessian at the centre (complex, exact up to rounding), and
* bounds ``D_k`` (k = 0..3) over the whole box of the k-th derivative majorant
  ``sum_{i_1..i_k} sup |d^k q / dw_{i_1} .. dw_{i_k}| r_{i_1} .. r_{i_k}``.

Sums add, products follow Leibniz's rule (``D_k(ab) <= sum_i C(k,i) D_i(a) D_{k-i}(b)``)
and every result is intersected with its Taylor form at the centre (``D_0 <= |q| +
sum |g_i| r_i + 1/2 sum |h_ij| r_i r_j + D_3 / 6`` and likewise for ``D_1``, ``D_2``),
and D_0, D_1 and the remainder R below with Lagrange's forms of D_2 (``|q| + sum |g_i|
r_i + D_2 / 2``, ``sum |g_i| r_i + D_2``, ``(D_2 + sum |h_ij| r_i r_j) / 2``), so the
bounds stay close to the true derivatives.  Each factor 1/A(j sigma_B),
sigma_B the sum of a block's frequencies, gets the exact extrema over the interval of
sigma_B of |A| and of the numerators of its first three derivatives (stationary points
isolated once in Arb), so a box straddling a resonance is bounded by the resonance
peak, not by infinity.

A box's bound is the least of three valid bounds:

1. ``D_0`` (magnitude arithmetic);
2. the largest |H(c) + grad H(c) . d| over the box vertices (the affine part is convex)
   plus ``1/2 sum |h_ij| r_i r_j + D_3 / 6``;
3. the square root of a bound of F = |H|^2 = H conj(H): its exact quadratic Taylor
   polynomial at the centre maximised over the box (where the Hessian of F is negative
   definite: its unconstrained maximum, else term by term) plus the remainder
   ``D_3(F) / 6 <= (2 D_0 D_3 + 6 D_1 D_2) / 6``.

The third bound closes gaps: near a resonance the phase of H_n turns quickly while
|H_n| is stationary, and the quadratic model of |H_n|^2 carries that cancellation
exactly.  Factors common to every term of H_n are replaced by their moduli (|H_n| is
unchanged): the top factor 1/A(j(w_1 + .. + w_n)) always, and each H1(w_i) leaf when no
input enters a nonlinear term; being stationary at their resonance, their derivative
bounds are second order (the pendulum's H5 needs 5x fewer boxes).

Carriers (discrete-time models).  A variable q_i = exp(-j w_i T) of a NARX kernel turns
fast on a box while its modulus stays 1.  A jet of a NARX kernel therefore stands for
env(w) exp(j phi . (w - c)): ``phase`` holds the carrier phi per box (-T on q_i's own
coordinate), the value, derivatives and bounds D_k are the envelope's.  The variables
are exact carriers with a constant envelope (D_1 = D_2 = D_3 = 0), products add
carriers, and a sum of two terms on carriers p_a and p_b takes, per box, the carrier
lam p_a + (1 - lam) p_b with lam = D_0(a) / (D_0(a) + D_0(b)) (0 or 1 when below 0.1 or
above 0.9) and multiplies each envelope by exp(j delta . (w - c)), delta the difference
of its carrier from that one (a turn, whose D_k are (sum |delta_i| r_i)^k and whose
remainder is cubic in that sum: two half turns leave a quarter of one whole turn's).
|H_n| = |env|, so the three bounds below apply to the envelope unchanged, and they no
longer pay for the phase turns of the q_i.  Measured on the identified example's H5 at
boxes of side 2 pi / 32 in theta = w T: the bound over the sampled sup 1.96 with the
weighted carrier, 2.47 with the larger term's; its search to 1e-3 from the known lower
end 55,000 boxes instead of 168,000.

Taylor models (discrete-time models).  A NARX jet also carries R (column 4 of ``d``): a
bound over the box of |q - P|, P its quadratic Taylor polynomial at the centre (the
value, gradient and Hessian above).  The variables are exact (R = 0), a factor's R is
its Lagrange remainder D_3 / 6, a turn's s^3 / 6 (|exp(jx) - 1 - jx + x^2/2| <=
|x|^3/6), sums add R, and a product's R bounds the degree-3 and -4 terms of P_a P_b by
the Taylor forms (M1_a M2_b + M2_a M1_b + M2_a M2_b, M1 = sum |g_i| r_i, M2 = 1/2
sum |h_ij| r_i r_j) plus R_a sup|b| + sup|P_a| R_b.  Unlike D_3, which sums magnitudes
of third derivatives through every level, R keeps the cancellations of the quadratic
parts exact, and every R is intersected with D_3 / 6.  Two more bounds of a box follow:
sqrt(max of the quadratic model of |P|^2 + 2 M1 M2 + M2^2) + R, and the vertex bound
with R in place of D_3 / 6.  Measured on the identified example's H5 at its maximiser:
a box of side 2 pi / 64 in every theta = w T is bounded to 1.115x its sup instead of
1.32x (2 pi / 128: 1.0125x instead of 1.032x).  Continuous models carry R = inf (not
tracked): their enclosures are unchanged.

Soundness.  The extrema of |A| and its derivatives' numerators use critical points
isolated exactly (Arb) and endpoint values widened by an a-priori Horner error bound.
Taylor arithmetic in double precision without outward rounding; a centre's values are
used only where |A| is accurate to 1e-8 relative: certified in floating point.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache
from typing import Any

import numpy as np

__all__ = ["Jet", "enclose"]

#: Relative error of a centre's 1/A and Taylor terms above which its values are not used
#: (the box keeps its magnitude bounds); below it the bound is inflated by 8x the errors.
_POINT_RTOL = 1e-5
#: Relative margin of negative definiteness required before the unconstrained maximum
#: of the quadratic model of |H|^2 is used (rounding of the Hessian is far below it).
_DEFINITE_MARGIN = 1e-9


def _safe(x: np.ndarray) -> np.ndarray:
    """NaN (0 * inf) becomes inf: an undetermined bound is no bound."""
    return np.where(np.isnan(x), np.inf, x)


def _fused_kernels() -> Any:
    """:mod:`gfrf.bounds.jet_kernels` if numba is installed, else None (imported on first use)."""
    from gfrf.kernels.compiled import HAVE_NUMBA

    if not HAVE_NUMBA:
        return None
    from gfrf._cache import trust_dispatchers
    from gfrf.bounds import jet_kernels

    if not getattr(jet_kernels, "checked", False):  # numba reads its cache at the first call
        trust_dispatchers([jet_kernels.jet_add, jet_kernels.jet_mul, jet_kernels.jet_turn])
        jet_kernels.checked = True
    return jet_kernels


#: Binomial coefficients C(k, i), k <= 3.
_BINOMIAL = ((1,), (1, 1), (1, 2, 1), (1, 3, 3, 1))
#: Columns of a jet's ``d``: the bounds D_0..D_3, the remainder R and the forms at the
#: centre (sum |g_i| r_i, sum |h_ij| r_i r_j; upper bounds of them after a scaling), kept
#: so that a product reads its operands' forms instead of recomputing them.
_COLUMNS = 7


class _Boxes:
    """Box centres c and half-widths r, shape (N, n), and the 1/A evaluator."""

    def __init__(self, centre: np.ndarray, radius: np.ndarray, inverse: Any,
                 fused: Any = None, sample_time: float | None = None) -> None:
        self.c, self.r, self.inverse, self.fused = centre, radius, inverse, fused
        self.sample_time = sample_time
        self._radii: dict[tuple[int, ...], np.ndarray] = {}
        # jets of 1/A per block with their centre errors, reused by a second evaluation
        self._inverses: dict[tuple[int, ...], tuple[Jet, np.ndarray]] = {}
        self.error = np.zeros(centre.shape[0])  # sum of the factors' relative errors
        self._last_error = self.error

    def release(self) -> None:
        """Drop the cached jets and radii (they refer back to these boxes: a cycle only
        the cyclic garbage collector frees, late in a long search)."""
        self._inverses.clear()
        self._radii.clear()

    def block(self, names: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(sigma, rho, error) of a block: the rounded sum of its centres, a half-width
        that covers the rounding of that sum, and the centre's relative error."""
        idx = list(names)
        m = len(idx)
        sigma = self.c[:, idx].sum(axis=1)
        slack = (m + 1) * 2.0 ** -52 * (np.abs(self.c[:, idx]).sum(axis=1) + np.abs(sigma))
        rho = self.r[:, idx].sum(axis=1) * (1 + (m + 1) * 2.0 ** -52) + slack
        error = self.inverse.centre_error(sigma, slack, rho)
        self.error += np.where(error <= _POINT_RTOL, error, 0.0)
        return sigma, rho, error

    def radii(self, names: tuple[int, ...]) -> np.ndarray:
        """Half-widths of the coordinates ``names`` (contiguous (N, m) array)."""
        if names not in self._radii:
            self._radii[names] = np.ascontiguousarray(self.r[:, list(names)])
        return self._radii[names]

    def variable(self, i: int) -> Jet:
        """x_i = j w_i, or q_i = exp(-j w_i T) for a discrete model (|q_i| = 1 and its
        k-th derivative has modulus T^k everywhere)."""
        size = self.c.shape[0]
        if self.sample_time is not None:
            t = self.sample_time
            q = np.exp(-1j * t * self.c[:, i])  # q_c exp(-j T delta): a carrier, no envelope
            d = np.zeros((size, _COLUMNS))  # exact: remainder R = 0
            d[:, 0] = 1.0
            return Jet(q, np.zeros((size, 1), complex), np.zeros((size, 1, 1), complex), d,
                       (i,), self, phase=np.full((size, 1), -t), pure=True)
        d = np.zeros((size, _COLUMNS))
        d[:, 0] = np.abs(self.c[:, i]) + self.r[:, i]
        d[:, 1] = d[:, 5] = self.r[:, i]
        d[:, 4] = np.inf  # continuous models: no Taylor-model remainder
        return Jet(1j * self.c[:, i], np.full((size, 1), 1j), np.zeros((size, 1, 1), complex),
                   d, (i,), self)

    def modulus(self, block: tuple[int, ...]) -> Jet:
        """1/|A(j sigma_B)|, sigma_B = sum of the block's w_i (a real jet).

        Valid in place of 1/A(j sigma_B) where that factor is common to every term of
        H_n: the top block (H_n = -P_n / A(j(w_1 + .. + w_n))) always, and the
        one-coordinate blocks when the model has no input in a nonlinear term.  |H_n|
        is unchanged and the jets lose the fast phase rotation of those resonant
        factors, so their derivative bounds shrink.
        """
        return self._factor(block, self.inverse.modulus_point, self.inverse.modulus_bounds)

    def inv_a(self, block: tuple[int, ...]) -> Jet:
        """1 / A(j sigma_B), sigma_B = sum of the block's w_i (computed once per block)."""
        names = tuple(sorted(block))
        if names in self._inverses:
            jet, error = self._inverses[names]
            self.error += np.where(error <= _POINT_RTOL, error, 0.0)  # as block() adds it
            return jet
        jet = self._factor(names, self.inverse.point, self.inverse.bounds)
        self._inverses[names] = (jet, self._last_error)
        return jet

    def _factor(self, block: tuple[int, ...], point: Callable[..., tuple[np.ndarray, ...]],
                bounds: Callable[..., np.ndarray]) -> Jet:
        """Jet of f(sigma_B) from its value and two derivatives at the centre (``point``)
        and the sups of |f| and of its first three derivatives over the interval of sigma_B."""
        names = tuple(sorted(block))
        sigma, rho, error = self.block(names)
        self._last_error = error
        value, slope, curve = (np.asarray(x, complex) for x in point(sigma, error))
        sups = bounds(sigma - rho, sigma + rho)
        m = len(names)
        spread = self.radii(names).sum(axis=1)  # g and h are constant over the block
        with np.errstate(invalid="ignore", over="ignore"):
            forms = (np.abs(slope) * spread, np.abs(curve) * spread * spread)
            d = _safe(sups * rho[:, None] ** np.arange(4))
        rest = d[:, 3:] / 6 if self.sample_time is not None else np.full((sigma.size, 1), np.inf)
        # Lagrange's remainder of the quadratic Taylor polynomial; the forms (set by tighten)
        d = np.hstack([d, rest, np.zeros((sigma.size, 2))])
        return Jet(value, np.repeat(slope[:, None], m, axis=1),
                   np.repeat(np.repeat(curve[:, None, None], m, axis=1), m, axis=2),
                   d, names, self).tighten(forms)


@lru_cache(maxsize=4096)
def _union(a: tuple[int, ...], b: tuple[int, ...]
           ) -> tuple[tuple[int, ...], np.ndarray, np.ndarray]:
    """Sorted union of two coordinate sets and the positions of each in it."""
    names = tuple(sorted(set(a) | set(b)))
    where = {x: i for i, x in enumerate(names)}
    return (names, np.array([where[x] for x in a], dtype=np.int64),
            np.array([where[x] for x in b], dtype=np.int64))


class Jet:
    """Value, gradient and Hessian at box centres; derivative-majorant bounds D_0..D_3 and
    the Taylor-model remainder R (``d``'s five columns; R = inf for continuous models).

    ``g`` and ``h`` hold the derivatives with respect to the coordinates ``names`` only
    (the others are zero), so products of low-order factors stay small.
    """

    __slots__ = ("v", "g", "h", "d", "names", "boxes", "phase", "pure")

    def __init__(self, v: np.ndarray, g: np.ndarray, h: np.ndarray, d: np.ndarray,
                 names: tuple[int, ...], boxes: _Boxes, phase: np.ndarray | None = None,
                 pure: bool = False) -> None:
        self.v, self.g, self.h, self.d, self.names, self.boxes = v, g, h, d, names, boxes
        self.phase, self.pure = phase, pure

    def carrier(self, names: tuple[int, ...]) -> np.ndarray | None:
        """The carrier over ``names`` (a superset of the jet's), None when it is zero.

        Parameters
        ----------
        names : tuple of int
            Sorted coordinate indices, a superset of the jet's ``names``.

        Returns
        -------
        numpy.ndarray or None
            Shape (boxes, len(names)): the carrier's frequency per coordinate (s), 0 on
            the coordinates the jet does not depend on.
        """
        if self.phase is None or names == self.names:
            return self.phase
        out = np.zeros((self.phase.shape[0], len(names)))
        out[:, _union(names, self.names)[2]] = self.phase
        return out

    def _rotated(self, delta: np.ndarray, names: tuple[int, ...]) -> Jet:
        """The envelope times exp(j delta . (w - c)) over ``names`` (its carrier dropped;
        the jet itself where every delta is 0)."""
        if not delta.any():
            return self
        fused = self.boxes.fused
        if fused is not None:  # the jet is on ``names`` already (see _aligned)
            return Jet(*fused.jet_turn(self.v, self.g, self.h, self.d, delta,
                                       self.boxes.radii(names)), names, self.boxes)
        size = delta.shape[0]
        r = self.boxes.radii(names)
        s = np.sum(np.abs(delta) * r, axis=1)
        turn = Jet(np.ones(size, complex), 1j * delta,
                   -(delta[:, :, None] * delta[:, None, :]).astype(complex),
                   np.stack([np.ones(size), s, s * s, s ** 3, s ** 3 / 6, s, s * s], axis=1), names,
                   self.boxes)
        return Jet(self.v, self.g, self.h, self.d, self.names, self.boxes) * turn

    def forms(self) -> tuple[np.ndarray, np.ndarray]:
        """(sum |g_i| r_i, sum |h_ij| r_i r_j) at the centres (NaN where unknown)."""
        r = self.boxes.radii(self.names)
        first = np.sum(np.abs(self.g) * r, axis=1)
        second = np.einsum("kij,ki,kj->k", np.abs(self.h), r, r)
        return first, second

    def tighten(self, forms: tuple[np.ndarray, np.ndarray] | None = None) -> Jet:
        """Intersect D_0, D_1, D_2 with the Taylor forms at the centre, in place.

        Parameters
        ----------
        forms : tuple of numpy.ndarray, optional
            The first- and second-order Taylor sums of :meth:`forms`, when already known.
        """
        first, second = self.forms() if forms is None else forms
        d3 = self.d[:, 3]
        rest = np.where(np.isnan(self.d[:, 4]), np.inf, self.d[:, 4])
        rest = np.where(rest < np.inf, np.fmin(rest, d3 / 6), rest)
        with np.errstate(invalid="ignore", over="ignore"):
            d2 = np.fmin(self.d[:, 2], second + d3)
            forms = np.stack([np.abs(self.v) + first + np.fmin(0.5 * second + np.fmin(rest, d3 / 6),
                                                               0.5 * d2),
                              first + np.fmin(second + 0.5 * d3, d2), d2], axis=1)
            # a Taylor model's remainder is also at most D_2 / 2 + second / 2 (Lagrange)
            self.d[:, 4] = np.where(rest < np.inf, np.fmin(rest, 0.5 * (d2 + second)), rest)
        self.d[:, :3] = np.fmin(self.d[:, :3], forms)
        self.d[:, 5], self.d[:, 6] = first, second
        return self

    def embedded(self, names: tuple[int, ...]) -> Jet:
        """The same jet with derivatives over the (larger, sorted) coordinate set ``names``.

        Parameters
        ----------
        names : tuple of int
            Sorted coordinate indices, a superset of the jet's ``names``.
        """
        if names == self.names:
            return self
        where = _union(names, self.names)[2]
        size, m = self.g.shape[0], len(names)
        g = np.zeros((size, m), complex)
        h = np.zeros((size, m, m), complex)
        g[:, where] = self.g
        h[:, where[:, None], where[None, :]] = self.h
        return Jet(self.v, g, h, self.d, names, self.boxes, phase=self.carrier(names))

    def _scaled(self, c: complex) -> Jet:
        if self.pure:  # g = h = 0 (never written in place: shared)
            return Jet(c * self.v, self.g, self.h, abs(c) * self.d, self.names, self.boxes,
                       phase=self.phase, pure=True)
        return Jet(c * self.v, c * self.g, c * self.h, abs(c) * self.d, self.names,
                   self.boxes, phase=self.phase)

    def __neg__(self) -> Jet:
        return self._scaled(-1.0)

    def _fused(self, loop: str, other: Jet, phase: np.ndarray | None = None
               ) -> tuple[tuple[int, ...], Jet | None]:
        """(joint coordinates, the result of the fused numba ``loop`` of
        :mod:`gfrf.bounds.jet_kernels` with carrier ``phase``, or None without those
        loops)."""
        names, ia, ib = _union(self.names, other.names)
        fused = self.boxes.fused
        if fused is None:
            return names, None
        return names, Jet(*getattr(fused, loop)(self.v, self.g, self.h, self.d, ia, other.v,
                                                 other.g, other.h, other.d, ib,
                                                 self.boxes.radii(names)),
                          names, self.boxes, phase=phase)

    def _aligned(self, other: Jet) -> tuple[Jet, Jet, np.ndarray | None]:
        """Both terms of a sum on one carrier: per box their mean weighted by D_0 (the
        larger term's when its weight exceeds 0.9); each envelope turns by the difference
        (:meth:`_rotated`)."""
        names = _union(self.names, other.names)[0]
        pa, pb = self.carrier(names), other.carrier(names)
        if pa is None and pb is None or pa is not None and pb is not None and \
                np.array_equal(pa, pb):
            return self, other, pa
        size = self.v.shape[0]
        pa = np.zeros((size, len(names))) if pa is None else pa
        pb = np.zeros((size, len(names))) if pb is None else pb
        sa, sb = self.d[:, 0], other.d[:, 0]
        with np.errstate(invalid="ignore", divide="ignore"):
            weight = np.where(sa + sb > 0, sa / (sa + sb), 1.0)
        weight = np.where(np.isfinite(weight), weight, (sa >= sb).astype(float))
        weight = np.where(weight > 0.9, 1.0, np.where(weight < 0.1, 0.0, weight))
        target = weight[:, None] * pa + (1.0 - weight[:, None]) * pb
        a, b = self.embedded(names), other.embedded(names)
        return a._rotated(pa - target, names), b._rotated(pb - target, names), target

    def __add__(self, other: Any) -> Jet:
        if not isinstance(other, Jet):
            if self.phase is not None:
                return self + _constant(other, self.boxes)
            d = self.d.copy()
            d[:, 0] += abs(other)
            return Jet(self.v + other, self.g, self.h, d, self.names, self.boxes)
        left, right, phase = self._aligned(other)
        names, fused = left._fused("jet_add", right, phase)
        if fused is not None:
            return fused
        a, b = left.embedded(names), right.embedded(names)
        return Jet(a.v + b.v, a.g + b.g, a.h + b.h, a.d + b.d, names, self.boxes,
                   phase=phase).tighten()

    __radd__ = __add__

    def __sub__(self, other: Any) -> Jet:
        return self + (-other)

    def __rsub__(self, other: Any) -> Jet:
        return (-self) + other

    def __mul__(self, other: Any) -> Jet:
        if not isinstance(other, Jet):
            return self._scaled(complex(other))
        names = _union(self.names, other.names)[0]
        pa, pb = self.carrier(names), other.carrier(names)
        phase = pb if pa is None else pa if pb is None else pa + pb
        if self.pure or other.pure:
            return self._carried(other, names, phase)
        names, fused = self._fused("jet_mul", other, phase)
        if fused is not None:
            return fused
        a, b = self.embedded(names), other.embedded(names)
        outer = a.g[:, :, None] * b.g[:, None, :]
        h = (a.h * b.v[:, None, None] + outer + outer.transpose(0, 2, 1)
             + a.v[:, None, None] * b.h)
        d = np.empty_like(a.d)
        with np.errstate(invalid="ignore", over="ignore"):
            for k, row in enumerate(_BINOMIAL):
                d[:, k] = sum(c * a.d[:, i] * b.d[:, k - i] for i, c in enumerate(row))
            d[:, 4] = _remainder(a, b)
        return Jet(a.v * b.v, a.g * b.v[:, None] + a.v[:, None] * b.g, h, _safe(d), names,
                   self.boxes, phase=phase).tighten()

    __rmul__ = __mul__

    def _carried(self, other: Jet, names: tuple[int, ...], phase: np.ndarray | None) -> Jet:
        """Product with a pure carrier (constant envelope: g = h = 0, D_1..D_3 = R = 0):
        the other envelope times that constant c, whose D_k and R scale by D_0 >= |c|
        (Leibniz's rule and the product's remainder with those zeros), so the product
        needs no new bounds."""
        pure, jet = (self, other) if self.pure else (other, self)
        jet = jet.embedded(names)
        c, scale = pure.v, pure.d[:, 0]
        return Jet(jet.v * c, jet.g * c[:, None], jet.h * c[:, None, None],
                   _safe(jet.d * scale[:, None]), names, self.boxes, phase=phase,
                   pure=jet.pure)

    def __pow__(self, k: int) -> Jet:
        if not (isinstance(k, int) and k >= 1):
            raise ValueError(f"only positive integer powers are enclosed, got {k!r}")
        result = self
        for _ in range(k - 1):
            result = result * self
        return result


def _remainder(a: Jet, b: Jet) -> np.ndarray:
    """Taylor-model remainder of the product of a and b (on one coordinate set): the
    degree-3 and -4 terms of the product of their quadratic parts P_a, P_b, bounded by
    their forms, plus R_a sup|b| + sup|P_a| R_b (inf where either remainder is)."""
    (a1, a2), (b1, b2) = a.forms(), b.forms()
    a2, b2 = a2 / 2, b2 / 2
    ra, rb = a.d[:, 4], b.d[:, 4]
    sup_a = np.fmin(np.abs(a.v) + a1 + a2, a.d[:, 0] + ra)
    out = (a1 * b2 + a2 * b1 + a2 * b2 + np.where(ra > 0, ra * b.d[:, 0], 0.0)
           + np.where(rb > 0, sup_a * rb, 0.0))
    return np.where((ra < np.inf) & (rb < np.inf) & ~np.isnan(out), out, np.inf)


def _constant(c: complex, boxes: _Boxes) -> Jet:
    """The constant ``c`` as a jet over no coordinates (exact: remainder 0)."""
    size = boxes.c.shape[0]
    d = np.zeros((size, _COLUMNS))
    d[:, 0] = abs(c)
    return Jet(np.full(size, complex(c)), np.zeros((size, 0), complex),
               np.zeros((size, 0, 0), complex), d, (), boxes)


def _modulus_bound(h: Jet) -> np.ndarray:
    """Bound 3 of the module docstring: sqrt of the bound of |H|^2 over each box."""
    r = h.boxes.r
    n = r.shape[1]
    vc = np.conj(h.v)
    f0 = np.abs(h.v) ** 2
    grad = 2 * np.real(vc[:, None] * h.g)
    hess = 2 * np.real(np.conj(h.g)[:, :, None] * h.g[:, None, :] + vc[:, None, None] * h.h)
    d0, d1, d2, d3, rest = h.d.T[:5]
    remainder = (2 * d0 * d3 + 6 * d1 * d2) / 6
    off = np.abs(hess) * (1 - np.eye(n))
    diagonal = np.maximum(np.einsum("kii->ki", hess), 0.0)
    termwise = (f0 + np.sum(np.abs(grad) * r, axis=1)
                + 0.5 * (np.sum(diagonal * r * r, axis=1)
                         + np.einsum("kij,ki,kj->k", off, r, r)))
    best = termwise.copy()
    finite = np.isfinite(hess).all(axis=(1, 2)) & np.isfinite(grad).all(axis=1)
    if finite.any():
        neg = -hess[finite]
        scale = np.abs(neg).max(axis=(1, 2))
        shifted = neg - (_DEFINITE_MARGIN * scale)[:, None, None] * np.eye(n)
        definite = np.linalg.eigvalsh(shifted)[:, 0] > 0
        if definite.any():
            rows = np.flatnonzero(finite)[definite]
            gd, sd = grad[rows], neg[definite]
            y = np.linalg.solve(sd, gd[:, :, None])[:, :, 0]
            residual = gd - np.einsum("kij,kj->ki", sd, y)
            peak = (f0[rows] + 0.5 * np.sum(y * (gd - residual), axis=1)
                    + np.sum(np.abs(residual) * r[rows], axis=1))
            best[rows] = np.minimum(best[rows], peak)
    first, second = h.forms()
    with np.errstate(invalid="ignore", over="ignore"):
        # the Taylor model H = P + e, |e| <= R: |P|^2 is its quadratic model plus its
        # degree-3 and -4 terms, at most 2 M1 M2 + M2^2 (M1 = first, M2 = second / 2)
        model = np.sqrt(np.maximum(best, 0.0) + first * second + second * second / 4) + rest
        return _safe(np.fmin(np.sqrt(np.maximum(best, 0.0) + remainder), model))


def enclose(kernel_code: Callable[..., Any], inverse: Any, lo: np.ndarray,
            hi: np.ndarray, compiled: bool = False, modulus_leaves: bool = False,
            sample_time: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Bounds of |H_n| on boxes [lo, hi] (rows), |H_n| at the centres and a split axis.

    Parameters
    ----------
    kernel_code : callable
        ``kernel_code(x, inv_a)``: the straight-line recursion of H_n.
    inverse : gfrf.bounds.inverse.InverseA or gfrf.bounds.torus.InverseTrig
        1/A of the model's linear part (the latter for a discrete model).
    lo, hi : numpy.ndarray, shape (N, n)
        Box corners (rad/s).
    compiled : bool, optional
        Use the fused numba loops of :mod:`gfrf.bounds.jet_kernels` (when numba is installed):
        about 2x less time per box than numpy (40 against 73 us per box for the
        pendulum's H5 on a 2-core 2026 machine, one core) after a one-off cost: the
        numba import and cache load, ~0.5-1 s per process, and a compile of ~9 s once per
        installation.  The bounds agree with the numpy path to rounding.
    modulus_leaves : bool, optional
        Evaluate the one-coordinate factors 1/A(j w_i) by their moduli, as the top
        factor 1/A(j(w_1 + .. + w_n)) always is (:meth:`_Boxes.modulus`).  Only valid
        when every term of H_n holds each of them once, i.e. the model has no input in a
        nonlinear term.  The centre values carry |H_n|, with another phase.
    sample_time : float or None, optional
        T of a discrete model, whose code runs on q_i = exp(-j w_i T); None (default)
        for a continuous model (x_i = j w_i).

    Returns
    -------
    bound : numpy.ndarray, shape (N,)
        sup over each box of |H_n| is at most ``bound``.
    centre_modulus : numpy.ndarray, shape (N,)
        |H_n| at the box centres (NaN where the centre's 1/A is not accurate).
    split : numpy.ndarray of int, shape (N,)
        The coordinate whose bisection most reduces the enclosure width.
    """
    centre = 0.5 * (lo + hi)
    radius = np.nextafter(np.maximum(hi - centre, centre - lo), np.inf)  # covers [lo, hi]
    fused = _fused_kernels() if compiled else None
    n = centre.shape[1]
    boxes = _Boxes(centre, radius, inverse, fused, sample_time)
    common = (lambda block: len(block) in (1, n)) if modulus_leaves else (
        lambda block: len(block) == n)
    try:
        if sample_time is not None and n >= 2:  # NARX: the common factors by their moduli
            # only; the other form's bounds were at most 1-4 % lower (sampled boxes of the
            # identified examples' H3 and H5) for the same work again
            return _evaluate(kernel_code, boxes, common)
        bound, modulus, split = _evaluate(kernel_code, boxes, lambda block: False)
        if n >= 2:  # the common factors by their moduli: far better for moderate damping,
            # worse where the interval of a sum is wide against a tiny damping: keep the least
            boxes.error = np.zeros(centre.shape[0])  # the errors of this evaluation's factors
            other, _, other_split = _evaluate(kernel_code, boxes, common)
            split = np.where(other < bound, other_split, split)
            bound = np.minimum(bound, other)
    finally:
        boxes.release()
    return bound, modulus, split


def _evaluate(kernel_code: Callable[..., Any], boxes: _Boxes,
              common: Callable[[tuple[int, ...]], bool]
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(bound, |H_n| at the centres, split axis) with the blocks ``common`` by moduli."""
    centre, radius = boxes.c, boxes.r
    n = centre.shape[1]

    def factor(block: tuple[int, ...]) -> Jet:
        return boxes.modulus(block) if common(block) else boxes.inv_a(block)

    h = kernel_code([boxes.variable(i) for i in range(n)], factor)
    if not isinstance(h, Jet):  # a constant kernel
        h = Jet(np.full(centre.shape[0], complex(h)), np.zeros((centre.shape[0], 0), complex),
                np.zeros((centre.shape[0], 0, 0), complex),
                np.tile([abs(complex(h))] + [0.0] * (_COLUMNS - 1), (centre.shape[0], 1)), (),
                boxes)
    h = h.embedded(tuple(range(n)))
    signs = np.array(np.meshgrid(*([[-1.0, 1.0]] * n), indexing="ij")).reshape(n, -1)
    _, second = h.forms()
    with np.errstate(invalid="ignore", over="ignore"):
        # einsum, not a matrix product: no BLAS threads (they spin on an idle core)
        vertex = np.abs(h.v[:, None] + np.einsum("ki,ij->kj", h.g * radius, signs)).max(axis=1)
        affine = _safe(vertex + 0.5 * second + np.fmin(h.d[:, 3] / 6, h.d[:, 4]))
        bound = np.minimum(np.minimum(h.d[:, 0], affine), _modulus_bound(h))
        # centre values accepted with a relative error up to _POINT_RTOL per factor
        bound = bound * (1 + 8 * boxes.error)
        width = radius * (np.abs(h.g) + np.einsum("kij,kj->ki", np.abs(h.h), radius))
    width = np.where(np.isnan(width).any(axis=1, keepdims=True), radius, width)
    return bound, np.abs(h.v), np.argmax(width, axis=1)
