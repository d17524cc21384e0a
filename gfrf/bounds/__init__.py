"""Bounds: everything that bounds a number, with the kind of proof it carries.

Owns exact polynomial algebra and ball arithmetic (:mod:`.exact`, :mod:`.exact_sup`,
:mod:`.rational`), majorants of the kernels (:mod:`.majorant`; the radius of their
fixed-point system in :mod:`.fixed_point`, computed on an O(1) rescaled system by
:mod:`.radius_scaling`) and of their tails
(:mod:`.tail`), box enclosures (:mod:`.enclosure`, numba loops in :mod:`.jet_kernels`),
proven witnesses (:mod:`.witness`), the branch-and-bound (:mod:`.branch_bound`), its
start points and local search (:mod:`.starts`, :mod:`.simplex`), and the norm brackets
``||H_n||`` that put them together (:mod:`.norms`).

May import: :mod:`gfrf.kernels`, :mod:`gfrf.model`, and the shared helpers
(:mod:`gfrf.errors`, :mod:`gfrf._results`).
Public face: ``h1_norm``, ``kernel_norm``, ``Bound`` (:mod:`.norms`); ``majorant``
(:mod:`.majorant`); ``hurwitz``, ``schur``, ``poles`` (:mod:`.exact`);
``sup_abs`` (:mod:`.exact_sup`).
"""
