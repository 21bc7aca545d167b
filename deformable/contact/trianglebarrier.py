"""IPC's barrier and lagged friction on a triangle mesh that carries the sheet, over flat vectors (``ipctk``).

One class, :class:`TriangleBarrier`, serves the two contacts that meet the sheet primitive against primitive on an
IPC Toolkit mesh: the sheet against itself (:mod:`deformable.contact.selfpotential`, the contact mesh of
:class:`deformable.contact.selfmesh.ContactMesh`) and the sheet against triangle-mesh obstacles
(:mod:`deformable.contact.meshpotential`). The sheet's P vertices come first, ``V = W X`` (W the fixed map of the
contact points, :mod:`.points`); the rest, if any, are prescribed (obstacles), not degrees of freedom.

The barrier. Every pair of primitives that may touch (point-triangle, edge-edge) within the activation distance dhat
beyond the thickness dmin adds the IPC barrier of its squared distance (Li et al. 2020, "Incremental Potential
Contact", ACM TOG 39(4), eq. (6) on d^2, as the IPC Toolkit writes it; offset by dmin),

    b(s; shat) = -(s - shat)^2 ln(s / shat)   for 0 < s < shat,  0 beyond,
    S(x) = kappa sum_c A_c b(d_c^2 - dmin^2; dhat^2 + 2 dmin dhat)                   (J)

with A_c the pair's area weight (the vertex or edge areas of the rest mesh, m^2) and the stiffness kappa (N/m^5)
each subclass chooses (:func:`motion_stiffness` sizes it by a closing speed). S is infinite at d = dmin; the energy
is +inf where two triangles cross. Its gradient and Hessian are the toolkit's with respect to the vertices, each
pair's Hessian projected onto the positive semi-definite cone; the sheet's rows map to the degrees of freedom by W,
``grad_x = W^T grad_V`` and ``H_x = W^T H_V W`` per coordinate block; prescribed vertices' rows are dropped. The
Hessian's pattern follows the pairs in contact: it enters Newton's matrix as a ``loose`` matrix
(:meth:`deformable.algebra.upper.FreeUpper.assemble`).

The collision-free step, :meth:`TriangleBarrier.max_step`: ``margin`` of the fraction of a straight step that the
toolkit's continuous collision detection finds collision-free (additive CCD: Li, Kaufman and Jiang 2021,
"Codimensional Incremental Potential Contact", ACM TOG 40(4), section 5, conservative advancement to the minimum
separation dmin; at most :data:`CCD_ITERATIONS` iterations). Every Newton direction is clipped to it. Before any CCD
a conservative bound (:meth:`TriangleBarrier.free_fraction`): a pair's distance falls along a straight motion by at
most the largest relative motion of its vertices, so where every vertex moves less than half its distance to the
nearest pair it is in (beyond dmin) the whole step is collision-free.

The broad phase. Every pair the barrier or the collision-free step may need is found once a step and kept: the IPC
Toolkit's candidates (``ipctk.Candidates``) of the straight motion from V_0 to V_1 that the step first asks about,
each primitive's box swept along its vertices' segments and grown by (dhat + dmin) / 2 plus a margin m = (dhat +
dmin) / 4. While every vertex stays within m of its segment (the *tube*), any pair closer than dhat + dmin, and any
pair that comes within dmin along a straight motion with both ends in the tube, is a candidate; a state outside the
tube builds it again on the motion asked about then. It is built anew at every step's start
(:meth:`TriangleBarrier.lag`), so a resumed run builds the same ones.

Friction (IPC section 5: lagged, smoothed Coulomb friction, as :mod:`deformable.contact.potential`'s), with
Coulomb's coefficient mu_f and the slip speed eps_v (m/s, ``Contact.slip``) below which it is smoothed. At the start
of each implicit step (vertices V_n, step dt; :meth:`TriangleBarrier.lag`) every pair of the barrier within reach
gets, frozen through the step, its normal force

    lambda_c = A_c kappa |d b(d^2 - dmin^2) / dd| = -2 kappa A_c d b'(d^2 - dmin^2)   at d = d_c(V_n)        (N)

its orthonormal tangent basis T_c (3 x 2) of the plane across which the pair meets (nearly parallel edges get no
friction) and the barycentric coordinates of its closest points, which make the relative displacement operator
Gamma_c (3 x 12). With U = V(x) - V_n (m; a prescribed vertex's own motion included, so a sheet carried by a moving
obstacle does not slip) and u_c = T_c^T Gamma_c U (m),

    D(x) = sum_c mu_f lambda_c f0(|u_c|),   eps_x = eps_v dt                                                 (J)
    f0(y) = -y^3 / (3 eps_x^2) + y^2 / eps_x + eps_x / 3   (y < eps_x),   y otherwise                     (m)

is the toolkit's ``FrictionPotential(eps_x)`` on the displacements U, dt times its velocity form (f0 is homogeneous
of degree one in (y, eps)). D's gradient (N), ``mu_f lambda_c f1(|u_c|) Gamma_c^T T_c u_c / |u_c|`` (f1 = f0', 1
once sliding: Coulomb's force against the slip), and its Hessian (N/m, positive semi-definite) join the barrier's.
Without a lag, or with mu_f = 0, there is no friction.
"""

