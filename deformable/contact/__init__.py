"""Rigid obstacles and the sheet's contact with them.

- :mod:`.obstacles`: the shapes, their exact signed distances and safe steps;
- :mod:`.settings`: :class:`Contact`, how the sheet meets them;
- :mod:`.points`: where the sheet may touch (contact points), and the clearance;
- :mod:`.barrier`: the IPC barrier and friction mollifier as functions of a distance;
- :mod:`.potential`: the barrier and lagged friction potential, its safe steps and the solved contact normals (the
  direction filter Newton's method takes from here);
- :mod:`.repulsion`: the paper's (TPBF87's) exponential obstacle force;
- :mod:`.selfmesh`: the sheet as a triangle mesh for self-contact, its self-distance and intersection test (the IPC
  Toolkit, ``ipctk``);
- :mod:`.selfpotential`: the self-contact barrier on that mesh and its collision-free step;
- :mod:`.meshobstacle`: a rigid obstacle of any shape, a triangle mesh, static or on a prescribed rigid path;
- :mod:`.meshpotential`: the sheet against the mesh obstacles, triangle against triangle;
- :mod:`.terms`: the obstacles' and the self-contact's terms as one term of Newton's potential and one direction
  filter.

Imports the ground floor, :mod:`deformable.geometry`, :mod:`deformable.algebra` and :mod:`deformable.physics`.
"""

from .barrier import barrier, barrier_derivative, barrier_second, mollifier
from .meshobstacle import MeshObstacle
from .meshpotential import MeshObstaclePotential, ObstacleMesh
from .obstacles import Box, Cylinder, HalfSpace, Obstacle, Sphere, from_table, to_table
from .clearance import clearance, require_clear
from .points import ContactPoints, contact_points, require_outside, subgrid
from .potential import ContactPotential
from .repulsion import Repulsion
from .selfmesh import ContactMesh, grid_triangles
from .selfpotential import SelfContactPotential
from .settings import METHODS, Contact, weight_per_area
from .terms import ContactTerms

__all__ = ["Obstacle", "HalfSpace", "Sphere", "Box", "Cylinder", "MeshObstacle", "from_table", "to_table",
           "Contact", "METHODS", "weight_per_area", "ContactPoints", "subgrid", "contact_points", "require_outside",
           "clearance", "require_clear", "barrier", "barrier_derivative", "barrier_second", "mollifier", "ContactPotential", "Repulsion",
           "ContactMesh", "grid_triangles", "SelfContactPotential", "ObstacleMesh", "MeshObstaclePotential", "ContactTerms"]
