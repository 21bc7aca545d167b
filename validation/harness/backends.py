"""The backends by name: the one module above the backends that imports them (and so registers them).

``fdmodel`` registers ``"fd"`` (finite differences) and ``femodel`` ``"fe"``
(finite elements) as :class:`deformable.backends.Discretisation` descriptors;
the harness, the studies and the command line turn a backend name into a
model here, and read what they need of a backend (its grid unit, its cost)
from its descriptor.

A run of a scene config (``deformable run``, each case of ``deformable sweep``,
``deformable view`` and ``params``, the benches and the studies' scene runs) is a
:class:`deformable.Simulation`, one path: the same scene and backend give the same
grid, model and step. :func:`make_model` builds a model of a Scene already built.
"""

from __future__ import annotations

import fdmodel  # noqa: F401  (registers "fd")
import femodel  # noqa: F401  (registers "fe")
from deformable.backends.registry import Discretisation

__all__ = ["BACKENDS", "make_model", "descriptor"]

#: the registered backends' names, FD first
BACKENDS = Discretisation.names()


def descriptor(backend: str) -> type[Discretisation]:
    """The descriptor of the backend called ``backend``; InputError naming the known ones for any other name."""
    return Discretisation.lookup(backend)


def make_model(scene, backend: str, **options):
    """The model of ``scene`` on ``backend``; ``options`` go to the backend (e.g. FD ``weighting``).

    Raises InputError naming the known backends for any other name.
    """
    return descriptor(backend).build(scene, **options)
