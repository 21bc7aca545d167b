"""Newton's method and what it solves.

- :mod:`.potential`: a model's potential over flat coordinate-blocked vectors (elastic energy, springs, contact);
- :mod:`.newton`: Newton's method on it, with a definite fallback and factorisation reuse;
- :mod:`.equilibrium`: static equilibrium, ``grad E = F`` under load continuation.
"""

from .equilibrium import equilibrium
from .newton import WATCHDOG, ConvergenceError, Newton, NewtonReport, NewtonSettings
from .potential import FlatEnergy, flat, unflat

__all__ = ["FlatEnergy", "flat", "unflat", "ConvergenceError", "NewtonReport", "NewtonSettings", "Newton", "WATCHDOG",
           "equilibrium"]
