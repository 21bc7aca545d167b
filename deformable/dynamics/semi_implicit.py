"""The paper's semi-implicit step of the semi-discrete system (21), eq. (22)-(27).

    A_t R_{t+dt} = G_t,                                           (24)
    A_t = K(r_t) + M/dt^2 + C/(2 dt),                             (25)
    G_t = F_t + (M/dt^2 + C/(2 dt)) R_t + (M/dt - C/2) V_t,       (26)
    V_t = (R_t - R_{t-dt})/dt.                                    (27)

The stiffness is lagged (evaluated at r_t) and the force at t, so each step is one linear solve, written once over
the :class:`~deformable.backends.Backend` contract. For one undamped linear mode of frequency w the amplification
per step is ``(1 + w^2 dt^2)^(-1/2)`` and the phase advance ``atan(w dt)``: first order, numerically damped. Lagging
alpha makes the step conditionally stable: dt below :meth:`~deformable.backends.Backend.stable_step` (FD: about ``h
sqrt(mu / (2 eta G))``).

A_t lives on one fixed pattern refilled each step (:class:`deformable.algebra.reduced.ReducedSystem`), held degrees
of freedom eliminated by precomputed gathers; each group of coordinates that shares its constraints is factorised
once per step (:mod:`deformable.algebra.solvers`) and solved for all its right-hand sides; once per run for a linear
("frozen") model.

Obstacles: the paper's exponential field ``c exp(-d / eps) n`` (:class:`deformable.contact.Repulsion`, contact
method "exponential") at the start of the step. It does not guarantee non-penetration; the implicit schemes' barrier
does.
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from ..algebra.reduced import ReducedSystem
from ..algebra.solvers import SPLU_OPTIONS, make_solver
from ..contact.repulsion import Repulsion
from ..errors import DivergenceError, SelfContactIgnored
from .scheme import Scheme
from .state import State

__all__ = ["OTHER_STEPS", "SemiImplicit", "SPLU_OPTIONS"]

#: the schemes at other step lengths kept for reuse, the most recently used (steps shortened to end on frame times
#: differ only by the round-off of summing dt)
OTHER_STEPS = 4


class SemiImplicit(Scheme):
    """Steps of eq. (22)-(27) for a model with a strength matrix (force models tpbf87 and frozen).

    Parameters
    ----------
    model : Backend
    dt : float
        Time step (s).
    newton : ignored
        (The implicit schemes' Newton settings; this scheme solves one linear system a step.)
    solver : str
        "auto", "superlu" or "pardiso" (:func:`deformable.algebra.solvers.make_solver`).

    Attributes
    ----------
    timings : dict
        Seconds spent in "assembly" (K(r) and A_t), "factorisation" and "solve".
    """

    name = "semi-implicit"
    rank = 0

    def __init__(self, model, dt: float, newton=None, solver: str = "auto"):
        self.model, self.dt, self.solver = model, dt, solver
        self._options = dict(newton=newton, solver=solver)
        self.timings = {"assembly": 0.0, "factorisation": 0.0, "solve": 0.0}
        M, C = model.mass(), model.damping()
        self._B1 = (M / dt**2 + C / (2 * dt)).tocsr()  # multiplies R_t in (26)
        self._B2 = (M / dt - C / 2).tocsr()  # multiplies V_t in (26)
        # components that share their constraints share one factorisation
        groups: dict[bytes, list[int]] = {}
        sets: dict[bytes, np.ndarray] = {}
        for c, f in enumerate(model.fixed_dofs()):
            f = np.unique(np.asarray(f, dtype=np.int64))
            groups.setdefault(f.tobytes(), []).append(c)
            sets[f.tobytes()] = f
        self._groups = [(sets[k], comps) for k, comps in groups.items()]
        self._system = None
        self._solvers = None
        self._lu_cache = None
        self._other: dict[float, SemiImplicit] = {}  # the same scheme at other dt (shortened steps), by last use
        self._repulsion = None
        if model.scene.contact is not None and model.scene.contact.self_distance is not None:
            warnings.warn(f"scene {model.scene.name!r}: Contact.self_distance = {model.scene.contact.self_distance!r} "
                          "is left out: self-contact is a barrier in the implicit schemes' Newton method, and the "
                          "semi-implicit scheme has none, so the sheet may pass through itself (use an implicit "
                          "scheme for self-contact)", SelfContactIgnored, stacklevel=3)
        if model.scene.obstacles:
            meshes = [o for o in model.scene.obstacles if not o.analytic]
            if meshes:
                raise ValueError(f"the semi-implicit scheme takes the paper's exponential obstacle force, which needs a "
                                 f"signed distance; a {meshes[0].kind} obstacle has none: use an implicit scheme, "
                                 "whose barrier meets it triangle against triangle")
            if model.scene.contact.method != "exponential":
                raise ValueError("the semi-implicit scheme takes the paper's exponential obstacle force: set the "
                                 "contact method to 'exponential' (it does not guarantee non-penetration), or use an "
                                 "implicit scheme with the barrier")
            self._repulsion = Repulsion(model)

    def _factorise(self, X):
        model = self.model
        if self._lu_cache is not None:
            return self._lu_cache
        t0 = time.perf_counter()
        K = model.stiffness(X)
        if self._system is None:
            self._system = ReducedSystem(
                K, model.mass(), model.damping(), 1 / self.dt**2, 1 / (2 * self.dt), [f for f, _ in self._groups]
            )
        A = self._system.data(K)
        t1 = time.perf_counter()
        factors = []
        if self._solvers is None:  # one solver per block: each keeps its pattern's analysis
            self._solvers = [make_solver(self.solver) for _ in self._system.blocks]
        for block, solver in zip(self._system.blocks, self._solvers):
            Aff, Afc = self._system.matrices(A, block)
            factors.append((block, solver.factor(Aff), Afc))
        t2 = time.perf_counter()
        self.timings["assembly"] += t1 - t0
        self.timings["factorisation"] += t2 - t1
        if model.linear:
            self._lu_cache = factors
        return factors

    def step(self, state: State, X0: np.ndarray, dt: float | None = None) -> State:
        """The state at t + dt by eq. (24); ``X0`` is the run's constraint reference.

        ``dt``: this scheme's own by default; another one (a run's shorter last step, or a step shortened to end on
        a frame time) is taken by the same scheme built for it, with its own step matrix; the :data:`OTHER_STEPS`
        most recently used of those are kept. A singular step matrix, or positions that leave the finite numbers,
        raise DivergenceError with ``state`` as the last good one.
        """
        if dt is not None and dt != self.dt:
            other = self._other.pop(dt, None) or SemiImplicit(self.model, dt, solver=self.solver)
            self._other[dt] = other  # the most recently used last
            if len(self._other) > OTHER_STEPS:
                del self._other[next(iter(self._other))]
            new = other.step(state, X0)
            for k, v in other.timings.items():
                self.timings[k] += v
                other.timings[k] = 0.0
            return new
        dt, model = self.dt, self.model
        where = f"at step {state.step + 1} (t = {state.t + dt:.6g} s)"
        try:
            factors = self._factorise(state.X)
            t0 = time.perf_counter()
            G = model.load(state.X, state.t, state.V) + self._B1 @ state.X + self._B2 @ state.V
            if self._repulsion is not None:
                G += self._repulsion.force(state.X)
            Xn = np.array(model.prescribed(X0, state.t + dt), dtype=float)
            for (block, lu, Afc), (_, comps) in zip(factors, self._groups):
                free, fixed = block["free"], block["fixed"]
                rhs = G[np.ix_(free, comps)] - Afc @ Xn[np.ix_(fixed, comps)]
                Xn[np.ix_(free, comps)] = lu.solve(rhs)
        except (ArithmeticError, RuntimeError, np.linalg.LinAlgError) as err:  # SingularMatrix, SuperLU, PARDISO
            raise DivergenceError(f"diverged {where}: the step matrix A_t of eq. (25) is singular ({err})",
                                  state) from err
        self.timings["solve"] += time.perf_counter() - t0
        if not np.all(np.isfinite(Xn)):
            raise DivergenceError(f"diverged {where}: non-finite positions", state)
        return State(t=state.t + dt, X=Xn, V=(Xn - state.X) / dt, step=state.step + 1)
