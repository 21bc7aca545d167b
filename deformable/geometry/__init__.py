"""The surface and its tensors: the parameter rectangle, surfaces on it, G and B, and their compatibility.

- :mod:`.tensors`: the metric (eq. 4), normal and curvature (eq. 8) as pure functions;
- :mod:`.surfaces`: the Surface protocol, the plane, callables as surfaces;
- :mod:`.sheet`: the parameter rectangle and its node grid, edges, corners, cells;
- :mod:`.compatibility`: the paper's compatibility test of G and B (section 3.2, eq. 10).

Imports only the ground floor (:mod:`deformable.errors`, :mod:`deformable.checks`, :mod:`deformable.limits`).
"""

from .compatibility import (
    Comparison,
    Compatibility,
    IncompatibleRestState,
    brioschi,
    check_compatibility,
    check_rest_state,
    christoffel,
    rest_tensors,
    third_derivatives,
    warn_if_incompatible,
)
from .sheet import CELL_CORNERS, CORNERS, EDGES, Edge, Sheet, bilinear, bilinear_weights
from .surfaces import CallableSurface, FlatSurface, Plane, Surface, as_surface
from .tensors import cross, curvature, det2, dot, frame, gaussian_curvature, metric, normal, tangent_basis

__all__ = ["metric", "normal", "frame", "dot", "cross", "curvature", "gaussian_curvature", "det2", "tangent_basis",
           "Surface", "CallableSurface", "Plane", "FlatSurface", "as_surface", "Sheet", "Edge", "EDGES", "CORNERS",
           "bilinear", "bilinear_weights", "CELL_CORNERS", "Compatibility", "Comparison", "check_compatibility",
           "brioschi", "christoffel", "third_derivatives", "rest_tensors", "check_rest_state", "warn_if_incompatible",
           "IncompatibleRestState"]
