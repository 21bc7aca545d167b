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

The forces (:mod:`deformable.physics.forces`):

- applied, independent of the state: body densities (gravity ``mu g``),
  edge tractions, point loads;
- springs (the paper's "coils", section 5) and edge moments
  (:mod:`deformable.physics.moments`): conservative, with an energy, its
  gradient and Hessian; the implicit schemes and the equilibrium treat them as
  part of the potential (:meth:`Loads.potential_energy` and its derivatives;
  ``factor`` scales the moments with ``equilibrium``'s load steps);
- wind: ``c ((w - v) . n) |(w - v) . n| n`` per unit current area, depending
  on positions (n, area) and velocities (v); its Jacobian in v, the damping
  ``D = integral 2 c |u . n| |r_1 x r_2| n n^T phi_k phi_l``, lets the implicit
  schemes take the wind's velocity dependence implicitly (a damping).

Blocked matrices (the springs' Hessian, the wind's damping) follow the
contract's coordinate-blocked index ``a * ndof + k`` and keep one sparsity
pattern for a run (:class:`deformable.algebra.patterns.FixedPattern`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..algebra.patterns import BlockPattern, FixedPattern
from ..geometry.tensors import frame
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
        ``at_points``, ``density_matrix``, ``point_dofs``, ``edge_load``).

    Attributes
    ----------
    springs, moments, winds : tuples of the scene's Spring, EdgeMoment and Wind forces
    potentials : bool
        Springs or moments: a potential that depends on the state.
    conservative : bool
        No wind: the external force is the gradient of a potential.
    linear : bool
        Conservative with linear springs only (rest length 0) and no moment: the
        Hessian of the potential does not depend on the state.
    """

    def __init__(self, model):
        self.model, self.n = model, model.ndof
        forces = model.scene.forces
        self.springs = tuple(f for f in forces if f.kind == "spring")
        self.moments = tuple(f for f in forces if f.kind == "moment")
        self.pressures = tuple(f for f in forces if f.kind == "pressure")
        self.winds = tuple(f for f in forces if f.kind == "surface")
        self.potentials = bool(self.springs or self.moments or self.pressures)
        self.conservative = not self.winds
        self.linear = self.conservative and not self.moments and not self.pressures and all(s.rest_length == 0 for s in self.springs)
        self._rules = {}
        self._moments = EdgeMoments(model, self.moments) if self.moments else None
        self._pressure = PressurePotential(model, self.pressures) if self.pressures else None
        #: the state-dependent loads that scale with the load factor (moments, pressures)
        self._factored = [p for p in (self._moments, self._pressure) if p is not None]
        self._points = [(f, *model.point_dofs(f.at, "PointLoad.at")) for f in forces if f.kind == "point"]
        self._springs = [(s, *model.point_dofs(s.at, "Spring.at")) for s in self.springs]
        self._spring_pattern = self._spring_hessian_pattern() if self.springs else None
        self._wind_pattern = None

    # -- applied loads ----------------------------------------------------------
    def applied(self, t: float) -> np.ndarray:
        """Body, edge and point loads at time t, (ndof, 3) (N)."""
        m = self.model
        F = np.zeros((self.n, 3))
        for force in m.scene.forces:
            if force.kind == "body":
                F += m.integrate(force.density(*m.points, t, m.mu))
            elif force.kind == "edge":
                rule = self.edge_rule(force.edge)
                F += rule.at.T @ (rule.weights[:, None] * force.traction(rule.a1, rule.a2, t))
        for force, dofs, w in self._points:
            F[dofs] += w[:, None] * force.force(t)[None]
        return F

    def edge_rule(self, name: str):
        """The model's :class:`~deformable.backends.contract.EdgeRule` of an edge (built once)."""
        if name not in self._rules:
            self._rules[name] = self.model.edge_rule(name)
        return self._rules[name]

    def total(self, X: np.ndarray, t: float, V: np.ndarray | None = None) -> np.ndarray:
        """F of eq. (21): applied loads, springs and moments at X and wind at (X, V) (V None: at rest), (ndof, 3)
        (N)."""
        F = self.applied(t)
        if self.potentials:
            F -= self.potential_gradient(X, t)
        if self.winds:
            F += self.wind_force(X, V, t)
        return F

    # -- the potential of springs and moments -------------------------------------
    def potential_energy(self, X: np.ndarray, t: float, factor: float = 1.0) -> float:
        """The springs' energy and the moments' and pressures' potentials (J); ``factor`` scales the latter."""
        e = self.spring_energy(X, t) if self.springs else 0.0
        return e + sum(p.energy(X, t, factor) for p in self._factored)

    def potential_gradient(self, X: np.ndarray, t: float, factor: float = 1.0) -> np.ndarray:
        """The gradient of :meth:`potential_energy`, (ndof, 3) (N): minus the springs' and moments' force."""
        G = self.spring_gradient(X, t) if self.springs else np.zeros((self.n, 3))
        return G + sum(p.gradient(X, t, factor) for p in self._factored)

    def factored_gradient(self, X: np.ndarray, t: float) -> np.ndarray:
        """The gradient of the part of :meth:`potential_energy` that ``factor`` scales (moments, pressures) at factor 1,
        (ndof, 3) (N): minus the derivative of the load in the load factor, beside the applied loads."""
        return sum((p.gradient(X, t, 1.0) for p in self._factored), np.zeros((self.n, 3)))

    def potential_hessians(self, X: np.ndarray, t: float, factor: float = 1.0) -> list:
        """The Hessians of :meth:`potential_energy`, each (3 ndof, 3 ndof) blocked on its fixed pattern."""
        out = [self.spring_hessian(X, t)] if self.springs else []
        return out + [p.hessian(X, t, factor) for p in self._factored]

    # -- springs -----------------------------------------------------------------
    def _ends(self, X):
        return [(s, dofs, w, w @ X[dofs]) for s, dofs, w in self._springs]

    def spring_energy(self, X: np.ndarray, t: float) -> float:
        """Sum of k (|r(a) - anchor| - L0)^2 / 2 over the springs (J)."""
        return float(sum(s.energy(r, t) for s, _, _, r in self._ends(X)))

    def spring_gradient(self, X: np.ndarray, t: float) -> np.ndarray:
        """Gradient of :meth:`spring_energy` (N), (ndof, 3): minus the springs' force."""
        G = np.zeros((self.n, 3))
        for s, dofs, w, r in self._ends(X):
            G[dofs] -= w[:, None] * s.force(r, t)[None]
        return G

    def _spring_hessian_pattern(self) -> FixedPattern:
        rows, cols = [], []
        n = self.n
        for _, dofs, _ in self._springs:
            k = dofs.size
            for a in range(3):
                for b in range(3):
                    rows.append(np.repeat(a * n + dofs, k))
                    cols.append(np.tile(b * n + dofs, k))
        return FixedPattern(np.concatenate(rows), np.concatenate(cols), (3 * n, 3 * n))

    def spring_hessian(self, X: np.ndarray, t: float) -> sp.csr_matrix | None:
        """Hessian of :meth:`spring_energy`, (3 ndof, 3 ndof) blocked, fixed pattern (definite part); None without springs."""
        if not self.springs:
            return None
        values = []
        for s, dofs, w, r in self._ends(X):
            H = s.hessian(r, t)
            ww = np.outer(w, w).ravel()
            values += [H[a, b] * ww for a in range(3) for b in range(3)]
        return self._spring_pattern.matrix(self._spring_pattern.data(np.concatenate(values)))

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
        """-d(wind force)/dV, (3 ndof, 3 ndof) blocked, symmetric positive semi-definite, fixed pattern; None without wind."""
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
