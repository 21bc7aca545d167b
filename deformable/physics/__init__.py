"""What a sheet is made of and what acts on it: the material, the elastic law and its derivatives, the forces.

- :mod:`.material`: mu, gamma, eta, xi (and the frozen model's alpha, beta);
- :mod:`.energy`: the energy split into stretching and bending, the kinetic energy;
- :mod:`.elasticity`: eq. (13)-(15): alpha, beta, the energy density, the semi-implicit stretching bound;
- :mod:`.integrand`: eq. (13)'s integrand at points with its exact gradient and Hessians;
- :mod:`.kernels`: their compiled (numba) loops;
- :mod:`.forces`: gravity, body and edge loads, point loads, springs (the paper's coils), wind;
- :mod:`.loads`: the external force F of eq. (21) over a backend's hooks.

Imports the ground floor, :mod:`deformable.geometry` and :mod:`deformable.algebra`.
"""

from .elasticity import (
    QuadraticEnergy,
    alpha,
    beta,
    energy_density,
    lagged_alpha_step,
    require_energy_gradient,
    require_strength_matrix,
    stretching_step,
)
from .energy import Energy, kinetic_energy
from .forces import BodyForce, EdgeLoad, Force, Gravity, PointLoad, Sinusoidal, Spring, Wind
from .integrand import FD_SLOTS, FE_SLOTS, HESSIANS, Integrand, for_blocks, hessian_threads, slot_tensors
from .kernels import KINDS, element_upper, point_gradients, point_hessians, positive_part
from .loads import Loads
from .material import Material

__all__ = ["Material", "Energy", "kinetic_energy", "alpha", "beta", "energy_density", "stretching_step",
           "lagged_alpha_step", "QuadraticEnergy", "require_energy_gradient", "require_strength_matrix", "Integrand",
           "slot_tensors", "for_blocks", "hessian_threads", "HESSIANS", "FE_SLOTS", "FD_SLOTS", "KINDS",
           "point_gradients", "point_hessians", "element_upper", "positive_part", "Gravity", "BodyForce", "EdgeLoad",
           "PointLoad", "Spring", "Wind", "Sinusoidal", "Force", "Loads"]
