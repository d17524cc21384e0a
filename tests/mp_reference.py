"""Independent reference for the tests: sup of |N(jw)/D(jw)| in mpmath (no FLINT, no numpy).

The stationary points of |N|^2/|D|^2 are the real roots of an exact polynomial built in
mpmath at the requested precision; the sup is the largest value at those roots, at the
start of the range and at infinity.
"""

from __future__ import annotations

import mpmath as mp


def mp_sup(num: list[float], den: list[float], beyond: float = 0.0,
           digits: int = 60) -> mp.mpf:
    """sup over |w| >= ``beyond`` of |N(jw)/D(jw)| (coefficients highest power first)."""
    with mp.workdps(digits):
        def abs2(c: list[float]) -> list[mp.mpf]:  # |F(jw)|^2, lowest power of w first
            low = [mp.mpf(x) * mp.j ** k for k, x in enumerate(reversed(c))]
            out = [mp.mpc(0)] * (2 * len(low) - 1)
            for i, a in enumerate(low):
                for k, b in enumerate(low):
                    out[i + k] += a * mp.conj(b)
            return [mp.re(x) for x in out]

        p, q = abs2(num), abs2(den)
        dp = [k * p[k] for k in range(1, len(p))]
        dq = [k * q[k] for k in range(1, len(q))]
        s = [mp.mpf(0)] * (len(p) + len(q))
        for i, a in enumerate(dp):
            for k, b in enumerate(q):
                s[i + k] += a * b
        for i, a in enumerate(p):
            for k, b in enumerate(dq):
                s[i + k] -= a * b
        while s and s[-1] == 0:
            s.pop()
        while s and s[0] == 0:  # w = 0 is a root of multiplicity > 1; the start is a candidate
            s.pop(0)

        def f(w: mp.mpf) -> mp.mpf:
            return mp.sqrt(mp.polyval(p[::-1], w) / mp.polyval(q[::-1], w))

        start = mp.mpf(beyond)
        candidates = [f(start)]
        if len(s) > 1:
            roots = mp.polyroots(s[::-1], maxsteps=2000, extraprec=2000)
            candidates += [f(mp.re(r)) for r in roots
                           if abs(mp.im(r)) < mp.mpf(10) ** -40 * (1 + abs(r))
                           and mp.re(r) >= start]
        if len(p) == len(q):
            candidates.append(mp.sqrt(p[-1] / q[-1]))
        return max(candidates)
