r"""Newton's method on a potential over the free degrees of freedom of a model.

The implicit time steps (:mod:`deformable.dynamics.implicit`) and static
equilibrium (:mod:`deformable.solve.equilibrium`) both minimise a potential

    Phi(x) = (inertia and damping terms) + E(x) - F . x

whose elastic part E is the model's energy (the exact gradient of eq. (13)
for the "variational" model, the quadratic energy of the frozen one), and
whose Newton matrix is ``c_M M + c_C C + Hess E`` (implicit Euler: 1/dt^2,
1/dt; Newmark: 4/dt^2, 2/dt; statics: 0, 0). This module holds what they
share, over the potential of :class:`deformable.solve.potential.FlatEnergy`:
:class:`Newton`'s loop, which computes directions and leaves the step to a
line search (:mod:`deformable.solve.search`, a registered strategy):

- the Newton matrix, its positive definite factorisation (the exact
  Hessian's where definite, else the definite one's) and the chord and CG
  directions are :class:`deformable.solve.directions.Directions`;
- the factorisation is kept while it pays: within a solve an iteration
  reuses the last one when the previous iteration with it reduced the
  residual at least a hundredfold (:data:`CONTRACTION`), else it
  refactorises (a chord method with a contraction test); a linear model's
  matrix is factorised once for as long as c_M and c_C stay the same (the
  frozen model: once per dt). Measured on the curtain (FD 48 x 48, 2 s):
  iterations and factorisations per step 3.0 and 2.05 with a tenfold test,
  2.45 and 2.37 with a hundredfold one, 2.45 and 2.45 without reuse (a chord
  step after a first Newton step that gained 20-50x gains only 2-4x more).
  Across time steps: ``lag`` below.
- the step along a direction is a line search's: by default the watchdog
  of :class:`deformable.solve.search.Watchdog` (full Newton steps, watched
  for a sufficient decrease, with a return to the last good point), or
  plain Armijo backtracking (``NewtonSettings(search="armijo")``); the
  Armijo constant is a setting (``armijo``).

The potential's elastic part may carry the scene's springs
(:class:`deformable.physics.loads.Loads`: an energy with its Hessian), evaluated at
the time :attr:`FlatEnergy.t`; the wind, not conservative, enters the
implicit steps as a load and a damping (:mod:`deformable.dynamics.implicit`).

Convergence tests (``NewtonSettings(test=...)``). "force": the max-norm of
the free residual at most ``rtol`` times its scale. "step" (the default;
it applies in time steps without obstacles, with or without self-contact,
"force" elsewhere): also when a trusted direction moves no degree of freedom
further than ``vtol dt`` (Li et al. 2020, IPC, section 5) and the direction
filter takes it whole; x + d is then returned without a further gradient. A
direction is trusted when it comes from a factorisation of the exact Newton
matrix, or after the directions contracted at least twofold (a
definite fallback's). Under ``lag=True`` a factorisation outlives a solve
that ended on the step test with no fallback, chords going on while they pay
(:meth:`Directions.slow`, a count: the trajectory does not depend on the
machine's load); a checkpoint keeps where it was made and a resumed run
makes it again (:meth:`Newton.memory`, :meth:`Newton.recall`), so the run
continues bit for bit. ``krylov=True``: where a chord does not pay, PCG on the
exact matrix preconditioned by the factorisation at hand instead of a new
factorisation (:mod:`.krylov`), within a budget of half the solves a
factorisation costs. The Newton error the step test leaves against the time
discretisation's is measured in docs/design.md ("Newton's convergence test");
studies that need a tight solve set ``test="force"``.

Fine grids. Both are ``"auto"`` by default: on where one factorisation costs
at least :data:`deformable.solve.directions.LAG_FROM` (100) solves, by the
solver's own count (PARDISO's flops of the factorisation over four times the
factor's entries; a count, so the trajectory does not depend on the machine),
off elsewhere. The count grows with the grid (the curtain's Newton matrix: FD
20 x 20 nodes 28, 32 x 32 48, 64 x 64 78, 128 x 128 124; FE 16 x 16 elements
55, 32 x 32 88), and so does a factorisation's share of a step. Measured on
the curtain with its self-contact (CPU, one thread): FD 32 x 32 for 1 s
38.1 ms a step, 42.7 with both on (3.29 iterations and 0.53 factorisations a
step against 2.24 and 1.21); FD 64 x 64 149 against 168 ms; FD 128 x 128 for
0.5 s 647 against 443 ms (2.22 iterations, 0.22 factorisations a step, against
1.33 and 1.03; ``lag`` alone 492 ms); FD 256 x 256 for 0.15 s 5.7 against
3.4 s a step, set-up included. With SuperLU, which counts nothing, both stay
off.

Loads below the absolute terms of the tolerance. The tolerance has two
absolute terms, ``atol`` and the round-off floor of the internal forces
(``1e3 eps max|diag A| max(1, |x|)``); neither may swallow the load itself.
``atol`` is capped at ``rtol`` times the applied load (max-norm over the free
degrees of freedom): a sheet whose weight is 4e-14 N a node (``scale = 1e-12``)
still falls, where an absolute 1e-12 N once accepted its start as converged.
When the load is at or below the floor (a load far below the elastic force
scale, e.g. ``eta = 1e20`` N/m against a weight of 0.04 N), the start is not
accepted on the floor's word: Newton takes at least one step, whose exact
solve applies the load wherever the factorisation resolves the inertia
(the free sheet falls on FE at eta = 1e20); a solve whose residual then stays
of the size of the load warns once (:class:`deformable.errors.LoadBelowRoundOff`)
that the residual cannot tell the solution and the load may be lost in
round-off: FD at eta = 1e20, where the stiffness-to-inertia ratio of the
Newton matrix, 1e18, is beyond double precision and the free sheet does not
move; and the cloth of ``hanging`` at ``scale = 1e-12``, whose elastic forces'
round-off (4e-13 N) exceeds its weight (4e-14 N a node), though it swings
within 0.3 % of its swing at 1e-9 (the round-off forces barely reach its
rigid swing). A load far above the floor (every ordinary scene) leaves every
iterate as it was.

Direction filters. A term of the potential may change and bound Newton's
direction before the search sees it (:class:`DirectionFilter`; the contact
wing's :class:`deformable.contact.potential.ContactPotential` is one, and
the loop imports no contact): every direction is clipped to the filter's
largest safe step (``max_step``), so no iterate, tried or taken, carries a
contact point across an obstacle (Li et al. 2020, "Incremental Potential
Contact", section 4), and the Armijo test compares against the slope of the
clipped step. In a time step (a Newton matrix with inertia) the filter may
first propose another direction (``propose``: the contact normals solved
against the barrier, a nonlinear elimination); the search tries it first and
falls back to Newton's own clipped step when it fails to decrease Phi from
the current iterate (Armijo), at the cost of a second gradient. Equilibrium
has no inertia to bound the filter's 1-D models, and takes Newton's clipped
direction.
"""

