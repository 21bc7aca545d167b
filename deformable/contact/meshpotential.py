"""The sheet against triangle-mesh obstacles: their joint contact mesh and barrier (the IPC Toolkit, ``ipctk``).

A :class:`deformable.contact.meshobstacle.MeshObstacle` has no signed distance, so the sheet meets it as it meets
itself (:mod:`deformable.contact.selfpotential`), primitive against primitive, on one IPC Toolkit mesh
(:class:`ObstacleMesh`): the sheet's contact mesh (:class:`deformable.contact.selfmesh.ContactMesh`'s vertices ``W
X`` and triangles) followed by every mesh obstacle's vertices and triangles. Only pairs of one sheet primitive and
one obstacle primitive may touch (the toolkit's vertex-patches filter), so an obstacle that intersects itself is
never counted. The barrier and the lagged friction are :class:`deformable.contact.trianglebarrier.TriangleBarrier`'s
on that mesh; the obstacles' rows are dropped. The friction's slip is the sheet's displacement relative to the
obstacle's own over the step, so a sheet resting on a moving obstacle is carried, not rubbed.

The stiffness. kappa (N/m^5) starts where the analytic obstacles' does (the same pressure rests the sheet at dhat /
10, :meth:`deformable.contact.settings.Contact.barrier_stiffness`): ``pressure = kappa |d b(d^2) / dd|`` at d = dhat
/ 10. A taut sheet pressed over a polyhedral corner carries a force on a point, which no pressure bounds, so kappa
adapts as in IPC (Li et al. 2020, section 4.3 and its supplement; the IPC Toolkit's ``update_barrier_stiffness``):
at a step's start whose smallest distance is below :data:`ADAPTIVE_FRACTION` of dhat and smaller than at the last
step's start (itself below it), kappa doubles, up to the self-contact's stiffness (a sheet closing at
``Contact.self_speed`` stopped at dhat / 10, :func:`deformable.contact.trianglebarrier.motion_stiffness`). Where an
obstacle moves, kappa starts at that limit.

A moving obstacle (its prescribed rigid path, :meth:`.meshobstacle.MeshObstacle.points`) stands, through an implicit
step from t_n to t_{n+1}, where it is at t_{n+1} (:meth:`MeshObstaclePotential.move`). Its motion over the step is
checked with the held degrees of freedom's prescribed motion (:meth:`MeshObstaclePotential.prescribed_step`, from
:meth:`deformable.contact.terms.ContactTerms.safe_start`): the obstacle moving along straight lines, the sheet where
it is. Where that would strike the sheet, the sheet near the obstacle rides with it
(:meth:`MeshObstaclePotential.carry`) and the check is made again; when even that strikes it, the step is rejected
and retried shorter. So a fast obstacle does not tunnel through a thin sheet between two steps.
"""

from __future__ import annotations

import math
import weakref

import ipctk
import numpy as np

from ..checks import count, real
from .points import contact_points
from .selfmesh import grid_triangles
from .settings import REST_FRACTION
from .trianglebarrier import TriangleBarrier

__all__ = ["ObstacleMesh", "MeshObstaclePotential", "obstacle_contact_mesh"]

#: IPC's adaptive stiffness: kappa doubles at a step's start whose smallest distance, below this fraction of dhat,
#: is smaller than the last step's, itself below it
ADAPTIVE_FRACTION = 1e-3


