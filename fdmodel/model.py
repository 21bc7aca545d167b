r"""The finite-difference discretisation of the paper's section 2.3 (TPBF87 appendix).

On the M x N node grid (:mod:`fdmodel.operators`):

- metric, eq. (18):      ``G_ij[m,n] = D_i+ r . D_j+ r``
- curvature, eq. (19):   ``B_ij[m,n] = n[m,n] . D_ij r`` with D_ij = D11, D12+, D22
- eq. (15) at the nodes: ``alpha_ij = eta_ij (G_ij - G0_ij)``, ``beta_ij = xi_ij (B_ij - B0_ij)``
- force, eq. (16)-(17):  ``e = sum_ij -D_i-(alpha_ij D_j+ r) + D_ij(beta_ij D_ij r)``
- strength matrix, eq. (20): ``E = K(r) R`` with
  ``K = sum_ij D_i+^T diag(alpha_ij) D_j+ + D_ij^T diag(beta_ij) D_ij`` (symmetric).

The normal at a node is ``(D1 r x D2 r)/|.|`` with forward differences, backward
where a forward difference would leave the grid (DESIGN.md).

Mass, damping and loads are pointwise as in the paper (M = diag(mu),
C = diag(gamma), F = f at the node). With ``weighting="control-area"`` the
mass, damping and body loads of edge nodes are weighted by 1/2 and of corners
by 1/4 together, and so is every difference row of K by the share of its
centre's control area that lies in the sheet (rows of D1+ and D11 on the edges
a2 = 0, L2 by 1/2, rows of D2+ and D22 on a1 = 0, L1 by 1/2; cell-centred rows
D12+ and the shear terms keep weight 1). That is the trapezoidal rule for the
energy (13) and turns the natural-boundary rows into a consistent
control-volume scheme: second order at free edges. Weighting only M, C and F
(DESIGN.md's wording) is consistent in 1-D but not in 2-D, where the fluxes
along an edge row would keep their full weight against a halved load.

Assembly: K's data array is linear in the 7 node fields (alpha_11, alpha_12,
alpha_21, alpha_22, beta_11, beta_12 + beta_21, beta_22), so a sparse matrix P
that maps them to K.data is built once; each step is one sparse mat-vec
``K.data = P w`` on a fixed pattern. When the bending weights (xi, or beta for
the frozen model) vanish everywhere, the pattern holds the membrane stencil
only, so the factorisation does not pay for explicit zeros of the bending one.
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp

from deformable import tensors
from deformable.backend import Energy, Sample
from deformable.constraints import Clamp, Pin, Slide, select
from deformable.scene import Scene
from deformable.sheet import as_surface

from .operators import node_derivatives, operators, valid_rows
from .variational import DiscreteEnergy

__all__ = ["FDModel", "WEIGHTINGS"]

log = logging.getLogger(__name__)
WEIGHTINGS = ("pointwise", "control-area")

# (outer, inner) operator pairs of K in the order of the weight fields
_TERMS = (("D1", "D1"), ("D1", "D2"), ("D2", "D1"), ("D2", "D2"), ("D11", "D11"), ("D12", "D12"), ("D22", "D22"))
_STRETCH_TERMS = 4


def _pair_products(Da: sp.csr_matrix, Db: sp.csr_matrix):
    """COO triples of Da^T diag(w) Db: entry (p, q) gets coef * w[k].

    Returns rows p, cols q, coefficients and the weight index k of every product.
    """
    na = np.diff(Da.indptr)
    nb = np.diff(Db.indptr)
    ka = np.repeat(np.arange(Da.shape[0]), na)  # row of every Da entry
    counts = nb[ka]
    rep = np.repeat(np.arange(Da.nnz), counts)
    offsets = np.arange(rep.size) - np.repeat(np.cumsum(counts) - counts, counts)
    jb = Db.indptr[ka[rep]] + offsets
    return Da.indices[rep], Db.indices[jb], Da.data[rep] * Db.data[jb], ka[rep]


class FDModel:
    """Finite-difference backend (paper section 2.3); satisfies :class:`deformable.Backend`.

    Parameters
    ----------
    scene : deformable.Scene
    weighting : "pointwise" | "control-area"
        Weighting of mass, damping and body loads at edge nodes (module docstring).

    State arrays X are (M N, 3), node (m, n) at row m N + n.
    """

    #: the tpbf87 step is stable on stretching for dt below about step_factor h sqrt(mu / (2 eta G))
    step_factor = 1.0

    def __init__(self, scene: Scene, weighting: str = "pointwise"):
        if weighting not in WEIGHTINGS:
            raise ValueError(f"weighting must be one of {WEIGHTINGS}, got {weighting!r}")
        self.scene, self.weighting = scene, weighting
        sheet, mat = scene.sheet, scene.material
        self.M, self.N = M, N = sheet.nodes
        self.h1, self.h2 = sheet.h
        self.ndof = M * N
        self.measure = self.h1 * self.h2  # each row of M, C, F stands for this area
        self.linear = scene.force_model == "frozen"
        self.a1, self.a2 = sheet.coordinates()

        self.ops = operators(M, N, self.h1, self.h2)
        self.valid = valid_rows(M, N)
        # without bending weights K is the 5-point membrane stencil: keep its pattern that small
        bend = mat.beta if scene.force_model == "frozen" else mat.xi
        self._bending = bend is not None and bool(np.any(np.asarray(bend) != 0))
        self._build_assembly()

        # node control-area weights: 1 inside, 1/2 on edges, 1/4 at corners
        w1, w2 = np.ones(M), np.ones(N)
        if weighting == "control-area":
            w1[[0, -1]] = w2[[0, -1]] = 0.5
        self.area_weight = np.outer(w1, w2)
        # quadrature weight of each difference row (zero where the row is undefined)
        across = {"D1": w2[None, :], "D2": w1[:, None], "D11": w2[None, :], "D22": w1[:, None], "D12": 1.0}
        self.row_weight = {k: self.valid[k] * across[k] for k in self.valid}
        self.mu = mat.field("mu", (M, N))
        self.gamma = mat.field("gamma", (M, N))

        # rest state: discrete G0, B0 of the rest shape, or the scene's overrides
        R0 = self.discretize(sheet.rest)
        self.G0, self.B0 = scene.rest_tensors(self.a1, self.a2, *self.tensors(R0))
        if scene.force_model == "frozen":
            self.alpha_fixed = mat.tensor("alpha", (M, N))
            self.beta_fixed = mat.tensor("beta", (M, N))
            self._K_const = self._assemble(self._weights(self.alpha_fixed, self.beta_fixed))
        else:
            self.eta = mat.tensor("eta", (M, N))
            self.xi = mat.tensor("xi", (M, N))
            self._energy = DiscreteEnergy(self)
        self._build_constraints()

    # -- assembly -----------------------------------------------------------
    def _build_assembly(self):
        n = self.ndof
        rows, cols, coefs, widx = [], [], [], []
        for t, (a, b) in enumerate(_TERMS):
            if t >= _STRETCH_TERMS and not self._bending:
                continue
            p, q, c, k = _pair_products(self.ops[a], self.ops[b])
            rows.append(p)
            cols.append(q)
            coefs.append(c)
            widx.append(k + t * n)
        rows, cols = np.concatenate(rows).astype(np.int64), np.concatenate(cols).astype(np.int64)
        coefs, widx = np.concatenate(coefs), np.concatenate(widx)
        keys = rows * n + cols
        ukeys, entry = np.unique(keys, return_inverse=True)
        self._indices = (ukeys % n).astype(np.int32)
        self._indptr = np.concatenate([[0], np.cumsum(np.bincount(ukeys // n, minlength=n))]).astype(np.int32)
        self._P = sp.csr_matrix((coefs, (entry, widx)), shape=(ukeys.size, len(_TERMS) * n))
        split = _STRETCH_TERMS * n
        self._P_stretch = self._P[:, :split].tocsr()
        self._P_bend = self._P[:, split:].tocsr()

    def _weights(self, alpha: np.ndarray, beta: np.ndarray) -> np.ndarray:
        """The 7 weight fields of K (times the row weights), flattened in the order of _TERMS."""
        rw = self.row_weight
        w = [alpha[0, 0] * rw["D1"], alpha[0, 1] * rw["D12"], alpha[1, 0] * rw["D12"], alpha[1, 1] * rw["D2"],
             beta[0, 0] * rw["D11"], (beta[0, 1] + beta[1, 0]) * rw["D12"], beta[1, 1] * rw["D22"]]
        return np.concatenate([x.ravel() for x in w])

    def _assemble(self, w: np.ndarray, P=None) -> sp.csr_matrix:
        P = self._P if P is None else P
        return sp.csr_matrix((P @ w, self._indices, self._indptr), shape=(self.ndof, self.ndof))

    # -- geometry -----------------------------------------------------------
    def grid(self, X: np.ndarray) -> np.ndarray:
        """Node positions, (M, N, 3)."""
        return np.asarray(X).reshape(self.M, self.N, 3)

    def discretize(self, surface) -> np.ndarray:
        """Node values of a surface (or callable (a1, a2) -> (..., 3)): X (M N, 3)."""
        return as_surface(surface).r(self.a1, self.a2).reshape(self.ndof, 3)

    def initial_state(self) -> np.ndarray:
        """The sheet's initial shape at the nodes, (M N, 3)."""
        return self.discretize(self.scene.sheet.initial)

    def tensors(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """G (eq. 18) and B (eq. 19) at every node, two (2, 2, M, N) arrays."""
        dr, ddr = node_derivatives(self.grid(X), self.h1, self.h2)
        return tensors.metric(dr), tensors.curvature(ddr, tensors.normal(dr))

    def alpha_beta(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """alpha_ij and beta_ij of eq. (15)/(18)-(19) at the nodes, two (2, 2, M, N) arrays."""
        if self.linear:
            return self.alpha_fixed, self.beta_fixed
        G, B = self.tensors(X)
        return self.eta * (G - self.G0), self.xi * (B - self.B0)

    def sample(self, X: np.ndarray, a: np.ndarray) -> Sample:
        """r, G, B at parameter points a (P, 2): exact at nodes, bilinear between them."""
        a = np.atleast_2d(np.asarray(a, float))
        L1, L2 = self.scene.sheet.size
        if a.shape[-1] != 2 or np.any(a < -1e-12) or np.any(a[:, 0] > L1 + 1e-12) or np.any(a[:, 1] > L2 + 1e-12):
            raise ValueError(f"sample points must be (P, 2) inside [0, {L1}] x [0, {L2}]")
        G, B = self.tensors(X)
        fields = np.concatenate(
            [self.grid(X), G.reshape(4, self.M, self.N).transpose(1, 2, 0), B.reshape(4, self.M, self.N).transpose(1, 2, 0)],
            axis=-1,
        )  # (M, N, 11)
        s, t = a[:, 0] / self.h1, a[:, 1] / self.h2
        i = np.clip(np.floor(s).astype(int), 0, self.M - 2)
        j = np.clip(np.floor(t).astype(int), 0, self.N - 2)
        s, t = (s - i)[:, None], (t - j)[:, None]
        v = (
            (1 - s) * (1 - t) * fields[i, j]
            + s * (1 - t) * fields[i + 1, j]
            + (1 - s) * t * fields[i, j + 1]
            + s * t * fields[i + 1, j + 1]
        )
        return Sample(r=v[:, :3], G=v[:, 3:7].reshape(-1, 2, 2), B=v[:, 7:].reshape(-1, 2, 2))

    # -- the semi-discrete system (21) --------------------------------------
    def stiffness(self, X: np.ndarray) -> sp.csr_matrix:
        """Strength matrix K(r) of eq. (20), (M N, M N), symmetric; fixed pattern.

        Defined for the tpbf87 and frozen force models; the variational model
        couples the coordinates and has :meth:`energy_hessian` instead.
        """
        if self.linear:
            return self._K_const
        if self.scene.force_model == "variational":
            raise ValueError("the variational force model has no strength matrix K(r) of eq. (20); "
                             "use energy_gradient / energy_hessian (TimeStepper scheme 'implicit-euler' or 'newmark')")
        return self._assemble(self._weights(*self.alpha_beta(X)))

    def energy_gradient(self, X: np.ndarray) -> np.ndarray:
        """Exact gradient of the discrete energy, (M N, 3) (N per unit displacement).

        Variational model: the gradient of eq. (13) (:mod:`fdmodel.variational`);
        frozen model: h1 h2 K R. The tpbf87 force (14) is not a gradient.
        """
        if self.linear:
            return self.measure * (self._K_const @ X)
        if self.scene.force_model != "variational":
            raise ValueError("force_model 'tpbf87' has no energy gradient: its force (14) is not the gradient "
                             "of eq. (13); use force_model 'variational'")
        return self._energy.gradient(X)

    def energy_hessian(self, X: np.ndarray, kind: str = "newton") -> sp.csr_matrix:
        """Hessian of the discrete energy (3 M N, 3 M N), coordinates in blocks (index a M N + k).

        ``kind`` "newton" (exact) or "gauss-newton" (positive semi-definite).
        """
        if self.linear:
            return sp.kron(sp.identity(3), self.measure * self._K_const, format="csr")
        if self.scene.force_model != "variational":
            raise ValueError("force_model 'tpbf87' has no energy Hessian; use force_model 'variational'")
        return self._energy.hessian(X, kind)

    def internal_force(self, X: np.ndarray) -> np.ndarray:
        """e of eq. (16) at the nodes: K(r) R, (M N, 3)."""
        return self.stiffness(X) @ X

    def mass(self) -> sp.csr_matrix:
        """M = diag(mu) (times the control-area weights when chosen)."""
        return sp.diags((self.mu * self.area_weight).ravel(), format="csr")

    def damping(self) -> sp.csr_matrix:
        """C = diag(gamma) (times the control-area weights when chosen)."""
        return sp.diags((self.gamma * self.area_weight).ravel(), format="csr")

    def load(self, X: np.ndarray, t: float) -> np.ndarray:
        """F of eq. (21) at time t, (M N, 3).

        Each load is its integral over the node's control volume divided by the
        cell area h1 h2: body forces f (times the control-area weight when
        chosen; pointwise as in the paper otherwise), edge tractions q h_t/(h1 h2)
        (half at the edge's end nodes), point loads P/(h1 h2) spread bilinearly.
        """
        M, N, h1, h2 = self.M, self.N, self.h1, self.h2
        F = np.zeros((M, N, 3))
        for force in self.scene.forces:
            if force.kind == "body":
                F += self.area_weight[..., None] * force.density(self.a1, self.a2, t, self.mu)
            elif force.kind == "edge":
                idx = {"left": (0, slice(None)), "right": (-1, slice(None)),
                       "bottom": (slice(None), 0), "top": (slice(None), -1)}[force.edge]
                along = h2 if force.edge in ("left", "right") else h1
                share = np.full(N if force.edge in ("left", "right") else M, along)
                share[[0, -1]] *= 0.5
                F[idx] += force.traction(self.a1[idx], self.a2[idx], t) * (share / (h1 * h2))[:, None]
            else:
                a1, a2 = force.at
                s = np.clip(a1 / h1, 0, M - 1)
                u = np.clip(a2 / h2, 0, N - 1)
                i, j = min(int(s), M - 2), min(int(u), N - 2)
                s, u = s - i, u - j
                P = force.force(t) / (h1 * h2)
                F[i, j] += (1 - s) * (1 - u) * P
                F[i + 1, j] += s * (1 - u) * P
                F[i, j + 1] += (1 - s) * u * P
                F[i + 1, j + 1] += s * u * P
        return F.reshape(self.ndof, 3)

    def energy(self, X: np.ndarray) -> Energy:
        """Elastic energy (J): eq. (13) for tpbf87, h1 h2 R^T K R / 2 for the frozen model.

        Eq. (13) is summed over the nodes where each difference of eq. (17) is
        defined, each node standing for an area h1 h2 (times the row weights
        of the control-area weighting).
        """
        if self.linear:
            ws = self._weights(self.alpha_fixed, self.beta_fixed)
            split = _STRETCH_TERMS * self.ndof
            Ks = self._assemble(ws[:split], self._P_stretch)
            Kb = self._assemble(ws[split:], self._P_bend)
            dA = self.h1 * self.h2
            return Energy(0.5 * dA * float(np.sum(X * (Ks @ X))), 0.5 * dA * float(np.sum(X * (Kb @ X))))
        return Energy(*self._energy.energy(X))

    def kinetic_energy(self, V: np.ndarray) -> float:
        """Kinetic energy h1 h2 V^T M V / 2 (J): the FD rows are per unit area."""
        nodal = (self.mu * self.area_weight).ravel()  # the diagonal of M
        return 0.5 * self.measure * float(np.sum(nodal[:, None] * V * V))

    # -- constraints ----------------------------------------------------------
    def _build_constraints(self):
        sheet = self.scene.sheet
        fixed = [np.zeros((self.M, self.N), bool) for _ in range(3)]
        self._motions = []
        for c in self.scene.constraints:
            if isinstance(c, Pin):
                mask = select(c.where, sheet)
                for f in fixed:
                    f |= mask
                if c.motion is not None:
                    self._motions.append((np.flatnonzero(mask), c.motion))
            elif isinstance(c, Slide):
                mask = select(c.where, sheet)
                for k in range(3):
                    if k != c.axis:
                        fixed[k] |= mask
            elif isinstance(c, Clamp):
                mask = np.zeros((self.M, self.N), bool)
                for edge in c.edges:
                    rows = {"left": (slice(0, 2), slice(None)), "right": (slice(-2, None), slice(None)),
                            "bottom": (slice(None), slice(0, 2)), "top": (slice(None), slice(-2, None))}[edge]
                    mask[rows] = True
                for f in fixed:
                    f |= mask
        self._fixed = tuple(np.flatnonzero(f) for f in fixed)

    def fixed_dofs(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Indices of the held degrees of freedom of x, y and z."""
        return self._fixed

    def prescribed(self, X0: np.ndarray, t: float) -> np.ndarray:
        """Positions with the held degrees of freedom at their values at time t, (M N, 3)."""
        X = np.array(X0, dtype=float)
        for idx, motion in self._motions:
            X[idx] += np.asarray(motion(t), float)
        return X