from __future__ import annotations

import math
import time

import ipctk
import numpy as np
import scipy.sparse as sp

from .selfmesh import vertex_map
from .settings import REST_FRACTION

__all__ = ["TriangleBarrier", "PARTS", "motion_stiffness", "CCD_ITERATIONS"]

#: the parts of the time kept in :attr:`TriangleBarrier.seconds`
PARTS = ("collisions", "barrier", "hessian", "ccd")

#: the additive CCD's iteration cap
CCD_ITERATIONS = 1_000_000
#: the conservative bound of the collision-free step holds a vertex's motion to this fraction of half its distance
SAFE_FRACTION = 0.9
#: the broad phase's tube around the motion it was built for, a fraction of the reach dhat + dmin (module docstring)
TUBE_FRACTION = 0.25


def motion_stiffness(mu: float, speed: float, dhat: float, dmin: float = 0.0) -> float:
    """kappa (N/m^5) under which a sheet of mass per area mu (kg/m^2) closing at ``speed`` (m/s) on a barrier is
    stopped at a gap of dmin + dhat / 10: its kinetic energy per area mu v^2 / 2 equals the barrier's energy per
    area there, ``kappa b(d0^2 - dmin^2; dhat^2 + 2 dmin dhat)`` at d0 = dmin + dhat / 10 (module docstring)."""
    d0 = dmin + REST_FRACTION * dhat
    return 0.5 * mu * speed**2 / ipctk.barrier(d0 * d0 - dmin * dmin, dhat * dhat + 2 * dmin * dhat)


def _number(owner: str, name: str, v, zero: bool) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0 or (v == 0 and not zero):
        raise ValueError(f"{owner}.{name} must be a {'non-negative' if zero else 'positive'} finite number, got {v!r}")
    return float(v)


