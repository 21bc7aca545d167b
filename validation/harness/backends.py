"""The backends by name: the one module above the backends that imports them (and so registers them).

``fdmodel`` registers ``"fd"`` (finite differences) and ``femodel`` ``"fe"``
(finite elements) as :class:`deformable.backends.Discretisation` descriptors;
the harness, the studies and the command line turn a backend name into a
model here, and read what they need of a backend (its grid unit, its cost)
from its descriptor.

A run of a scene config (``deformable run``, each case of ``deformable sweep``,
``deformable view`` and ``params``) takes its grid, model and step from
:func:`run_model`, one path: the same scene and backend give the same grid.
"""

from __future__ import annotations

from typing import NamedTuple

import fdmodel  # noqa: F401  (registers "fd")
import femodel  # noqa: F401  (registers "fe")
from deformable import scenes
from deformable.backends.registry import Discretisation
from deformable.dynamics.stepper import round_down

__all__ = ["BACKENDS", "make_model", "backend_dt", "descriptor", "RunModel", "run_grid", "run_model"]

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


def run_grid(scene_nodes, backend: str, nodes=None) -> tuple[int, int]:
    """The node grid (M, N) a run takes on ``backend``.

    ``nodes`` (M, N), where the user set the grid (KEY=VALUE, ``--grid``, a scene file's or a checkpoint's
    ``nodes``), is taken as is. Otherwise the scene's own grid ``scene_nodes`` (M, N), written in FD's nodes,
    is taken in the backend's unit (:meth:`Discretisation.scene_nodes`): FD as is, FE half as many elements a
    side (32 x 32 nodes -> 16 x 16 elements, 17 x 17 nodes). InputError for an unknown backend.
    """
    if nodes is not None:
        return tuple(int(n) for n in nodes)
    return descriptor(backend).scene_nodes(scene_nodes)


class RunModel(NamedTuple):
    """A scene config as a run takes it on a backend, and what is built from it (:func:`run_model`).

    config : the scene config with the grid (``nodes``, (M, N) nodes) and step (``dt``, s) the run takes
    scene : the :class:`deformable.Scene` of ``config``
    model : the backend's model of ``scene``
    """

    config: scenes.SceneConfig
    scene: object
    model: object


def run_model(config, backend: str, nodes=None, dt=None, **options) -> RunModel:
    """The grid, the model and the step of a run of scene config ``config`` on ``backend``: the one path of
    ``deformable run``, ``sweep`` (each case), ``view`` and ``params``.

    ``nodes`` (M, N) is an explicit grid, or None for the scene's grid in the backend's unit (:func:`run_grid`);
    ``dt`` (s) an explicit step, or None for the config's dt, or half the backend's stretching bound where that
    is smaller (:func:`backend_dt`). ``options`` go to the backend (:func:`make_model`). InputError on a value
    the scene or the backend refuses.
    """
    config = config.replace(nodes=run_grid(config.nodes, backend, nodes))
    scene = scenes.build(config)
    model = make_model(scene, backend, **options)
    step = dt if dt is not None else backend_dt(model, config.dt)
    if step != config.dt:
        config = config.replace(dt=step)
    return RunModel(config, scene, model)
