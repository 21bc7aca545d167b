"""The backend contract: what a discretisation offers (:class:`Backend`, a protocol) and what it is checked
against before it allocates anything.

The backends themselves, ``fdmodel.FDModel`` and ``femodel.FEModel``, live outside the core and satisfy the
protocol structurally.
"""

from .contract import BYTES_PER_NODE, Backend, EnergyBackend, Sample, check_scene, memory_estimate

__all__ = ["Backend", "EnergyBackend", "Sample", "check_scene", "memory_estimate", "BYTES_PER_NODE"]
