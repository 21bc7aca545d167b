"""The self-contact barrier and friction over flat vectors, with the collision-free step (the IPC Toolkit, ``ipctk``).

On the contact mesh (:class:`deformable.contact.selfmesh.ContactMesh`: vertices ``V = W X``), every pair of
primitives that may touch (point-triangle, edge-edge; rest neighbours excluded) within the activation distance dhat
beyond the sheet's thickness dmin adds IPC's barrier, and the pairs in contact at a step's start its lagged friction
between folds (Coulomb's ``Contact.self_friction``): :class:`deformable.contact.trianglebarrier.TriangleBarrier`.
The thickness dmin (``Contact(thickness=...)``) offsets every distance: no two fold faces come closer than it.

The stiffness. kappa (N/m^5) is by default chosen from the sheet's motion, not its weight
(:func:`deformable.contact.trianglebarrier.motion_stiffness`): the kinetic energy per area of a fold closing at the
speed v (``Contact.self_speed``, 2 m/s), mu v^2 / 2, is the barrier's energy per area at a gap of dmin + dhat / 10.
The log barrier's energy grows only as ln(1/d) below dhat, so a barrier sized by the weight (as the analytic
obstacles' is) would let a fast fold into round-off distances.

In Newton's method (:mod:`deformable.solve.newton`, through :class:`deformable.contact.terms.ContactTerms`) S joins
the potential of each implicit step, its Hessian on a pattern that grows, and every direction is clipped to
:meth:`SelfContactPotential.max_step`, so no iterate passes the sheet through itself.
"""

from __future__ import annotations

import numpy as np

from .selfmesh import ContactMesh
from .settings import SELF_SPEED
from .trianglebarrier import PARTS, TriangleBarrier, motion_stiffness

__all__ = ["SelfContactPotential", "PARTS"]


class SelfContactPotential(TriangleBarrier):
    """The self-contact barrier S(x), with the lagged friction D(x) between folds, over flat coordinate-blocked
    vectors (3 ndof,) (module docstring).

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
    friction : float
        Coulomb's coefficient mu_f between folds of the sheet (0: frictionless).
    slip : float
        eps_v (m/s): below this tangential speed friction is smoothed (a creep instead of a stick); over a step dt
        the smoothing length is eps_x = eps_v dt.

    Attributes
    ----------
    mesh : ContactMesh
    kappa : float
        The barrier stiffness (N/m^5).
    seconds : dict
        Wall seconds spent in the IPC Toolkit (:class:`TriangleBarrier`): where self-contact's time goes.
    """

    def __init__(self, model, distance: float, stiffness: float | None = None, margin: float = 0.8,
                 thickness: float = 0.0, speed: float = SELF_SPEED, *, friction: float = 0.0, slip: float = 1e-3):
        mesh = ContactMesh(model, distance, thickness=thickness)
        if stiffness is None:
            stiffness = motion_stiffness(float(np.max(model.scene.nodal_material().mu)), speed, mesh.distance,
                                         mesh.thickness)
        super().__init__(model, mesh, distance, stiffness, margin, thickness, friction, slip)

    def vertices(self, x) -> np.ndarray:
        """The contact mesh's vertices (P, 3) (m) of a flat state x."""
        return self.mesh.vertices(np.asarray(x, float).reshape(3, self.n).T)

    def carry(self, x, dx, held) -> np.ndarray:
        """dx (flat) with the sheet in the way of its moving held part carried along: every vertex of a primitive
        that a candidate pair of the motion (the broad phase of x to x + dx) puts against a primitive the held
        motion moves, if it is its own degree of freedom's point (FD's nodes, FE's node values;
        :attr:`ContactPoints.owner`) and free, takes the displacement of the moving primitive's fastest vertex. A
        drawn edge pushing the sheet gathered beside it: where the held motion alone would press the sheet through
        itself, the sheet in front of it moves with it, and Newton's method finds where it goes from there
        (:meth:`deformable.contact.terms.ContactTerms.safe_start`)."""
        x, dx = np.asarray(x, float), np.asarray(dx, float)
        V0, V1 = self.vertices(x), self.vertices(x + dx)
        U = V1 - V0
        length = np.sqrt(np.sum(U * U, axis=1))
        out = dx.copy()
        if not np.any(length > 0):
            return out
        self._candidates(np.asfortranarray(V0), np.asfortranarray(V1))
        groups, first = self.candidate_groups()
        side = np.arange(4)[None, :] < first[:, None]  # the first primitive's vertices
        speed = length[groups]
        lead = np.where(side, speed, 0.0).max(axis=1), np.where(~side, speed, 0.0).max(axis=1)
        owner = self.mesh.points.owner
        blocked = np.zeros(3 * self.n, bool)
        blocked[np.asarray(held, np.int64)] = True
        for pushed, pusher in ((~side, 0), (side, 1)):  # the other primitive of a pair whose one primitive moves
            rows = np.flatnonzero(lead[pusher] > 0)
            if rows.size == 0:
                continue
            ids = groups[rows]
            fastest = ids[np.arange(rows.size), np.argmax(np.where(~pushed[rows], speed[rows], -1.0), axis=1)]
            riders, whose = ids[pushed[rows]], np.broadcast_to(fastest[:, None], ids.shape)[pushed[rows]]
            still = (length[riders] == 0) & (owner[riders] >= 0)
            for a in range(3):
                dofs = a * self.n + owner[riders[still]]
                free = ~blocked[dofs]
                out[dofs[free]] = U[whose[still][free], a]
        return out
