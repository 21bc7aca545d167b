"""Where Newton's directions come from: the Newton matrix, its factorisation kept while it pays, and inexact solves.

:class:`Directions` is the linear algebra of one :class:`deformable.solve.newton.Newton` object (one run):

- the Newton matrix ``c_M M + c_C C + Hess E`` (+ the springs' Hessian and the wind's damping) is assembled as its
  free block's upper triangle by precomputed slots (:class:`deformable.algebra.upper.FreeUpper`), the self-contact's
  Hessian on a pattern that grows (``loose``);
- a factorisation is positive definite: by default ("auto") the exact Hessian's when the factorisation finds it so,
  else the *definite* Hessian's (:mod:`deformable.physics.integrand`: Gauss-Newton plus the membrane's tension
  stiffness); a Levenberg-Marquardt shift is the last resort for a singular matrix. :attr:`exact` says which;
- a chord direction is a solve with a factorisation made at an earlier iterate (of this solve or, under ``lag``, of
  an earlier time step), kept while the chords still needed cost less than a factorisation (:meth:`slow`);
- an inexact direction (:meth:`inexact`) solves the exact Newton matrix by conjugate gradients preconditioned by the
  factorisation at hand (:mod:`deformable.solve.krylov`), within a budget that costs no more than a new
  factorisation (:meth:`break_even`), and factorises that matrix when CG does not converge.

The costs are wall-clock seconds, kept in each :class:`deformable.solve.newton.NewtonReport`; only the CG budget,
where the solver does not count, reads them.
"""

from __future__ import annotations

import math
import time

import numpy as np
import scipy.sparse as sp

from ..algebra.upper import FreeUpper
from ..algebra.solvers import make_solver
from ..checks import real
from ..errors import InputError, SingularMatrix
from .krylov import pcg
from .settings import NewtonReport

__all__ = ["Directions"]

#: CG's budget is at least this many iterations, at most this many
CG_BUDGET = (2, 40)
#: "auto" keeps factorisations across steps, and solves by preconditioned CG rather than refactorise, where one
#: factorisation costs at least this many solves by the solver's own count (:mod:`deformable.solve.newton`)
LAG_FROM = 100.0


