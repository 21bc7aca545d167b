"""femodel: finite elements on the parameter rectangle (bicubic Hermite on skfem's tensor mesh).

``FEModel(scene, element="hermite")`` discretises the same model as
``fdmodel.FDModel`` behind the same protocol (:class:`deformable.Backend`):
the weak form of eq. (14) with alpha, beta of eq. (15) at Gauss points,
consistent mass and damping, integrated loads; for ``force_model="variational"``
the exact gradient and Hessians of the Gauss-rule energy (13). See
:mod:`femodel.model`, :mod:`femodel.hermite` (the element),
:mod:`femodel.assembly` (forms and fixed-pattern assembly) and
:mod:`femodel.variational` (the energy-consistent model).
"""

from .assembly import FixedPattern, bending, mass, membrane
from .hermite import basis, cubic_hermite
from .model import ELEMENTS, GAUSS_POINTS, FEModel
from .variational import DiscreteEnergy

__all__ = ["FEModel", "ELEMENTS", "GAUSS_POINTS", "FixedPattern", "membrane", "bending", "mass", "basis",
           "cubic_hermite", "DiscreteEnergy"]
