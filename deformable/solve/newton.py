"""Newton's method on a potential over the free degrees of freedom of a model.

The implicit time steps (:mod:`deformable.dynamics.implicit`) and static equilibrium (:mod:`.equilibrium`) minimise

    Phi(x) = (inertia and damping terms) + E(x) - F . x

over :class:`deformable.solve.potential.FlatEnergy` (E: the energy of eq. (13), or the frozen model's, with the
springs'), whose Newton matrix is ``c_M M + c_C C + Hess E`` (implicit Euler: 1/dt^2, 1/dt; Newmark: 4/dt^2, 2/dt;
statics: 0, 0). :class:`Newton` computes directions (:class:`deformable.solve.directions.Directions`) and leaves the
step to a registered line search (:mod:`deformable.solve.search`). A factorisation is reused while each iteration
with it reduces the residual by the factor :data:`CONTRACTION` (a chord method); a linear model's, while c_M and c_C
stay the same.

Convergence tests (``NewtonSettings(test=...)``). "force": the max-norm of the free residual at most ``rtol`` times
its scale. "step" (the default in time steps without obstacles): also when a trusted direction (from a factorisation
of the exact Newton matrix, or after the directions contracted twofold) moves no degree of freedom further than
``vtol dt`` (Li et al. 2020, IPC, section 5) and the direction filter takes it whole; x + d is returned.

Fine grids. ``lag``: a factorisation outlives a solve that ended on the step test without a fallback, chords going
on while they pay (:meth:`Directions.slow`; a checkpoint keeps it, :meth:`Newton.memory`). ``krylov``: where a chord
does not pay, PCG preconditioned by the factorisation at hand (:mod:`.krylov`). "auto" turns both on where one
factorisation costs at least :data:`deformable.solve.directions.LAG_FROM` solves by the solver's own count.

Loads below the absolute terms of the tolerance. ``atol`` is capped at ``rtol`` times the applied load (max-norm over
the free degrees of freedom); a load at or below the round-off floor of the internal forces (``1e3 eps max|diag A|
max(1, |x|)``) gets at least one Newton step, and a warning (:class:`deformable.errors.LoadBelowRoundOff`) when the
residual stays of its size.

Direction filters (:class:`DirectionFilter`, e.g. :class:`deformable.contact.potential.ContactPotential`). Every
direction is clipped to the filter's largest safe step (``max_step``: no iterate carries a contact point across an
obstacle, Li et al. 2020, section 4), and the Armijo test uses the clipped slope. In a time step the filter may
propose another direction first (``propose``); the search falls back to Newton's clipped step when it fails.
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
    """What a term of the potential may do to Newton's direction (module docstring); directions are flat (3 ndof,),
    zero on the held degrees of freedom."""

    def propose(self, x: np.ndarray, dx: np.ndarray, stiffness: np.ndarray) -> np.ndarray:
        """Another direction to try first, or ``dx`` itself; ``stiffness``: the Newton matrix's diagonal without the
        filter's own Hessian (N/m, 0 on held degrees of freedom). Called in time steps only."""

    def max_step(self, x: np.ndarray, dx: np.ndarray) -> float:
        """The largest fraction in (0, 1] of ``dx`` that x may move along."""

    def hessian_diagonal(self) -> np.ndarray:
        """The diagonal (3 ndof,) of the filter's own Hessian, as last assembled into the Newton matrix."""


