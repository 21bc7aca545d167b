"""The barrier and friction potential over flat vectors, with its safe steps and the solved contact normals.

The barrier (implicit schemes; Li et al. 2020, "Incremental Potential Contact", ACM TOG 39(4), eq. (6)). With d_pk
the signed distance of point p to obstacle k (:mod:`deformable.contact.obstacles`) and the activation distance dhat,

    b(d) = -(d - dhat)^2 ln(d / dhat)   for 0 < d < dhat,   0 for d >= dhat,
    B(x) = kappa sum_pk A_p b(d_pk(x))                                    (J)

is zero beyond dhat, C2 at dhat, and grows without bound as d -> 0. kappa (N/m^3) is a contact stiffness per unit
area (:meth:`deformable.contact.settings.Contact.barrier_stiffness`). Its gradient is ``kappa A_p b'(d) n`` per
point and its Hessian ``kappa A_p (b''(d) n n^T + b'(d) hess d)``; for a convex obstacle the second term is negative
semi-definite, and the "definite" Hessian drops it (the projection of the 3 x 3 block onto the positive
semi-definite cone). Every Newton direction is clipped to ``margin`` (0.8, as IPC) of the largest step that keeps
every point outside (:meth:`ContactPotential.max_step`, exact for the convex obstacles here), so the clearance stays
positive at every iterate.

The contact normals solved against the barrier (:meth:`ContactPotential.relax`; nonlinear elimination: Lanzkron,
Rose and Wilkes 1996, SIAM J. Sci. Comput. 17(2); Cai and Keyes 2002, SIAM J. Sci. Comput. 24(1)). Newton's linear
model of b is poor within a few gaps of an obstacle (b' ~ -dhat^2 / d): a point carried towards an obstacle
overshoots and is clipped deep into the barrier. So in a time step, before the direction is clipped, each active
contact point has its normal displacement s re-solved from a 1-D model along its normal n: the rest of the Newton
matrix by its diagonal k (barrier excluded), the rest's force as Newton's linear model predicts it, and the barrier
exact,

    k (s - s_N) - kappa A_p (b'(d) + b''(d) s_N) + kappa A_p b'(d + s) = 0,

s_N = n . (W dx)_p. Its 1-D energy is convex in s; a safeguarded 1-D Newton solves it. Newton
(:mod:`deformable.solve.newton`) keeps the direction so changed when its step decreases the potential, else takes
its own. It needs every contact point to be a degree of freedom's own point (FD's nodes); with sample points between
the nodes (FE's, FD's under ``Contact(samples > 1)``) the direction stays Newton's.

Friction (IPC section 5): lagged, smoothed Coulomb friction with coefficient mu_f. At the start of each step
(positions x_n) every active pair gets its normal force ``lambda = -kappa A_p b'(d_n)`` (N) and an orthonormal
tangent basis T (3 x 2) of the obstacle's tangent plane at the point, fixed through the step. With the tangential
displacement u = T^T (r_p(x) - r_p(x_n)) and eps_x = eps_v dt (eps_v: the slip speed below which friction is
smoothed, m/s), the dissipative potential

    D(x) = sum mu_f lambda f0(|u|),
    f0(y) = -y^3 / (3 eps_x^2) + y^2 / eps_x + eps_x / 3  (y < eps_x),  y otherwise

gives the force ``-mu_f lambda f1(|u|) T u / |u|`` with f1 = f0' (1 for |u| >= eps_x: sliding, Coulomb's mu_f
lambda; linear in |u| below: sticking). Its Hessian ``mu_f lambda T ((f1/y) I + (f1' - f1/y) / y^2 u u^T) T^T`` is
positive semi-definite. The barrier function and the mollifier are :mod:`deformable.contact.barrier`'s; the contact
points :mod:`deformable.contact.points`'.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..geometry.tensors import tangent_basis
from .barrier import barrier, barrier_derivative, barrier_second, mollifier
from .obstacles import Obstacle
from .points import contact_points, require_outside
from .settings import Contact, weight_per_area

__all__ = ["ContactPotential"]


# -- the barrier potential with lagged friction -------------------------------------------------
def _normal_solve(k, rest, sN, d0, w, dhat, keep, iterations: int = 30):
    """Solve ``k (s - sN) + rest + w b'(d0 + s) = 0`` for s per point (:meth:`ContactPotential.relax`).

    The left side increases with s (k >= 0, b'' > 0: the 1-D energy is convex). Newton from s = sN, each iterate
    keeping at least the fraction ``keep`` of the gap d0 + s it starts from (the start too, of d0), until every step
    is below 1e-6 of its gap. All arrays (P,) (m, N/m, N); returns s (P,) (m).
    """
    s = np.maximum(sN, (keep - 1.0) * d0)
    for _ in range(iterations):
        gap = d0 + s
        f = k * (s - sN) + rest + w * barrier_derivative(gap, dhat)
        fp = k + w * barrier_second(gap, dhat)
        step = np.where(fp > 0, -f / np.where(fp > 0, fp, 1.0), 0.0)
        step = np.maximum(step, (keep - 1.0) * gap)
        s = s + step
        if np.all(np.abs(step) <= 1e-6 * gap):
            break
    return s


@dataclass(frozen=True)
class _Lagged:
    """Friction data of one obstacle, frozen at the start of a step: active points, lambda (N), T (., 3, 2), r_n."""

    obstacle: int
    points: np.ndarray
    normal_force: np.ndarray
    basis: np.ndarray
    start: np.ndarray


class ContactPotential:
    """The barrier B(x) and the lagged friction potential D(x) over flat coordinate-blocked vectors (module docstring).

    Parameters
    ----------
    model : Backend whose scene has obstacles and a Contact of method "barrier"

    Attributes
    ----------
    kappa : float
        The barrier stiffness (N/m^3).
    dhat : float
        The activation distance (m).
    """

    def __init__(self, model):
        scene = model.scene
        self.model, self.n = model, model.ndof
        self.settings: Contact = scene.contact
        self.obstacles: tuple[Obstacle, ...] = tuple(o for o in scene.obstacles if o.analytic)  # meshes: meshpotential
        self.points = contact_points(model)
        self.dhat = self.settings.distance
        self.kappa = self.settings.barrier_stiffness(weight_per_area(scene))
        self.weight = self.kappa * self.points.area  # kappa A_p (N/m^3 m^2 = N/m)
        self._lagged: list[_Lagged] = []
        self._eps = None
        self._hessian = None

    def _positions(self, x) -> np.ndarray:
        return self.points.W @ x.reshape(3, self.n).T

    def _scatter(self, f: np.ndarray) -> np.ndarray:
        """Point forces (P, 3) -> a flat coordinate-blocked vector of the degrees of freedom."""
        return (self.points.WT @ f).T.ravel()

    # -- lagging ---------------------------------------------------------------------
    def lag(self, x, dt: float) -> None:
        """Freeze the friction's normal forces and tangent bases at the step's start x (flat), step dt (s).

        Raises ValueError when a contact point of x is not strictly outside an obstacle (the barrier is infinite
        there).
        """
        x = np.asarray(x, float)
        require_outside(self.model, x.reshape(3, self.n).T, "the step's start")
        r = self._positions(x)
        self._lagged, self._eps = [], self.settings.slip * dt
        for k, obstacle in enumerate(self.obstacles):
            d, nrm, _ = obstacle.derivatives(r, hessian=False)
            if self.settings.friction == 0:
                continue
            on = np.flatnonzero(d < self.dhat)
            lam = -self.weight[on] * barrier_derivative(d[on], self.dhat)
            self._lagged.append(_Lagged(k, on, lam, tangent_basis(nrm[on]), r[on]))

    def _friction(self, r, what: str):
        """Per lagged pair: the friction potential, point forces, or 3 x 3 Hessian blocks at positions r."""
        mu, eps = self.settings.friction, self._eps
        for lg in self._lagged:
            u = np.einsum("pik,pi->pk", lg.basis, r[lg.points] - lg.start)  # (Q, 2)
            y = np.sqrt(np.sum(u * u, axis=1))
            f0, f1y, c2 = mollifier(y, eps)
            s = mu * lg.normal_force
            if what == "energy":
                yield float(np.sum(s * f0))
            elif what == "gradient":
                yield lg.points, np.einsum("pik,pk->pi", lg.basis, (s * f1y)[:, None] * u)
            else:
                A = (s * f1y)[:, None, None] * np.eye(2) + (s * c2)[:, None, None] * u[:, :, None] * u[:, None, :]
                yield lg.points, np.einsum("pik,pkl,pjl->pij", lg.basis, A, lg.basis)

    # -- the potential ------------------------------------------------------------------
    def energy(self, x) -> float:
        """B(x) + D(x) (J); +inf when a contact point is not outside an obstacle."""
        r = self._positions(x)
        e = 0.0
        for obstacle in self.obstacles:
            d = obstacle.distance(r)
            if np.min(d) <= 0:
                return math.inf
            e += float(self.weight @ barrier(d, self.dhat))
        return e + sum(self._friction(r, "energy"))

    def gradient(self, x) -> np.ndarray:
        """grad (B + D), flat (3 ndof,) (N)."""
        r = self._positions(x)
        f = np.zeros_like(r)
        for obstacle in self.obstacles:
            d, nrm, _ = obstacle.derivatives(r, hessian=False)
            f += (self.weight * barrier_derivative(d, self.dhat))[:, None] * nrm
        for points, g in self._friction(r, "gradient"):
            f[points] += g
        return self._scatter(f)

    def hessian(self, x, kind: str = "newton") -> sp.csr_matrix:
        """Hessian of B + D, (3 ndof, 3 ndof) on a fixed pattern (N/m).

        ``kind`` "newton": exact; any other: the barrier's curvature term dropped (its projection onto the positive
        semi-definite cone; the friction's Hessian is positive semi-definite as it is).
        """
        r = self._positions(x)
        K = np.zeros((r.shape[0], 3, 3))
        for obstacle in self.obstacles:
            d, nrm, hd = obstacle.derivatives(r, hessian=kind == "newton")
            on = np.flatnonzero(d < self.dhat)
            w = self.weight[on]
            K[on] += (w * barrier_second(d[on], self.dhat))[:, None, None] * nrm[on, :, None] * nrm[on, None, :]
            if kind == "newton":
                K[on] += (w * barrier_derivative(d[on], self.dhat))[:, None, None] * hd[on]
        for points, H in self._friction(r, "hessian"):
            K[points] += H
        self._hessian = self.points.blocks(K)
        return self._hessian

    def hessian_diagonal(self) -> np.ndarray:
        """The diagonal of the Hessian :meth:`hessian` assembled last (3 ndof,) (N/m): what Newton's matrix holds of
        the contact, for :meth:`propose` (:class:`deformable.solve.newton.DirectionFilter`)."""
        return self._hessian.diagonal()

    def safe_start(self, x, dx) -> np.ndarray:
        """A point between x and x + dx (flat) that keeps every contact point outside every obstacle.

        Each degree of freedom moves the fraction of its own dx that the contact points it carries allow (the
        smallest of theirs, :meth:`max_step` per point), and the result is clipped once more along its segment from
        x (exact for interpolated points that mix moved and held degrees of freedom): a few points near an obstacle
        do not hold back the rest of the sheet.
        """
        s = self._point_steps(x, dx)
        W = self.points.W
        fraction = np.ones(self.n)
        np.minimum.at(fraction, W.indices, np.repeat(s, np.diff(W.indptr)))
        step = (dx.reshape(3, self.n) * fraction).ravel()
        return x + self.max_step(x, step) * step

    def max_step(self, x, dx) -> float:
        """The largest alpha in (0, 1] for which x + s dx keeps every contact point outside every obstacle.

        Exact for the convex obstacles (:meth:`deformable.contact.obstacles.Obstacle.first_contact`): the first s at
        which a point would have closed ``margin`` of its gap, over all points and obstacles, capped at 1.
        """
        return float(np.min(self._point_steps(x, dx), initial=1.0))

    def propose(self, x, dx, stiffness) -> np.ndarray:
        """Newton's direction with the contact normals solved against the barrier (:meth:`relax`), the contact's
        proposal as a :class:`deformable.solve.newton.DirectionFilter`."""
        return self.relax(x, dx, stiffness)

    def relax(self, x, dx, stiffness) -> np.ndarray:
        """Newton's direction dx (flat) with the normal displacement of each active own contact point re-solved
        against the barrier (module docstring).

        Parameters
        ----------
        x, dx : arrays (3 ndof,)
            The iterate and Newton's direction (held degrees of freedom: dx 0).
        stiffness : array (3 ndof,)
            The diagonal of the Newton matrix without the contact's Hessian (N/m); 0 on held degrees of freedom.

        Returns
        -------
        array (3 ndof,)
            A new direction; dx itself when no point is active, or when some contact points are not a degree of
            freedom's own (they share the nodes' degrees of freedom, so the 1-D models are not independent). Points
            near two obstacles at once keep Newton's displacement.
        """
        own = self.points.owner
        if np.any(own < 0):
            return dx
        r, dr = self._positions(x), self._positions(dx)
        k3 = stiffness.reshape(3, self.n).T
        moves = []
        pairs = np.zeros(r.shape[0], np.int64)
        for obstacle in self.obstacles:
            d, nrm, _ = obstacle.derivatives(r, hessian=False)
            sN = np.sum(nrm * dr, axis=1)
            near = d + np.minimum(sN, 0.0) < self.dhat
            pairs += near
            moves.append((near, d, nrm, sN))
        out = None
        for near, d, nrm, sN in moves:
            on = np.flatnonzero(near & (pairs == 1))
            free = np.all(k3[own[on]] > 0, axis=1)  # a held degree of freedom has no stiffness
            on, dof = on[free], own[on[free]]
            if on.size == 0:
                continue
            n_, d0, sn, w = nrm[on], d[on], sN[on], self.weight[on]
            k = np.sum(k3[dof] * n_ * n_, axis=1)
            rest = -w * (barrier_derivative(d0, self.dhat) + barrier_second(d0, self.dhat) * sn)
            s = _normal_solve(k, rest, sn, d0, w, self.dhat, 1.0 - self.settings.margin)
            out = dx.reshape(3, self.n).copy() if out is None else out
            np.add.at(out.T, dof, (s - sn)[:, None] * n_)
        return dx if out is None else out.ravel()

    def _point_steps(self, x, dx) -> np.ndarray:
        """Per contact point, the largest s in (0, 1] for which it stays ``margin`` of its gap away from every
        obstacle along x + s dx, (P,)."""
        r, dr = self._positions(x), self._positions(dx)
        keep = 1.0 - self.settings.margin
        s = np.ones(r.shape[0])
        for obstacle in self.obstacles:
            s = np.minimum(s, obstacle.first_contact(r, dr, keep * obstacle.distance(r)))
        return s


