"""Two-sided answers: the amplitude where stability is proven, and where it is broken.

:mod:`.falsify` searches sums of tones switched on at t = 0 for the smallest amplitude
whose response from rest escapes (on the compiled fast path), and re-checks the witness
with scipy's DOP853 at two tolerances; :mod:`.threshold` puts it beside the proven lower
side (Theorem 1 or 2's r* and the energy certificate of :mod:`gfrf.stability.energy`)
in a :class:`~gfrf.twosided.threshold.Threshold`.

May import: :mod:`gfrf.sim` and everything below it, and the shared helpers.
Public face: ``threshold`` (re-exported as ``gfrf.threshold``), ``Threshold``;
``falsify``, ``Falsification``.
"""
