r"""The self-contact barrier over flat vectors, with its collision-free step (the IPC Toolkit, ``ipctk``).

On the contact mesh (:class:`deformable.contact.selfmesh.ContactMesh`: vertices ``V = W X``), every pair of
primitives that may touch (point-triangle, edge-edge) closer than the activation distance dhat adds the IPC
barrier of its squared distance (Li et al. 2020, "Incremental Potential Contact", ACM TOG 39(4), eq. (6) on
d^2, as the IPC Toolkit writes it),

    b(d^2) = -(d^2 - dhat^2)^2 ln(d^2 / dhat^2)   for d < dhat,  0 beyond,
    S(x) = kappa sum_c A_c b(d_c^2)                                               (J)

with A_c the pair's area weight (the IPC Toolkit's area weighting: the vertex or edge areas of the rest mesh,
m^2) and kappa (N/m^5) by default chosen from the sheet's motion, not its weight: the kinetic energy per area
of a fold closing at the speed v (``Contact.self_speed``, 2 m/s), mu v^2 / 2, is the barrier's energy per area
at a gap of dhat / 10, ``kappa b((dhat / 10)^2)``. The log barrier's energy grows only as ln(1/d) below dhat,
so a barrier sized by the weight (as the obstacles' is, :meth:`deformable.contact.settings.Contact.barrier_stiffness`)
lets a fast fold into round-off distances: measured on the ``sphere`` scene (FD 32 x 32 nodes, 1.5 s), the weight's
kappa (9.3e7 N/m^5) brought two folds to 3e-7 m by t = 0.27 s and Newton's line search stalled at t = 0.33 s
(no step down to dt_min); 100 times it ran through with folds 1.2e-7 m apart, 1000 times with 2.7e-4 m
(the rule above gives 8.9e10 N/m^5 there, 960 times the weight's). Its gradient and
Hessian are the IPC Toolkit's with respect to the mesh's vertices, each pair's Hessian projected onto the
positive semi-definite cone (the toolkit's clamping of its eigenvalues), mapped to the degrees of freedom by W:
``grad_x = W^T grad_V`` and ``H_x = W^T H_V W`` per coordinate block. :meth:`SelfContactPotential.max_step`
is the toolkit's continuous collision detection along a straight step (additive CCD): the fraction of a step
``dx`` the mesh can take without any two of its primitives meeting (times ``margin``).

The sheet's thickness dmin (``Contact(thickness=...)``) offsets every distance: the barrier is the IPC Toolkit's
of ``d^2 - dmin^2`` over ``dhat^2 + 2 dmin dhat``, infinite at d = dmin, and the collision-free step keeps every pair
at least dmin apart, so no two fold faces come closer than the thickness.

In Newton's method (:mod:`deformable.solve.newton`, through :class:`deformable.contact.terms.ContactTerms`) S joins
the potential of each implicit step; its Hessian couples degrees of freedom the elastic pattern does not, and its
pattern changes with the pairs in contact: it enters the Newton matrix on a pattern that grows
(:meth:`deformable.algebra.reduced.ReducedSystem.free_block`'s ``loose`` matrices). Every direction is clipped to
:meth:`SelfContactPotential.max_step`, so no iterate, tried or taken, passes the sheet through itself.
"""

from __future__ import annotations

import math
import time

import ipctk
import numpy as np
import scipy.sparse as sp

from .selfmesh import ContactMesh
from .settings import REST_FRACTION, SELF_SPEED

__all__ = ["SelfContactPotential", "PARTS"]

#: the parts of the self-contact's time kept in :attr:`SelfContactPotential.seconds`
PARTS = ("collisions", "barrier", "hessian", "ccd", "intersections")