def _in_tube(V: np.ndarray, V0: np.ndarray, V1: np.ndarray, margin: float) -> bool:
    """Whether every vertex of V is within ``margin`` of its segment from V0 to V1."""
    if V.shape != V0.shape:
        return False
    D = V1 - V0
    length = np.sum(D * D, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.clip(np.where(length > 0, np.sum((V - V0) * D, axis=1) / length, 0.0), 0.0, 1.0)
    return float(np.max(np.sum((V - V0 - t[:, None] * D) ** 2, axis=1), initial=0.0)) <= margin**2


class TriangleBarrier:
    """The barrier S(x) and the lagged friction D(x) on a triangle mesh whose first P vertices are the sheet's
    contact points, over flat coordinate-blocked vectors (3 ndof,) (module docstring).

    A subclass gives the mesh and :meth:`vertices`.

    Parameters
    ----------
    model : Backend
    mesh : an object with ``mesh`` (the ipctk.CollisionMesh) and ``points`` (ContactPoints: the map W, P rows)
    distance : float
        The activation distance dhat (m), beyond the thickness.
    stiffness : float
        kappa (N/m^5).
    margin : float
        The fraction, in (0, 1), of the collision-free step that :meth:`max_step` allows.
    thickness : float
        dmin (m): no pair comes closer.
    friction : float
        Coulomb's coefficient mu_f (0: frictionless).
    slip : float
        eps_v (m/s): below this tangential speed friction is smoothed; over a step dt the smoothing length is
        eps_x = eps_v dt.

    Attributes
    ----------
    kappa : float
        The barrier stiffness (N/m^5).
    seconds : dict
        Wall seconds spent so far in the IPC Toolkit's "collisions" (the broad phase, and the narrow phase of the
        barrier's pairs and of the friction's pairs frozen by :meth:`lag`), "barrier" (its value and gradient, and
        the friction's), "hessian" (with the projections; the friction's too) and "ccd" (the safe steps).
    broad_phases : int
        The broad phases built so far (:meth:`_candidates`): one a step, and another where an iterate or a step
        leaves the tube of the last.
    bounded, ccd_calls : int
        The collision-free steps settled by the conservative bound, and by CCD.
    """

    def __init__(self, model, mesh, distance: float, stiffness: float, margin: float = 0.8, thickness: float = 0.0,
                 friction: float = 0.0, slip: float = 1e-3):
        owner = type(self).__name__
        if not 0 < margin < 1:
            raise ValueError(f"{owner}.margin must lie in (0, 1), got {margin!r}")
        self.friction, self.slip = _number(owner, "friction", friction, True), _number(owner, "slip", slip, False)
        self.mesh = mesh
        self.n, self.margin, self.dhat, self.dmin = model.ndof, float(margin), float(distance), float(thickness)
        self.kappa = _number(owner, "stiffness", stiffness, False)
        self.barrier = ipctk.BarrierPotential(self.dhat, self.kappa)
        self.ccd = ipctk.AdditiveCCD(CCD_ITERATIONS)
        self.Wv, self.WvT = vertex_map(mesh.points.W)
        self.P = mesh.points.W.shape[0]
        self._last = None  # (x, V, collisions) of the last state asked about
        self._lagged = None  # (tangential collisions, V_n, FrictionPotential(eps_v dt)) frozen by lag, or None
        self._starts = None  # (x, V, collisions) of the last step's start asked about (_start)
        self._zeros = np.zeros(3 * self.n)
        self._kept = None  # (V_0, V_1, margin, ipctk.Candidates) of the broad phase at hand (:meth:`_candidates`)
        self.broad_phases = 0
        self.bounded = 0  # collision-free steps the conservative bound settled (no CCD)
        self.ccd_calls = 0  # collision-free steps the CCD settled
        self.seconds = dict.fromkeys(PARTS, 0.0)

    def vertices(self, x) -> np.ndarray:
        """The mesh's vertices (Fortran-ordered, (V, 3), m) of a flat state x, as the potential evaluates it."""
        raise NotImplementedError

    def start_vertices(self, x) -> np.ndarray:
        """The mesh's vertices at the step's start x (flat), where :meth:`lag` freezes the friction."""
        return self.vertices(x)

    def _clock(self, name: str, t0: float) -> None:
        self.seconds[name] += time.perf_counter() - t0

    def _candidates(self, V0, V1=None):
        """The broad phase's candidate pairs, valid for the vertices V0 and, if given, the straight motion from V0
        to V1 (module docstring, "The broad phase"): the kept ones while both lie within the kept tube, else new
        ones on the tube of the motion asked about."""
        kept = self._kept
        if kept is not None and _in_tube(V0, *kept[:3]) and (V1 is None or _in_tube(V1, *kept[:3])):
            return kept[3]
        t0 = time.perf_counter()
        V1 = V0 if V1 is None else V1
        margin = TUBE_FRACTION * (self.dhat + self.dmin)
        candidates = ipctk.Candidates()
        candidates.build(self.mesh.mesh, V0, V1, 0.5 * (self.dhat + self.dmin) + margin)
        self._kept = (np.array(V0, order="F"), np.array(V1, order="F"), margin, candidates)
        self.broad_phases += 1
        self._clock("collisions", t0)
        return candidates

    def candidate_groups(self) -> tuple[np.ndarray, np.ndarray]:
        """The vertices of the broad phase's candidate pairs at hand: (G, 4) vertex indices, each pair's first
        primitive's then its second's, and (G,) how many of the four are the first's (a face and a vertex: 3; two
        edges: 2)."""
        candidates = self._kept[3]
        mesh = self.mesh.mesh
        E, F = np.asarray(mesh.edges, np.int64), np.asarray(mesh.faces, np.int64)
        fv = np.array([(c.face_id, c.vertex_id) for c in candidates.fv_candidates], np.int64).reshape(-1, 2)
        ee = np.array([(c.edge0_id, c.edge1_id) for c in candidates.ee_candidates], np.int64).reshape(-1, 2)
        groups = np.concatenate([np.column_stack([F[fv[:, 0]], fv[:, 1]]), np.column_stack([E[ee[:, 0]], E[ee[:, 1]]])])
        return groups, np.concatenate([np.full(len(fv), 3), np.full(len(ee), 2)])

    def reserve(self) -> tuple[np.ndarray, np.ndarray]:
        """The couplings (rows, columns of the coordinate-blocked (3 ndof, 3 ndof) matrix) the Hessian may have within
        the step: those of every candidate pair of the broad phase at hand, between the sheet's degrees of freedom
        (each vertex's by W). Newton's matrix grows its pattern by them where it must grow anyway, so that it grows
        again only when the pairs in reach move on (:meth:`deformable.algebra.upper.FreeUpper.assemble`)."""
        if self._kept is None:
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
        if len(self._kept) == 4:
            groups, _ = self.candidate_groups()
            a, b = np.repeat(groups, 4, axis=1).ravel(), np.tile(groups, (1, 4)).ravel()
            keep = (a < self.P) & (b < self.P) & (a < b)  # the sheet's vertices: the obstacles' are held
            ones = np.ones(int(np.count_nonzero(keep)))
            S = sp.csr_matrix((ones, (a[keep], b[keep])), shape=(self.P, self.P))
            W = self.mesh.points.W
            D = (W.T @ (S + S.T) @ W).tocoo()  # the couplings of the pairs' degrees of freedom
            r, c = D.row.astype(np.int64), D.col.astype(np.int64)
            i, j = np.meshgrid(np.arange(3), np.arange(3), indexing="ij")
            self._kept = (*self._kept, ((i.ravel()[:, None] * self.n + r).ravel(),
                                        (j.ravel()[:, None] * self.n + c).ravel()))
        return self._kept[4]

    def _collisions(self, V):
        t0 = time.perf_counter()
        candidates = self._candidates(V)
        collisions = ipctk.NormalCollisions()
        collisions.use_area_weighting = True
        collisions.build(candidates, self.mesh.mesh, V, self.dhat, self.dmin)
        self._clock("collisions", t0)
        return collisions

    def _at(self, x):
        """The vertices and the barrier's collisions of a flat state x, kept for the next call at the same x
        (energy, gradient and Hessian at one iterate build them once)."""
        x = np.asarray(x, float)
        if self._last is not None and np.array_equal(self._last[0], x):
            return self._last[1], self._last[2]
        V = self.vertices(x)
        collisions = self._collisions(V)
        self._last = (x.copy(), V, collisions)
        return V, collisions

    def _start(self, x):
        """The vertices at the step's start x (flat) and their barrier's collisions, kept for the next call at the
        same x (a subclass's own use of them at the start, then the friction's, build them once)."""
        x = np.asarray(x, float)
        if self._starts is None or not np.array_equal(self._starts[0], x):
            V = self.start_vertices(x)
            self._starts = (x.copy(), V, self._collisions(V))
        return self._starts[1], self._starts[2]

    def _sheet(self, g) -> np.ndarray:
        """The toolkit's gradient over the mesh (3 V,) -> the degrees of freedom (3 ndof,): the sheet's rows by W^T."""
        return self.WvT @ np.asarray(g).ravel()[:3 * self.P]

    # -- friction ------------------------------------------------------------------------
    def lag(self, x, dt: float) -> None:
        """Freeze the friction at the step's start x (flat), step dt (s): each pair's normal force and tangent basis
        there, and the smoothing length eps_x = eps_v dt (module docstring). Nothing without friction."""
        self._lagged = None
        self._kept = None  # a broad phase of its own for every step, built where the step first asks
        self.begin(x)
        if self.friction == 0:
            return
        if isinstance(dt, bool) or not isinstance(dt, (int, float)) or not (math.isfinite(dt) and dt > 0):
            raise ValueError(f"{type(self).__name__}.lag: the step dt must be a positive finite number (s), got "
                             f"{dt!r}")
        V, collisions = self._start(x)
        if len(collisions) == 0:
            return
        t0 = time.perf_counter()
        tangential = ipctk.TangentialCollisions()
        tangential.build(self.mesh.mesh, V, collisions, self.barrier, self.friction)
        self._clock("collisions", t0)
        if len(tangential):
            self._lagged = (tangential, np.array(V, order="F"), ipctk.FrictionPotential(self.slip * dt))

    def begin(self, x) -> None:
        """A subclass's own work at a step's start x (flat), before the friction is frozen: nothing here."""

    def _slip(self, V) -> np.ndarray:
        """The vertices' displacements U = V - V_n since the lagged start (m), as the IPC Toolkit takes them."""
        return np.asfortranarray(V - self._lagged[1])

    # -- the potential ------------------------------------------------------------------
    def energy(self, x) -> float:
        """S(x) + D(x) (J); +inf where a pair is not more than the thickness apart. Two triangles cannot cross at an
        x the solvers ask about: each is the end of a step cut short by :meth:`max_step` from a state that does not
        cross (the intersection test, :meth:`deformable.contact.selfmesh.ContactMesh.intersects`, is the
        measurements' and the run's start's)."""
        V, collisions = self._at(x)
        t0 = time.perf_counter()
        try:
            if len(collisions) and collisions.compute_minimum_distance(self.mesh.mesh, V) <= self.dmin * self.dmin:
                return math.inf
            e = float(self.barrier(collisions, self.mesh.mesh, V))
            if self._lagged is not None:
                tangential, _, friction = self._lagged
                e += float(friction(tangential, self.mesh.mesh, self._slip(V)))
            return e
        finally:
            self._clock("barrier", t0)

    def gradient(self, x) -> np.ndarray:
        """grad (S + D), flat (3 ndof,) (N)."""
        V, collisions = self._at(x)
        if len(collisions) == 0 and self._lagged is None:
            return self._zeros.copy()
        t0 = time.perf_counter()
        g = np.asarray(self.barrier.gradient(collisions, self.mesh.mesh, V)).ravel() if len(collisions) else 0.0
        if self._lagged is not None:
            tangential, _, friction = self._lagged
            g = g + np.asarray(friction.gradient(tangential, self.mesh.mesh, self._slip(V))).ravel()
        self._clock("barrier", t0)
        return self._sheet(g)

    def hessian(self, x) -> sp.csr_matrix:
        """The Hessian of S + D with each pair's part projected onto the positive semi-definite cone, (3 ndof, 3
        ndof) (N/m). Its pattern follows the pairs in contact and the friction's lagged pairs (no entries without
        one)."""
        V, collisions = self._at(x)
        if len(collisions) == 0 and self._lagged is None:
            return sp.csr_matrix((3 * self.n, 3 * self.n))
        t0 = time.perf_counter()
        clamp = ipctk.PSDProjectionMethod.CLAMP
        H = sp.csr_matrix(self.barrier.hessian(collisions, self.mesh.mesh, V, clamp)) if len(collisions) else None
        if self._lagged is not None:
            tangential, _, friction = self._lagged
            F = sp.csr_matrix(friction.hessian(tangential, self.mesh.mesh, self._slip(V), clamp))
            H = F if H is None else H + F
        m = 3 * self.P
        if H.shape[0] > m:  # prescribed vertices: not degrees of freedom
            H = H[:m, :m]
        H = (self.WvT @ H @ self.Wv).tocsr()
        self._clock("hessian", t0)
        return H

    # -- the collision-free step -------------------------------------------------------------
    def free_fraction(self, V0, V1, collisions=None) -> float:
        """The collision-free fraction in [0, 1] of the straight motion from vertices V0 to V1 (no pair within the
        thickness on the way): 1 where a conservative bound shows it (module docstring, "The collision-free step";
        ``collisions``: the barrier's at V0, when known), else the toolkit's CCD over the candidates."""
        V0, V1 = np.asfortranarray(V0), np.asfortranarray(V1)
        candidates = self._candidates(V0, V1)
        t0 = time.perf_counter()
        try:
            if len(candidates) == 0:
                return 1.0
            motion = 2.0 * np.sqrt(np.sum((V1 - V0) ** 2, axis=1))
            if collisions is not None:  # every vertex is at least min(dhat, closest - dmin) from every pair it is in
                closest = math.sqrt(collisions.compute_minimum_distance(self.mesh.mesh, V0)) if len(collisions) \
                    else math.inf
                if float(np.max(motion)) <= SAFE_FRACTION * min(self.dhat, closest - self.dmin):
                    self.bounded += 1
                    return 1.0
            safe = candidates.compute_per_vertex_safe_distances(self.mesh.mesh, V0, math.inf, self.dmin)
            if np.all(motion <= SAFE_FRACTION * np.asarray(safe)):
                self.bounded += 1
                return 1.0
            self.ccd_calls += 1
            return float(candidates.compute_collision_free_stepsize(self.mesh.mesh, V0, V1, self.dmin, self.ccd))
        finally:
            self._clock("ccd", t0)

    def max_step(self, x, dx) -> float:
        """The fraction in (0, 1] of the step dx (flat) that x may take with no pair coming closer than the
        thickness on the way (``margin`` of the collision-free fraction when that is below 1)."""
        x = np.asarray(x, float)
        last = self._last
        collisions = last[2] if last is not None and np.array_equal(last[0], x) else None
        alpha = self.free_fraction(self.vertices(x), self.vertices(x + np.asarray(dx, float)), collisions)
        return 1.0 if alpha >= 1.0 else self.margin * alpha
