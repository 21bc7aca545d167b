r"""Equilibrium paths by arc-length continuation, through limit points, with stability and branch switching.

The path of ``R(x, lambda) = grad E(x) + lambda grad Pi_m(x) - lambda F = 0`` over the free degrees of freedom, F
the scene's applied loads at time t (body, edge, point) and Pi_m the potential of its edge moments, both scaled by
the load factor lambda (springs and held values are not). Load control (:func:`.equilibrium.equilibrium`'s load
steps) fails where dlambda/ds changes sign, at a limit point (snap-through); the arc-length method constrains each
increment (Delta x, Delta lambda) from the last point instead:

    |Delta x|^2 + psi^2 Delta lambda^2 = Delta s^2,        q = -dR/dlambda = F - grad Pi_m(x)

(Crisfield 1981, "A fast incremental/iterative solution procedure that handles snap-through", Computers &
Structures 13, 55-62; Riks 1979, "An incremental approach to the solution of snapping and buckling problems",
Int. J. Solids Struct. 15, 529-551). Each corrector iteration solves K a = -R and K b = q with the exact
Newton matrix K (one sparse LU, indefinite past a limit point), takes dx = a + dlambda b, and dlambda from
the quadratic constraint; of its two roots, the one whose increment turns least from the last one
(Crisfield's angle criterion); complex roots, or no convergence in ``max_iter`` iterations, halve the arc
length and retry. The predictor follows the tangent K t = q with the sign of the last increment (the first:
along increasing load). The arc length adapts to the iterations: Delta s (target / iterations)^(1/2), within
half and twice the last, within ``[length / 64, 4 length]``. ``psi`` (m) is the displacement one unit of
load factor counts as: 0 (the default) is the cylindrical arc, the displacement alone measures the step,
the usual choice for structures; a stiff path (a column before it buckles, whose displacement hardly grows
with the load) needs psi > 0, or the first step's load factor is huge.

Stability of each point: the inertia of K (:func:`deformable.solve.equilibrium.stability`, Sylvester's law), the
count of its negative eigenvalues. Between two points the count changes by one at a limit point (where Delta lambda
changes sign) or at a bifurcation (where it does not). Branch switching (``switch=True``): at the first point past a
simple bifurcation, the path is taken up from the last stable point before it along the critical mode (the
eigenvector of K's eigenvalue nearest 0 there, scaled to the arc length), with Delta lambda = 0 as predictor:
eigenvector injection (Wagner and Wriggers 1988, "A simple method for the calculation of postcritical branches",
Engineering Computations 5, 103-109), which for a symmetric bifurcation leaves the fundamental path for the
secondary one.
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np
import scipy.sparse.linalg as spla

from ..checks import count, real
from ..errors import ConvergenceError, InputError
from .equilibrium import Stability, nearest_modes, stability
from .newton import Newton
from .potential import FlatEnergy, flat, unflat

__all__ = ["PathPoint", "Path", "equilibrium_path"]

log = logging.getLogger(__name__)

#: Newton iterations a step aims at (the arc length adapts to reach it)
TARGET_ITERATIONS = 4
#: the smallest arc length, as a fraction of the first, before the path gives up
SMALLEST = 1 / 64


@dataclasses.dataclass(frozen=True)
class PathPoint:
    """One converged point of an equilibrium path.

    Attributes
    ----------
    load : float
        The load factor lambda (the applied loads and moments are lambda times the scene's).
    X : array (ndof, 3)
        The state.
    stability : Stability
        The inertia of the Newton matrix there (``stability.negative``: 0 on a stable branch).
    iterations : int
        Corrector iterations it took.
    branch : int
        0 on the path from the start; 1 after a branch switch.
    """

    load: float
    X: np.ndarray = dataclasses.field(repr=False)
    stability: Stability
    iterations: int
    branch: int = 0


class Path(list):
    """The points of an equilibrium path (:class:`PathPoint`), in order, with helpers."""

    @property
    def loads(self) -> np.ndarray:
        """The load factor of each point, (points,)."""
        return np.array([p.load for p in self])

    @property
    def negative(self) -> np.ndarray:
        """The negative eigenvalues of each point's Newton matrix, (points,)."""
        return np.array([p.stability.negative for p in self])

    def displacement(self, model, a, component: int = 2) -> np.ndarray:
        """A coordinate of the sheet's point a = (a1, a2) (m) along the path, minus its start, (points,)."""
        r = np.array([model.sample(p.X, np.asarray(a, float)[None]).r[0, component] for p in self])
        return r - r[0]

    def limit_points(self) -> list[int]:
        """Indices where the load factor has a local extremum (Delta lambda changes sign after the point)."""
        d = np.diff(self.loads)
        return [k + 1 for k in range(d.size - 1) if d[k] * d[k + 1] < 0]


def equilibrium_path(model, X0, length: float, steps: int = 50, max_load: float | None = None, t: float = 0.0,
                     psi: float = 0.0, tol: float = 1e-9, max_iter: int = 15, switch: bool = False,
                     progress=None) -> Path:
    """The equilibrium path from X0 at load factor 0 (module docstring).

    Parameters
    ----------
    model : Backend with an energy (force model "variational", "koiter", "frozen", ...)
    X0 : array (ndof, 3)
        An equilibrium at lambda = 0 (the rest state, without other loads); held values stay as in X0.
    length : float
        The first arc length Delta s (scene units, m): about the displacement of the first step.
    steps : int
        The most points after the start.
    max_load : float, optional
        Stop at the first point whose load factor reaches it (the path is not cut back to it).
    t : float
        The time the loads are taken at (s).
    psi : float
        The displacement (scene units, m) one unit of load factor counts as in the constraint (0: the cylindrical
        arc).
    tol : float
        Converged when the free residual's max-norm is at most tol times that of q (the load's).
    max_iter : int
        Corrector iterations before the arc length is halved.
    switch : bool
        Switch to the secondary branch at the first simple bifurcation (module docstring).
    progress : callable (point index, PathPoint) -> None, optional
        Called after each point.

    Returns
    -------
    Path
        The start and the points after it.

    Raises
    ------
    ConvergenceError
        When the arc length falls below ``length / 64`` without a converged step.
    """
    length = real("equilibrium_path length", length, positive=True)
    steps = count("equilibrium_path steps", steps)
    max_iter = count("equilibrium_path max_iter", max_iter)
    psi = real("equilibrium_path psi", psi, non_negative=True)
    tol = real("equilibrium_path tol", tol, positive=True)
    fl = FlatEnergy(model)
    if not fl.loads.conservative:
        raise InputError("equilibrium_path: the scene's Wind is not conservative (it depends on velocities)")
    fl.t = t
    solver = Newton(fl, {"rtol": 0.0})
    X0 = np.asarray(X0, float)
    x = fl.hold(flat(X0), X0, t)
    F = fl.load(t)
    free = fl.free

    def q_of(x):  # -dR/dlambda at x, flat
        return F - flat(fl.loads.factored_gradient(unflat(x, fl.n), t)) if fl.loads.potentials else F

    def residual(x, lam):
        fl.factor = lam
        return fl.gradient(x) - lam * F

    floor = [0.0]

    def matrix(x, lam):
        fl.factor = lam
        A = solver.newton_matrix(x, 0.0, 0.0, kind="newton").tocsc()
        floor[0] = float(10 * np.finfo(float).eps * np.max(np.abs(A.diagonal())) * max(1.0, np.max(np.abs(x))))
        try:
            return spla.splu(A)
        except RuntimeError as err:  # SuperLU: "Factor is exactly singular"
            raise ConvergenceError(f"equilibrium_path: the tangent matrix is singular at load factor {lam:.6g} "
                                   f"({err}): a deformation the constraints leave free costs no energy there",
                                   [], unflat(x, fl.n)) from None

    def point(x, lam, iterations, branch):
        fl.factor = lam
        return PathPoint(load=lam, X=unflat(x, fl.n), stability=stability(solver, x), iterations=iterations,
                         branch=branch)

    path = Path([point(x, 0.0, 0, 0)])
    lam, ds, previous, branch = 0.0, length, None, 0
    scale = float(np.max(np.abs(q_of(x)[free]), initial=0.0))
    if not scale > 0:
        raise InputError(f"equilibrium_path: no load to follow at t = {t:g} s: the load factor scales the scene's "
                         "applied loads, edge moments and pressures, and on the free degrees of freedom they are all "
                         "zero there (a load with time= may be zero at t = 0: give t, the time whose loads the path "
                         "follows)", field="t", value=t)
    switched = not switch
    while len(path) <= steps:
        step = _step(x, lam, ds, previous, residual, matrix, q_of, free, psi, tol * scale, max_iter, fl, X0, t, fl_floor=floor)
        if step is None:
            ds *= 0.5
            if ds < SMALLEST * length:
                raise ConvergenceError(f"equilibrium_path: no converged step at load factor {lam:.6g} down to an arc "
                                       f"length of {ds:.3g} (from {length:.3g})", [], unflat(x, fl.n))
            continue
        x_new, lam_new, iterations = step
        new = point(x_new, lam_new, iterations, branch)
        last = path[-1]
        if (not switched and new.stability.negative == last.stability.negative + 1 and
                np.sign(lam_new - lam) == (np.sign(lam - path[-2].load) if len(path) > 1 else 1.0)):
            # a simple bifurcation between last and new (the count rose while the load kept its direction)
            fl.factor = last.load
            A = solver.newton_matrix(flat(last.X), 0.0, 0.0, kind="newton")
            _, V = nearest_modes(A, 1)
            mode = np.zeros(3 * fl.n)
            mode[free] = V[:, 0] / np.linalg.norm(V[:, 0])
            log.info("equilibrium_path: a bifurcation between load factors %.6g and %.6g; switching along its mode",
                     last.load, lam_new)
            switched, branch = True, 1
            x, lam = flat(last.X), last.load
            previous = (ds * mode, 0.0)  # the predictor: along the critical mode at constant load
            step = _step(x, lam, ds, previous, residual, matrix, q_of, free, psi, tol * scale, max_iter, fl, X0, t,
                         predictor=previous, fl_floor=floor)
            if step is None:
                raise ConvergenceError(f"equilibrium_path: the branch switch at load factor {lam:.6g} did not "
                                       "converge", [], unflat(x, fl.n))
            x_new, lam_new, iterations = step
            new = point(x_new, lam_new, iterations, branch)
        previous = (x_new - x, lam_new - lam)
        x, lam = x_new, lam_new
        path.append(new)
        if progress is not None:
            progress(len(path) - 1, new)
        ds = float(np.clip(ds * np.sqrt(TARGET_ITERATIONS / max(iterations, 1)), 0.5 * ds, 2.0 * ds))
        ds = float(np.clip(ds, SMALLEST * length, 4.0 * length))
        if max_load is not None and lam >= max_load:
            break
    return path


def _step(x, lam, ds, previous, residual, matrix, q_of, free, psi, atol, max_iter, fl, X0, t, predictor=None,
          fl_floor=(0.0,)):
    """One arc-length step from (x, lam): (x, lam, iterations), or None when it did not converge.

    Converged when the free residual is at most ``atol`` or the round-off floor of the internal forces, ``10 eps
    max|diag K| max(1, |x|)`` (Newton's, :mod:`deformable.solve.newton`, allows 1e3 eps: a path's points are
    compared with each other, so they are solved a hundredfold further)."""
    q = q_of(x)
    qq = 1.0  # the constraint weighs Delta lambda by psi alone (module docstring)
    if predictor is None:
        lu = matrix(x, lam)
        tangent = np.zeros_like(x)
        tangent[free] = lu.solve(q[free])
        norm = np.sqrt(tangent[free] @ tangent[free] + psi**2 * qq)
        dlam = ds / norm
        if previous is not None and (tangent[free] @ previous[0][free] + psi**2 * qq * previous[1]) < 0:
            dlam = -dlam  # keep going the way the path went
        dx = dlam * tangent
    else:
        dx, dlam = predictor[0].copy(), predictor[1]
        dx *= ds / max(np.sqrt(dx[free] @ dx[free]), np.finfo(float).tiny)
    for iteration in range(1, max_iter + 1):
        xi = fl.hold(x + dx, X0, t)
        R = residual(xi, lam + dlam)
        if np.max(np.abs(R[free]), initial=0.0) <= max(atol, fl_floor[0]) and iteration > 1:
            return xi, lam + dlam, iteration - 1
        lu = matrix(xi, lam + dlam)
        qi = q_of(xi)
        a, b = np.zeros_like(x), np.zeros_like(x)
        a[free] = lu.solve(-R[free])
        b[free] = lu.solve(qi[free])
        u, w = (dx + a)[free], b[free]
        c1 = w @ w + psi**2 * qq
        c2 = 2 * (w @ u) + 2 * psi**2 * qq * dlam
        c3 = u @ u + psi**2 * qq * dlam**2 - ds**2
        disc = c2**2 - 4 * c1 * c3
        if disc < 0:
            return None
        roots = ((-c2 + np.sqrt(disc)) / (2 * c1), (-c2 - np.sqrt(disc)) / (2 * c1))
        # Crisfield's angle criterion: the root whose increment keeps closest to the last one
        cosines = [float(dx[free] @ (u + r * w) + psi**2 * qq * dlam * (dlam + r)) for r in roots]
        d = roots[int(np.argmax(cosines))]
        dx = dx + a + d * b
        dlam = dlam + d
    xi = fl.hold(x + dx, X0, t)
    if np.max(np.abs(residual(xi, lam + dlam)[free]), initial=0.0) <= max(atol, fl_floor[0]):
        return xi, lam + dlam, max_iter
    return None