class SelfContactPotential:
    """The self-contact barrier S(x) over flat coordinate-blocked vectors (3 ndof,) (module docstring).

    Parameters
    ----------
    model : Backend
    distance : float
        The activation distance dhat (m), beyond the thickness.
    stiffness : float, optional
        kappa (N/m^5); default: a fold closing at ``speed`` is stopped at a gap of dmin + dhat / 10 (module
        docstring).
    margin : float
        The fraction, in (0, 1), of the collision-free step that :meth:`max_step` allows.
    thickness : float
        The sheet's thickness dmin (m).
    speed : float
        The closing speed (m/s) the default stiffness is sized for.

    Attributes
    ----------
    mesh : ContactMesh
    kappa : float
        The barrier stiffness (N/m^5).
    seconds : dict
        Wall seconds spent so far in the IPC Toolkit's "collisions" (broad and narrow phase of the barrier's
        pairs), "barrier" (its value and gradient), "hessian" (with the projections), "ccd" (the safe steps) and
        "intersections" (the intersection test of :meth:`energy`): where self-contact's time goes.
    """

    def __init__(self, model, distance: float, stiffness: float | None = None, margin: float = 0.8,
                 thickness: float = 0.0, speed: float = SELF_SPEED):
        if not 0 < margin < 1:
            raise ValueError(f"SelfContactPotential.margin must lie in (0, 1), got {margin!r}")
        self.mesh = ContactMesh(model, distance, thickness=thickness)
        self.n, self.margin, self.dhat, self.dmin = model.ndof, float(margin), float(distance), float(thickness)
        if stiffness is None:  # mu v^2 / 2 = kappa b(d0^2 - dmin^2) at d0 = dmin + dhat / 10 (module docstring)
            d0 = self.dmin + REST_FRACTION * self.dhat
            reach = self.dhat * self.dhat + 2 * self.dmin * self.dhat
            mu = float(np.max(model.scene.nodal_material().mu))
            stiffness = 0.5 * mu * speed**2 / ipctk.barrier(d0 * d0 - self.dmin * self.dmin, reach)
        self.kappa = float(stiffness)
        self.barrier = ipctk.BarrierPotential(self.dhat, self.kappa)
        # additive CCD (Li, Kaufman and Jiang 2021, "Codimensional Incremental Potential Contact", ACM TOG 40(4),
        # section 5: conservative advancement to a minimum separation): measured on a fold closing at 10 m/s (FD
        # 24 x 24 nodes, 103 Newton directions) 0.30 s CPU against Tight-Inclusion CCD's 7.4 s (Wang et al. 2021;
        # tolerance 1e-6, 10^4 iterations), its steps within 0.1 of the latter's; capped at 10^6 iterations
        self.ccd = ipctk.AdditiveCCD(1_000_000)
        W = self.mesh.points.W
        self.P = W.shape[0]
        # x (coordinate blocks, a ndof + k) -> the mesh's vertices as the IPC Toolkit orders them (3 p + a)
        W3 = sp.kron(sp.identity(3, format="csr"), W, format="csr")
        order = (3 * np.arange(self.P)[None, :] + np.arange(3)[:, None]).ravel()  # blocked index a P + p -> 3 p + a
        self.Wv = W3[np.argsort(order)].tocsr()
        self.WvT = self.Wv.T.tocsr()
        self._last = None  # (x, V, collisions) of the last state asked about
        self._zeros = np.zeros(3 * self.n)
        self.seconds = dict.fromkeys(PARTS, 0.0)

    def _clock(self, name: str, t0: float) -> None:
        self.seconds[name] += time.perf_counter() - t0

    def _at(self, x):
        """The vertices (P, 3) and the barrier's collisions of a flat state x, kept for the next call at the same x
        (energy, gradient and Hessian at one iterate build them once)."""
        x = np.asarray(x, float)
        if self._last is not None and np.array_equal(self._last[0], x):
            return self._last[1], self._last[2]
        t0 = time.perf_counter()
        V = self.mesh.vertices(x.reshape(3, self.n).T)
        collisions = self.mesh.collisions(V, area_weighting=True)
        self._last = (x.copy(), V, collisions)
        self._clock("collisions", t0)
        return V, collisions

    def lag(self, x, dt: float) -> None:
        """Freeze the friction between folds at the step's start x (flat), step dt (s): none yet."""

    def energy(self, x) -> float:
        """S(x) (J); +inf where the mesh intersects itself or two primitives that may touch are not more than the
        thickness apart."""
        V, collisions = self._at(x)
        t0 = time.perf_counter()
        crossed = ipctk.has_intersections(self.mesh.mesh, V)
        self._clock("intersections", t0)
        if crossed:
            return math.inf
        t0 = time.perf_counter()
        try:
            if len(collisions) and collisions.compute_minimum_distance(self.mesh.mesh, V) <= self.dmin * self.dmin:
                return math.inf
            return float(self.barrier(collisions, self.mesh.mesh, V))
        finally:
            self._clock("barrier", t0)

    def gradient(self, x) -> np.ndarray:
        """grad S, flat (3 ndof,) (N)."""
        V, collisions = self._at(x)
        if len(collisions) == 0:
            return self._zeros.copy()
        t0 = time.perf_counter()
        g = np.asarray(self.barrier.gradient(collisions, self.mesh.mesh, V)).ravel()
        self._clock("barrier", t0)
        return self.WvT @ g

    def hessian(self, x) -> sp.csr_matrix:
        """The Hessian of S with each pair's part projected onto the positive semi-definite cone, (3 ndof, 3 ndof)
        (N/m). Its pattern follows the pairs in contact (no entries without one)."""
        V, collisions = self._at(x)
        if len(collisions) == 0:
            return sp.csr_matrix((3 * self.n, 3 * self.n))
        t0 = time.perf_counter()
        H = sp.csr_matrix(self.barrier.hessian(collisions, self.mesh.mesh, V, ipctk.PSDProjectionMethod.CLAMP))
        H = (self.WvT @ H @ self.Wv).tocsr()
        self._clock("hessian", t0)
        return H

    def max_step(self, x, dx) -> float:
        """The fraction in (0, 1] of the step dx (flat) that x may take with no two primitives coming closer than
        the thickness on the way (``margin`` of the collision-free fraction when that is below 1)."""
        x = np.asarray(x, float)
        V0 = self.mesh.vertices(x.reshape(3, self.n).T)
        V1 = self.mesh.vertices((x + np.asarray(dx, float)).reshape(3, self.n).T)
        t0 = time.perf_counter()
        alpha = float(ipctk.compute_collision_free_stepsize(self.mesh.mesh, V0, V1, self.dmin, None, self.ccd))
        self._clock("ccd", t0)
        return 1.0 if alpha >= 1.0 else self.margin * alpha
