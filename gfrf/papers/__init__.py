"""What serves one paper only: the checks behind the GFRF paper's report.

:mod:`.gfrf_paper` recomputes the numbers of paper ``001`` (the hanging pendulum and
its examples); :mod:`.cartpole` and its siblings hold the cart-pole findings (why the
paper's controller cannot be certified, and what can).  The second paper (the
parametrically excited pendulum) has its own package, :mod:`gfrf.periodic`.

May import: :mod:`gfrf.sim` and everything below it, and the shared helpers; nothing
imports it but the reports.
"""
