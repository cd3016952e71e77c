"""Layer 3: simulation on navground — scenario files, human models, the episode runner.

``socialnav.sim.scenario`` is pure data (no simulator import); ``engine``, ``humans``,
``runner`` and ``baselines`` use navground.
"""
