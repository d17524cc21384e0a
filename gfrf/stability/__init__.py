"""Stability: the theorems that turn bounds into a verdict.

Owns Theorem 1 (the norm series of the open-loop plant, :mod:`.theorem1`) and Theorem 2
(the loop series of a plant under a controller, :mod:`.theorem2`), the verdict objects
(:mod:`.verdicts`), the entry points ``verdict`` and ``parameter_margin`` with the margin
object (:mod:`.criteria`), the linear loops they rest on (:mod:`.loops`), the static
branch points that bound the radius from above (:mod:`.static`), the many-term
estimate of the radius (:mod:`.estimate`), and the energy certificates that prove
stability beyond r* for damped oscillators (:mod:`.energy`: every bounded input for a
hardening force; :mod:`.energy_local`: an invariant sublevel set for a softening one).

May import: :mod:`gfrf.bounds`, :mod:`gfrf.kernels`, :mod:`gfrf.model` and the shared
helpers.
Public face: ``verdict``, ``Verdict``, ``parameter_margin``, ``Margin``;
``closed_loop``, ``ClosedLoop`` (:mod:`.loops`).
"""
