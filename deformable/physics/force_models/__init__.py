"""Force models: the force e(r) of eq. (11) as registered objects (:mod:`.base`).

- :class:`TPBF87` (``"tpbf87"``): the paper's force (14)-(15), a strength matrix K(r) (:mod:`.tpbf87`);
- :class:`Frozen` (``"frozen"``): alpha and beta given directly, section 3.2 (:mod:`.frozen`);
- :class:`Variational` (``"variational"``): the exact gradient of the energy (13) (:mod:`.variational`);
- :class:`Koiter` (``"koiter"``): Koiter's isotropic shell, E, nu and h, strains in the rest metric
  (:mod:`.koiter`);
- :class:`Orthotropic` (``"orthotropic"``): the same shell with a fabric's orthotropic law, warp and weft moduli and
  a shear modulus (:mod:`.orthotropic`).

A new energy is one subclass of :class:`EnergyModel` with a ``name`` and its density W(s, b) with two derivatives
(examples/custom_energy.py).
"""

from .base import RESIDUALS, EnergyModel, ForceModel, StrengthModel, energy_density
from .frozen import Frozen, QuadraticEnergy
from .koiter import Koiter, ShellEnergy
from .orthotropic import Orthotropic
from .tpbf87 import TPBF87, alpha, beta, stretching_step
from .variational import Variational

__all__ = ["ForceModel", "StrengthModel", "EnergyModel", "RESIDUALS", "energy_density", "TPBF87", "Frozen",
           "Variational", "Koiter", "ShellEnergy", "Orthotropic", "QuadraticEnergy", "alpha", "beta", "stretching_step"]
