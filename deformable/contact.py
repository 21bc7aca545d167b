r"""Contact of the sheet with rigid obstacles: the settings, the contact points, the barrier and friction.

Contact points. The sheet touches an obstacle at a fixed set of material
points a_p (parameter coordinates): a sub-grid of the parameter rectangle with
``samples`` points per cell side, the nodes among them (:class:`ContactPoints`).
Finite differences take the nodes (samples = 1); finite elements take a
sub-grid of spacing h / 2 by default (the nodes, the element sides' midpoints
and the element centres), so that the cubic surface between nodes is covered
too. Each point maps to the degrees of freedom by a fixed sparse matrix W
(P, ndof), ``r(a_p) = W X`` (the backend hook ``point_matrix``), and stands
for an area A_p (m^2): FD's own node areas (those of its mass, so that every
node's barrier carries its own weight), the trapezoidal rule on FE's sub-grid.
Non-penetration is guaranteed at the contact points: between them the surface
may cut a curved obstacle by its chord's sag, about h^2 / (8 R) for FD's
bilinear cells of side h over a radius R (``Contact(samples=2)`` quarters it).

The barrier (implicit schemes; Li et al. 2020, "Incremental Potential
Contact", ACM TOG 39(4), eq. (6)). With d_pk the signed distance of point p
to obstacle k (:mod:`deformable.obstacles`) and the activation distance dhat,

    b(d) = -(d - dhat)^2 ln(d / dhat)   for 0 < d < dhat,   0 for d >= dhat,
    B(x) = kappa sum_pk A_p b(d_pk(x))                                    (J)

is zero beyond dhat, C2 at dhat, and grows without bound as d -> 0. kappa
(N/m^3) is a contact stiffness per unit area; by default the sheet's own
weight mu g rests at d = dhat / 10 (:meth:`Contact.barrier_stiffness`). Its
gradient is ``kappa A_p b'(d) n`` per point and its Hessian
``kappa A_p (b''(d) n n^T + b'(d) hess d)``: b'' > 0 along the normal; b' < 0
and ``hess d`` is positive semi-definite for a convex obstacle, so the second
term is negative semi-definite across it. The "definite" Hessian drops it,
which is exactly the projection of the 3 x 3 block onto the positive
semi-definite cone (``hess d n = 0``). B joins the elastic energy in the
incremental potential of each implicit step; Newton's line search never
takes a step that would carry a contact point across an obstacle: every
Newton direction is clipped to ``margin`` (0.8, as IPC) of the largest step
that keeps every point outside (:meth:`ContactPotential.max_step`, exact for
the convex obstacles here), so every iterate keeps at least (1 - margin) of
every point's gap, and the clearance stays positive at every step.

The contact normals, solved against the barrier itself
(:meth:`ContactPotential.relax`; nonlinear elimination: Lanzkron, Rose and
Wilkes 1996, "An analysis of approximate nonlinear elimination", SIAM J. Sci.
Comput. 17(2); Cai and Keyes 2002, "Nonlinearly preconditioned inexact Newton
algorithms", SIAM J. Sci. Comput. 24(1)). Newton's linear model of b is poor
within a few gaps of an obstacle (b' ~ -dhat^2 / d): a point the direction
carries towards an obstacle overshoots its equilibrium gap and is clipped
deep into the barrier, and the iterations after climb back out at Newton's
rate for a 1/d force from below, slowly (measured: the largest residual of a
step's second and third iterations sat at points 0.01 dhat from the ball,
whose equilibrium gap was 0.025 dhat). So in a time step (not in
equilibrium, where no inertia bounds the 1-D models), before the direction
is clipped, each active contact point has its normal displacement
s re-solved from a 1-D model along its normal n: the rest of the Newton
matrix by its diagonal k (inertia and elasticity, barrier excluded), the
rest's force as Newton's linear model predicts it where the direction carries
the point, and the barrier exact,

    k (s - s_N) - kappa A_p (b'(d) + b''(d) s_N) + kappa A_p b'(d + s) = 0,

s_N = n . (W dx)_p: Newton's model with the barrier's linearisation replaced
by the barrier. Its 1-D energy is convex in s; a safeguarded 1-D Newton
solves it. Newton (:mod:`deformable.newton`) keeps the direction so changed
when its step decreases the potential, else takes its own. It needs every
contact point to be a degree of freedom's own point (FD's nodes, its
default); sample points between the nodes (FE's, and FD's under
``Contact(samples > 1)``, as the ``drape`` scene's) share their degrees of
freedom, and there the direction stays Newton's. Measured on the ``sphere``
scene, FD 64 x 64 nodes starting in contact (``deformable bench``): over the
first 5 steps 3.40 -> 2.40 Newton iterations a step (221.8 -> 167.5 ms a
step), over the first 40 steps 5.60 -> 4.55 (393.8 -> 334.5 ms; there the
draped cloth's folds, away from the ball, hold Newton back); FD 32 x 32 over
the whole 1.5 s, 6.36 -> 4.81 (43.0 -> 35.4 s).

Friction (IPC section 5): lagged, smoothed Coulomb friction with coefficient
mu_f. At the start of each step (positions x_n) every active pair gets its
normal force ``lambda = -kappa A_p b'(d_n)`` (N) and an orthonormal tangent
basis T (3 x 2) of the obstacle's tangent plane at the point; both stay fixed
through the step. With the tangential displacement u = T^T (r_p(x) - r_p(x_n))
and eps_x = eps_v dt (eps_v: the slip speed below which friction is smoothed,
m/s), the dissipative potential

    D(x) = sum mu_f lambda f0(|u|),
    f0(y) = -y^3 / (3 eps_x^2) + y^2 / eps_x + eps_x / 3  (y < eps_x),  y otherwise

gives the force ``-mu_f lambda f1(|u|) T u / |u|`` with f1 = f0' (1 for
|u| >= eps_x: sliding, Coulomb's mu_f lambda; linear in |u| below: sticking,
a creep slower than eps_v). Its Hessian
``mu_f lambda T ((f1/y) I + (f1' - f1/y) / y^2 u u^T) T^T`` is positive
semi-definite.

The paper's own obstacle force (semi-implicit scheme; Terzopoulos et al. 1987,
section 4, "Collisions"): an exponential force field along the obstacle's
normal, ``f = c exp(-d / eps) n`` per unit area (c in N/m^2, eps = the
contact ``distance``), evaluated at the start of each step like the other
applied forces (:class:`Repulsion`). It is soft: a point pressed hard
enough, or arriving fast enough within one step, goes through. It does not
guarantee non-penetration, and is offered as the paper's model, not as a
contact model one can rely on.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass, fields, replace

import numpy as np
import scipy.sparse as sp

from .assembly import BlockPattern, FixedPattern
from .forces import Gravity
from .obstacles import Obstacle

__all__ = ["Contact", "METHODS", "ContactPoints", "subgrid", "ContactPotential", "Repulsion", "clearance",
           "require_outside", "contact_points",
           "barrier", "barrier_derivative", "barrier_second", "mollifier"]

METHODS = ("barrier", "exponential")
#: the barrier stiffness's default: the sheet's weight rests at this fraction of dhat
REST_FRACTION = 0.1
#: the exponential force's default strength c, in units of the sheet's weight per area
REPULSION_STRENGTH = 100.0
#: standard gravity (m/s^2): sizes the default stiffness of a scene without Gravity
STANDARD_GRAVITY = 9.81


# -- settings -----------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class Contact:
    """How the sheet meets the scene's obstacles (module docstring).

    Parameters
    ----------
    distance : float
        The activation distance dhat of the barrier (m); for the exponential
        force, its length eps.
    friction : float
        Coulomb's coefficient mu_f (0: frictionless).
    stiffness : float or None
        The barrier's kappa (N/m^3); None: the sheet's own weight rests at
        dhat / 10.
    slip : float
        eps_v (m/s): below this tangential speed friction is smoothed (a creep
        instead of a stick).
    samples : int or None
        Contact points per cell side; None: the backend's own (FD 1, the
        nodes; FE 2).
    method : "barrier" or "exponential"
        The barrier with friction (implicit schemes), or the paper's
        exponential force (semi-implicit scheme; no guarantee).
    pressure : float or None
        c of the exponential force (N/m^2); None: 100 times the sheet's weight per area.
    margin : float
        The fraction, in (0, 1), of the largest safe step a Newton step may take.
    """

    distance: float = 1e-3
    friction: float = 0.0
    stiffness: float | None = None
    slip: float = 1e-3
    samples: int | None = None
    method: str = "barrier"
    pressure: float | None = None
    margin: float = 0.8

    def __post_init__(self):
        for name in ("distance", "friction", "stiffness", "slip", "pressure", "margin"):
            v = getattr(self, name)
            if v is None and name in ("stiffness", "pressure"):
                continue
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ValueError(f"Contact.{name} must be a finite number, got {v!r}")
            if v < 0 or (v == 0 and name not in ("friction",)):
                raise ValueError(f"Contact.{name} must be {'non-negative' if name == 'friction' else 'positive'}, "
                                 f"got {v!r}")
            object.__setattr__(self, name, float(v))
        if not self.margin < 1:
            raise ValueError(f"Contact.margin must lie in (0, 1), got {self.margin!r}")
        if self.samples is not None and (isinstance(self.samples, bool) or not isinstance(self.samples, int)
                                         or self.samples < 1):
            raise ValueError(f"Contact.samples must be a positive integer or None, got {self.samples!r}")
        if self.method not in METHODS:
            raise ValueError(f"Contact.method must be one of {METHODS}, got {self.method!r}")

    @classmethod
    def from_table(cls, table, source: str = "contact", base: Contact | None = None) -> Contact:
        """Contact from a TOML table, over ``base`` (default ``Contact()``); an unknown key is a ValueError."""
        if isinstance(table, Contact):
            return table
        if not isinstance(table, dict):
            raise ValueError(f"{source} must be a table of {', '.join(f.name for f in fields(cls))}, got {table!r}")
        known = [f.name for f in fields(cls)]
        for key in table:
            if key not in known:
                raise ValueError(f"unknown key {key!r} in {source}; known keys: {', '.join(known)}")
        return replace(base, **table) if base is not None else cls(**table)

    def table(self) -> dict:
        """The settings as a TOML table (None values left out)."""
        return {f.name: getattr(self, f.name) for f in fields(self) if getattr(self, f.name) is not None}

    def barrier_stiffness(self, weight: float) -> float:
        """kappa (N/m^3): the given one, or the one under which a weight per area (N/m^2) rests at dhat / 10."""
        if self.stiffness is not None:
            return self.stiffness
        return weight / -barrier_derivative(np.array([REST_FRACTION * self.distance]), self.distance)[0]

    def repulsion_pressure(self, weight: float) -> float:
        """c (N/m^2) of the exponential force: the given one, or 100 times the weight per area."""
        return self.pressure if self.pressure is not None else REPULSION_STRENGTH * weight


def weight_per_area(scene) -> float:
    """The heaviest weight per area of the sheet, max(mu) |g| (N/m^2), standard gravity when there is none."""
    g = sum(abs(f.g) for f in scene.forces if isinstance(f, Gravity)) or STANDARD_GRAVITY
    return float(np.max(scene.material.mu)) * g


# -- the barrier and the friction mollifier -----------------------------------------------
def barrier(d: np.ndarray, dhat: float) -> np.ndarray:
    """b(d) = -(d - dhat)^2 ln(d / dhat) for d < dhat, 0 beyond, +inf for d <= 0 (m^2)."""
    d = np.asarray(d, float)
    out = np.zeros_like(d)
    on = d < dhat
    with np.errstate(divide="ignore", invalid="ignore"):
        out[on] = np.where(d[on] > 0, -(d[on] - dhat) ** 2 * np.log(d[on] / dhat), np.inf)
    return out


def barrier_derivative(d: np.ndarray, dhat: float) -> np.ndarray:
    """b'(d) = (dhat - d) (2 ln(d / dhat) - dhat / d + 1) for 0 < d < dhat, 0 beyond (m)."""
    d = np.asarray(d, float)
    out = np.zeros_like(d)
    on = d < dhat
    x = d[on]
    out[on] = (dhat - x) * (2 * np.log(x / dhat) - dhat / x + 1)
    return out


