r"""The protocol both discretisations satisfy (DESIGN.md, "The library contract").

A backend turns a :class:`~deformable.scene.Scene` into the semi-discrete
system (21), ``M R'' + C R' + K(r) R = F``, over ``ndof`` degrees of freedom
per coordinate; the state X is an ``(ndof, 3)`` array (x, y, z columns share
one scalar discretisation). The TimeStepper knows nothing else about it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
import scipy.sparse as sp

from .scene import Scene

__all__ = ["Backend", "EnergyBackend", "Sample", "Energy"]


@dataclass(frozen=True)
class Sample:
    """Surface quantities at P parameter points: r (P, 3), G (P, 2, 2), B (P, 2, 2)."""

    r: np.ndarray
    G: np.ndarray
    B: np.ndarray


@dataclass(frozen=True)
class Energy:
    """Elastic energy of eq. (13), split into stretching (eta) and bending (xi) parts (J)."""

    stretching: float
    bending: float

    @property
    def total(self) -> float:
        return self.stretching + self.bending


@runtime_checkable
class Backend(Protocol):
    """What TimeStepper, the scenes and the validation harness need of a discretisation."""

    scene: Scene
    ndof: int
    linear: bool  # True when K does not depend on X (the "frozen" model)
    measure: float  # area each row of M, C and F stands for (FD: h1 h2, pointwise rows; FE: 1)

    def initial_state(self) -> np.ndarray: ...
    def discretize(self, surface) -> np.ndarray: ...
    def sample(self, X: np.ndarray, a: np.ndarray) -> Sample: ...
    def stiffness(self, X: np.ndarray) -> sp.csr_matrix: ...
    def mass(self) -> sp.csr_matrix: ...
    def damping(self) -> sp.csr_matrix: ...
    def fixed_dofs(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]: ...
    def prescribed(self, X0: np.ndarray, t: float) -> np.ndarray: ...
    def load(self, X: np.ndarray, t: float) -> np.ndarray: ...
    def energy(self, X: np.ndarray) -> Energy: ...
    def kinetic_energy(self, V: np.ndarray) -> float: ...


class EnergyBackend(Backend, Protocol):
    """A backend whose internal force is the gradient of an energy ("variational", "frozen").

    The implicit schemes and :func:`deformable.equilibrium` need these; vectors
    of the Hessian are coordinate-blocked (index ``a * ndof + k``).
    """

    def energy_gradient(self, X: np.ndarray) -> np.ndarray: ...
    def energy_hessian(self, X: np.ndarray, kind: str = "newton") -> sp.csr_matrix: ...
    def grid(self, X: np.ndarray) -> np.ndarray: ...
