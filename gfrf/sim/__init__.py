"""Time domain: simulation, Volterra prediction and validation against simulation.

Owns the generated right-hand sides and scipy stepping (:mod:`.integrate`), building a
plant or closed loop as an ODE system (:mod:`.system`) and simulating it
(:mod:`.simulation`), the numba fixed-step fast path (:mod:`.fastsim`), the Volterra
series prediction of a steady state (:mod:`.volterra`), its truncation error against
the shot steady state and the choice of its order (:mod:`.truncation`), the check of a
verdict against simulation (:mod:`.validation`), and the plant as a python-control
``NonlinearIOSystem`` (:mod:`.nlsys`).

May import: :mod:`gfrf.stability` and everything below it, and the shared helpers.
Public face: ``simulate``, ``build_system``, ``SimulationResult``; ``predict``,
``VolterraPrediction``; ``to_nlsys``.
"""
