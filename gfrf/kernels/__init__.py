"""Kernels: the generalised frequency response functions H1..Hn of a model.

Owns the Billings / Peyton Jones recursion with symmetrisation (:mod:`.recursion`, the
public face; :mod:`.generator`, the symbolic plans; :mod:`.numeric`, their evaluation on
numpy arrays), the generated straight-line evaluators and their numba / on-disk cache
(:mod:`.compiled`, written in real arithmetic by :mod:`.realcode`),
the multiset and composition counting they share (:mod:`.combinatorics`), one value never
nan (a pole named, beyond the float range in mpmath: :mod:`.pointwise`), and harmonic
probing, the independent method that checks the recursion (:mod:`.probing`).

May import: :mod:`gfrf.model`, :mod:`gfrf.errors`, :mod:`gfrf._atomic`, :mod:`gfrf._cache`.
Public face: ``kernel``, ``Kernel`` (:mod:`.recursion`); ``probe_kernel``
(:mod:`.probing`).
"""
