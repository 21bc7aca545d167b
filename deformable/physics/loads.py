r"""The external force F of eq. (21), written once over five hooks of a backend.

A backend integrates loads its own way (FD: per node, times the node's area;
FE: against its basis by Gauss quadrature). What is common, the forces
themselves, their state dependence and their derivatives, is here, on top of
these backend hooks (the backend contract, :mod:`deformable.backends`):

- ``points``, ``mu``: the backend's own points and the mass density there;
- ``integrate(density)``: ``integral f phi_k`` of a density (N/m^2) given at
  the points, (ndof, 3);
- ``at_points(X, d)``: the field X or its derivative ``d = (d1, d2)`` at the
  points, (P, 3);
- ``density_matrix(c)``: ``integral c phi_k phi_l`` (ndof, ndof) of a scalar
  field at the points, on one pattern for every c;
- ``point_dofs(a, what)``: the degrees of freedom and weights of ``r(a) = sum_k w_k X_k``;
- ``edge_rule(name)``: the backend's quadrature along an edge
  (:class:`~deformable.backends.contract.EdgeRule`: points, weights, r and its
  derivative across the edge as fixed sparse matrices), which integrates edge
  tractions (``at^T (w q)``) and edge moments.

The forces (:mod:`deformable.physics.forces`) are asked, never named: each says by its role what it adds.

- applied loads (:class:`~deformable.physics.forces.AppliedLoad`), independent of the state: each integrates
  itself (:meth:`~deformable.physics.forces.AppliedLoad.applied`; body densities such as gravity ``mu g``,
  edge tractions, point loads), summed in the scene's order, the concentrated ones last;
- conservative loads (:class:`~deformable.physics.forces.ConservativeLoad`): the springs (the paper's
  "coils", section 5), edge moments (:mod:`deformable.physics.moments`) and pressures
  (:mod:`deformable.physics.pressure`), each class's potential built once over all its loads, with an energy,
  its gradient and Hessian; the implicit schemes and the equilibrium treat them as part of the potential
  (:meth:`Loads.potential_energy` and its derivatives; ``factor`` scales the moments and pressures with
  ``equilibrium``'s load steps);
- velocity loads (:class:`~deformable.physics.forces.VelocityLoad`), the wind:
  ``c ((w - v) . n) |(w - v) . n| n`` per unit current area, depending on positions (n, area) and
  velocities (v); its Jacobian in v, the damping ``D = integral 2 c |u . n| |r_1 x r_2| n n^T phi_k phi_l``,
  lets the implicit schemes take the wind's velocity dependence implicitly (a damping).

Blocked matrices (the springs' Hessian, the wind's damping) follow the
contract's coordinate-blocked index ``a * ndof + k`` and keep one sparsity
pattern for a run (:class:`deformable.algebra.patterns.FixedPattern`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..algebra.patterns import BlockPattern
from ..geometry.tensors import frame
from .forces import AppliedLoad, ConservativeLoad, SpringPotential, VelocityLoad
from .moments import EdgeMoments
from .pressure import PressurePotential

__all__ = ["Loads"]

#: the coordinate pairs (a, b) of a symmetric 3 x 3 block matrix, upper triangle first
_PAIRS = [(a, b) for a in range(3) for b in range(a, 3)]


class Loads:
    """The external forces of a model's scene, with their state dependence (module docstring).

    Parameters
    ----------
    model : Backend
        Built far enough to have its hooks (``points``, ``mu``, ``integrate``,
        ``at_points``, ``density_matrix``, ``point_dofs``, ``edge_rule``).

    Attributes
    ----------
    winds : tuple of the scene's velocity loads (Wind)
    parts : list
        The potentials of the conservative loads, one per ``potential`` class, by ``rank`` (springs, moments,
        pressures).
    potentials : bool
        Conservative loads: a potential that depends on the state.
    conservative : bool
        No wind: the external force is the gradient of a potential.
    linear : bool
        Conservative, every potential with a constant Hessian (linear springs only, rest length 0; no moment, no
        pressure): the Hessian of the potential does not depend on the state.
    """

    def __init__(self, model):
        self.model, self.n = model, model.ndof
        forces = model.scene.forces
        #: the applied loads, distributed ones first, each in the scene's order (a stable sort)
        self._applied = sorted((f for f in forces if isinstance(f, AppliedLoad)), key=lambda f: f.concentrated)
        self.winds = tuple(f for f in forces if isinstance(f, VelocityLoad))
        groups: dict[type, list] = {}
        for f in forces:
            if isinstance(f, ConservativeLoad):
                groups.setdefault(f.potential, []).append(f)
        self.parts = [cls(model, tuple(fs)) for cls, fs in sorted(groups.items(), key=lambda g: g[0].rank)]
        self.potentials = bool(self.parts)
        self.conservative = not self.winds
        self.linear = self.conservative and all(p.linear for p in self.parts)
        self._free = [p for p in self.parts if not p.factored]
        #: the state-dependent loads that scale with the load factor (moments, pressures)
        self._factored = [p for p in self.parts if p.factored]
        self._springs, self._moments, self._pressure = (self.part(c) for c in (SpringPotential, EdgeMoments,
                                                                                  PressurePotential))
        self._rules, self._points = {}, {}
        self._wind_pattern = None

    def part(self, cls):
        """The potential of the scene's loads that ``cls`` computes (an instance of it), or None."""
        return next((p for p in self.parts if isinstance(p, cls)), None)

    # -- applied loads ----------------------------------------------------------
    def applied(self, t: float) -> np.ndarray:
        """The applied loads at time t, (ndof, 3) (N): each integrates itself (body, edge and point loads)."""
        F = np.zeros((self.n, 3))
        for force in self._applied:
            F += force.applied(self, t)
        return F

    def edge_rule(self, name: str):
        """The model's :class:`~deformable.backends.contract.EdgeRule` of an edge (built once)."""
        if name not in self._rules:
            self._rules[name] = self.model.edge_rule(name)
        return self._rules[name]

    def point_dofs(self, at: tuple, what: str):
        """The model's degrees of freedom and weights of ``r(at) = sum_k w_k X_k`` (built once); ``what`` names
        the point in an error."""
        if (at, what) not in self._points:
            self._points[at, what] = self.model.point_dofs(at, what)
        return self._points[at, what]

    def total(self, X: np.ndarray, t: float, V: np.ndarray | None = None) -> np.ndarray:
        """F of eq. (21): applied loads, the potentials' force at X and wind at (X, V) (V None: at rest), (ndof, 3)
        (N)."""
        F = self.applied(t)
        if self.potentials:
            F -= self.potential_gradient(X, t)
        if self.winds:
            F += self.wind_force(X, V, t)
        return F

    # -- the potentials of springs, moments and pressures --------------------------
    def potential_energy(self, X: np.ndarray, t: float, factor: float = 1.0) -> float:
        """The potentials' energy (J): the springs' and those ``factor`` scales (moments, pressures)."""
        return sum(p.energy(X, t, factor) for p in self._free) + sum(p.energy(X, t, factor) for p in self._factored)

    def potential_gradient(self, X: np.ndarray, t: float, factor: float = 1.0) -> np.ndarray:
        """The gradient of :meth:`potential_energy`, (ndof, 3) (N): minus the conservative loads' force."""
        G = sum((p.gradient(X, t, factor) for p in self._free), np.zeros((self.n, 3)))
        return G + sum(p.gradient(X, t, factor) for p in self._factored)

    def factored_gradient(self, X: np.ndarray, t: float) -> np.ndarray:
        """The gradient of the part of :meth:`potential_energy` that ``factor`` scales (moments, pressures) at factor 1,
        (ndof, 3) (N): minus the derivative of the load in the load factor, beside the applied loads."""
        return sum((p.gradient(X, t, 1.0) for p in self._factored), np.zeros((self.n, 3)))

    def potential_hessians(self, X: np.ndarray, t: float, factor: float = 1.0) -> list:
        """The Hessians of :meth:`potential_energy`, each (3 ndof, 3 ndof) blocked on its fixed pattern."""
        return [p.hessian(X, t, factor) for p in self._free + self._factored]

    # -- springs (their potential, :class:`~deformable.physics.forces.SpringPotential`) ------------------------
    def spring_energy(self, X: np.ndarray, t: float) -> float:
        """Sum of k (|r(a) - anchor| - L0)^2 / 2 over the springs (J)."""
        return self._springs.energy(X, t) if self._springs else 0.0

    def spring_gradient(self, X: np.ndarray, t: float) -> np.ndarray:
        """Gradient of :meth:`spring_energy` (N), (ndof, 3): minus the springs' force."""
        return self._springs.gradient(X, t) if self._springs else np.zeros((self.n, 3))

    def spring_hessian(self, X: np.ndarray, t: float) -> sp.csr_matrix | None:
        """Hessian of :meth:`spring_energy`, (3 ndof, 3 ndof) blocked, fixed pattern (definite part); None without
        springs."""
        return self._springs.hessian(X, t) if self._springs else None

    # -- wind --------------------------------------------------------------------
    def _surface(self, X, V):
        """Unit normals n (P, 3), area elements |r_1 x r_2| (P,) and velocities (P, 3) at the points."""
        m = self.model
        n, area = frame(m.at_points(X, (1, 0)), m.at_points(X, (0, 1)))
        n = np.nan_to_num(n, nan=0.0)  # a degenerate point (parallel tangents) takes no wind
        v = np.zeros_like(n) if V is None else m.at_points(V, (0, 0))
        return n, area, v

    def wind_force(self, X: np.ndarray, V: np.ndarray | None, t: float) -> np.ndarray:
        """The wind's integrated force at positions X and velocities V (None: at rest), (ndof, 3) (N)."""
        n, area, v = self._surface(X, V)
        shape = self.model.points[0].shape
        f = sum(w.density(n, area, v, t) for w in self.winds)
        return self.model.integrate(f.reshape(*shape, 3))

    def wind_damping(self, X: np.ndarray, V: np.ndarray | None, t: float) -> sp.csr_matrix | None:
        """-d(wind force)/dV, (3 ndof, 3 ndof) blocked, symmetric positive semi-definite, fixed pattern; None without
        wind."""
        if not self.winds:
            return None
        m = self.model
        n, area, v = self._surface(X, V)
        d = sum(w.damping(n, area, v, t) for w in self.winds)  # (P, 3, 3)
        shape = m.points[0].shape
        blocks = {ab: m.density_matrix(d[:, ab[0], ab[1]].reshape(shape)) for ab in _PAIRS}
        if self._wind_pattern is None:
            self._wind_pattern = BlockPattern(blocks[0, 0], self.n)
        return self._wind_pattern.matrix(blocks)
