"""femodel: finite elements on the parameter rectangle (bicubic Hermite on skfem's tensor mesh).

``FEModel(scene, element="hermite")`` discretises the same model as
``fdmodel.FDModel`` behind the same contract (:class:`deformable.Backend`, on
:class:`deformable.backends.BackendBase`), module for module:

- :mod:`femodel.model`: the model (geometry, loads, constraints, the system (21));
- :mod:`femodel.hermite`: the element (FD's counterpart: :mod:`fdmodel.operators`);
- :mod:`femodel.strength`: K of the weak form of eq. (14) on a fixed pattern, and the consistent mass;
- :mod:`femodel.energy`: the energy (13) by the Gauss rule, its exact gradient and Hessians;
- :mod:`femodel.backend`: the descriptor registered as ``"fe"`` (:class:`deformable.backends.Discretisation`).
"""

from .backend import FiniteElements
from .energy import DiscreteEnergy
from .hermite import basis, cubic_hermite
from .model import ELEMENTS, GAUSS_POINTS, FEModel
from .strength import StrengthMatrix, bending, mass, membrane

__all__ = ["FEModel", "FiniteElements", "ELEMENTS", "GAUSS_POINTS", "StrengthMatrix", "membrane", "bending", "mass",
           "basis", "cubic_hermite", "DiscreteEnergy"]