class ObstacleMesh:
    """The sheet's contact mesh and the mesh obstacles' triangles, as one IPC Toolkit mesh (module docstring).

    Parameters
    ----------
    model : Backend (with the hook ``point_matrix``)
    obstacles : sequence of MeshObstacle
    samples : int, optional
        Contact points per cell side (default: the scene's ``Contact.samples``, else the backend's own).

    Attributes
    ----------
    points : ContactPoints
        The sheet's vertices: parameter points and their map W (P, ndof).
    P : int
        The number of sheet vertices (the first P of the mesh).
    offsets : int array (K,)
        Where each obstacle's vertices start in the mesh.
    faces : int array (F, 3)
        The sheet's triangles, then each obstacle's (its indices shifted past the vertices before it).
    mesh : ipctk.CollisionMesh
    """

    def __init__(self, model, obstacles, samples: int | None = None):
        self.obstacles = tuple(obstacles)
        if not self.obstacles:
            raise ValueError("ObstacleMesh needs at least one mesh obstacle")
        self.points = contact_points(model, samples)
        self.P = self.points.W.shape[0]
        faces = [grid_triangles(self.points.shape)]
        start = self.P
        offsets = []
        for o in self.obstacles:
            offsets.append(start)
            faces.append(np.asarray(o.triangles, np.int32) + start)
            start += len(o.points())
        self.offsets = np.asarray(offsets)
        self.faces = np.asfortranarray(np.concatenate(faces).astype(np.int32))
        self.edges = np.asfortranarray(np.asarray(ipctk.edges(self.faces), dtype=np.int32))
        rest = self.vertices(model.initial_state(), 0.0)
        self.mesh = ipctk.CollisionMesh(rest, self.edges, self.faces)
        # the barrier's weights: the sheet's vertices stand for their contact points' own areas, those of the
        # analytic obstacles' barrier (FD's nodes: the areas of its mass), so that a node's barrier carries its own
        # weight (the toolkit's barycentric areas give an FD sheet's edge nodes half their weight's support)
        areas = np.array(self.mesh.vertex_areas, dtype=float)
        areas[:self.P] = self.points.area
        self.mesh.vertex_areas = areas
        patch = np.ones(len(rest), np.int32)
        patch[:self.P] = 0
        self.mesh.can_collide = ipctk.make_vertex_patches_filter(patch)

    def obstacle_vertices(self, t: float) -> np.ndarray:
        """Every obstacle's vertices at time t (s), stacked (Q, 3) (m)."""
        return np.concatenate([o.points(t) for o in self.obstacles])

    def vertices(self, X, t: float | np.ndarray) -> np.ndarray:
        """The mesh's vertices (P + Q, 3) (m) of a state X (ndof, 3), the obstacles at time t (s) or given as their
        vertices (Q, 3); Fortran-ordered as the IPC Toolkit takes them."""
        Y = self.obstacle_vertices(t) if np.ndim(t) == 0 else np.asarray(t, float)
        return np.asfortranarray(np.vstack([self.points.positions(np.asarray(X, float)), Y]))

    def intersects(self, X, t: float = 0.0) -> bool:
        """Whether a triangle of the sheet crosses a triangle of an obstacle, state X (ndof, 3) at time t (s)."""
        return bool(ipctk.has_intersections(self.mesh, self.vertices(X, t)))

    def distance(self, X, t: float = 0.0, within: float | None = None) -> float:
        """The smallest distance between the sheet's contact mesh and the obstacles' triangles (m), state X
        (ndof, 3) at time t (s); -inf where they intersect (the depth is not measured). Searched within
        ``within`` (m; default the whole extent of the mesh, in radii growing eightfold from a millionth of it, so
        that a sheet near an obstacle costs the pairs near it only): inf when nothing is closer."""
        V = self.vertices(X, t)
        if ipctk.has_intersections(self.mesh, V):
            return -math.inf
        extent = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
        radius = extent if within is None else float(within)
        reach = min(radius, 1e-6 * extent) if within is None else radius
        while True:
            collisions = ipctk.NormalCollisions()
            collisions.build(self.mesh, V, reach)
            if len(collisions):
                return math.sqrt(max(0.0, float(collisions.compute_minimum_distance(self.mesh, V))))
            if reach >= radius:
                return math.inf
            reach = min(radius, 8.0 * reach)


_MESHES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def obstacle_contact_mesh(model, obstacles=None) -> ObstacleMesh:
    """The model's :class:`ObstacleMesh` with the given mesh obstacles (default the scene's), built once per model
    and obstacles (a measurement every step does not build it again)."""
    obstacles = tuple(o for o in (model.scene.obstacles if obstacles is None else obstacles) if not o.analytic)
    cache = _MESHES.setdefault(model, {})
    key = tuple(id(o) for o in obstacles)
    if key not in cache:
        cache[key] = ObstacleMesh(model, obstacles)
    return cache[key]