class Newton:
    """Newton's method for potentials whose Newton matrix is ``c_M M + c_C C + Hess E`` (module docstring).

    One object serves a whole run: it keeps the matrix's pattern, the solver's analysis, the last factorisation and
    the step bound between solves.

    Parameters
    ----------
    problem : FlatEnergy
        The potential; its ``filter`` (None without one) changes and clips the directions.
    settings : NewtonSettings or dict, optional
    inertia : bool
        The problem's Newton matrices have inertia (time steps; :class:`Directions`).
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
        """The problem's energy, mass or damping changed (same pattern): drop the factorisation at hand
        (:meth:`Directions.retune`)."""
        self.directions.retune()
        self._smooth = False

    def memory(self) -> dict:
        """A factorisation kept across solves (``lag``) for a checkpoint: {"lag": :meth:`Directions.memory`}, or {};
        :meth:`recall` makes it again."""
        return {"lag": self.directions.memory()} if self._lagging() and self.directions.factored is not None else {}

    def _lagging(self) -> bool:
        """Whether the next solve under the step test may start from the factorisation at hand (``lag``)."""
        s = self.settings
        return self._on("lag") and s.reuse and self._smooth and not self.problem.linear

    def _on(self, name: str) -> bool:
        """Whether ``lag`` or ``krylov`` is on: as set, or for "auto" where a factorisation is costly."""
        value = getattr(self.settings, name)
        return self.directions.costly() if value == "auto" else bool(value)

    def recall(self, memory: dict) -> None:
        """Make again the factorisation :meth:`memory` describes (InputError naming the key when it does not fit)."""
        if isinstance(memory, dict) and memory.get("lag") is not None:
            self.directions.recall(memory["lag"])
            self._smooth = True

    @property
    def solver(self):
        """The linear solver of the Newton matrices (:mod:`deformable.algebra.solvers`)."""
        return self.directions.solver

    @property
    def floor(self) -> float:
        """The round-off floor of the last Newton matrix (N), where the next solve's tolerance starts; a resumed run
        sets it (:meth:`deformable.TimeStepper.restore`)."""
        return self.directions.floor

    @floor.setter
    def floor(self, value: float) -> None:
        self.directions.floor = float(value)

    def newton_matrix(self, x, cm: float, cc: float, report: NewtonReport | None = None, kind: str | None = None):
        """The free block of c_M M + c_C C + Hess E (+ the springs' Hessian and :meth:`minimise`'s damping) at x
        (CSC, both triangles); ``kind``: the Hessian (default the settings'; "auto" is the exact one here)."""
        return self.directions.matrix(x, cm, cc, NewtonReport() if report is None else report, kind).tocsc()

    def minimise(self, phi, grad, x, cm: float = 0.0, cc: float = 0.0, label: str = "Newton", damping=None,
                 scale: float | None = None, load: float | None = None, xtol: float | None = None):
        """Minimise phi over the free degrees of freedom from x (held ones stay), OpenBLAS on one thread
        (:func:`deformable.algebra.solvers.one_blas_thread`); returns (x, NewtonReport).

        Parameters
        ----------
        phi, grad : callables of the flat vector x
            The potential and its gradient (3 ndof,).
        cm, cc : float
            The multipliers of M and C in the Newton matrix.
        label : str
            Named in the ConvergenceError of a failed search.
        damping : sparse (3 ndof, 3 ndof), optional
            A further constant term of the Newton matrix in this solve (the wind's damping times c_C), on the same
            pattern in every solve.
        scale : float, optional
            The residual (N) that ``rtol`` is relative to; default the residual at x.
        load : float, optional
            The max-norm of the applied load on the free degrees of freedom (N), which no absolute term of the
            tolerance may swallow; default that of ``problem.load(problem.t)``, evaluated only when an absolute term
            exceeds ``rtol * scale``.
        xtol : float, optional
            The step test's tolerance (m; the implicit steps give ``vtol * dt``); None: the force test alone.
        """
        with one_blas_thread():
            return self._minimise(phi, grad, x, cm, cc, label, damping, scale, load, xtol)

    def _load(self, load) -> float | None:
        """The max-norm of the applied load over the free degrees of freedom (N): ``load``, else the problem's, or
        None."""
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
        """Newton's next direction at x: (d, trusted, its max-norm, the CG forcing term used). ``trusted``: d solves
        the exact Newton matrix at x, or is a chord of an exact factorisation; only such a direction may end a solve
        by the step test."""
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
        """(x + alpha d, alpha), alpha the direction filter's safe fraction of the free direction d (1 without a
        filter)."""
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
        """Warn once when the residual stayed of the size of a load at or below the tolerance (module docstring)."""
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
