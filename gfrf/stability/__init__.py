"""Stability: the theorems that turn bounds into a verdict.

Owns Theorem 1 (the norm series of the open-loop plant) and Theorem 2 (the loop series
of a plant under a controller), the verdict and margin objects, the linear loops they
rest on (:mod:`.loops`), and the static branch points that bound the radius from above
(:mod:`.static`).

May import: :mod:`gfrf.bounds`, :mod:`gfrf.kernels`, :mod:`gfrf.model` and the shared
helpers.
Public face: ``verdict``, ``Verdict``, ``parameter_margin``, ``Margin``;
``closed_loop``, ``ClosedLoop`` (:mod:`.loops`).
"""
