r"""The self-contact barrier over flat vectors, with its collision-free step (the IPC Toolkit, ``ipctk``).

On the contact mesh (:class:`deformable.contact.selfmesh.ContactMesh`: vertices ``V = W X``), every pair of
primitives that may touch (point-triangle, edge-edge) closer than the activation distance dhat adds the IPC
barrier of its squared distance (Li et al. 2020, "Incremental Potential Contact", ACM TOG 39(4), eq. (6) on
d^2, as the IPC Toolkit writes it),

    b(d^2) = -(d^2 - dhat^2)^2 ln(d^2 / dhat^2)   for d < dhat,  0 beyond,
    S(x) = kappa sum_c A_c b(d_c^2)                                               (J)

with A_c the pair's area weight (the IPC Toolkit's area weighting: the vertex or edge areas of the rest mesh,
m^2) and kappa (N/m^5) chosen so that the sheet's own weight per area mu g rests at a gap of dhat / 10, as the
obstacle barrier's kappa is (:meth:`deformable.contact.settings.Contact.barrier_stiffness`). Its gradient and
Hessian are the IPC Toolkit's with respect to the mesh's vertices, each pair's Hessian projected onto the
positive semi-definite cone (the toolkit's clamping of its eigenvalues), mapped to the degrees of freedom by W:
``grad_x = W^T grad_V`` and ``H_x = W^T H_V W`` per coordinate block. :meth:`SelfContactPotential.max_step`
is the toolkit's continuous collision detection along a straight step: the fraction of a step ``dx`` the mesh
can take without any two of its primitives meeting (times ``margin``).

Newton's method (:mod:`deformable.solve.newton`) does not take this potential yet: its matrix lives on fixed
sparsity patterns and a contact pair couples degrees of freedom the elastic pattern does not.
"""

from __future__ import annotations

import math

import ipctk
import numpy as np
import scipy.sparse as sp

from .selfmesh import ContactMesh
from .settings import REST_FRACTION, weight_per_area

__all__ = ["SelfContactPotential"]


class SelfContactPotential:
    """The self-contact barrier S(x) over flat coordinate-blocked vectors (3 ndof,) (module docstring).

    Parameters
    ----------
    model : Backend
    distance : float
        The activation distance dhat (m).
    stiffness : float, optional
        kappa (N/m^5); default: the sheet's weight per area rests at dhat / 10.
    margin : float
        The fraction, in (0, 1), of the collision-free step that :meth:`max_step` allows.

    Attributes
    ----------
    mesh : ContactMesh
    kappa : float
        The barrier stiffness (N/m^5).
    """

    def __init__(self, model, distance: float, stiffness: float | None = None, margin: float = 0.8):
        if not 0 < margin < 1:
            raise ValueError(f"SelfContactPotential.margin must lie in (0, 1), got {margin!r}")
        self.mesh = ContactMesh(model, distance)
        self.n, self.margin, self.dhat = model.ndof, float(margin), float(distance)
        if stiffness is None:
            d0 = REST_FRACTION * self.dhat  # the weight per area rests there: kappa |b'(d0^2)| 2 d0 = mu g
            slope = -ipctk.barrier_first_derivative(d0 * d0, self.dhat * self.dhat) * 2 * d0
            stiffness = weight_per_area(model.scene) / slope
        self.kappa = float(stiffness)
        self.barrier = ipctk.BarrierPotential(self.dhat, self.kappa)
        # Tight-Inclusion CCD (Wang et al. 2021) capped at 10^4 iterations: a capped query returns a conservative
        # time of impact; the default cap (10^7) left one FE step query running for minutes
        self.ccd = ipctk.TightInclusionCCD(1e-6, 10_000)
        W = self.mesh.points.W
        self.P = W.shape[0]
        self.W3 = sp.kron(sp.identity(3, format="csr"), W, format="csr")  # coordinate-blocked x -> V blocks
        # the IPC Toolkit orders a vertex quantity vertex by vertex (3 p + a); ours is blocked (a P + p)
        self.order = (3 * np.arange(self.P)[None, :] + np.arange(3)[:, None]).ravel()

    def _vertices(self, x) -> np.ndarray:
        """The mesh's vertices (P, 3) of a flat state x."""
        return self.mesh.vertices(np.asarray(x, float).reshape(3, self.n).T)

    def energy(self, x) -> float:
        """S(x) (J); +inf where the mesh intersects itself."""
        V = self._vertices(x)
        if ipctk.has_intersections(self.mesh.mesh, V):
            return math.inf
        return float(self.barrier(self.mesh.collisions(V, area_weighting=True), self.mesh.mesh, V))

    def gradient(self, x) -> np.ndarray:
        """grad S, flat (3 ndof,) (N)."""
        V = self._vertices(x)
        g = np.asarray(self.barrier.gradient(self.mesh.collisions(V, area_weighting=True), self.mesh.mesh, V)).ravel()
        return self.W3.T @ g[self.order]

    def hessian(self, x) -> sp.csr_matrix:
        """The Hessian of S with each pair's part projected onto the positive semi-definite cone, (3 ndof, 3 ndof)
        (N/m). Its pattern follows the pairs in contact."""
        V = self._vertices(x)
        H = self.barrier.hessian(self.mesh.collisions(V, area_weighting=True), self.mesh.mesh, V, ipctk.PSDProjectionMethod.CLAMP)
        H = sp.csr_matrix(H)[self.order][:, self.order]
        return (self.W3.T @ H @ self.W3).tocsr()

    def max_step(self, x, dx) -> float:
        """The fraction in (0, 1] of the step dx (flat) that x may take with no two primitives meeting on the way
        (``margin`` of the collision-free fraction when that is below 1)."""
        V0 = self._vertices(x)
        V1 = self._vertices(np.asarray(x, float) + np.asarray(dx, float))
        alpha = float(ipctk.compute_collision_free_stepsize(self.mesh.mesh, V0, V1, 0.0, None, self.ccd))
        return 1.0 if alpha >= 1.0 else self.margin * alpha
