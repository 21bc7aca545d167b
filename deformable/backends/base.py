r"""The base under the backend contract: what every discretisation writes alike, written once.

:class:`BackendBase` stands under the backends as scikit-fem's ``AbstractBasis`` stands under its bases: it holds
the contract's methods (:class:`~deformable.backends.contract.Backend`) that read the discretisation only through
a few hooks, and a backend subclasses it and writes those hooks, the geometry and the quadrature that are its own.
"""

from __future__ import annotations

import abc
from typing import ClassVar

import numpy as np
import scipy.sparse as sp

from ..physics.energy import Energy, kinetic_energy
from ..physics.force_models import ForceModel
from ..physics.loads import Loads
from ..scene.constraints import hold
from ..scene.scene import Scene
from .contract import EdgeRule, Patches, Sample
from .registry import Discretisation, check_scene

__all__ = ["BackendBase"]


class BackendBase(abc.ABC):
    """A backend's common part; a subclass that writes the hooks below satisfies :class:`deformable.Backend`.

    A new backend is a package of three modules, ``__init__.py``, ``model.py`` (a subclass of this class) and
    ``backend.py`` (its descriptor, a :class:`~deformable.backends.Discretisation` whose ``model`` is that class),
    and one entry point of the group ``deformable.backends`` in its pyproject.toml: four files, nothing of the
    core. Its model writes:

    - ``__init__(scene, **options)``: ``super().__init__(scene)`` first (it checks the scene against the
      descriptor's memory estimate and sets ``scene``, ``force_model``, ``linear``, the node grid ``M``, ``N``,
      ``h1``, ``h2``, ``spacing`` and ``contact_samples``), then the contract's ``ndof``, ``value_dofs``,
      ``points``, ``mu``; the Material's tensor fields at the points, ``fields`` (``eta`` among them, the
      stable step's); ``strength``, whose ``matrix(alpha, beta)`` is K(r); the mass and damping matrices
      ``_M``, ``_C``; the energy (13) ``_energy`` (``energy``, ``gradient``, ``hessian`` and ``elements`` of a
      state, e.g. :class:`~deformable.physics.force_models.QuadraticEnergy`); for a linear force model the
      fixed coefficients by :meth:`_fix_coefficients`, for the others the rest tensors ``G0``, ``B0`` at the
      points; last :meth:`_complete`, with the degrees of freedom each constraint holds;
    - the geometry: :meth:`discretize`, :meth:`grid`, :meth:`tensors`, :meth:`sample`;
    - the quadrature the loads integrate by: :meth:`integrate`, :meth:`at_points`, :meth:`density_matrix`,
      :meth:`edge_rule`, :meth:`patches`, and :meth:`_point_weights` (r at parameter points);
    - :meth:`_strain_tensors`, G and B where the strength matrix's alpha and beta are formed (eq. (15));
    - optionally :meth:`_affine_force`, a force K(r) R leaves out (None by default).

    What it inherits, written here once: :meth:`initial_state`; the system (21) :meth:`stiffness`,
    :meth:`mass`, :meth:`damping`, :meth:`load`, :meth:`internal_force`, :meth:`fixed_dofs`,
    :meth:`prescribed`, :meth:`stable_step`; the energy :meth:`energy`, :meth:`kinetic_energy`,
    :meth:`energy_gradient`, :meth:`energy_hessian`, :meth:`energy_elements`; :meth:`point_dofs` and
    :meth:`point_matrix` over :meth:`_point_weights`; and :meth:`alpha_beta`.

    Class attributes
    ----------------
    descriptor : type
        The backend's :class:`~deformable.backends.Discretisation`, set when it is defined (``model = ...``).
    point_tolerance : float
        Entries of :meth:`point_matrix` below it in magnitude are dropped (round-off where the basis vanishes
        exactly); 0: none.
    """

    descriptor: ClassVar[type[Discretisation]]
    point_tolerance: ClassVar[float] = 0.0

    def __init__(self, scene: Scene):
        check_scene(scene, self.descriptor)  # a Scene whose grid fits in memory, before anything is allocated
        self.scene = scene
        self.force_model = scene.force_model
        self.linear = self.force_model.linear
        self.M, self.N = scene.sheet.nodes
        self.h1, self.h2 = self.spacing = scene.sheet.h
        self.contact_samples = self.descriptor.contact_samples

    def _fix_coefficients(self) -> None:
        """A linear force model's alpha and beta (``alpha_fixed``, ``beta_fixed``) and its constant K
        (``_K_const``), from ``fields`` and ``strength``."""
        self.alpha_fixed, self.beta_fixed = self.force_model.coefficients(self.fields.__getitem__,
                                                                          None, None, None, None)
        self._K_const = self.strength.matrix(self.alpha_fixed, self.beta_fixed)

    def _complete(self, node_dofs, edge_dofs, clamp_dofs, symmetry_dofs=None) -> None:
        """The last step of a subclass's ``__init__``, once its hooks work: the scene's constraints on its degrees
        of freedom (:func:`deformable.scene.constraints.hold`, whose callables these are) and its loads."""
        self._held = hold(self.scene, self.ndof, node_dofs=node_dofs, edge_dofs=edge_dofs, clamp_dofs=clamp_dofs,
                          symmetry_dofs=symmetry_dofs)
        self.loads = Loads(self)

    def _check_state(self, X, name: str = "X") -> np.ndarray:
        """X as a float array of the state's shape (ndof, 3); ValueError naming it otherwise."""
        X = np.asarray(X, float)
        if X.shape != (self.ndof, 3):
            raise ValueError(f"{name} has shape {X.shape}, expected ({self.ndof}, 3)")
        return X

    # -- the hooks: what each backend writes ------------------------------------------
    @abc.abstractmethod
    def discretize(self, surface) -> np.ndarray:
        """The degrees of freedom of a surface (or a callable (a1, a2) -> (..., 3)): X (ndof, 3)."""

    @abc.abstractmethod
    def grid(self, X: np.ndarray) -> np.ndarray:
        """Node positions, (M, N, 3)."""

    @abc.abstractmethod
    def tensors(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """G and B at the backend's points, two (2, 2, *pts) arrays."""

    @abc.abstractmethod
    def sample(self, X: np.ndarray, a: np.ndarray) -> Sample:
        """r, G, B at parameter points a (P, 2)."""

    @abc.abstractmethod
    def integrate(self, density: np.ndarray) -> np.ndarray:
        """A density (N/m^2) at the points, (*pts, 3), integrated against each degree of freedom: (ndof, 3) (N)."""

    @abc.abstractmethod
    def at_points(self, X: np.ndarray, d: tuple[int, int] = (0, 0)) -> np.ndarray:
        """r (d = (0, 0)) or its derivative r_1 (1, 0), r_2 (0, 1) at the points, (P, 3)."""

    @abc.abstractmethod
    def density_matrix(self, c: np.ndarray) -> sp.csr_matrix:
        """integral c phi_k phi_l, (ndof, ndof), for a field c at the points."""

    @abc.abstractmethod
    def edge_rule(self, name: str) -> EdgeRule:
        """The quadrature along the edge called ``name``."""

    @abc.abstractmethod
    def patches(self) -> Patches:
        """The points grouped by the degrees of freedom they read."""

    @abc.abstractmethod
    def _point_weights(self, a, what: str) -> tuple[np.ndarray, np.ndarray]:
        """The degrees of freedom r at parameter points a (P, 2) reads and their weights, two (P, k) arrays:
        r(a_p) = sum_k weights[p, k] X[dofs[p, k]]; ``what`` named in the ValueError for a point outside."""

    @abc.abstractmethod
    def _strain_tensors(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """G and B where the strength matrix's alpha and beta are formed (eq. (15)), two (2, 2, *pts) arrays."""

    def _affine_force(self, X: np.ndarray) -> np.ndarray | None:
        """A force (ndof, 3) that K(r) R leaves out of the internal force, subtracted from :meth:`load`; None."""
        return None

    # -- geometry ---------------------------------------------------------------------
    def initial_state(self) -> np.ndarray:
        """The sheet's initial shape, (ndof, 3)."""
        return self.discretize(self.scene.sheet.initial)

    def alpha_beta(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """alpha_ij and beta_ij of eq. (15) where :meth:`_strain_tensors` stands, two (2, 2, *pts) arrays."""
        if self.linear:
            return self.alpha_fixed, self.beta_fixed
        G, B = self._strain_tensors(X)
        return self.force_model.coefficients(self.fields.__getitem__, G, self.G0, B, self.B0)

    def point_dofs(self, a, what: str = "point") -> tuple[np.ndarray, np.ndarray]:
        """The degrees of freedom r at parameter point a reads and their weights: r(a) = w . X[dofs].

        ``what`` is named in the ValueError for a point outside the sheet.
        """
        dofs, w = self._point_weights(np.asarray(a, float)[None], what)
        return dofs[0], w[0]

    def point_matrix(self, a) -> sp.csr_matrix:
        """r at parameter points a (P, 2) as a sparse (P, ndof) matrix: ``r(a) = W @ X``."""
        dofs, w = self._point_weights(a, "points")
        P, k = dofs.shape
        W = sp.csr_matrix((w.ravel(), (np.repeat(np.arange(P), k), dofs.ravel())), shape=(P, self.ndof))
        if self.point_tolerance:
            W.data[np.abs(W.data) < self.point_tolerance] = 0.0
        W.eliminate_zeros()
        return W

    # -- the semi-discrete system (21) --------------------------------------------------
    def stiffness(self, X: np.ndarray) -> sp.csr_matrix:
        """The strength matrix K(r), (ndof, ndof), symmetric, on a fixed pattern (N/m).

        Defined for the force models with one (tpbf87, frozen); the others couple the coordinates and have
        :meth:`energy_hessian` instead (InputError).
        """
        if self.linear:
            return self._K_const
        self.force_model.require_strength_matrix()
        return self.strength.matrix(*self.alpha_beta(X))

    def mass(self) -> sp.csr_matrix:
        """M of eq. (21) (kg)."""
        return self._M

    def damping(self) -> sp.csr_matrix:
        """C of eq. (21) (kg/s)."""
        return self._C

    def load(self, X: np.ndarray, t: float, V: np.ndarray | None = None) -> np.ndarray:
        """F of eq. (21) at time t, (ndof, 3) (N): the scene's loads integrated by the hooks
        (:mod:`deformable.physics.loads`; wind with the velocities V, None: at rest), less :meth:`_affine_force`."""
        X = self._check_state(X)
        F = self.loads.total(X, t, V)
        f = self._affine_force(X)
        return F if f is None else F - f

    def internal_force(self, X: np.ndarray) -> np.ndarray:
        """The internal force (N), (ndof, 3): K(r) R (tpbf87, frozen), or the energy gradient."""
        if not self.force_model.has_strength_matrix:
            return self.energy_gradient(X)
        return self.stiffness(X) @ self._check_state(X)

    def fixed_dofs(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Indices of the held degrees of freedom of x, y and z."""
        return self._held.fixed

    def prescribed(self, X0: np.ndarray, t: float) -> np.ndarray:
        """X0 with the held degrees of freedom at their values at time t (pins' motions), (ndof, 3)."""
        return self._held.prescribed(self._check_state(X0, "X0"), t)

    def stable_step(self, force_model=None) -> float:
        """The stretching bound of the semi-implicit step (s), about h sqrt(mu / (2 eta)) for tpbf87 scaled by the
        descriptor's membrane eigenvalue, else inf; under ``force_model`` (a registered name or instance), when
        given, instead of the sheet's own."""
        fm = self.force_model if force_model is None else ForceModel.of(force_model)
        return fm.stable_step(self.mu, self.eta, self.spacing, self.descriptor.membrane_eigenvalue)

    # -- the energy (13) ------------------------------------------------------------------
    def energy(self, X: np.ndarray) -> Energy:
        """The elastic energy (J): eq. (13) by the backend's rule (tpbf87, variational), R^T K R / 2 (frozen)."""
        return self._energy.energy(self._check_state(X))

    def kinetic_energy(self, V: np.ndarray) -> float:
        """The kinetic energy V^T M V / 2 (J)."""
        return kinetic_energy(self._M, self._check_state(V, "V"))

    def energy_gradient(self, X: np.ndarray) -> np.ndarray:
        """The exact gradient of the discrete energy, (ndof, 3) (N); frozen: K R. The tpbf87 force (14) is not a
        gradient (InputError)."""
        self.force_model.require_energy()
        return self._energy.gradient(self._check_state(X))

    def energy_hessian(self, X: np.ndarray, kind: str = "newton") -> sp.csr_matrix:
        """The Hessian of the discrete energy, (3 ndof, 3 ndof), coordinates in blocks (index a ndof + k).

        ``kind`` "newton" (exact) or "gauss-newton" (positive semi-definite), on a fixed pattern; the frozen
        model's is K's block diagonal whatever the kind.
        """
        self.force_model.require_energy()
        return self._energy.hessian(self._check_state(X), kind)

    def energy_elements(self, X: np.ndarray, kind: str = "newton"):
        """The Hessian of :meth:`energy_hessian` as element upper triangles and their pattern: ((E, nu) array,
        :class:`deformable.algebra.elements.SymmetricElements`), or None where the energy has no elements (the
        frozen model's constant matrix). What Newton's method assembles its matrix from
        (:class:`deformable.algebra.upper.FreeUpper`)."""
        self.force_model.require_energy()
        return self._energy.elements(self._check_state(X), kind)