def barrier_second(d: np.ndarray, dhat: float) -> np.ndarray:
    """b''(d) = (dhat / d + 2) dhat / d - 2 ln(d / dhat) - 3 for 0 < d < dhat, 0 beyond (dimensionless)."""
    d = np.asarray(d, float)
    out = np.zeros_like(d)
    on = d < dhat
    r = dhat / d[on]
    out[on] = (r + 2) * r + 2 * np.log(r) - 3
    return out


def mollifier(y: np.ndarray, eps: float):
    """IPC's friction mollifier at tangential displacements y >= 0 (m), eps = eps_v dt (m).

    Returns f0(y) (m), f1(y) / y (1/m) and (f1'(y) - f1(y) / y) / y^2 (1/m^3), each (P,):
    the potential, and the two coefficients of its gradient ``f1/y u`` and Hessian
    ``(f1/y) I + c2 u u^T`` in the tangential displacement u, |u| = y.
    """
    y = np.asarray(y, float)
    slow = y < eps
    f0 = np.where(slow, y * y * (1 - y / (3 * eps)) / eps + eps / 3, y)
    with np.errstate(divide="ignore"):
        f1y = np.where(slow, (2 - y / eps) / eps, 1 / np.where(slow, 1.0, y))
        c2 = np.where(slow, -1 / (eps * eps * np.where(y > 0, y, 1.0)), -1 / np.where(slow, 1.0, y) ** 3)
    c2 = np.where(y > 0, c2, 0.0)
    return f0, f1y, c2


