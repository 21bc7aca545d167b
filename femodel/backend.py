"""The finite-element backend's descriptor: what the core and the harness know of it by its name, ``"fe"``.

Registered when :mod:`femodel` is imported (:class:`deformable.backends.Discretisation`).
"""

from __future__ import annotations

from deformable.backends.registry import Discretisation

from .model import CONTACT_SAMPLES, MEMBRANE_EIGENVALUE, FEModel

__all__ = ["FiniteElements"]


class FiniteElements(Discretisation):
    """Bicubic Hermite elements (Bogner-Fox-Schmit) on the sheet's cells, with scikit-fem."""

    name = "fe"
    rank = 1
    label = "bicubic Hermite finite elements on the same rectangle (scikit-fem)"
    model = FEModel
    grid = "elements"
    # peak memory per node of a model and two steps of the curtain, FE at 40-80 nodes a side, measured and
    # rounded up: variational 280-310 kB, tpbf87 45-55 kB (four degrees of freedom a node, 16 a element side)
    bytes_per_node = {"implicit": 340e3, "semi-implicit": 64e3}
    # work per node and step relative to FD's: four degrees of freedom per node
    cost = 4.0
    membrane_eigenvalue = MEMBRANE_EIGENVALUE
    contact_samples = CONTACT_SAMPLES
    # a scene's default grid (FD nodes) taken as half as many elements a side (Discretisation.scene_nodes)
    scene_fraction = 0.5