from __future__ import annotations

import time
import warnings
from typing import Protocol

import numpy as np

from ..algebra.solvers import one_blas_thread
from ..errors import ConvergenceError, LoadBelowRoundOff
from .directions import Directions
from .krylov import forcing
from .potential import FlatEnergy
from .search import LineSearch, candidates, spread
from .settings import NewtonReport, NewtonSettings

__all__ = ["NewtonReport", "NewtonSettings", "Newton", "DirectionFilter"]

#: a reused factorisation is kept while each iteration with it reduces the residual at least this much (ratio)
CONTRACTION = 0.01


class DirectionFilter(Protocol):
    """What a term of the potential may do to Newton's direction before the line search sees it (module docstring).

    Directions are flat (3 ndof,), zero on the held degrees of freedom.
    """

    def propose(self, x: np.ndarray, dx: np.ndarray, stiffness: np.ndarray) -> np.ndarray:
        """Another direction to try first, or ``dx`` itself; ``stiffness``: the Newton matrix's diagonal without
        the filter's own Hessian (N/m, 0 on held degrees of freedom). Called in time steps only."""

    def max_step(self, x: np.ndarray, dx: np.ndarray) -> float:
        """The largest fraction in (0, 1] of ``dx`` that x may move along."""

    def hessian_diagonal(self) -> np.ndarray:
        """The diagonal (3 ndof,) of the filter's own Hessian, as last assembled into the Newton matrix."""


