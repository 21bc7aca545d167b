"""The two discretisations by name: ``"fd"`` (:class:`fdmodel.FDModel`) and ``"fe"`` (:class:`femodel.FEModel`).

The one place where the harness, the studies and the command line turn a
backend name into a model.
"""

from __future__ import annotations

from deformable.errors import InputError

__all__ = ["BACKENDS", "make_model"]

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
