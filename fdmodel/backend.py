"""The finite-difference backend's descriptor: what the core and the harness know of it by its name, ``"fd"``.

Registered when :mod:`fdmodel` is imported (:class:`deformable.backends.Discretisation`).
"""

from __future__ import annotations

from deformable.backends.registry import Discretisation

from .model import CONTACT_SAMPLES, MEMBRANE_EIGENVALUE, FDModel

__all__ = ["FiniteDifferences"]


class FiniteDifferences(Discretisation):
    """The paper's finite differences (section 2.3) on the M x N node grid."""

    name = "fd"
    rank = 0
    label = "finite differences on the node grid (the paper's section 2.3)"
    model = FDModel
    grid = "nodes"
    # peak memory per node of a model and two steps of the curtain, FD at 40-160 nodes a side, measured and
    # rounded up: variational (Newton on the 3 ndof Hessian) 49-60 kB, tpbf87 (the strength matrix) 9-12 kB
    bytes_per_node = {"implicit": 64e3, "semi-implicit": 16e3}
    cost = 1.0
    membrane_eigenvalue = MEMBRANE_EIGENVALUE
    contact_samples = CONTACT_SAMPLES