class Newton:
    """Newton's method for potentials whose Newton matrix is ``c_M M + c_C C + Hess E`` (module docstring).

    Parameters
    ----------
    problem : FlatEnergy
        The potential; its ``filter`` (None without one) changes and clips the directions.
    settings : NewtonSettings or dict, optional
    inertia : bool
        The problem's Newton matrices have inertia (time steps; :class:`Directions`).

    One object serves a whole run: it keeps the Newton matrix's pattern, the
    solver's analysis, the last factorisation and the step bound between solves.
    """

    def __init__(self, problem: FlatEnergy, settings: NewtonSettings | dict | None = None, inertia: bool = False):
        self.problem = problem
        self.settings = NewtonSettings.of(settings)
        self.search = LineSearch.lookup(self.settings.search)
        self.directions = Directions(problem, self.settings, inertia)
        self._warned = False  # LoadBelowRoundOff said once for this object (one run)
        self._smooth = False  # the last solve ended on the step test without a fallback (module docstring)
        self._moved = 0.0  # the furthest a degree of freedom moved in the last iteration (m)

    def retune(self) -> None:
        """The problem's energy, mass or damping changed (same pattern): no factorisation at hand is of its matrix;
        the matrix's pattern and the solver's analysis stay (:meth:`Directions.retune`)."""
        self.directions.retune()
        self._smooth = False

    def memory(self) -> dict:
        """A factorisation kept across solves (``lag``), for a checkpoint: {"lag": ...}
        (:meth:`Directions.memory`), or {} when none is kept; :meth:`recall` makes it again, so that a resumed
        run is the same run bit for bit."""
        return {"lag": self.directions.memory()} if self._lagging() and self.directions.factored is not None else {}

    def _lagging(self) -> bool:
        """The next solve under the step test may start from the factorisation at hand (``lag``, after a solve
        that ended on the step test without a fallback; a linear model keeps its own anyway)."""
        s = self.settings
        return self._on("lag") and s.reuse and self._smooth and not self.problem.linear

    def _on(self, name: str) -> bool:
        """Whether ``lag`` or ``krylov`` is on: as set, or for "auto" where a factorisation is costly
        (:meth:`Directions.costly`)."""
        value = getattr(self.settings, name)
        return self.directions.costly() if value == "auto" else bool(value)

    def recall(self, memory: dict) -> None:
        """Make again the factorisation :meth:`memory` describes (InputError naming the key when it does not fit
        this problem)."""
        if isinstance(memory, dict) and memory.get("lag") is not None:
            self.directions.recall(memory["lag"])
            self._smooth = True

    @property
    def solver(self):
        """The linear solver of the Newton matrices (:mod:`deformable.algebra.solvers`)."""
        return self.directions.solver

    @property
    def floor(self) -> float:
        """The round-off floor of the last Newton matrix (N), where the next solve's tolerance starts; a
        resumed run sets it (:meth:`deformable.TimeStepper.restore`)."""
        return self.directions.floor

    @floor.setter
    def floor(self, value: float) -> None:
        self.directions.floor = float(value)

    def newton_matrix(self, x, cm: float, cc: float, report: NewtonReport | None = None, kind: str | None = None):
        """The free block of c_M M + c_C C + Hess E (+ the extra matrices) at x (CSC, both triangles).

        ``kind``: the Hessian (default the settings'; "auto" is the exact one
        here). The extra matrices are the springs' Hessian and the damping set
        by :meth:`minimise` (the wind's, times c_C).
        """
        return self.directions.matrix(x, cm, cc, NewtonReport() if report is None else report, kind).tocsc()

    def minimise(self, phi, grad, x, cm: float = 0.0, cc: float = 0.0, label: str = "Newton", damping=None,
                 scale: float | None = None, load: float | None = None, xtol: float | None = None):
        """Minimise phi over the free degrees of freedom from x (held ones stay); returns (x, NewtonReport).

        OpenBLAS keeps one thread meanwhile (:func:`deformable.algebra.solvers.one_blas_thread`).

        Parameters
        ----------
        phi, grad : callables of the flat vector x
            The potential and its gradient (3 ndof,).
        cm, cc : float
            The multipliers of M and C in the Newton matrix.
        label : str
            Named in the ConvergenceError of a failed search.
        damping : sparse (3 ndof, 3 ndof), optional
            A further constant term of the Newton matrix in this solve (the
            wind's damping times c_C), on the same pattern in every solve.
        scale : float, optional
            The residual (N) that ``rtol`` is relative to; default the residual at x.
        load : float, optional
            The max-norm of the applied load on the free degrees of freedom (N), which no absolute term of
            the tolerance may swallow (module docstring); default that of ``problem.load(problem.t)``,
            evaluated only when an absolute term exceeds ``rtol * scale``.
        xtol : float, optional
            The step test's tolerance (m): under ``test="step"`` the solve also ends when a direction from the
            exact Newton matrix moves no degree of freedom further than xtol (module docstring); the implicit
            steps give ``vtol * dt``. None: the force test alone.
        """
        with one_blas_thread():
            return self._minimise(phi, grad, x, cm, cc, label, damping, scale, load, xtol)

    def _load(self, load) -> float | None:
        """The max-norm of the applied load over the free degrees of freedom (N): ``load``, else the problem's (None
        for a problem without loads, ``load(t)`` and ``t``)."""
        if load is not None:
            return float(load)
        p = self.problem
        if not callable(getattr(p, "load", None)):
            return None
        F = p.load(getattr(p, "t", 0.0))[p.free]
        return float(np.max(np.abs(F))) if F.size else 0.0

    def _minimise(self, phi, grad, x, cm, cc, label, damping, scale, load, xtol):
        s, p, D = self.settings, self.problem, self.directions
        free = p.free
        steps = s.test == "step" and xtol is not None  # the step test applies (module docstring)
        report = NewtonReport(floor=D.floor, xtol=xtol if steps else None)
        D.damping = damping
        kept = p.linear or (steps and self._lagging())
        if D.factored is not None and (D.factored != (cm, cc) or not kept):
            D.factored = None  # a factorisation outlives its solve for a linear model, or lagged under the step test
        D.here = False
        g = grad(x)[free]
        r0 = float(np.max(np.abs(g))) if g.size else 0.0
        report.scale = r0 if scale is None else float(scale)
        atol, start = s.atol, None
        if max(atol, report.floor) > s.rtol * report.scale:  # an absolute term binds: it must not swallow the load
            report.load = F = self._load(load)
            if F is not None and s.rtol > 0 and F > 0:
                atol = min(atol, s.rtol * F)
            if F is not None and 0 < F <= max(s.rtol * report.scale, atol, report.floor):  # the floor may not stop it
                start = max(s.rtol * report.scale, atol)
        target = report.tolerance = max(s.rtol * report.scale, atol, report.floor)
        if D.factored is not None and not p.linear:  # lagged: only while the tolerance resolves the load, else a
            F = report.load if report.load is not None else self._load(load)  # chord's error in the soft modes
            if F is None or target >= F:  # (the stiff limit, section 3.1) goes unseen
                D.factored = None
        report.residuals.append(r0)
        if r0 <= (target if start is None else start):
            report.converged = True
            return x, report
        search = self.search(phi, grad, free, s.armijo, label)
        size = forcing_term = None  # the last direction's max-norm; the last CG forcing term
        for it in range(1, s.max_iter + 1):
            last = size
            d, trusted, size, forcing_term = self._direction(phi, x, g, cm, cc, report, steps, size,
                                                             forcing_term, xtol)
            # the step test: x + d resolves the step; a direction of the definite fallback only after it contracted
            # at least twofold (the error left after it is then at most its own size)
            trusted = trusted or (last is not None and size <= 0.5 * last)
            if steps and trusted and size <= xtol and float(g @ d) < 0:
                xt, alpha = self._clipped(x, d)
                if alpha == 1.0:  # a step the filter cuts short is no converged one: it goes to the search
                    x = xt
                    report.iterations, report.converged, report.by, report.step = it, True, "step", size
                    break
            t0 = time.perf_counter()
            slope = float(g @ d)
            newton = slope < 0
            if not newton:  # no descent (a stale factorisation): steepest descent, scaled like the step
                d = -g * (float(np.max(np.abs(d))) / max(float(np.max(np.abs(g))), 1e-300))
                slope = float(g @ d)
            first, fallback = candidates(p.filter, p.free, self.directions.stiffness, x, g, d, slope,
                                         newton and cm > 0)
            target = report.tolerance = max(target, report.floor)
            try:
                xt, gt = search.step(x, first, fallback, target, it, report.residuals[-1])
            except ConvergenceError as err:
                raise ConvergenceError(str(err), report.residuals, err.X) from None
            moved = self._moved = float(np.max(np.abs(xt - x)))
            x = xt
            g = grad(x)[free] if gt is None else gt
            seconds = time.perf_counter() - t0
            report.seconds["search"] += seconds
            report.residuals.append(float(np.max(np.abs(g))))
            report.iterations = it
            target = report.tolerance = max(target, report.floor)
            if report.residuals[-1] <= target:
                report.converged = True
                break
            if moved <= 1e-15 * max(1.0, float(np.max(np.abs(x)))):  # no move left: round-off, or stuck
                report.converged = report.residuals[-1] <= 1e3 * target
                break
        self._smooth = report.by == "step" and report.fallbacks == 0  # the next solve may start from its factor
        if report.by == "force" and (report.load is not None or report.tolerance > s.rtol * report.scale):
            self._check_load(report, load, label)
        return x, report

    def _direction(self, phi, x, g, cm, cc, report, steps: bool, last, forcing_term, xtol):
        """Newton's next direction at x (module docstring, "Directions"): (d, trusted, its max-norm, the CG forcing
        term used). ``trusted``: d solves the exact Newton matrix at x (fresh, or by CG), or comes from a chord of
        an exact factorisation; only such a direction may end a solve by the step test."""
        s, D = self.settings, self.directions
        r = report.residuals
        if steps:
            # no chords of a definite fallback, nor after an iteration that raised the residual or moved a degree
            # of freedom further than a grid spacing (the factorisation's matrix is of a point far away)
            far = len(r) >= 2 and (r[-1] > r[-2] or self._moved > self.problem.length)
            if D.factored is None or not s.reuse or not D.exact or far:
                D.factor_at(x, cm, cc, report)
            d = D.solve(g, report)
            size, trusted = self._norm(d), D.exact and D.here  # a chord ends a solve only once contracting
            # a chord is dropped when it does not pay (contraction), when it is short but contracted less than
            # twofold (its length alone bounds no error), or, first of the solve (a factorisation from an earlier
            # step), when its step does not decrease phi sufficiently (a soft mode of the lagged matrix)
            if last is None:  # a fresh factorisation's direction is Newton's own: nothing to check
                drop = not D.here and size > xtol and not self._descends(phi, x, g, d)
            else:
                drop = size > 0.5 * last if size <= xtol else D.slow(size, last, xtol)
            if not D.here and drop:
                if self._on("krylov"):
                    forcing_term = forcing(r[-1], r[-2] if len(r) > 1 else None, forcing_term)
                    d, solved = D.inexact(x, g, d, cm, cc, forcing_term, report)
                    trusted = solved and s.hessian in ("auto", "newton") or (not solved and D.exact)
                else:
                    D.factor_at(x, cm, cc, report)
                    d = D.solve(g, report)
                    trusted = D.exact
                size = self._norm(d)
            D.here = False
            return d, trusted, size, forcing_term
        # the force test: refactorise unless the factorisation at hand (also one from an earlier solve of a linear
        # model) keeps contracting the residual (CONTRACTION)
        slow = len(r) >= 2 and r[-1] > CONTRACTION * r[-2]
        if D.factored is None or not s.reuse or slow:
            D.factor_at(x, cm, cc, report)
        d = D.solve(g, report)
        D.here = False
        return d, False, self._norm(d), forcing_term

    def _clipped(self, x, d):
        """x + alpha d with alpha the direction filter's safe fraction of the free direction d (1 without a
        filter): (the point, alpha)."""
        f, free = self.problem.filter, self.problem.free
        alpha = 1.0 if f is None else f.max_step(x, spread(free, x, d))
        xt = x.copy()
        xt[free] += alpha * d
        return xt, alpha

    def _descends(self, phi, x, g, d) -> bool:
        """Whether the (clipped) step d from x decreases phi sufficiently (the settings' Armijo constant)."""
        xt, alpha = self._clipped(x, d)
        ft = phi(xt)
        return bool(np.isfinite(ft) and ft <= phi(x) + self.settings.armijo * alpha * float(g @ d))

    @staticmethod
    def _norm(d) -> float:
        return float(np.max(np.abs(d))) if d.size else 0.0

    def _check_load(self, report: NewtonReport, load, label: str) -> None:
        """Warn (once) when the tolerance accepted a residual as large as the load and the residual stayed of the
        load's size: the load is lost in round-off (module docstring)."""
        if report.load is None:
            report.load = self._load(load)
        F = report.load
        report.lost = bool(F is not None and 0 < F <= report.tolerance and report.residuals[-1] > 0.5 * F)
        if report.lost and not self._warned:
            self._warned = True
            warnings.warn(f"{label}: the applied load ({F:.3g} N at most on a degree of freedom) is below the "
                          f"round-off floor of the elastic forces ({report.floor:.3g} N, the largest at the iterates), "
                          f"and the residual left after {report.iterations} Newton iterations "
                          f"({report.residuals[-1]:.3g} N) is of the load's size: the residual cannot tell the "
                          "solution, and the load may be lost in round-off, what it drives not computed (a "
                          "stiffness eta, xi too large against the loads and the inertia for double precision, or "
                          "iterates far from the solution)", LoadBelowRoundOff, stacklevel=4)
