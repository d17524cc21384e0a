"""Models: the text language and the objects it builds (the pipeline's first stage).

Owns the one whitelisting parser of every user text field (:mod:`.expr`; its limits and
checked node arithmetic in :mod:`.limits`), the :class:`~gfrf.model.equation.Model` of a
polynomial ODE or NARX equation (:mod:`.equation`), model files in TOML
(:mod:`.modelfile`), input signals u(t) (:mod:`.signals`), parameter templates
(:mod:`.template`) and the normalisation of an equation before numerics (:mod:`.scaling`).

May import: :mod:`gfrf.errors` only (nothing else of gfrf).
Public face: ``parse_model``, ``Model`` (:mod:`.equation`); ``load_model``,
``ModelFile``, ``as_plant`` (:mod:`.modelfile`); ``parse_input`` (:mod:`.signals`).
"""
