r"""The finite-difference discretisation of the paper's section 2.3 (TPBF87 appendix).

On the M x N node grid (:mod:`fdmodel.operators`):

- metric, eq. (18):      ``G_ij[m,n] = D_i+ r . D_j+ r``
- curvature, eq. (19):   ``B_ij[m,n] = n[m,n] . D_ij r`` with D_ij = D11, D12+, D22
- eq. (15) at the nodes: ``alpha_ij = eta_ij (G_ij - G0_ij)``, ``beta_ij = xi_ij (B_ij - B0_ij)``
- force, eq. (16)-(17):  ``e = sum_ij -D_i-(alpha_ij D_j+ r) + D_ij(beta_ij D_ij r)``
- strength matrix, eq. (20): ``E = K(r) R`` with
  ``K = sum_ij D_i+^T diag(alpha_ij) D_j+ + D_ij^T diag(beta_ij) D_ij`` (symmetric).

The normal at a node is ``(D1 r x D2 r)/|.|`` with forward differences, backward
where a forward difference would leave the grid (docs/design.md).

Rows are integrated (the backend contract, :mod:`deformable.backends`): each
row of the paper's pointwise equations stands for a cell area h1 h2, so
M = h1 h2 diag(mu), C = h1 h2 diag(gamma), F = h1 h2 f at the node and
K = h1 h2 K_paper. Mass, damping and loads are pointwise as in the paper
(``weighting="pointwise"``, the default for tpbf87 and frozen). With
``weighting="control-area"`` (the default for a force model with an energy
density, the variational one among them, for which the paper defines no FD) the
mass, damping and body loads of edge nodes are weighted by 1/2 and of corners
by 1/4 together, and so is every difference row of K by the share of its
centre's control area that lies in the sheet (rows of D1+ and D11 on the edges
a2 = 0, L2 by 1/2, rows of D2+ and D22 on a1 = 0, L1 by 1/2; cell-centred rows
D12+ and the shear terms keep weight 1). That is the trapezoidal rule for the
energy (13) and turns the natural-boundary rows into a consistent
control-volume scheme: second order at free edges. Weighting only M, C and F
is consistent in 1-D but not in 2-D, where the fluxes along an edge row would
keep their full weight against a halved load.

Clamps. A clamp holds the edge row and eliminates a ghost row outside it by
the clamp's slope (:mod:`fdmodel.clamp`): second order. Under an energy
density the slots carry the ghost's affine part; under tpbf87 and frozen K(r)
is built on the ghost's operators and the affine part is a force f
(:meth:`FDModel._clamp_force`): the frozen energy's gradient is K R + f and
:meth:`FDModel.load` carries -f, so the semi-implicit K(r_t) r = F holds it.

G and B. For tpbf87 and frozen, :meth:`FDModel.tensors` gives the paper's
eq. (18)-(19) at the nodes (what alpha, beta and K use). For an energy density
it gives those of eq. (13) (:mod:`fdmodel.energy`: each term at the
point where its stencil is centred, B11 and B22 the mean of the halves with
the normals of forward and of backward tangents), carried to the nodes: second
order at every node, where eq. (18)-(19) are first order (G11 = D1+ r . D1+ r
stands at (m + 1/2, n); the normal of forward tangents is O(h)).

The strength matrix is :mod:`fdmodel.strength` (fixed-pattern assembly), the
energy (13) with its derivatives :mod:`fdmodel.energy`.
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp

from deformable.backends.base import BackendBase
from deformable.backends.contract import EdgeRule, Patches, Sample
from deformable.geometry.sheet import CELL_CORNERS, bilinear, bilinear_weights
from deformable.geometry.surfaces import as_surface
from deformable.physics.force_models import EnergyModel, QuadraticEnergy
from deformable.physics.integrand import FD_SLOTS, FE_SLOTS, DensityIntegrand, Integrand
from deformable.physics.material import TENSORS
from deformable.scene.constraints import Clamp
from deformable.scene.scene import Scene

from .clamp import GhostRows
from .energy import DiscreteEnergy, SlotMap
from .operators import cell_tangents, centred_tensor, node_tensors, operators, tangents, valid_rows
from .strength import StrengthMatrix

__all__ = ["MEMBRANE_EIGENVALUE", "WEIGHTINGS", "FDModel"]

log = logging.getLogger(__name__)
WEIGHTINGS = ("pointwise", "control-area")
#: largest eigenvalue of D1+^T D1+ against the identity, times h^2: the stiffest membrane mode (4/h^2)
MEMBRANE_EIGENVALUE = 4.0
#: contact points per cell side by default (deformable.contact): the nodes
CONTACT_SAMPLES = 1


def _to_nodes(n: int) -> np.ndarray:
    """(n, n - 1): values at the n - 1 midpoints of a row of n nodes to the nodes (mean inside, linear
    extrapolation at the two ends; second order)."""
    P = np.zeros((n, n - 1))
    k = np.arange(1, n - 1)
    P[k, k - 1] = P[k, k] = 0.5
    P[0, :2] = P[-1, -2:][::-1] = (1.5, -0.5)
    return P


def _extend(n: int) -> np.ndarray:
    """(n, n - 2): values at the n - 2 inner nodes of a row to all n (linear extrapolation at the ends)."""
    E = np.zeros((n, n - 2))
    E[1:-1] = np.eye(n - 2)
    if n > 3:
        E[0, :2] = E[-1, -2:][::-1] = (2.0, -1.0)
    else:
        E[0, 0] = E[-1, 0] = 1.0
    return E


class FDModel(BackendBase):
    """Finite-difference backend (paper section 2.3); satisfies :class:`deformable.Backend`.

    Over :class:`~deformable.backends.BackendBase`: rows integrated over each node's cell h1 h2, M = h1 h2
    diag(mu) and C = h1 h2 diag(gamma) (times the control-area weights when chosen); loads by the hooks below
    (body forces at the nodes, edge tractions by the trapezoidal rule, point loads and springs spread bilinearly
    over the corners of their cell, wind with the normal of eq. (19)), less the clamp's ghost-row force under
    K(r) (:meth:`_affine_force`); the energy (13) summed over the nodes where each difference of eq. (17) is
    defined (times the row weights).

    Parameters
    ----------
    scene : deformable.Scene
    weighting : "pointwise" | "control-area" | None
        Weighting of mass, damping, body loads and difference rows at edge nodes (module docstring).
        None (the default): "control-area" for a force model with an energy density (the trapezoidal rule
        for its energy; the paper defines no FD for it), the paper's "pointwise" for tpbf87 and frozen.

    State arrays X are (M N, 3), node (m, n) at row m N + n.
    """

    def __init__(self, scene: Scene, weighting: str | None = None):
        super().__init__(scene)
        fm = self.force_model
        #: the force is the gradient of an energy density (eq. (13) or another): ghost-row clamps, bending halves
        self.density = isinstance(fm, EnergyModel)
        if weighting is None:
            weighting = "control-area" if self.density else "pointwise"
        if weighting not in WEIGHTINGS:
            raise ValueError(f"weighting must be one of {WEIGHTINGS}, got {weighting!r}")
        self.weighting = weighting
        sheet, mat, M, N = scene.sheet, scene.material, self.M, self.N
        self.ndof = M * N
        self.value_dofs = np.arange(self.ndof)
        self.a1, self.a2 = sheet.coordinates()
        self.points = (self.a1, self.a2)
        area = self.h1 * self.h2

        self.ops = operators(M, N, self.h1, self.h2)
        self._tangents = tangents(M, N, self.h1, self.h2)
        self.valid = valid_rows(M, N)
        # the reflection clamp (ghost rows), for every force model: under K(r) its affine part is a force (_clamp_force)
        clamped = [e for c in scene.constraints if isinstance(c, Clamp) for e in c.edges]
        self.ghost = GhostRows(sheet, clamped)
        # node control-area weights: 1 inside, 1/2 on edges, 1/4 at corners
        w1, w2 = np.ones(M), np.ones(N)
        if weighting == "control-area":
            w1[[0, -1]] = w2[[0, -1]] = 0.5
        self.area_weight = np.outer(w1, w2)
        # quadrature weight of each difference row (zero where the row is undefined); a ghost row's second
        # difference stands for half a cell across its edge
        across = {"D1": w2[None, :], "D2": w1[:, None], "D11": w2[None, :], "D22": w1[:, None], "D12": 1.0}
        self.row_weight = {k: self.valid[k] * across[k] for k in self.valid}
        for k, rows in self.ghost.rows.items():
            self.row_weight[k] = np.where(rows, 0.5 * across[k], self.row_weight[k])
        self.mu, self.gamma = (mat.field_at(name, (M, N), (self.a1, self.a2), lambda f: f) for name in ("mu", "gamma"))
        self._M = sp.diags((area * self.mu * self.area_weight).ravel(), format="csr")
        self._C = sp.diags((area * self.gamma * self.area_weight).ravel(), format="csr")

        #: the Material's tensor fields where the difference terms they weigh are centred, (2, 2, M, N) each
        #: (:func:`fdmodel.operators.centred_tensor`: second order under weights that vary)
        self.fields = {name: centred_tensor(mat, name, sheet) for name in TENSORS}
        self.eta, self.xi = self.fields["eta"], self.fields["xi"]
        # without bending weights K is the 5-point membrane stencil: keep its pattern that small
        self._ghost_ops = self.ghost.operators(self.ops, self._tangents)[0]
        self.strength = StrengthMatrix(self._ghost_ops, self.row_weight, area,
                                       bending=bool(np.any(self.fields[fm.weights[1]] != 0)))
        #: the clamp's tangents in the ghost rows' affine part (D11, D22 slots), (2, M N, 3); None without a clamp
        self._ghost_offset = self.ghost.offset(sheet.initial, ("D11", "D22", "T1", "T2"))[:2] if self.ghost else None
        # rest state: discrete G0, B0 of the rest shape, or the scene's overrides
        self.G0, self.B0 = scene.rest_tensors(self.a1, self.a2,
                                              *node_tensors(self.discretize(sheet.rest).reshape(M, N, 3), *sheet.h))
        if self.linear:
            self._fix_coefficients()
            f = self._clamp_force(self.beta_fixed)
            c = 0.0 if f is None else self.ghost.constant(self.row_weight, area, self.beta_fixed, self._ghost_offset)
            self._energy = QuadraticEnergy(self._K_const, *self.strength.parts(self.alpha_fixed, self.beta_fixed),
                                           linear=f, constant=c)
        else:
            self._energy = self._discrete_energy(area)
        self._complete(node_dofs=np.flatnonzero, edge_dofs=lambda edge: np.array([], int),
                       clamp_dofs=lambda edge: np.flatnonzero(sheet.edge_nodes(edge)))

    def _discrete_energy(self, area: float) -> DiscreteEnergy:
        """The energy as node and cell parts (:mod:`fdmodel.energy`), rest tensors from the rest shape's own slots:
        eq. (13) by the compiled integrand (tpbf87's energy, and the variational model's), any other energy
        density by :class:`~deformable.physics.integrand.DensityIntegrand` (:meth:`_density_parts`).

        Keeps the slot maps (``_node_slots``, ``_cell_slots`` and, for an energy density, ``_backward_slots``, the
        bending half with the normal of backward tangents) for :meth:`tensors`.
        """
        M, N, sheet, rw = self.M, self.N, self.scene.sheet, self.row_weight
        zero = np.zeros((M, N))
        # the normal of B11, B22: eq. (19)'s forward tangents (the variational model adds a backward half below);
        # central ones were measured and dropped (docs/design.md)
        ops, T = self.ghost.operators(self.ops, self._tangents)
        names = ("D1", "D2", "T1", "T2", "D11", "D12", "D22")
        rows = [ops["D1"], ops["D2"], T[0], T[1], ops["D11"], ops["D12"], ops["D22"]]

        def offset(surface, slot_names):  # the clamp's affine part of the slots, None without a clamp
            return self.ghost.offset(surface, slot_names) if self.ghost else None

        self._node_slots = SlotMap(rows, (M, N), FD_SLOTS, offset(sheet.initial, names))
        A1, A2 = cell_tangents(M, N, self.h1, self.h2)
        Z = sp.csr_matrix((M * N, M * N))
        # the points past the last row are no cells: unit tangents there keep their (unused) normal defined
        beyond = np.zeros((5, M * N, 3))
        outside = ~self.valid["D12"].ravel()
        beyond[0, outside, 0] = beyond[1, outside, 1] = 1.0
        self._cell_slots = SlotMap([A1, A2, Z, ops["D12"], Z], (M, N), FE_SLOTS, beyond)
        shear = np.array([[zero, rw["D12"]], [rw["D12"], zero]])
        bend = np.array([[rw["D11"], zero], [zero, rw["D22"]]])
        # an energy density splits B11, B22 into halves with the normals of forward and of backward tangents,
        # whose O(h) errors are opposite: their squares sum to a second-order density (fdmodel.energy)
        self._backward_slots = None
        generic = self.density and not self.force_model.compiled
        if self.density:
            bops, Tb = self.ghost.operators(self.ops, tangents(M, N, self.h1, self.h2, backward=True))
            bnames = ("T1", "T2", "D11", "D12", "D22")
            v12 = bops["D12"] if generic else Z  # B12 in the backward half: for densities that couple it with B11, B22
            self._backward_slots = SlotMap([Tb[0], Tb[1], bops["D11"], v12, bops["D22"]], (M, N), FE_SLOTS,
                                           offset(sheet.initial, bnames))
            bend = 0.5 * bend
        X_rest = self.discretize(sheet.rest)
        if generic:
            return DiscreteEnergy(self._density_parts(area, X_rest, offset(sheet.rest, names),
                                                      offset(sheet.rest, bnames)))
        parts = [(self._node_slots, offset(sheet.rest, names), np.array([[rw["D1"], zero], [zero, rw["D2"]]]), bend)]
        if self._backward_slots is not None:
            parts.append((self._backward_slots, offset(sheet.rest, bnames), np.zeros((2, 2, M, N)), bend))
        if np.any(self.eta[0, 1] + self.eta[1, 0] != 0) or np.any(self.xi[0, 1] + self.xi[1, 0] != 0):
            parts.append((self._cell_slots, None, shear, shear))
        out = []
        for slots, rest_offset, eta_rows, xi_rows in parts:
            G0, B0 = self.scene.rest_tensors(self.a1, self.a2, *slots.tensors(X_rest, rest_offset))
            out.append((slots, Integrand(area * eta_rows * self.eta, area * xi_rows * self.xi, G0, B0, slots.layout)))
        return DiscreteEnergy(out)

    def _density_parts(self, area: float, X_rest, node_offset, backward_offset) -> list:
        """The parts of a general energy density: each residual where its term of eq. (13) stands, the residuals
        the density couples at one point (:mod:`fdmodel.energy`, "A general energy density")."""
        M, N, rw, fm = self.M, self.N, self.row_weight, self.force_model
        zero = np.zeros((M, N))
        # per residual (s11, s22, s12, b11, b22, b12), the weight of each part: eq. (13)'s places
        q = {"node": [rw["D1"], rw["D2"], zero, 0.5 * rw["D11"], 0.5 * rw["D22"], zero],
             "backward": [zero, zero, zero, 0.5 * rw["D11"], 0.5 * rw["D22"], zero],
             "cell": [zero, zero, rw["D12"], zero, zero, rw["D12"]]}
        for group in fm.groups():
            if len(group) == 1:
                continue
            if max(group) < 3:  # the metric alone: at the cell centres, from the cells' mean tangents
                places = {"cell": rw["D12"]}
            elif min(group) >= 3:  # the curvature alone: at the nodes, in the two halves
                places = {"node": 0.5 * self.area_weight, "backward": 0.5 * self.area_weight}
            else:  # metric and curvature together: at the nodes, eq. (18)-(19)
                places = {"node": self.area_weight}
            for k in group:
                for part in q:
                    q[part][k] = places.get(part, zero)
        slots = {"node": (self._node_slots, node_offset), "backward": (self._backward_slots, backward_offset),
                 "cell": (self._cell_slots, None)}
        # the weights where each part's terms stand: a node part's at their own centres, a cell part's at the cell
        cell = {name: centred_tensor(self.scene.material, name, self.scene.sheet, at="cell") for name in fm.fields}
        node = {name: self.fields[name] for name in fm.fields}
        # a density that reads the rest metric (EnergyModel.rest) gets a whole one at each point: the cells'
        # own; at the nodes, the centred one carried to the node (each component of a node part stands at its
        # own centre, a component the part does not carry is not there): exact for a uniform rest metric, first
        # order where it varies
        node_metric = None
        if fm.rest:
            node_metric = self.scene.rest_tensors(self.a1, self.a2, *self._centred_tensors(X_rest))[0]
        out = []
        for part, weights in q.items():
            if not any(np.any(w) for w in weights):
                continue
            smap, rest_offset = slots[part]
            G0, B0 = self.scene.rest_tensors(self.a1, self.a2, *smap.tensors(X_rest, rest_offset))
            params = cell if part == "cell" else node
            own = dict(params, G0=G0 if part == "cell" else node_metric) if fm.rest else params
            out.append((smap, DensityIntegrand(fm, own, area * np.stack(weights), G0, B0, smap.layout)))
        return out

    def _centred_tensors(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """G and B of the variational energy, each at its centre, carried to the nodes (second order).

        G11 (D1+ r . D1+ r) stands at the edge midpoints (m + 1/2, n), G22 at (m, n + 1/2), G12 and B12 at
        the cell centres, B11 and B22 at the interior nodes (the mean of the two halves, with the normals of
        forward and of backward tangents): the mean of the two (four) neighbouring centres at a node, linear
        extrapolation from the nearest two onto the edges.
        """
        Gn, Bn = self._node_slots.tensors(X)
        Gc, Bc = self._cell_slots.tensors(X)
        Bn = 0.5 * (Bn + self._backward_slots.tensors(X)[1])  # B11, B22 of forward and backward normals
        P1, P2 = _to_nodes(self.M), _to_nodes(self.N)
        E1, E2 = _extend(self.M), _extend(self.N)
        G12 = P1 @ Gc[0, 1, :-1, :-1] @ P2.T
        B12 = P1 @ Bc[0, 1, :-1, :-1] @ P2.T
        G = np.array([[P1 @ Gn[0, 0, :-1], G12], [G12, Gn[1, 1, :, :-1] @ P2.T]])
        B = np.array([[E1 @ Bn[0, 0, 1:-1, 1:-1] @ E2.T, B12], [B12, E1 @ Bn[1, 1, 1:-1, 1:-1] @ E2.T]])
        return G, B

    # -- geometry -----------------------------------------------------------
    def grid(self, X: np.ndarray) -> np.ndarray:
        """Node positions, (M, N, 3)."""
        return np.asarray(X).reshape(self.M, self.N, 3)

    def discretize(self, surface) -> np.ndarray:
        """Node values of a surface (or callable (a1, a2) -> (..., 3)): X (M N, 3)."""
        return as_surface(surface).r(self.a1, self.a2).reshape(self.ndof, 3)

    def tensors(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """G and B at every node, two (2, 2, M, N) arrays.

        The paper's eq. (18) and (19) at the nodes for tpbf87 and frozen (forward differences: G11, G22
        second order at the stencil centres, first order at the nodes); for the variational model those of
        its energy, carried from their centres to the nodes (:meth:`_centred_tensors`, second order).
        """
        if self.density:
            return self._centred_tensors(X)
        return node_tensors(self.grid(X), self.h1, self.h2)

    def _strain_tensors(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """G and B of eq. (18)-(19) at the nodes, where alpha and beta of eq. (15) are formed (the hook of
        :meth:`alpha_beta`), two (2, 2, M, N) arrays."""
        return node_tensors(self.grid(X), self.h1, self.h2)

    def sample(self, X: np.ndarray, a: np.ndarray) -> Sample:
        """r, G, B at parameter points a (P, 2): exact at nodes, bilinear between them."""
        i, j, s, t = self.scene.sheet.locate(a, "sample points")
        G, B = self.tensors(X)
        fields = np.concatenate([np.moveaxis(self.grid(X), -1, 0), G.reshape(4, self.M, self.N),
                                 B.reshape(4, self.M, self.N)])  # (11, M, N)
        v = bilinear(fields, i, j, s, t).T
        return Sample(r=v[:, :3], G=v[:, 3:7].reshape(-1, 2, 2), B=v[:, 7:].reshape(-1, 2, 2))

    # -- the semi-discrete system (21) --------------------------------------
    def _clamp_force(self, beta) -> np.ndarray | None:
        """The ghost rows' affine force under K(r) (:meth:`GhostRows.force`), (M N, 3) (N); None without a clamp
        or under an energy density (whose slots carry the offset themselves)."""
        if self.density or self._ghost_offset is None:
            return None
        return self.ghost.force(self._ghost_ops, self.row_weight, self.h1 * self.h2, beta, self._ghost_offset)

    def _affine_force(self, X: np.ndarray) -> np.ndarray | None:
        """Under K(r) (tpbf87, frozen) and a clamp, the ghost rows' affine force with beta at X (:meth:`_clamp_force`),
        which :meth:`load` subtracts; None otherwise."""
        if self._ghost_offset is None or self.density:
            return None
        return self._clamp_force(self.alpha_beta(X)[1])

    # -- the hooks of deformable.physics.loads ---------------------------------------
    def integrate(self, density: np.ndarray) -> np.ndarray:
        """A density (N/m^2) at the nodes, (M, N, 3), times each node's area: (M N, 3) (N)."""
        w = self.h1 * self.h2 * self.area_weight
        return (w[..., None] * np.asarray(density).reshape(self.M, self.N, 3)).reshape(self.ndof, 3)

    def at_points(self, X: np.ndarray, d: tuple[int, int] = (0, 0)) -> np.ndarray:
        """X (d = (0, 0)) or its tangent difference r_1 (1, 0), r_2 (0, 1) of the normal at every node, (M N, 3)."""
        if d == (0, 0):
            return np.asarray(X, float)
        return self._tangents[d.index(1)] @ X

    def density_matrix(self, c: np.ndarray) -> sp.csr_matrix:
        """diag(h1 h2 c) (times the control-area weights), (M N, M N), for a field c (M, N) at the nodes."""
        data = (self.h1 * self.h2 * self.area_weight * np.asarray(c).reshape(self.M, self.N)).ravel()
        return sp.csr_matrix((data, np.arange(self.ndof), np.arange(self.ndof + 1)), shape=(self.ndof, self.ndof))

    def _point_weights(self, a, what: str) -> tuple[np.ndarray, np.ndarray]:
        """The four nodes of the cell holding each parameter point a (P, 2) and their bilinear weights, (P, 4) each."""
        i, j, s, u = self.scene.sheet.locate(a, what)
        dofs = np.stack([(i + di) * self.N + j + dj for di, dj in CELL_CORNERS], axis=1)
        return dofs, np.stack(bilinear_weights(s, u), axis=1)

    def patches(self) -> Patches:
        """The cells, each reading its four corners at its centre: r their mean, r_1 and r_2 the mean of its two
        differences along a1 and a2 (the midpoint rule of the bilinear cell; summation by parts then holds on
        every row, which node-centred forward differences with backward ones on the last row break)."""
        M, N = self.M, self.N
        k = np.arange(self.ndof).reshape(M, N)[:-1, :-1].ravel()
        cols = np.stack([k, k + N, k + N + 1, k + 1], axis=1)  # corners (0, 0), (1, 0), (1, 1), (0, 1)
        c1, c2 = np.array([-1.0, 1.0, 1.0, -1.0]) / (2 * self.h1), np.array([-1.0, -1.0, 1.0, 1.0]) / (2 * self.h2)
        values = np.broadcast_to(np.stack([np.full(4, 0.25), c1, c2])[:, None, None, :], (3, k.size, 1, 4))
        return Patches(cols, values, np.full((k.size, 1), self.h1 * self.h2))

    def edge_rule(self, name: str) -> EdgeRule:
        """The edge's nodes with their shares of its length (the trapezoidal rule: half at its ends); r_across the
        difference of the edge row and the next one in, along a_i: the tangent of the last segment, which FD's
        bending energy is conjugate to (its B11 = n . D11 r is the difference of two segments' angles over h, so an
        edge moment on the last segment gives every segment the same curvature, as the continuum does; the
        one-sided second-order tangent (3 r[0] - 4 r[1] + r[2]) / 2h, tried first, spreads the moment over three
        rows and Newton stalled past a half turn of a rolled strip)."""
        sheet = self.scene.sheet
        edge = sheet.edge(name)
        nodes = np.arange(self.ndof).reshape(self.M, self.N)
        share = np.full(sheet.nodes[edge.along], self.spacing[edge.along])
        share[[0, -1]] *= 0.5
        rows = [nodes.take(k if edge.side == 0 else -1 - k, axis=edge.axis) for k in range(2)]  # the edge, then in
        P = rows[0].size
        sign = 1.0 if edge.side == 0 else -1.0  # forward into the sheet from a1 = 0, backward from a1 = L1
        c = sign * np.array([-1.0, 1.0]) / self.spacing[edge.axis]
        at = sp.csr_matrix((np.ones(P), (np.arange(P), rows[0])), shape=(P, self.ndof))
        across = sp.csr_matrix((np.repeat(c[None], P, 0).ravel(), (np.repeat(np.arange(P), 2),
                                np.stack(rows, 1).ravel())), shape=(P, self.ndof))
        return EdgeRule(self.a1[edge.index], self.a2[edge.index], share, at, across)