class Directions:
    """The Newton matrix, its kept factorisation, chord and inexact directions of one Newton object (module docstring).

    Parameters
    ----------
    problem : FlatEnergy
        The potential (its Hessians, mass, damping, held degrees of freedom, direction filter).
    settings : NewtonSettings
        ``hessian``, ``solver`` and ``precision`` are read here.
    inertia : bool
        The Newton matrices have inertia (time steps): "auto" precision is single there.
    """

    def __init__(self, problem, settings, inertia: bool = False):
        self.problem, self.settings = problem, settings
        definite = settings.hessian in ("auto", "definite", "gauss-newton", "projected")
        single = settings.precision == "single" or (settings.precision == "auto" and inertia)
        self.solver = make_solver(settings.solver, definite=definite, single=single)
        self._system = None
        self.factored = None  # (c_M, c_C) of the factorisation at hand, or None
        self.exact = False  # the factorisation at hand is of the exact Newton matrix (not the definite fallback)
        self.here = False  # it was made at the current iterate
        self.floor = 0.0  # the round-off floor of the last Newton matrix (N)
        self.damping = None  # an extra damping matrix of the current solve (already times c_C)
        self.made = None  # (x, the problem's t, damping) of the factorisation at hand: a checkpoint keeps it
        self.stiffness = None  # with a filter: the Newton matrix's diagonal without the filter's Hessian (3 ndof,)
        self._cost = {"hessian": None, "factor": None, "solve": None, "product": None}  # the last seconds of each

    # -- the matrix -----------------------------------------------------------------
    def matrix(self, x, cm: float, cc: float, report, kind: str | None = None):
        """The free block of the Newton matrix at x (CSC), on the fixed pattern; ``kind``: the Hessian (default the
        settings'; "auto" is the exact one here)."""
        t0 = time.perf_counter()
        p = self.problem
        kind = kind or self.settings.hessian
        kind = "newton" if kind == "auto" else kind
        H, elements = p.hessian_elements(x, kind)
        extra = p.extra_hessians(x, self.damping, kind)
        if self._system is None:
            self._system = FreeUpper(p.M.shape[0], p.fixed, p.M, p.C, cm, cc, H if elements is None else elements,
                                     extra)
        elif (self._system.cm, self._system.cc) != (cm, cc):
            self._system.rescale(cm, cc)
        A = self._system.assemble(H, extra, loose=p.loose_hessians(x), reserve=p.loose_reserve)
        if p.filter is not None:  # the diagonal without the filter's own Hessian, for its proposals
            self.stiffness = np.zeros(3 * p.n)
            self.stiffness[p.free] = A.diagonal() - p.filter.hessian_diagonal()[p.free]
        seconds = time.perf_counter() - t0
        report.seconds["hessian"] += seconds
        self._cost["hessian"] = seconds
        # round-off floor: internal forces are sums of terms of size |diag H| |x|
        self.floor = float(1e3 * np.finfo(float).eps * np.max(np.abs(A.diagonal())) * max(1.0, np.max(np.abs(x))))
        report.floor = max(report.floor, self.floor)
        return A

    def retune(self) -> None:
        """The problem's energy, M or C changed on the same patterns: the block takes the new M and C, and no
        factorisation at hand is of the new matrix."""
        if self._system is not None:
            self._system.refill(self.problem.M, self.problem.C)
        self.factored, self.here, self.made = None, False, None

    # -- factorisations -------------------------------------------------------------
    def factor_at(self, x, cm: float, cc: float, report, A=None) -> None:
        """Assemble (unless ``A``, the settings' matrix at x, is given) and factorise the Newton matrix at x
        ("auto": the exact one if definite, else the definite one)."""
        auto = self.settings.hessian == "auto"
        A = self.matrix(x, cm, cc, report) if A is None else A
        self.factored, self.here = (cm, cc), True
        self.made = (x.copy(), float(getattr(self.problem, "t", 0.0)), self.damping)  # what the factorisation is of
        if auto:
            t0 = time.perf_counter()
            try:
                self.solver.factor(A)
                self._counted(report, t0)
                self.exact = True
                return
            except SingularMatrix:  # indefinite (compression, or bending away from the rest state): make it definite
                report.seconds["factor"] += time.perf_counter() - t0
                report.fallbacks += 1
            A = self.matrix(x, cm, cc, report, self.settings.fallback)
        self._factor(A, report)
        self.exact = self.settings.hessian == "newton"

    def _factor(self, A, report) -> None:
        """Factorise A, adding a Levenberg-Marquardt shift if it is singular (or indefinite with Cholesky)."""
        t0 = time.perf_counter()
        scale = float(np.mean(np.abs(A.diagonal()))) or 1.0
        for shift in (0.0, 1e-8, 1e-4, 1e-2, 1.0):
            try:
                self.solver.factor(A if not shift else A.shifted(shift * scale))
                break
            except SingularMatrix:
                if not shift and self._in_double():
                    break
        else:
            raise SingularMatrix("the Newton matrix stays singular under a Levenberg-Marquardt shift")
        self._counted(report, t0)

    def _in_double(self) -> bool:
        """Whether the solver, turned to double precision for good, factorised the matrix a single-precision
        factorisation lost a pivot of (:mod:`deformable.algebra.solvers`, "Single precision")."""
        try:
            return self.solver.double()
        except SingularMatrix:
            return False

    def _counted(self, report, t0: float) -> None:
        seconds = time.perf_counter() - t0
        report.factorisations += 1
        report.seconds["factor"] += seconds
        self._cost["factor"] = seconds

    # -- a checkpoint's memory ----------------------------------------------------------
    def memory(self) -> dict:
        """Where the factorisation at hand was made, as numbers: {"x", "t", "cm", "cc", "damping"} (the iterate (3
        ndof,), the problem's time (s), the multipliers, the extra damping as COO rows, columns, values)."""
        x, t, damping = self.made
        c = sp.coo_matrix((x.size, x.size)) if damping is None else sp.coo_matrix(damping)
        return {"x": x.tolist(), "t": t, "cm": self.factored[0], "cc": self.factored[1],
                "damping": [c.row.tolist(), c.col.tolist(), c.data.tolist()]}

    def recall(self, lag) -> None:
        """Factorise again the Newton matrix :meth:`memory` describes (InputError naming the key when it does not
        fit this problem)."""
        p = self.problem
        if not isinstance(lag, dict) or sorted(lag) != ["cc", "cm", "damping", "t", "x"]:
            raise InputError(f"memory.lag must hold x, t, cm, cc and damping, got {lag!r:.60}", field="memory.lag",
                             value=lag)
        x = np.asarray(lag["x"], dtype=float)
        if x.shape != (3 * p.n,):
            raise InputError(f"memory.lag.x has {x.size} numbers, not the model's {3 * p.n}", field="memory.lag.x",
                             value=x.size)
        parts = [np.asarray(v) for v in lag["damping"]] if isinstance(lag["damping"], list) else []
        rows, cols, data = parts if len(parts) == 3 and parts[0].shape == parts[1].shape == parts[2].shape else (
            None, None, None)
        if rows is None or rows.size and (min(rows.min(), cols.min()) < 0 or max(rows.max(), cols.max()) >= x.size):
            raise InputError("memory.lag.damping is not a matrix of the model's size", field="memory.lag.damping",
                             value=str(lag["damping"])[:60])
        cm, cc = (real(f"memory.lag.{k}", lag[k], non_negative=True) for k in ("cm", "cc"))
        t, before = real("memory.lag.t", lag["t"]), getattr(p, "t", 0.0)
        p.t, self.damping = t, sp.csr_matrix((data, (rows, cols)), shape=(x.size, x.size)) if rows.size else None
        self.factor_at(x, cm, cc, NewtonReport())  # a report of its own: this factorisation is no solve's
        p.t, self.here = before, False

    # -- directions -----------------------------------------------------------------
    def solve(self, g: np.ndarray, report) -> np.ndarray:
        """The chord (or Newton) direction ``-A^-1 g`` with the factorisation at hand."""
        t0 = time.perf_counter()
        try:
            d = -self.solver.solve(g)
        except SingularMatrix:  # a float32 Cholesky passed a matrix that double precision finds indefinite
            self._remake(report)
            d = -self.solver.solve(g)
        seconds = time.perf_counter() - t0
        report.seconds["solve"] += seconds
        self._cost["solve"] = seconds
        return d

    def _remake(self, report) -> None:
        """Factorise again, in double precision, the Newton matrix the factorisation at hand was made of (same
        iterate, time, multipliers and damping): "auto" falls back to its definite matrix, any other a
        Levenberg-Marquardt shift (:meth:`factor_at`). A float32 Cholesky may pass a nearly singular indefinite
        matrix that double precision finds indefinite."""
        x, t, damping = self.made
        p, here, current = self.problem, self.here, self.damping
        before = getattr(p, "t", None)
        if before is not None:
            p.t = t
        self.damping = damping
        self.factor_at(x, *self.factored, report)
        if before is not None:
            p.t = before
        self.here, self.damping = here, current

    def cost(self, name: str) -> float:
        """The last measured seconds of a "hessian" (the Newton matrix's assembly), "factor", "solve" or "product"
        in this run (0 before the first)."""
        return self._cost[name] or 0.0

    def slow(self, size: float, last: float, xtol: float) -> bool:
        """Whether to refactorise rather than go on with chords: the chord iterations still needed to bring the
        direction's max-norm ``size`` under ``xtol`` at the contraction ``size / last`` outnumber the settings'
        ``chords`` plus one, or that contraction is above the settings' ``contraction``. A count, so that a
        trajectory does not depend on the machine's load."""
        if size <= xtol:
            return False
        ratio = size / last
        if not ratio < self.settings.contraction:
            return True
        return math.log(xtol / size) / math.log(ratio) > self.settings.chords + 1

    def costly(self) -> bool:
        """Whether a factorisation costs at least :data:`LAG_FROM` solves by the solver's own count (False before
        the first, or for a solver that does not count)."""
        ratio = self.solver.cost_ratio
        return ratio is not None and ratio >= LAG_FROM

    def break_even(self) -> int:
        """CG's budget within :data:`CG_BUDGET`: half the solver's own count of the solves a factorisation costs,
        else the iterations (a solve and a product each) that cost one factorisation by the times measured in this
        run."""
        ratio = self.solver.cost_ratio
        if ratio is not None:
            return int(min(CG_BUDGET[1], max(CG_BUDGET[0], ratio // 2)))
        factor, solve, product = (self._cost[k] for k in ("factor", "solve", "product"))
        if factor is None or solve is None:
            return CG_BUDGET[0]
        per = solve + (0.1 * solve if product is None else product)
        return int(min(CG_BUDGET[1], max(CG_BUDGET[0], factor // max(per, 1e-12))))

    def inexact(self, x, g: np.ndarray, d0: np.ndarray, cm: float, cc: float, rtol: float, report):
        """A direction for the exact Newton matrix at x: PCG from the chord direction ``d0``, preconditioned by the
        factorisation at hand, to ``||A d + g|| <= rtol ||g||`` within :meth:`break_even` iterations, else that
        matrix factorised. Returns (d, whether CG converged); ``report.cg`` counts the iterations."""
        A = self.matrix(x, cm, cc, report, "newton" if self.settings.hessian == "auto" else None)
        budget = self.break_even()
        t0 = time.perf_counter()
        result = pcg(A, -g, self.solver.solve, x0=d0, rtol=rtol, maxiter=budget)
        seconds = time.perf_counter() - t0
        report.seconds["solve"] += seconds
        report.cg += result.iterations
        if result.iterations:
            solve = self._cost["solve"] or 0.0
            self._cost["product"] = max(seconds / result.iterations - solve, 0.0)
        if result.status == "converged":
            return result.x, True
        self.factor_at(x, cm, cc, report, A)
        return self.solve(g, report), False
