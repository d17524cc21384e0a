"""Frequency response curves beyond the series radius: harmonic balance with continuation.

:mod:`.balance` writes the harmonic-balance equations of a polynomial model (continuous
or NARX) under ``u = A cos(omega t)``, exact by alternating frequency-time with enough
samples for the model's degree; :mod:`.continuation` follows the branch by
pseudo-arclength continuation in omega or A and locates its folds; :mod:`.hill` gives
the Floquet multipliers of every point by Hill's method; :mod:`.backbone` the free
oscillations of the unforced undamped system; :mod:`.curve` puts them in a
:class:`~gfrf.harmonic.curve.FrequencyResponseCurve` (:func:`~gfrf.harmonic.curve.frc`,
re-exported as ``gfrf.frc``).

May import: :mod:`gfrf.model` and the shared helpers (it sits beside
:mod:`gfrf.twosided` in the layers and needs none of the GFRF stack).
Public face: ``frc``, ``FrequencyResponseCurve``, ``CurvePoint``.
"""
