"""What a sheet is made of and what acts on it: the material, the elastic law and its derivatives, the forces.

- :mod:`.material`: mu, gamma, eta, xi (and the frozen model's alpha, beta);
- :mod:`.energy`: the energy split into stretching and bending, the kinetic energy;
- :mod:`.force_models`: the force of eq. (11) as registered objects: the paper's (14)-(15), the frozen
  model of section 3.2, the exact gradient of eq. (13), and any energy density W(s, b) one adds;
- :mod:`.integrand`: eq. (13)'s integrand at points with its exact gradient and Hessians;
- :mod:`.kernels`: their compiled (numba) loops;
- :mod:`.forces`: gravity, body and edge loads, point loads, springs (the paper's coils), wind;
- :mod:`.loads`: the external force F of eq. (21) over a backend's hooks.

Imports the ground floor, :mod:`deformable.geometry` and :mod:`deformable.algebra`.
"""

from .energy import Energy, kinetic_energy
from .force_models import (
    RESIDUALS,
    TPBF87,
    EnergyModel,
    ForceModel,
    Frozen,
    QuadraticEnergy,
    StrengthModel,
    Variational,
    alpha,
    beta,
    energy_density,
    stretching_step,
)
from .forces import BodyForce, EdgeLoad, EdgeMoment, Force, Gravity, PointLoad, Pressure, Sinusoidal, Spring, Wind
from .integrand import FD_SLOTS, FE_SLOTS, HESSIANS, DensityIntegrand, Integrand, slot_tensors
from .loads import Loads
from .material import Material

__all__ = ["Material", "Energy", "kinetic_energy", "ForceModel", "StrengthModel", "EnergyModel", "RESIDUALS",
           "TPBF87", "Frozen", "Variational", "QuadraticEnergy", "alpha", "beta", "energy_density", "stretching_step",
           "Integrand", "DensityIntegrand", "slot_tensors", "HESSIANS", "FE_SLOTS", "FD_SLOTS", "Gravity", "BodyForce",
           "EdgeLoad", "EdgeMoment", "PointLoad", "Pressure", "Spring", "Wind", "Sinusoidal", "Force", "Loads"]
