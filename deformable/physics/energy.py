r"""The elastic energy of a state, split as eq. (13) splits it, and the kinetic energy.

:class:`Energy` holds the stretching part (the eta terms of eq. (13)) and the bending part (the xi terms), in J;
:func:`kinetic_energy` is ``V^T M V / 2`` with a backend's integrated mass matrix.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["Energy", "kinetic_energy"]


@dataclass(frozen=True)
class Energy:
    """Elastic energy of eq. (13), split into stretching (eta) and bending (xi) parts (J)."""

    stretching: float
    bending: float

    @property
    def total(self) -> float:
        return self.stretching + self.bending


def kinetic_energy(M: sp.spmatrix, V: np.ndarray) -> float:
    """Kinetic energy ``V^T M V / 2`` (J) of velocities V (ndof, 3) with the (integrated) mass M."""
    return 0.5 * float(np.sum(V * (M @ V)))
