"""Implicit time steps for models with an energy: the Newton step both implicit schemes share.

For a model whose internal force is the gradient of an energy E (the exact gradient of eq. (13), or the quadratic
energy of the frozen model), each step minimises an incremental potential over the free degrees of freedom by
Newton's method (:class:`deformable.solve.newton.Newton`). With M, C, F the backend's integrated matrices and load
and x-hat = x_n + dt v_n:

- ``"implicit-euler"`` (:mod:`.implicit_euler`; first order, dissipative: with gamma = 0 and no load the total
  energy does not grow)::

      Phi(x) = |x - x-hat|^2_M / (2 dt^2) + |x - x_n|^2_C / (2 dt) + E(x) - F_{n+1} . x
      v_{n+1} = (x_{n+1} - x_n) / dt

- ``"newmark"`` (:mod:`.newmark`; beta = 1/4, gamma = 1/2, the trapezoidal rule: second order, no numerical damping
  of linear modes)::

      Phi(x) = 2 |x - x-hat|^2_M / dt^2 - (M a_n) . x + |x - x_n|^2_C / dt - (C v_n) . x + E(x) - F_{n+1} . x
      a_{n+1} = 4 (x_{n+1} - x-hat) / dt^2 - a_n,   v_{n+1} = 2 (x_{n+1} - x_n) / dt - v_n

The stationarity of Phi is the equation of motion (11) at t_{n+1}. A scheme of this kind is a subclass of
:class:`Implicit` that gives its Newton matrix's multipliers of M and C, its potential, the start of its search and
its update of v and a.

External forces (:mod:`deformable.physics.loads`): applied loads are F_{n+1}; the springs are part of E (anchors at
t_{n+1}); the wind is linearised about the start of the step, ``f(v) = f_n - D_n (v - v_n)`` with its velocity
Jacobian D_n (positive semi-definite), taken like C: C + D_n in place of C and f_n + D_n v_n added to F_{n+1}. The
step stays unconditionally stable in the wind's damping; its dependence on the normal is lagged (first order).

Contact (:mod:`deformable.contact`): the obstacles add the barrier and the friction to E, the friction's normal
forces and tangent bases lagged at x_n (:meth:`.potential.ContactPotential.lag`). The search starts from the
predictor only as far as the segment from x_n to it stays outside the obstacles, and the tolerance's scale (the
force imbalance at x-hat) leaves the contact forces out, which would balance the weight at rest.

Both schemes take the step length as an argument (the controller may shorten it). A step whose Newton solve does not
reach its tolerance is never returned: it raises :class:`StepRejected`.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
import scipy.sparse.linalg as spla

from ..checks import real
from ..errors import ConvergenceError, DivergenceError, InputError, StepRejected
from ..solve.newton import Newton, NewtonSettings
from ..solve.potential import FlatEnergy, flat, unflat
from .scheme import Scheme
from .state import State

__all__ = ["Implicit", "StepRejected"]


class Implicit(Scheme):
    """Newton-based steps on an incremental potential (module docstring); subclasses are the schemes.

    Parameters
    ----------
    model : Backend with an energy (a force model with ``has_energy``)
    dt : float
        The requested step (s); each :meth:`step` takes its own.
    newton : NewtonSettings or dict, optional
        rtol, atol, max_iter, hessian, solver, reuse (:class:`deformable.solve.newton.NewtonSettings`).
    solver : ignored
        (The semi-implicit scheme's; the Newton settings name the solver here.)

    Attributes
    ----------
    reports : list of NewtonReport, one per accepted step
    rejected : int
        Steps whose Newton solve failed (and were retried by the controller).
    timings : dict
        Seconds spent in the Newton solves: "hessian", "factor", "solve", "search".

    Notes
    -----
    Subclasses give :attr:`start` and the three methods below.
    """

    implicit = True
    adaptive = True
    #: the predictor's acceleration term: the search starts from x-hat + start dt^2 a_n
    start: ClassVar[float] = 1.0
    remembers = ("newton_floor", "lag", "contact")

    def __init__(self, model, dt: float | None = None, newton: NewtonSettings | dict | None = None,
                 solver: str = "auto"):
        self.model = model
        self.flat = FlatEnergy(model)
        self.newton = Newton(self.flat, newton, inertia=True)
        self.reports: list = []
        self.rejected = 0
        self.timings = {"hessian": 0.0, "factor": 0.0, "solve": 0.0, "search": 0.0}

    # -- what a scheme gives ------------------------------------------------------------
    def coefficients(self, dt: float) -> tuple[float, float]:
        """The multipliers (c_M, c_C) of M and C in the Newton matrix."""
        raise NotImplementedError

    def potential(self, state, M, C, F, xn, vn, xhat, dt: float):
        """The step's potential and its gradient, two callables of the flat x (``grad(x, contact=True)``)."""
        raise NotImplementedError

    def update(self, x, xn, vn, xhat, dt: float):
        """The velocity and acceleration (flat) at the step's end x."""
        raise NotImplementedError

    def memory(self) -> dict:
        """Newton's round-off floor of the last solve (N), which the next solve's tolerance starts from, the
        factorisation lagged across steps, if one is kept (:meth:`deformable.solve.newton.Newton.memory`), and the
        contact's (the mesh obstacles' adapted stiffness, :meth:`deformable.contact.terms.ContactTerms.memory`)."""
        contact = {} if self.flat.contact is None else self.flat.contact.memory()
        return {"newton_floor": self.newton.floor, **self.newton.memory(), **({"contact": contact} if contact else {})}

    def restore(self, memory: dict) -> None:
        self.newton.recall(memory)  # before the floor: making the factorisation again sets a floor of its own
        if "newton_floor" in memory:
            self.newton.floor = real("memory.newton_floor", memory["newton_floor"], non_negative=True)
        if "contact" in memory and self.flat.contact is not None:
            if not isinstance(memory["contact"], dict):
                raise InputError(f"memory.contact must be a table of numbers, got {memory['contact']!r:.60}",
                                 field="memory.contact", value=memory["contact"])
            self.flat.contact.recall(memory["contact"])

    def retune(self, model) -> None:
        """Go on with ``model`` (other material values and loads on the same grid and constraints): the potential
        takes its energy, mass, damping, loads and contact (:meth:`FlatEnergy.retune`); Newton's method keeps its
        matrix's pattern and the solver's analysis, and factorises the new matrix at its next solve."""
        self.model = model
        self.flat.retune(model)
        self.newton.retune()

    # -- the step --------------------------------------------------------------------
    def acceleration(self, state) -> np.ndarray:
        """a = M^-1 (F - C v - grad E) at a state (flat), for starting Newmark."""
        fl = self.flat
        fl.t = state.t
        F = fl.load(state.t)
        if fl.loads.winds:
            F += flat(fl.loads.wind_force(state.X, state.V, state.t))
        rhs = F - fl.C @ flat(state.V) - fl.gradient(flat(state.X))
        a = np.zeros(3 * fl.n)
        f = fl.free
        a[f] = spla.spsolve(fl.M[f][:, f].tocsc(), rhs[f])
        return a

    def step(self, state: State, X0: np.ndarray, dt: float) -> State:
        """The state at t + dt; ``X0`` is the run's constraint reference.

        Raises StepRejected when Newton does not converge (the state is not advanced), DivergenceError when
        positions leave the finite numbers.
        """
        fl = self.flat
        t1 = state.t + dt
        xn, vn = flat(state.X), flat(state.V)
        xhat = xn + dt * vn
        F = fl.load(t1)
        M, C = fl.M, fl.C
        D = None
        if fl.loads.winds:  # the wind linearised about the step's start: a damping D and a load (module docstring)
            D = fl.loads.wind_damping(state.X, state.V, t1)
            F = F + flat(fl.loads.wind_force(state.X, state.V, t1)) + D @ vn
            C = C + D
        cm, cc = self.coefficients(dt)
        phi, grad = self.potential(state, M, C, F, xn, vn, xhat, dt)
        label = f"{self.name} step {state.step + 1} (t = {t1:.6g} s, dt = {dt:.3g} s)"
        fl.t = t1
        # tolerance relative to the force imbalance at the inertial predictor x-hat; the search starts from the
        # predictor with the last acceleration, x-hat + dt^2 a_n (implicit Euler) or x-hat + dt^2 a_n / 2 (Newmark)
        start = fl.hold(xhat, X0, t1)
        scale = float(np.max(np.abs(grad(start, contact=False)[fl.free]), initial=0.0))
        # the step test (deformable.solve.newton, "Convergence tests"), unless the contact changes Newton's directions
        tested = fl.contact is None or fl.contact.step_test
        xtol = self.newton.settings.vtol * dt if self.newton.settings.test == "step" and tested else None
        if state.A is not None:
            start = fl.hold(xhat + (self.start * dt**2) * flat(state.A), X0, t1)
        if fl.contact is not None:  # friction lagged at x_n; the start no further than the obstacles (and the sheet
            # against itself) allow
            fl.contact.lag(xn, dt, t1)
            try:  # the held ones at their prescribed values at t1, unless that presses the sheet through itself
                start = fl.contact.safe_start(xn, start - xn, fl.fixed)
            except StepRejected as err:
                self.rejected += 1
                raise StepRejected(f"{label}: {err}") from err
        try:
            x, report = self.newton.minimise(phi, grad, start, cm, cc, label, None if D is None else cc * D, scale,
                                             xtol=xtol)
        except ConvergenceError as err:
            self.rejected += 1
            raise StepRejected(str(err)) from err
        except (ArithmeticError, np.linalg.LinAlgError) as err:  # SingularMatrix even under a shift, overflow
            raise DivergenceError(f"diverged at {label}: the Newton matrix is singular ({err})", state) from err
        for k, v in report.seconds.items():
            self.timings[k] += v
        if not np.all(np.isfinite(x)):
            raise DivergenceError(f"diverged at step {state.step + 1} (t = {t1:.6g} s): non-finite positions", state)
        if not report.converged:
            self.rejected += 1
            raise StepRejected(f"{label}: Newton stopped after {report.iterations} iterations at residual "
                               f"{report.residuals[-1]:.3e} N", report)
        self.reports.append(report)
        v, a = self.update(x, xn, vn, xhat, dt)
        n = fl.n
        return State(t=t1, X=unflat(x, n), V=unflat(v, n), step=state.step + 1, A=unflat(a, n))


def __getattr__(name):
    if name == "IMPLICIT_SCHEMES":  # the former tuple of names: the registry's implicit schemes
        return tuple(n for n in Scheme.names() if Scheme.lookup(n).implicit)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