class MeshObstaclePotential(TriangleBarrier):
    """The barrier (and lagged friction) between the sheet and its mesh obstacles over flat coordinate-blocked
    vectors (3 ndof,) (module docstring; the formulas: :class:`deformable.contact.trianglebarrier.TriangleBarrier`).

    Parameters
    ----------
    model : Backend
    obstacles : sequence of MeshObstacle
    distance : float
        The activation distance dhat (m).
    pressure : float
        The pressure (N/m^2) under which the sheet rests at dhat / 10: the starting kappa's (module docstring).
    limit : float
        The largest kappa (N/m^5) the adaptive rule may reach, and the start where an obstacle moves (module
        docstring).
    margin : float
        The fraction, in (0, 1), of the collision-free step that :meth:`max_step` allows.
    friction : float
        Coulomb's coefficient against the obstacles (0: frictionless).
    slip : float
        eps_v (m/s): below this tangential speed friction is smoothed.

    Attributes
    ----------
    mesh : ObstacleMesh
    kappa : float
        The barrier stiffness (N/m^5), as the adaptive rule has left it.
    raised : int
        How many times the adaptive rule has doubled kappa.
    """

    def __init__(self, model, obstacles, distance: float, pressure: float, limit: float, margin: float = 0.8,
                 friction: float = 0.0, slip: float = 1e-3):
        d0 = REST_FRACTION * distance
        stiffness = pressure / (2 * d0 * abs(ipctk.barrier_first_derivative(d0 * d0, distance * distance)))
        if any(o.moving for o in obstacles):  # an obstacle that moves strikes the sheet (module docstring)
            stiffness = max(stiffness, float(limit))
        super().__init__(model, ObstacleMesh(model, obstacles), distance, stiffness, margin, 0.0, friction, slip)
        self.value_dofs = np.asarray(model.value_dofs)
        self.limit = max(float(limit), self.kappa)
        self.raised = 0
        self.t0 = self.t1 = 0.0
        self.Y0 = self.Y1 = self.mesh.obstacle_vertices(0.0)
        self._closest = math.inf  # the smallest squared distance at the last step's start (m^2)

    def vertices(self, x, Y=None) -> np.ndarray:
        """The mesh's vertices (P + Q, 3) (m) of a flat state x, the obstacles where they stand at the step's end
        (or at Y (Q, 3))."""
        return self.mesh.vertices(np.asarray(x, float).reshape(3, self.n).T, self.Y1 if Y is None else Y)

    def start_vertices(self, x) -> np.ndarray:
        """The vertices at the step's start: the sheet at x, the obstacles where they stood at t_n (their motion
        over the step is then part of the friction's slip)."""
        return self.vertices(x, self.Y0)

    # -- the obstacles' motion --------------------------------------------------------------
    def move(self, t0: float, t1: float) -> None:
        """An implicit step from t0 to t1 (s): the obstacles stand where they are at t1; their motion from where
        they are at t0 is :meth:`prescribed_step`'s."""
        if (t0, t1) != (self.t0, self.t1):
            self.t0, self.t1 = float(t0), float(t1)
            self.Y0, self.Y1 = self.mesh.obstacle_vertices(t0), self.mesh.obstacle_vertices(t1)
            self._last = self._starts = None

    def begin(self, x) -> None:
        """At a step's start x (flat), before the friction is frozen (:meth:`TriangleBarrier.lag`): raise kappa by
        IPC's adaptive rule (module docstring)."""
        V, collisions = self._start(x)
        closest = float(collisions.compute_minimum_distance(self.mesh.mesh, V)) if len(collisions) else math.inf
        floor = (ADAPTIVE_FRACTION * self.dhat) ** 2
        if closest < floor and self._closest < floor and closest < self._closest and self.kappa < self.limit:
            self.kappa = min(self.limit, 2.0 * self.kappa)
            self.barrier = ipctk.BarrierPotential(self.dhat, self.kappa)
            self.raised += 1
            self._last = None
        self._closest = closest

    def carry(self, x, dx, held) -> np.ndarray:
        """A start x + dx (flat) in which the sheet near a moving obstacle rides with it over the step.

        Where an obstacle's own motion would strike the sheet standing still (:meth:`prescribed_step` below 1), the
        sheet must give way within the step, which a start with the sheet where it stood cannot: every step would be
        rejected down to the smallest. So the free degrees of freedom of positions (FD's nodes, FE's node values)
        whose contact points lie within the activation distance plus the obstacle's largest travel over the step
        move as that obstacle's rigid motion carries them (:meth:`.meshobstacle.MeshObstacle.carried`); the held
        ones (``held``, int array) keep their prescribed dx, and the rest keep dx. Newton's method then finds where
        the sheet goes from there.
        """
        x = np.asarray(x, float)
        out = x + np.asarray(dx, float)
        X = x.reshape(3, self.n).T
        travel = float(np.max(np.linalg.norm(self.Y1 - self.Y0, axis=1), initial=0.0))
        V = self.vertices(x, self.Y0)
        near = ipctk.NormalCollisions()
        near.build(self.mesh.mesh, V, self.dhat + travel)
        owner = np.searchsorted(self.mesh.offsets, np.arange(len(V)), side="right") - 1  # obstacle of each vertex
        which = np.full(self.P, -1, np.int64)
        for c in near:
            ids = np.asarray(c.vertex_ids(self.mesh.edges, self.mesh.faces))
            ids = ids[ids >= 0]
            sheet, obstacle = ids[ids < self.P], ids[ids >= self.P]
            if obstacle.size:
                which[sheet[which[sheet] < 0]] = owner[obstacle[0]]
        W = self.mesh.points.W
        values = np.zeros(self.n, bool)
        values[np.asarray(self.value_dofs)] = True
        blocked = np.zeros(3 * self.n, bool)
        blocked[np.asarray(held, np.int64)] = True
        for k, obstacle in enumerate(self.mesh.obstacles):
            rows = np.flatnonzero(which == k)
            if rows.size == 0 or not obstacle.moving:
                continue
            dofs = np.unique(W[rows].indices)
            dofs = dofs[values[dofs]]
            moved = obstacle.carried(X[dofs], self.t0, self.t1)
            for a in range(3):
                free = ~blocked[a * self.n + dofs]
                out[a * self.n + dofs[free]] = moved[free, a]
        return out

    def memory(self) -> dict:
        """What the adaptive rule carries from step to step (a checkpoint keeps it, so that a resumed run is the
        same run): kappa (N/m^5), the smallest squared distance at the last step's start (m^2) and the doublings."""
        return {"kappa": self.kappa, "closest": self._closest, "raised": self.raised}

    def recall(self, memory: dict) -> None:
        """Take up :meth:`memory` of another instance; InputError naming the key when a value does not fit."""
        kappa = real("memory.contact.kappa", memory.get("kappa", self.kappa), positive=True)
        closest = memory.get("closest", self._closest)
        if closest != math.inf:  # no pair within reach at the last step's start
            closest = real("memory.contact.closest", closest, non_negative=True)
        raised = count("memory.contact.raised", memory.get("raised", self.raised), minimum=0)
        self.kappa, self._closest, self.raised = kappa, closest, raised
        self.barrier = ipctk.BarrierPotential(self.dhat, self.kappa)
        self._last = None

    def prescribed_step(self, x, dx) -> float:
        """The collision-free fraction of the prescribed motion over the step: the obstacles from where they stand
        at t_n to t_{n+1} and the sheet from x to x + dx (flat; its held degrees of freedom's motion), together
        along straight lines (1: no contact on the way)."""
        x = np.asarray(x, float)
        if self.t0 == self.t1 and not np.any(dx):
            return 1.0
        return self.free_fraction(self.vertices(x, self.Y0), self.vertices(x + np.asarray(dx, float), self.Y1))
