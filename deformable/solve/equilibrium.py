"""Static equilibrium of a model with an energy: ``grad E(X) = F(t)`` at the free degrees of freedom.

E is the model's energy (the exact discrete eq. (13) for the "variational" model, the quadratic energy of the frozen
model) plus the energy of the scene's springs at time t; the equilibrium minimises ``E(x) - F . x`` by Newton's
method (:class:`deformable.solve.newton.Newton`), optionally under load continuation.

Stability. A stationary point of ``E - F . x`` need not be a minimum (a column beyond its Euler load, started
straight, stays straight: a saddle). Its stability is the inertia of the exact Hessian on the free degrees of
freedom: stable when no eigenvalue is negative, each negative one a direction along which the energy falls (Koiter's
energy criterion). The count comes from Sylvester's law of inertia on SuperLU's ``P A P^T = L D L^T`` (symmetric
ordering, diagonal pivots; :mod:`deformable.algebra.solvers`); where a pivot is at round-off (a bifurcation point,
or deformations that cost no energy) it is the count of negative eigenvalues among those nearest 0 (ARPACK in
shift-invert mode, :func:`scipy.sparse.linalg.eigsh`), a lower bound. An unstable state warns
(:class:`deformable.errors.UnstableEquilibrium`); ``perturb`` moves it along the eigenvector of the lowest
eigenvalue (the buckling mode) and solves again, as an imperfection of that amplitude would select the branch.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from ..algebra.solvers import SPLU_OPTIONS
from ..checks import real
from ..errors import ConvergenceError, InputError, UnstableEquilibrium
from .newton import Newton
from .potential import FlatEnergy, flat, unflat

__all__ = ["RESTARTS", "History", "Stability", "equilibrium", "nearest_modes", "stability"]

#: the most solves ``perturb`` adds, each from the last unstable state moved along its lowest mode
RESTARTS = 3
#: below this many unknowns the lowest modes come from a dense eigensolver
_DENSE = 400


@dataclasses.dataclass(frozen=True)
class Stability:
    """The stability of an equilibrium: the inertia of its Newton matrix (module docstring).

    Attributes
    ----------
    negative : int
        Negative eigenvalues of the exact Hessian of ``E - F . x`` on the free degrees of freedom: the directions
        along which the energy falls (0: a stable state, a minimum).
    method : str
        "pivots" (Sylvester's law on the LDL^T factorisation: exact) or "eigenvalues" (the negative ones among the
        eigenvalues nearest 0, a lower bound, where a pivot was at round-off).
    lowest : float or None
        The lowest eigenvalue found (N/m), where it was computed (an unstable state, or "eigenvalues").
    mode : array (ndof, 3) or None
        Its eigenvector as a displacement of the sheet, largest entry 1 (zero on held degrees of freedom).
    """

    negative: int
    method: str
    lowest: float | None = None
    mode: np.ndarray | None = dataclasses.field(default=None, repr=False, compare=False)

    @property
    def stable(self) -> bool:
        """No negative eigenvalue: a minimum of the energy."""
        return self.negative == 0


class History(list):
    """The residual max-norm per Newton iteration (N), a list, with the :class:`Stability` of the state found
    (``stability``; None when not checked)."""

    stability: Stability | None = None


def nearest_modes(A, k: int):
    """The k eigenvalues (ascending) of the symmetric A nearest 0 (dense below :data:`_DENSE` unknowns: the k
    lowest) and their eigenvectors (n, k)."""
    n = A.shape[0]
    if n <= _DENSE:
        w, V = sla.eigh(A.toarray(), subset_by_index=[0, min(k, n) - 1])
        return w, V
    shift = -1e-9 * float(np.mean(np.abs(A.diagonal())))  # just below 0: A - shift I is regular when A is singular
    w, V = spla.eigsh(A, k=min(k, n - 1), sigma=shift, which="LM", v0=np.ones(n))
    order = np.argsort(w)
    return w[order], V[:, order]


def stability(solver: Newton, x, mode: bool = False) -> Stability:
    """The inertia of the exact Newton matrix of ``solver`` at the flat state x, with c_M = c_C = 0 (statics).

    Parameters
    ----------
    solver : Newton
        The solver of the equilibrium (its problem's free degrees of freedom, springs and contact).
    x : array (3 ndof,)
        The state, flat.
    mode : bool
        Also the lowest eigenvalue and its eigenvector when the state is unstable.

    Returns
    -------
    Stability
    """
    A = solver.newton_matrix(x, 0.0, 0.0, kind="newton")
    n = A.shape[0]
    if n == 0:  # everything held: nothing can move
        return Stability(negative=0, method="pivots")
    tiny = 1e3 * np.finfo(float).eps * float(np.max(np.abs(A.diagonal()), initial=0.0))
    negative = None
    try:
        d = spla.splu(A.tocsc(), **SPLU_OPTIONS).U.diagonal()
        if np.all(np.abs(d) > tiny):  # every pivot above round-off: Sylvester's law counts exactly
            negative, method = int(np.sum(d < 0)), "pivots"
    except RuntimeError:  # "Factor is exactly singular"
        pass
    lowest = vector = None
    if negative is None:  # a pivot at round-off: the negative eigenvalues among those nearest 0
        w, V = nearest_modes(A, 6)
        negative, method = int(np.sum(w < -tiny)), "eigenvalues"
        lowest, vector = float(w[0]), V[:, 0]
    if mode and negative and vector is None:
        k = negative + 2
        while True:  # eigenvalues nearest 0 until every negative one is among them (or all are)
            w, V = nearest_modes(A, k)
            if int(np.sum(w < 0)) >= negative or k >= n - 1:
                break
            k = min(2 * k, n - 1)
        lowest, vector = float(w[0]), V[:, 0]
    displacement = None
    if mode and negative and vector is not None:
        p = solver.problem
        full = np.zeros(3 * p.n)
        full[p.free] = vector / vector[np.argmax(np.abs(vector))]  # largest entry +1: the same sign on every run
        displacement = unflat(full, p.n)
    return Stability(negative=negative, method=method, lowest=lowest, mode=displacement)


def equilibrium(model, X0, tol: float = 1e-10, t: float = 0.0, max_iter: int = 200, load_steps: int = 1,
                newton: dict | None = None, perturb: float | None = None, check_stability: bool = True):
    """Static equilibrium grad E(X) = F(t) by Newton's method with line search, and its stability.

    Parameters
    ----------
    model : Backend with an energy (force_model "variational" or "frozen")
    X0 : array (ndof, 3)
        Starting positions; held degrees of freedom keep their prescribed values at t.
    tol : float
        Relative tolerance on the max-norm of the free residual (relative to the larger of the load and the starting
        residual), never below the round-off floor of the internal forces.
    max_iter : int
        Newton iterations per load step.
    load_steps : int
        Apply the load in this many equal increments (continuation), each solved to the tolerance.
    newton : dict, optional
        Further :class:`deformable.solve.newton.NewtonSettings` (hessian, solver, reuse).
    perturb : float, optional
        When the state found is unstable, move it by ``perturb`` (scene units, the largest displacement) along the
        eigenvector of the Newton matrix's lowest eigenvalue and solve again, up to :data:`RESTARTS` times: the
        stable branch next to a saddle, e.g. the buckled column. Default: none (the state found is returned, with a
        warning when unstable).
    check_stability : bool
        Count the negative eigenvalues of the Newton matrix at the solution (default True; one further
        factorisation) and warn (:class:`deformable.errors.UnstableEquilibrium`) when there are any.

    Returns
    -------
    X : array (ndof, 3)
    history : History
        Residual max-norm per iteration (N), a list; ``history.stability`` is the :class:`Stability` of X (None when
        not checked).

    Raises
    ------
    ConvergenceError
        If the residual does not fall below the tolerance within ``max_iter`` iterations.

    Warns
    -----
    UnstableEquilibrium
        When the state returned has negative eigenvalues (a saddle of the energy).
    """
    if int(load_steps) != load_steps or load_steps < 1:
        raise InputError(f"load_steps must be a positive integer, got {load_steps!r}")
    if perturb is not None:
        perturb = real("equilibrium perturb", perturb, positive=True)
    if not isinstance(check_stability, (bool, np.bool_)):
        raise InputError(f"equilibrium check_stability must be True or False, got {check_stability!r}",
                         field="check_stability", value=check_stability)
    fl = FlatEnergy(model)
    if not fl.loads.conservative:
        raise InputError("equilibrium: the scene's Wind is not conservative (it depends on velocities); "
                         "find a steady state by running the dynamics instead")
    fl.t = t
    solver = Newton(fl, dict(newton or {}, max_iter=max_iter, rtol=0.0))
    X0 = np.asarray(X0, float)
    F_full = fl.load(t)
    x = fl.hold(flat(X0), X0, t)
    history = History()

    def solve(x, phi, grad, load, where):
        x, report = solver.minimise(phi, grad, x, label="equilibrium", load=load)
        history.extend(report.residuals)
        if not report.converged:
            raise ConvergenceError(
                f"equilibrium did not converge in {report.iterations} Newton iterations ({where}): residual "
                f"{report.residuals[-1]:.3e} N, tolerance {report.tolerance:.3e} N", list(history), unflat(x, fl.n))
        return x

    for k in range(1, int(load_steps) + 1):
        F = F_full * (k / load_steps)
        fl.factor = k / load_steps  # the edge moments, a potential, in the same increments

        def phi(x, F=F):
            return fl.energy(x) - F @ x

        def grad(x, F=F):
            return fl.gradient(x) - F

        load = float(np.max(np.abs(F[fl.free]))) if F[fl.free].size else 0.0
        scale = max(load, np.max(np.abs(grad(x)[fl.free])))
        solver.settings = dataclasses.replace(solver.settings, atol=tol * scale)
        x = solve(x, phi, grad, load, f"load step {k} of {load_steps}")
    if check_stability or perturb is not None:
        state = stability(solver, x, mode=True)
        for restart in range(1, RESTARTS + 1 if perturb is not None else 1):
            if state.stable or state.mode is None:
                break
            x = fl.hold(x + perturb * flat(state.mode), X0, t)
            x = solve(x, phi, grad, load, f"perturbed along the lowest mode, {restart} of {RESTARTS}")
            state = stability(solver, x, mode=True)
        history.stability = state
        if not state.stable:
            lowest = "" if state.lowest is None else f", the lowest {state.lowest:.3g} N/m"
            warnings.warn(f"equilibrium: the state found is unstable: its Newton matrix has {state.negative} negative "
                          f"eigenvalue{'s' if state.negative > 1 else ''}{lowest} (a saddle of the energy, e.g. a "
                          "column beyond its buckling load left straight); equilibrium(..., perturb=a) finds the "
                          "stable branch next to it", UnstableEquilibrium, stacklevel=2)
    return unflat(x, fl.n), history
