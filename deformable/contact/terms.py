"""A scene's contact terms in one potential: the obstacles' barrier and friction, the sheet's self-contact barrier.

Newton's method (:mod:`deformable.solve.newton`) sees one contact term of the potential
(:class:`deformable.solve.potential.FlatEnergy` holds it) and one direction filter; :class:`ContactTerms` is both,
over whichever parts the scene has:

- the analytic obstacles (:class:`deformable.contact.potential.ContactPotential`): barrier and lagged friction,
  their Hessian on a fixed pattern, the exact safe step, the contact normals solved against the barrier
  (``propose``);
- the mesh obstacles (:class:`deformable.contact.meshpotential.MeshObstaclePotential`): the barrier between the
  sheet's triangles and theirs, the collision-free step of continuous collision detection, and a moving obstacle's
  prescribed motion over the step;
- the sheet against itself (``Contact(self_distance=...)``,
  :class:`deformable.contact.selfpotential.SelfContactPotential`): the barrier on the contact mesh and the
  collision-free step. The last two have Hessians whose pattern follows the pairs in contact
  (:meth:`ContactTerms.loose_hessians`).

Every direction is clipped to the smallest of the safe steps (:meth:`ContactTerms.max_step`), so no iterate carries
a contact point into an obstacle or a fold through the sheet (Li et al. 2020, "Incremental Potential Contact", ACM
TOG 39(4), section 4). The start of each implicit step is made safe the same way (:meth:`ContactTerms.safe_start`).
"""

from __future__ import annotations

import numpy as np

from ..errors import StepRejected

from .barrier import barrier_derivative
from .meshpotential import MeshObstaclePotential
from .potential import ContactPotential
from .selfpotential import SelfContactPotential
from .trianglebarrier import motion_stiffness
from .settings import REST_FRACTION, weight_per_area

__all__ = ["ContactTerms"]


