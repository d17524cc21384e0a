"""Two-sided answers: the amplitude where stability is proven, and where it is broken.

:mod:`.falsify` searches bounded inputs switched on at t = 0 from rest (switching inputs
u = +-U of :mod:`.switching` and :mod:`.narx_signs`, sums of tones) for the smallest
amplitude whose response escapes (:mod:`.escape`: a certified escape region or a level
from the model's scale; the runs in :mod:`.runner`, the witness in :mod:`.witness`),
re-checks the witness with scipy's DOP853 at two tolerances,
and :mod:`.enclose` proves its escape in Arb ball arithmetic; :mod:`.threshold` puts it
beside the proven lower side in a :class:`~gfrf.twosided.threshold.Threshold`.

May import: :mod:`gfrf.sim` and everything below it, and the shared helpers.
Public face: ``threshold`` (re-exported as ``gfrf.threshold``), ``Threshold``;
``falsify``, ``Falsification``.
"""
