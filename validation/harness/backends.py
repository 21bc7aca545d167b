"""The two discretisations by name: ``"fd"`` (:class:`fdmodel.FDModel`) and ``"fe"`` (:class:`femodel.FEModel`).

The one place where the harness, the studies and the command line turn a
backend name into a model.
"""

from __future__ import annotations

from deformable.errors import InputError

__all__ = ["BACKENDS", "make_model", "backend_dt"]

BACKENDS = ("fd", "fe")


def make_model(scene, backend: str, **options):
    """The model of ``scene`` on ``backend``; ``options`` go to the backend (e.g. FD ``weighting``).

    Raises ValueError naming the known backends for any other name.
    """
    if backend == "fd":
        from fdmodel import FDModel

        return FDModel(scene, **options)
    if backend == "fe":
        from femodel import FEModel

        return FEModel(scene, **options)
    raise InputError(f"unknown backend {backend!r}; choose one of {', '.join(BACKENDS)}")


def backend_dt(model, dt: float) -> float:
    """The step (s) a scene's default ``dt`` becomes on ``model``'s backend.

    The scenes' default dt is the FD one; a backend whose stretching bound ``model.stable_step()``
    (eq. 25 lags alpha; docs/design.md, "Time stepping") is tighter gets half that bound, rounded
    down to two significant digits. The frozen and variational models have no bound (inf): dt stays.
    """
    from deformable.dynamics.stepper import round_down

    bound = model.stable_step()
    return round_down(0.5 * bound) if dt > 0.5 * bound else dt