def _normal_solve(k, rest, sN, d0, w, dhat, keep, iterations: int = 30):
    """Solve ``k (s - sN) + rest + w b'(d0 + s) = 0`` for s per point (:meth:`ContactPotential.relax`).

    The left side increases with s (k >= 0, b'' > 0: the 1-D energy is convex). Newton from s = sN, each iterate
    keeping at least the fraction ``keep`` of the gap d0 + s it starts from (the start too, of d0), until every
    step is below 1e-6 of its gap. All arrays (P,) (m, N/m, N); returns s (P,) (m).
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


def tangent_basis(n: np.ndarray) -> np.ndarray:
    """An orthonormal basis (P, 3, 2) of the planes perpendicular to unit normals n (P, 3)."""
    e = np.where(np.abs(n[:, 2:3]) < 0.9, np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0]))
    t1 = np.cross(n, e)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return np.stack([t1, np.cross(n, t1)], axis=2)


# -- contact points ---------------------------------------------------------------------
def subgrid(sheet, samples: int):
    """The parameter points of a sub-grid with ``samples`` points per cell side (1: the nodes).

    Returns
    -------
    a : array (P, 2)
        The points (m), row-major on the (m, n) sub-grid.
    area : array (P,)
        The area each stands for (the trapezoidal rule, m^2), summing to L1 L2.
    shape : (m, n)
    """
    (L1, L2), (M, N) = sheet.size, sheet.nodes
    m, n = samples * (M - 1) + 1, samples * (N - 1) + 1
    w1, w2 = np.full(m, L1 / (m - 1)), np.full(n, L2 / (n - 1))
    w1[[0, -1]] *= 0.5
    w2[[0, -1]] *= 0.5
    A1, A2 = np.meshgrid(np.linspace(0.0, L1, m), np.linspace(0.0, L2, n), indexing="ij")
    return np.stack([A1.ravel(), A2.ravel()], axis=1), np.outer(w1, w2).ravel(), (m, n)


class ContactPoints:
    """The sheet's contact points: a sub-grid of the parameter rectangle, mapped to the degrees of freedom.

    Parameters
    ----------
    model : Backend (with the hook ``point_matrix``)
    samples : int
        Points per cell side (1: the nodes).

    Attributes
    ----------
    a : array (P, 2)
        Parameter coordinates (m).
    W : sparse (P, ndof)
        ``r(a_p) = W @ X``.
    owner : int array (P,)
        The degree of freedom whose own point each is (W's row is that one alone, with weight 1: FD's nodes,
        FE's at the nodes), else -1.
    area : array (P,)
        The area each point stands for (m^2): the backend's own weights where the contact points are its own
        points (FD's nodes: h1 h2, times the control-area weights when chosen), else the trapezoidal rule on
        the sub-grid (summing to L1 L2).
    """

    def __init__(self, model, samples: int):
        self.samples = samples
        self.a, self.area, self.shape = subgrid(model.scene.sheet, samples)
        own = np.stack([np.ravel(p) for p in model.points], axis=1)
        if own.shape == self.a.shape and np.allclose(own, self.a, rtol=0, atol=1e-12 * max(model.scene.sheet.size)):
            # the backend's own points (FD: the nodes): its own weights, so that each stands for what its mass does
            density = np.zeros(model.points[0].shape + (3,))
            density[..., 0] = 1.0
            self.area = model.integrate(density)[np.asarray(model.value_dofs), 0]
        W = sp.csr_matrix(model.point_matrix(self.a))
        # weights at round-off of zero (a neighbour's bilinear weight at a node, 4e-16) are zeros: a point at a node is
        # that node's alone (ContactPotential.relax needs to know)
        W.data[np.abs(W.data) <= 1e-12 * np.max(np.abs(W.data), initial=0.0)] = 0.0
        W.eliminate_zeros()
        self.W = W
        single = np.flatnonzero(np.diff(W.indptr) == 1)  # rows of one weight; weight 1: the point is its dof's own
        first = W.indptr[single]
        one = np.abs(W.data[first] - 1.0) <= 1e-12
        self.owner = np.full(W.shape[0], -1, np.int64)
        self.owner[single[one]] = W.indices[first[one]]
        self.WT = self.W.T.tocsr()
        self.n, self.P = model.ndof, self.a.shape[0]
        self._gram = None

    def positions(self, X: np.ndarray) -> np.ndarray:
        """The contact points' positions (P, 3) of a state X (ndof, 3) (m)."""
        return self.W @ X

    def _build_gram(self):
        """The pattern of W^T diag(c) W and the (nnz, P) matrix that fills it from c."""
        W = self.W
        counts = np.diff(W.indptr)
        k = int(counts.max())
        cols = np.full((self.P, k), -1, np.int64)
        vals = np.zeros((self.P, k))
        pos = np.arange(W.nnz) - np.repeat(W.indptr[:-1], counts)
        rows = np.repeat(np.arange(self.P), counts)
        cols[rows, pos], vals[rows, pos] = W.indices, W.data
        ok = (cols[:, :, None] >= 0) & (cols[:, None, :] >= 0)
        r = np.broadcast_to(cols[:, :, None], ok.shape)[ok]
        c = np.broadcast_to(cols[:, None, :], ok.shape)[ok]
        v = (vals[:, :, None] * vals[:, None, :])[ok]
        p = np.broadcast_to(np.arange(self.P)[:, None, None], ok.shape)[ok]
        pattern = FixedPattern(r, c, (self.n, self.n))
        fill = sp.csr_matrix((v, (pattern.slot, p)), shape=(pattern.nnz, self.P))
        self._gram = (pattern, fill, BlockPattern(pattern.matrix(np.zeros(pattern.nnz)), self.n))

    def blocks(self, K: np.ndarray) -> sp.csr_matrix:
        """``sum_p W_p^T K_p W_p`` for symmetric 3 x 3 blocks K (P, 3, 3): (3 ndof, 3 ndof), coordinate-blocked.

        On one fixed pattern for every K (the pattern of W^T W in every coordinate block).
        """
        if self._gram is None:
            self._build_gram()
        pattern, fill, block = self._gram
        mats = {(a, b): pattern.matrix(fill @ K[:, a, b]) for a in range(3) for b in range(a, 3)}
        return block.matrix(mats)


_POINTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def contact_points(model, samples: int | None = None) -> ContactPoints:
    """The model's contact points (:class:`ContactPoints`), built once per model and sample count.

    ``samples`` None: the scene's ``Contact.samples``, else the backend's own ``contact_samples``.
    """
    if samples is None:
        contact = model.scene.contact
        samples = (contact.samples if contact is not None and contact.samples else None) or model.contact_samples
    cache = _POINTS.setdefault(model, {})
    if samples not in cache:
        cache[samples] = ContactPoints(model, samples)
    return cache[samples]


def require_outside(model, X: np.ndarray, what: str = "the state") -> None:
    """Raise a ValueError naming the deepest contact point when one of X (ndof, 3) is not strictly outside every
    obstacle of the scene (the barrier is infinite there: no step can start from such a state)."""
    r = contact_points(model).positions(np.asarray(X, float))
    for k, obstacle in enumerate(model.scene.obstacles):
        d = obstacle.distance(r)
        p = int(np.argmin(d))
        if d[p] <= 0:
            a = contact_points(model).a[p]
            raise ValueError(f"{what}: contact point a = ({a[0]:.4g}, {a[1]:.4g}) m lies {-d[p]:.3g} m inside "
                             f"obstacle {k} ({obstacle.kind}); every contact point must start outside every obstacle")


def clearance(model, X: np.ndarray, obstacles=None) -> float:
    """The smallest signed distance from the sheet's contact points to the obstacles (m); negative: penetration.

    Parameters
    ----------
    model : Backend
    X : array (ndof, 3)
    obstacles : sequence of Obstacle, optional
        Default the scene's. Without obstacles the clearance is infinite.
    """
    obstacles = model.scene.obstacles if obstacles is None else tuple(obstacles)
    if not obstacles:
        return math.inf
    r = contact_points(model).positions(np.asarray(X, float))
    return float(min(np.min(o.distance(r)) for o in obstacles))


# -- the barrier potential with lagged friction -------------------------------------------------
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
        self.obstacles: tuple[Obstacle, ...] = tuple(scene.obstacles)
        self.points = contact_points(model)
        self.dhat = self.settings.distance
        self.kappa = self.settings.barrier_stiffness(weight_per_area(scene))
        self.weight = self.kappa * self.points.area  # kappa A_p (N/m^3 m^2 = N/m)
        self._lagged: list[_Lagged] = []
        self._eps = None

    def _positions(self, x) -> np.ndarray:
        return self.points.W @ x.reshape(3, self.n).T

    def _scatter(self, f: np.ndarray) -> np.ndarray:
        """Point forces (P, 3) -> a flat coordinate-blocked vector of the degrees of freedom."""
        return (self.points.WT @ f).T.ravel()

    # -- lagging ---------------------------------------------------------------------
    def lag(self, x, dt: float) -> None:
        """Freeze the friction's normal forces and tangent bases at the step's start x (flat), step dt (s).

        Raises ValueError when a contact point of x is not strictly outside an obstacle (the barrier is
        infinite there).
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

        ``kind`` "newton": exact; any other: the barrier's curvature term dropped (its projection onto the
        positive semi-definite cone; the friction's Hessian is positive semi-definite as it is).
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
        return self.points.blocks(K)

    def safe_start(self, x, dx) -> np.ndarray:
        """A point between x and x + dx (flat) that keeps every contact point outside every obstacle.

        Each degree of freedom moves the fraction of its own dx that the contact points it carries allow (the
        smallest of theirs, :meth:`max_step` per point), and the result is clipped once more along its segment
        from x (exact for interpolated points that mix moved and held degrees of freedom). Unlike one common
        fraction for the whole sheet, a few points near an obstacle do not hold back the rest of it: where an
        implicit step starts its search (measured on the ``sphere`` scene, FD 64 x 64: the common fraction was
        0.26-0.49).
        """
        s = self._point_steps(x, dx)
        W = self.points.W
        fraction = np.ones(self.n)
        np.minimum.at(fraction, W.indices, np.repeat(s, np.diff(W.indptr)))
        step = (dx.reshape(3, self.n) * fraction).ravel()
        return x + self.max_step(x, step) * step

    def max_step(self, x, dx) -> float:
        """The largest alpha in (0, 1] for which x + s dx keeps every contact point outside every obstacle.

        Exact for the convex obstacles (:meth:`deformable.obstacles.Obstacle.first_contact`): the first s at
        which a point would have closed ``margin`` of its gap, over all points and obstacles, capped at 1.
        """
        return float(np.min(self._point_steps(x, dx), initial=1.0))

    def relax(self, x, dx, stiffness) -> np.ndarray:
        """Newton's direction dx (flat) with the normal displacement of each active own contact point re-solved
        against the barrier (module docstring).

        Parameters
        ----------
        x, dx : arrays (3 ndof,)
            The iterate and Newton's direction (held degrees of freedom: dx 0).
        stiffness : array (3 ndof,)
            The diagonal of the Newton matrix without the contact's Hessian (N/m); 0 on held degrees of freedom.

        Returns a new direction; dx itself when no point is active, or when some contact points are not a degree
        of freedom's own (FE's sample points between the nodes: they share the nodes' degrees of freedom, so the
        1-D models are not independent; relaxing the nodes alone measured worse, the ``sphere`` scene on FE 16 x 16
        elements 7.65 -> 8.30 Newton iterations a step over its 1.5 s). Points near two obstacles at once keep
        Newton's displacement.
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


class Repulsion:
    """TPBF87's obstacle force, ``c exp(-d / eps) n`` per unit area at the contact points (module docstring).

    For the semi-implicit scheme, evaluated at the start of each step. It does not guarantee non-penetration.
    """

    def __init__(self, model):
        scene = model.scene
        self.obstacles = tuple(scene.obstacles)
        self.points = contact_points(model)
        self.eps = scene.contact.distance
        self.c = scene.contact.repulsion_pressure(weight_per_area(scene))

    def force(self, X: np.ndarray) -> np.ndarray:
        """The integrated force on the degrees of freedom, (ndof, 3) (N)."""
        r = self.points.positions(np.asarray(X, float))
        f = np.zeros_like(r)
        for obstacle in self.obstacles:
            d, nrm, _ = obstacle.derivatives(r, hessian=False)
            f += (self.c * self.points.area * np.exp(-np.maximum(d, -50 * self.eps) / self.eps))[:, None] * nrm
        return self.points.WT @ f