class ContactTerms:
    """The barrier (and friction) of a scene's obstacles and of the sheet against itself (module docstring).

    Parameters
    ----------
    model : Backend whose scene has obstacles, or a ``Contact(self_distance=...)``, with the barrier method

    Attributes
    ----------
    obstacles : ContactPotential or None
        The analytic obstacles' barrier and friction (None without them).
    meshes : MeshObstaclePotential or None
        The mesh obstacles' barrier and friction (None without them).
    sheet : SelfContactPotential or None
        The self-contact barrier and friction (None without ``Contact.self_distance``).
    blocked : int
        The steps :meth:`safe_start` rejected: their prescribed motion alone (held degrees of freedom, moving mesh
        obstacles) would have pressed the sheet through itself or an obstacle through the sheet.
    """

    def __init__(self, model):
        scene = model.scene
        settings = scene.contact
        self.n = model.ndof
        analytic = [o for o in scene.obstacles if o.analytic]
        meshes = [o for o in scene.obstacles if not o.analytic]
        self.obstacles = ContactPotential(model) if analytic else None
        self.meshes = None
        if meshes:  # the pressure under which the sheet rests at dhat / 10 is the analytic obstacles' (settings)
            d = settings.distance
            pressure = settings.barrier_stiffness(weight_per_area(scene)) * -float(
                barrier_derivative(np.array([REST_FRACTION * d]), d)[0])
            limit = motion_stiffness(float(np.max(scene.nodal_material().mu)), settings.self_speed, d)
            self.meshes = MeshObstaclePotential(model, meshes, d, pressure, limit, settings.margin, settings.friction,
                                                settings.slip)
        self.sheet = None
        if settings.self_distance is not None:
            self.sheet = SelfContactPotential(model, settings.self_distance, settings.self_stiffness,
                                              settings.margin, settings.thickness, settings.self_speed,
                                              friction=settings.self_friction, slip=settings.slip)
        self._parts = [p for p in (self.obstacles, self.meshes, self.sheet) if p is not None]
        self._loose = [p for p in (self.meshes, self.sheet) if p is not None]
        self.blocked = 0

    @property
    def step_test(self) -> bool:
        """Whether Newton's step test may end a solve (:mod:`deformable.solve.newton`, "Convergence tests"): not
        with analytic obstacles, whose proposals (:meth:`propose`) change Newton's directions; the CCD parts (mesh
        obstacles, self-contact) only cut a direction short, and a direction cut short ends no solve."""
        return self.obstacles is None

    def energy(self, x) -> float:
        """The barriers' and the friction's energy (J); +inf where a point is not outside an obstacle, the sheet
        crosses a mesh obstacle or itself (or comes closer to itself than its thickness)."""
        return sum(p.energy(x) for p in self._parts)

    def gradient(self, x) -> np.ndarray:
        """Their gradient, flat (3 ndof,) (N)."""
        g = self._parts[0].gradient(x)
        for p in self._parts[1:]:
            g = g + p.gradient(x)
        return g

    def hessian(self, x, kind: str = "newton"):
        """The obstacles' Hessian on its fixed pattern (3 ndof, 3 ndof) (N/m), None without obstacles."""
        return None if self.obstacles is None else self.obstacles.hessian(x, kind)

    def loose_hessians(self, x) -> list:
        """The mesh obstacles' and the self-contact's positive semi-definite Hessians (3 ndof, 3 ndof) (N/m), whose
        patterns change with the pairs in contact (none without either)."""
        return [p.hessian(x) for p in self._loose]

    def reserve(self) -> tuple[np.ndarray, np.ndarray]:
        """The couplings the loose Hessians may have within the step (rows, columns of the (3 ndof, 3 ndof) matrix):
        :meth:`deformable.contact.trianglebarrier.TriangleBarrier.reserve` of each part."""
        parts = [p.reserve() for p in self._loose]
        return tuple(np.concatenate([q[k] for q in parts]) if parts else np.zeros(0, np.int64) for k in (0, 1))

    def memory(self) -> dict:
        """What the contact carries from step to step besides the state (the mesh obstacles' adapted stiffness,
        :meth:`MeshObstaclePotential.memory`), for a checkpoint; {} when nothing."""
        return {} if self.meshes is None else self.meshes.memory()

    def recall(self, memory: dict) -> None:
        """Take up :meth:`memory` of another instance of the same run."""
        if self.meshes is not None and memory:
            self.meshes.recall(memory)

    def lag(self, x, dt: float, t: float | None = None) -> None:
        """Freeze the friction (the obstacles' and the sheet's against itself) at the step's start x (flat), step dt
        (s) ending at t (s): the moving mesh obstacles stand where they are at t (default: where they stand)."""
        if self.meshes is not None and t is not None:
            self.meshes.move(t - dt, t)
        for p in self._parts:
            p.lag(x, dt)

    def safe_start(self, x, dx, held=None) -> np.ndarray:
        """A point between x and x + dx (flat) that keeps every contact point outside every analytic obstacle (per
        degree of freedom, :meth:`ContactPotential.safe_start`), the sheet clear of the mesh obstacles where they
        stand at the step's end, and clear of itself.

        ``held`` (int array): the degrees of freedom a constraint prescribes, whose part of dx is their prescribed
        motion over the step; they move all of it. The whole step first, everything moving together: taken where it
        is collision-free. Else, against the meshes and the sheet, that prescribed motion and the mesh obstacles'
        own come first, with the sheet within reach of a moving obstacle, or of its own moving held part, carried
        along (:meth:`MeshObstaclePotential.carry`, :meth:`SelfContactPotential.carry`); the others then take one
        fraction of the rest of the way. When even that would press the sheet through itself or an obstacle through
        the sheet (or within the thickness), StepRejected: the time stepper retries a shorter step (:attr:`blocked`
        counts these).
        """
        dx = np.asarray(dx, float)
        x1 = x + dx if self.obstacles is None else self.obstacles.safe_start(x, dx)
        held = np.zeros(0, np.int64) if held is None else np.asarray(held, np.int64)
        x1[held] = x[held] + dx[held]
        if not self._loose:
            return x1
        if min(1.0 if self.meshes is None else self.meshes.prescribed_step(x, x1 - x),
               1.0 if self.sheet is None else self.sheet.max_step(x, x1 - x)) >= 1.0:
            return x1  # the whole step, the held degrees of freedom and the obstacles moving with it, is collision-free
        moved = np.zeros_like(dx)
        moved[held] = dx[held]
        first = np.zeros(dx.size, bool)  # what moves first: the held degrees of freedom, and what obstacles carry
        first[held] = True
        if self.meshes is not None and self.meshes.prescribed_step(x, moved) < 1.0:
            carried = self.meshes.carry(x, moved, held) - x  # the sheet near a moving obstacle rides with it
            if self.meshes.prescribed_step(x, carried) < 1.0:
                self.blocked += 1
                raise StepRejected("the prescribed motion of a mesh obstacle (or of the held degrees of freedom) "
                                   "would strike the sheet within this step")
            first |= carried != 0
            moved = carried
        if self.sheet is not None and np.any(moved) and self.sheet.max_step(x, moved) < 1.0:
            carried = self.sheet.carry(x, moved, held)  # the sheet pushed by its held part rides with it
            if self.sheet.max_step(x, carried) < 1.0:
                self.blocked += 1
                raise StepRejected("the prescribed motion of the held degrees of freedom (or of a mesh obstacle) would "
                                   "press the sheet through itself (or within its thickness) within this step")
            first |= carried != 0
            moved = carried
        xh = x + moved
        rest = x1 - x
        rest[first] = 0.0
        return xh + min(p.max_step(xh, rest) for p in self._loose) * rest

    # -- the direction filter (deformable.solve.newton.DirectionFilter) ---------------------------------------
    def max_step(self, x, dx) -> float:
        """The largest fraction in (0, 1] of dx that keeps every part's guarantee: the smallest of their safe steps."""
        alpha = 1.0
        for p in self._parts:
            alpha = min(alpha, p.max_step(x, alpha * np.asarray(dx)) * alpha)
        return alpha

    def propose(self, x, dx, stiffness) -> np.ndarray:
        """The obstacles' proposal (their contact normals solved against the barrier), else dx itself."""
        return dx if self.obstacles is None else self.obstacles.propose(x, dx, stiffness)

    def hessian_diagonal(self) -> np.ndarray:
        """The diagonal of the obstacles' Hessian as last assembled (3 ndof,) (N/m): what :meth:`propose`'s 1-D
        models leave out of the Newton matrix (the self-contact's stays in, as the rest of the matrix)."""
        return np.zeros(3 * self.n) if self.obstacles is None else self.obstacles.hessian_diagonal()
