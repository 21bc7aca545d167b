"""The backends by name: the one module above the backends that imports them (and so registers them).

``fdmodel`` registers ``"fd"`` (finite differences) and ``femodel`` ``"fe"``
(finite elements) as :class:`deformable.backends.Discretisation` descriptors;
the harness, the studies and the command line turn a backend name into a
model here, and read what they need of a backend (its grid unit, its cost)
from its descriptor.
"""

from __future__ import annotations

import fdmodel  # noqa: F401  (registers "fd")
import femodel  # noqa: F401  (registers "fe")
from deformable.backends.registry import Discretisation
from deformable.dynamics.stepper import round_down

__all__ = ["BACKENDS", "make_model", "backend_dt", "descriptor"]

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


def backend_dt(model, dt: float) -> float:
    """The step (s) a scene's default ``dt`` becomes on ``model``'s backend.

    The scenes' default dt is the FD one; a backend whose stretching bound ``model.stable_step()``
    (eq. 25 lags alpha; docs/design.md, "Time stepping") is tighter gets half that bound, rounded
    down to two significant digits. The frozen and variational models have no bound (inf): dt stays.
    """
    bound = model.stable_step()
    return round_down(0.5 * bound) if dt > 0.5 * bound else dt
