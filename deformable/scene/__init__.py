"""One problem, ready for a backend: :class:`Scene` (sheet, material, forces, constraints, force model,
obstacles) and the constraints (:class:`Pin`, :class:`Slide`, :class:`Clamp`) with their mapping to held degrees of
freedom.

The catalogue of shipped scenes and scene files is :mod:`deformable.scenes`.
"""

from .constraints import AXES, CORNERS, EDGES, Clamp, HeldDofs, Pin, Slide, Symmetry, edges_named, hold, select
from .scene import Scene

__all__ = ["Scene", "Pin", "Slide", "Clamp", "Symmetry", "select", "EDGES", "CORNERS", "AXES",
           "HeldDofs", "hold", "edges_named"]
