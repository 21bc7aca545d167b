"""Newton's method and what it solves.

- :mod:`.potential`: a model's potential over flat coordinate-blocked vectors (elastic energy, springs, contact);
- :mod:`.newton`: Newton's method on it, with a definite fallback and factorisation reuse, and the protocol of the
  direction filters a potential's terms supply (contact);
- :mod:`.search`: the line searches, registered strategies beside the loop (watchdog, Armijo);
- :mod:`.equilibrium`: static equilibrium, ``grad E = F`` under load continuation;
- :mod:`.continuation`: equilibrium paths by arc length, through limit points, with each point's stability and
  branch switching at a simple bifurcation.
"""

from .continuation import Path, PathPoint, equilibrium_path
from .equilibrium import equilibrium
from .newton import DirectionFilter, Newton, NewtonReport, NewtonSettings
from .potential import FlatEnergy, flat, unflat
from .search import WATCHDOG, Armijo, Candidate, LineSearch, Watchdog

__all__ = ["FlatEnergy", "flat", "unflat", "Newton", "NewtonReport", "NewtonSettings", "DirectionFilter",
           "LineSearch", "Watchdog", "Armijo", "Candidate", "WATCHDOG", "equilibrium",
           "equilibrium_path", "Path", "PathPoint"]
