"""Shared by the enclosure tests: a witness built by hand, and ball containment of an
mpmath reference value (with mpmath's own error at 50 digits)."""

from __future__ import annotations

import mpmath as mp

from gfrf.twosided.falsify import Falsification

#: mpmath's own error at 50 digits (odefun's tolerance), added to every ball's radius.
MP_SLACK = mp.mpf("1e-44")


def witness(kind: str, amplitude: float, t_end: float, **kw: object) -> Falsification:
    """A witness of ``kind`` whose enclosure runs to ``t_end`` (= 1.5 * t_escape)."""
    return Falsification(amplitude, kw.pop("tones", []), t_end / 1.5, amplitude,  # type: ignore[arg-type]
                         cap=10.0, t_end=t_end, runs=0, escape="", kind=kind,
                         levels=[1e6, 1e6, 1e6], **kw)  # type: ignore[arg-type]


def contains(ball: object, value: mp.mpf) -> bool:
    """True when the Arb ball holds ``value`` (up to :data:`MP_SLACK`)."""
    mid = mp.mpf(ball.mid().str(60, radius=False))  # type: ignore[attr-defined]
    rad = mp.mpf(ball.rad().str(20, radius=False))  # type: ignore[attr-defined]
    return abs(value - mid) <= rad + MP_SLACK
