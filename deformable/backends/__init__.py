"""The backends: the contract every discretisation satisfies, and their registry by name.

- :mod:`.contract`: what a discretisation offers (:class:`Backend`, a protocol) and what it gives back
  (:class:`Sample`);
- :mod:`.registry`: :class:`Discretisation`, the descriptor each backend package registers (its name, model
  class, grid unit, memory per node, cost, stiffest membrane mode, contact points), and :func:`check_scene`;
- :mod:`.base`: :class:`BackendBase`, the contract's methods every discretisation writes alike, written once
  over a few hooks (what a new backend writes and what it inherits: its docstring).

The backends themselves, ``fdmodel.FDModel`` and ``femodel.FEModel``, live outside the core, subclass
:class:`BackendBase` (so satisfy the protocol), and register their descriptors when imported; the core names none
of them.
"""

from .base import BackendBase
from .contract import Backend, EnergyBackend, Sample
from .registry import Discretisation, check_scene

__all__ = ["Backend", "BackendBase", "EnergyBackend", "Sample", "Discretisation", "check_scene"]
