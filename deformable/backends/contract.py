r"""The contract both discretisations satisfy (docs/design.md, "The backend contract").

A backend turns a :class:`~deformable.scene.Scene` into the semi-discrete
system (21), ``M R'' + C R' + e(R) = F``, over ``ndof`` degrees of freedom
per coordinate; a state X is an ``(ndof, 3)`` array (x, y, z columns share
one scalar discretisation). Everything the time stepper, the output writer,
the scenes and the validation harness use of a backend is here; nothing
above the backends reads anything else of them.

One unit convention for both backends: every row is *integrated* over the
area a degree of freedom stands for. M and C are in kg and kg/s, F and the
internal force in N, K in N/m, the energy (13) in J and its gradient in N.
(The FD rows of the paper are per unit area; FD multiplies them by the cell
area h1 h2, so its ``stiffness(X) / (h1 h2)`` is the paper's K(r) of eq. (20).)

Coordinate-blocked vectors (the Hessians, the implicit schemes): index
``a * ndof + k`` for coordinate a of degree of freedom k.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
import scipy.sparse as sp

from ..physics.energy import Energy
from ..physics.loads import Loads
from ..scene.scene import Scene

__all__ = ["Backend", "EnergyBackend", "Sample"]


@dataclass(frozen=True)
class Sample:
    """Surface quantities at P parameter points: r (P, 3), G (P, 2, 2), B (P, 2, 2)."""

    r: np.ndarray
    G: np.ndarray
    B: np.ndarray


@dataclass(frozen=True)
class EdgeRule:
    """A backend's quadrature along one edge of the sheet: P points, their parameter coordinates a1, a2 (P,), their
    weights (P,) (parameter length, scene units: int_edge f ds = sum w f), and two fixed sparse (P, ndof)
    matrices: ``at @ X`` is r at the points, ``across @ X`` the derivative of r across the edge (r_1 on the left
    and right edges, r_2 on the bottom and top), along the parameter's own direction."""

    a1: np.ndarray
    a2: np.ndarray
    weights: np.ndarray
    at: sp.csr_matrix
    across: sp.csr_matrix


@dataclass(frozen=True)
class Patches:
    """A backend's quadrature points grouped by the degrees of freedom they read: G groups (FE: elements; FD:
    cells, one point at the centre) of q points each, reading c degrees of freedom ``cols`` (G, c); ``values``
    (3, G, q, c) the weights by which r, r_1 and r_2 at a point are sums of those degrees of freedom
    (r = sum_c values[0] X[cols]);
    ``weights`` (G, q) the points' quadrature weights (area, scene units). Local derivatives of a density of
    (r, r_1, r_2) assemble on the fixed pattern of the pairs of each group's columns."""

    cols: np.ndarray
    values: np.ndarray
    weights: np.ndarray


@runtime_checkable
class Backend(Protocol):
    """What a discretisation offers: geometry, the system (21), the energy (13) and its derivatives.

    A backend writes it on :class:`~deformable.backends.base.BackendBase`, which holds the methods that read the
    discretisation only through a few hooks (what a backend writes and what it inherits: its docstring).

    Attributes
    ----------
    scene : Scene
    ndof : int
        Degrees of freedom per coordinate.
    linear : bool
        True when K does not depend on X (the "frozen" force model).
    spacing : (h1, h2)
        The grid spacings (scene units): node spacing (FD), element sides (FE).
    value_dofs : int array (M N,)
        The rows of X that hold the node positions, node (m, n) at m N + n:
        ``grid(X) == X[value_dofs].reshape(M, N, 3)``.
    points : (a1, a2), two arrays of shape (*pts)
        The parameter coordinates of the backend's own points, where
        :meth:`tensors` evaluates G and B (FD: the nodes, (M, N); FE: the
        Gauss points, (elements, points per element)).
    mu : array (*pts)
        The mass density at the points (kg/m^2).
    loads : deformable.physics.loads.Loads
        The scene's external forces over the hooks below: applied loads,
        springs (their energy, gradient, Hessian) and wind (its force and
        velocity Jacobian).
    contact_samples : int
        Contact points per cell side by default (:mod:`deformable.contact`):
        FD 1 (its nodes), FE 2 (a sub-grid of spacing h / 2).
    """

    scene: Scene
    ndof: int
    linear: bool
    spacing: tuple[float, float]
    value_dofs: np.ndarray
    points: tuple[np.ndarray, np.ndarray]
    mu: np.ndarray
    loads: Loads
    contact_samples: int

    # -- geometry
    def initial_state(self) -> np.ndarray: ...
    def discretize(self, surface) -> np.ndarray: ...
    def grid(self, X: np.ndarray) -> np.ndarray: ...
    def tensors(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]: ...
    def sample(self, X: np.ndarray, a: np.ndarray) -> Sample: ...

    # -- the semi-discrete system (21), integrated rows
    def stiffness(self, X: np.ndarray) -> sp.csr_matrix: ...
    def mass(self) -> sp.csr_matrix: ...
    def damping(self) -> sp.csr_matrix: ...
    def load(self, X: np.ndarray, t: float, V: np.ndarray | None = None) -> np.ndarray: ...
    def internal_force(self, X: np.ndarray) -> np.ndarray: ...
    def fixed_dofs(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]: ...
    def prescribed(self, X0: np.ndarray, t: float) -> np.ndarray: ...
    def stable_step(self, force_model=None) -> float: ...

    # -- the energy (13)
    def energy(self, X: np.ndarray) -> Energy: ...
    def kinetic_energy(self, V: np.ndarray) -> float: ...
    def energy_gradient(self, X: np.ndarray) -> np.ndarray: ...
    def energy_hessian(self, X: np.ndarray, kind: str = "newton") -> sp.csr_matrix: ...
    def energy_elements(self, X: np.ndarray, kind: str = "newton"): ...  # (element uppers, their pattern) or None

    # -- the hooks of deformable.physics.loads: integration at the backend's own points
    def integrate(self, density: np.ndarray) -> np.ndarray: ...
    def at_points(self, X: np.ndarray, d: tuple[int, int] = (0, 0)) -> np.ndarray: ...
    def density_matrix(self, c: np.ndarray) -> sp.csr_matrix: ...
    def point_dofs(self, a, what: str = "point") -> tuple[np.ndarray, np.ndarray]: ...
    def edge_rule(self, name: str) -> EdgeRule: ...
    def patches(self) -> Patches: ...

    # -- the hook of deformable.contact: r at parameter points a (P, 2) as a fixed sparse matrix, r(a) = W @ X
    def point_matrix(self, a) -> sp.csr_matrix: ...


#: the former name of the contract's energy part; every backend has it now
EnergyBackend = Backend

