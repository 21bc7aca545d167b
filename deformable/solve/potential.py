"""A model's potential over flat coordinate-blocked vectors: what Newton's method minimises.

The implicit time steps (:mod:`deformable.dynamics.implicit`) and static equilibrium
(:mod:`deformable.solve.equilibrium`) minimise ``Phi(x) = (inertia and damping terms) + E(x) - F . x`` over the free
degrees of freedom. :class:`FlatEnergy` gives its elastic part E over flat vectors (index ``a * ndof + k`` for
coordinate a of degree of freedom k, the backend contract's layout): the model's energy (the exact gradient of eq.
(13), or the frozen model's quadratic energy), the scene's springs (:class:`deformable.physics.loads.Loads`) at the
time :attr:`FlatEnergy.t` and, with obstacles or self-contact, the barriers and friction
(:class:`deformable.contact.terms.ContactTerms`), with gradients and Hessians; the mass and damping in the same
layout, the applied loads and the held degrees of freedom. The self-contact's Hessian changes its pattern with the
pairs in contact (:meth:`FlatEnergy.loose_hessians`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..contact.terms import ContactTerms
from ..errors import InputError

__all__ = ["FlatEnergy", "flat", "unflat"]


def flat(X) -> np.ndarray:
    """(ndof, 3) -> coordinate blocks (3 ndof,): index a * ndof + k."""
    return np.asarray(X, float).T.ravel()


def unflat(x, n: int) -> np.ndarray:
    """Coordinate blocks (3 n,) -> (n, 3)."""
    return x.reshape(3, n).T.copy()


class FlatEnergy:
    """A model's energy, gradient, Hessian, mass, damping and load over flat coordinate-blocked vectors.

    Parameters
    ----------
    model : Backend whose force model has an energy ("variational" or "frozen"; ValueError for tpbf87)

    Attributes
    ----------
    free : bool array (3 ndof,)
        The degrees of freedom that are not held.
    fixed : int array
        The held ones.
    M, C : sparse (3 ndof, 3 ndof)
        diag(M, M, M) and diag(C, C, C).
    loads : deformable.physics.loads.Loads
        The model's external forces.
    t : float
        The time of the springs' anchors and the moments in :meth:`energy`, :meth:`gradient`, :meth:`hessian` (s).
    factor : float
        The load factor of the state-dependent loads (the edge moments; 1 but in ``equilibrium``'s load steps).
    length : float
        The grid's shortest spacing (scene units, m in the shipped scenes): an iterate that moved further than this
        is far from where a kept factorisation was made (:class:`deformable.solve.newton.Newton`).
    linear : bool
        The Newton matrix does not depend on x (the frozen model, with linear springs at most, no wind, no
        obstacles).
    contact : deformable.contact.terms.ContactTerms or None
        The barrier and friction of the scene's obstacles and the sheet's self-contact barrier (None with neither).
    filter : DirectionFilter or None
        What changes and clips Newton's directions (:class:`deformable.solve.newton.DirectionFilter`): the contact,
        when there is one; None without.
    """

    def __init__(self, model):
        self._take(model)
        self.t = 0.0
        self.factor = 1.0

    def retune(self, model) -> None:
        """Go on with ``model``: the same grid, held degrees of freedom and contact settings, other material values
        and loads (InputError otherwise); its energy, mass, damping, loads and contact terms replace these."""
        if model.ndof != self.n or not np.array_equal(self._fixed_of(model), self.fixed):
            raise InputError("retune: the new model must have the grid and the held degrees of freedom of the old",
                             field="model", value=type(model).__name__)
        self._take(model)

    @staticmethod
    def _fixed_of(model) -> np.ndarray:
        return np.concatenate([a * model.ndof + np.asarray(f, dtype=np.int64) for a, f in enumerate(model.fixed_dofs())])

    def _take(self, model) -> None:
        model.scene.force_model.require_energy()
        self.model, self.n = model, model.ndof
        self.length = float(min(model.spacing))
        I3 = sp.identity(3, format="csr")
        self.M = sp.kron(I3, model.mass(), format="csr")
        self.C = sp.kron(I3, model.damping(), format="csr")
        self.fixed = self._fixed_of(model)
        self.free = np.ones(3 * self.n, bool)
        self.free[self.fixed] = False
        self.loads = model.loads
        self.contact = None
        settings = model.scene.contact
        if model.scene.obstacles or (settings is not None and settings.self_distance is not None):
            if settings.method != "barrier":
                raise ValueError(f"contact method {settings.method!r} (the paper's exponential force) is "
                                 "for the semi-implicit scheme; the implicit schemes and equilibrium take the barrier")
            self.contact = ContactTerms(model)
        self.filter = self.contact
        self.linear = bool(model.linear and self.loads.linear and self.contact is None)

    def energy(self, x) -> float:
        """Elastic energy (13) plus the springs', moments' and the contact's (J); +inf where a contact point is not
        outside."""
        X = unflat(x, self.n)
        e = self.model.energy(X).total
        if self.contact is not None:
            e += self.contact.energy(x)
        return e + self.loads.potential_energy(X, self.t, self.factor) if self.loads.potentials else e

    def gradient(self, x, contact: bool = True) -> np.ndarray:
        """The gradient of :meth:`energy` (N); ``contact=False`` leaves the contact's out."""
        X = unflat(x, self.n)
        g = self.model.energy_gradient(X)
        g = flat(g + self.loads.potential_gradient(X, self.t, self.factor) if self.loads.potentials else g)
        return g + self.contact.gradient(x) if contact and self.contact is not None else g

    def hessian(self, x, kind: str = "newton") -> sp.csr_matrix:
        """The elastic energy's Hessian (the springs' is :meth:`extra_hessians`)."""
        return self.model.energy_hessian(unflat(x, self.n), kind)

    def hessian_elements(self, x, kind: str = "newton"):
        """The elastic energy's Hessian as the Newton matrix assembles it: (element upper triangles (E, nu), their
        :class:`deformable.algebra.elements.SymmetricElements`) where the model has elements, else (the whole
        matrix, None) (:meth:`deformable.Backend.energy_elements`)."""
        parts = self.model.energy_elements(unflat(x, self.n), kind)
        return (self.hessian(x, kind), None) if parts is None else parts

    def extra_hessians(self, x, damping=None, kind: str = "newton") -> list:
        """The matrices the Newton matrix adds to the elastic Hessian: the springs' and the contact's Hessians at x
        (the contact's of ``kind``), and ``damping``."""
        out = []
        if self.loads.potentials:
            out += self.loads.potential_hessians(unflat(x, self.n), self.t, self.factor)
        H = None if self.contact is None else self.contact.hessian(x, kind)  # None: no obstacles
        if H is not None:
            out.append(H)
        if damping is not None:
            out.append(damping)
        return out

    def loose_hessians(self, x) -> list:
        """The matrices of the Newton matrix whose pattern changes from one x to the next: the mesh obstacles' and
        the self-contact's Hessians (positive semi-definite), when the scene has them."""
        return [] if self.contact is None else self.contact.loose_hessians(x)

    def loose_reserve(self) -> tuple[np.ndarray, np.ndarray]:
        """The couplings the loose Hessians may have within the step, (rows, columns)
        (:meth:`ContactTerms.reserve`): what Newton's matrix adds to its pattern where it must grow anyway."""
        return (np.zeros(0, np.int64),) * 2 if self.contact is None else self.contact.reserve()

    def load(self, t: float) -> np.ndarray:
        """The applied loads at t (body, edge, point), flat (N)."""
        return flat(self.loads.applied(t))

    def hold(self, x, X0, t: float) -> np.ndarray:
        """A copy of flat x with the held degrees of freedom at their prescribed values at t (reference X0)."""
        x = np.array(x, dtype=float)
        x[self.fixed] = flat(self.model.prescribed(X0, t))[self.fixed]
        return x
