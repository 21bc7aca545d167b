"""The top floor of the core: a run of a scene as one object (:class:`Simulation`), on any installed backend.

:class:`Simulation` takes a scene config, a backend's name and an output folder; it holds the run's model and
stepper and runs, resumes and checkpoints (:mod:`deformable.session.simulation`). The command line's ``run``,
``view`` and ``sweep``, the benches, the studies' scene runs and the examples go through it.
"""

from .simulation import DEFAULT_EVERY, Simulation

__all__ = ["Simulation", "DEFAULT_EVERY"]
