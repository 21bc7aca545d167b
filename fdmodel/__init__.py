"""fdmodel: the paper's finite-difference discretisation (section 2.3, TPBF87 appendix).

``FDModel(scene, weighting=None)`` behind the backend contract
(:class:`deformable.Backend`, on :class:`deformable.backends.BackendBase`), module for module like :mod:`femodel`:

- :mod:`fdmodel.model`: the model (geometry, loads, constraints, the system (21));
- :mod:`fdmodel.operators`: the difference operators (FE's counterpart: :mod:`femodel.hermite`);
- :mod:`fdmodel.strength`: the strength matrix K(r) of eq. (16)-(20) on a fixed pattern;
- :mod:`fdmodel.energy`: the discrete energy (13), its exact gradient and Hessians;
- :mod:`fdmodel.clamp`: the reflection clamp (a ghost row outside a clamped edge);
- :mod:`fdmodel.backend`: the descriptor registered as ``"fd"`` (:class:`deformable.backends.Discretisation`).
"""

from .backend import FiniteDifferences
from .energy import DiscreteEnergy
from .model import WEIGHTINGS, FDModel
from .operators import node_derivatives, node_tensors, operators
from .strength import StrengthMatrix

__all__ = ["FDModel", "FiniteDifferences", "WEIGHTINGS", "node_derivatives", "node_tensors", "operators",
           "StrengthMatrix", "DiscreteEnergy"]
