"""What a Newton solve is asked and what it tells: :class:`NewtonSettings` (checked) and :class:`NewtonReport`; the
method is :mod:`deformable.solve.newton`'s docstring.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..checks import known_keys
from ..errors import InputError
from .search import LineSearch

__all__ = ["NewtonReport", "NewtonSettings", "TESTS"]

#: the convergence tests (:mod:`deformable.solve.newton`, "Convergence tests")
TESTS = ("step", "force")
#: the factorisations' precision (NewtonSettings.precision)
PRECISIONS = ("auto", "single", "double")


@dataclass
class NewtonReport:
    """Iterations, residual history and cost of one Newton solve."""

    iterations: int = 0
    residuals: list = field(default_factory=list)
    converged: bool = False
    floor: float = 0.0  # round-off floor the tolerance was raised to, if any (N)
    scale: float = 0.0  # the residual rtol is relative to (N)
    tolerance: float = 0.0  # the residual the solve had to reach (N)
    load: float | None = None  # max-norm of the applied load on the free dofs, where the tolerance needed it (N)
    lost: bool = False  # the load was at or below the tolerance and the residual stayed of its size (solve.newton)
    factorisations: int = 0
    fallbacks: int = 0  # exact Newton matrices found indefinite ("auto": the definite one took their place)
    cg: int = 0  # conjugate-gradient iterations (products with the Newton matrix) of the inexact directions
    by: str = "force"  # the test that ended the solve: "force" or "step"
    xtol: float | None = None  # the step test's tolerance (m), where it applied
    step: float = 0.0  # the max-norm of the last direction (m); by "step": at most xtol, the step added to x
    seconds: dict = field(default_factory=lambda: {"hessian": 0.0, "factor": 0.0, "solve": 0.0, "search": 0.0})


@dataclass(frozen=True)
class NewtonSettings:
    """Settings of :class:`deformable.solve.newton.Newton`, checked.

    Parameters
    ----------
    rtol, atol : float
        Converged when the max-norm of the free residual is at most ``max(rtol * scale, atol)`` (atol in N), never
        below the round-off floor of the internal forces; the scale is the residual at the start unless the caller
        gives one (in a time step: the force imbalance at the inertial predictor x_n + dt v_n, so rtol bounds the
        Newton error against the step's correction; a study of temporal order asks for less, e.g. 1e-10). atol is
        capped at rtol times the applied load (:mod:`deformable.solve.newton`, "Loads below the absolute terms of
        the tolerance").
    max_iter : int
        Iterations per solve (0 allowed: a solve that must already be converged).
    hessian : str
        "auto" (default): the exact Hessian when the Newton matrix it gives is positive definite (the factorisation
        tells), else the "definite" one; or one of "definite", "newton", "gauss-newton", "projected"
        (:mod:`deformable.physics.integrand`).
    solver : str
        "auto", "superlu" or "pardiso" (:mod:`deformable.algebra.solvers`).
    reuse : bool
        Keep a factorisation while it contracts.
    search : str
        The line search, a registered :class:`deformable.solve.search.LineSearch`: "watchdog" (default) or "armijo".
    armijo : float
        The sufficient-decrease constant c of the line search's Armijo test, in (0, 1/2).
    test, vtol : str, float
        "step" (default) or "force": "step" is also converged on a trusted direction no longer than vtol dt (vtol in
        m/s; time steps without obstacles; :mod:`deformable.solve.newton`, "Convergence tests").
    lag, contraction, chords, krylov : bool or "auto", float, float, bool or "auto"
        Under "step": keep a factorisation across steps; refactorise when a chord contracts less than
        ``contraction``, or when the chords still needed outnumber ``chords`` + 1 (the cost of a factorisation with
        its assembly, in chord iterations); PCG on the exact matrix preconditioned by the factorisation at hand
        instead of a refactorisation. "auto" (both defaults): on where a factorisation costs at least
        :data:`deformable.solve.directions.LAG_FROM` solves by the solver's own count, off elsewhere.
    fallback : str
        The matrix factorised where the exact one is indefinite: "definite" (default) or "projected".
    precision : str
        PARDISO's Cholesky in "single" or "double" precision; "auto" (default): single in time steps, whose Newton
        matrices the inertia keeps well conditioned, double in equilibrium (:mod:`deformable.algebra.solvers`,
        "Single precision").
    """

    rtol: float = 1e-3
    atol: float = 1e-12
    max_iter: int = 30
    hessian: str = "auto"
    solver: str = "auto"
    reuse: bool = True
    search: str = "watchdog"
    armijo: float = 1e-4
    test: str = "step"
    vtol: float = 1e-2
    lag: bool | str = "auto"
    contraction: float = 0.9
    chords: float = 8.0
    krylov: bool | str = "auto"
    fallback: str = "definite"
    precision: str = "auto"

    def __post_init__(self):
        from ..algebra.solvers import SOLVERS
        from ..physics.integrand import HESSIANS

        for name in ("rtol", "atol"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v < 0:
                raise InputError(f"newton {name} must be a finite non-negative number, got {v!r}")
        if isinstance(self.max_iter, bool) or not isinstance(self.max_iter, (int, np.integer)) or self.max_iter < 0:
            raise InputError(f"newton max_iter must be a non-negative integer, got {self.max_iter!r}")
        if self.hessian not in ("auto",) + HESSIANS:
            raise InputError(f"newton hessian must be 'auto' or one of {HESSIANS}, got {self.hessian!r}")
        if self.solver not in SOLVERS:
            raise InputError(f"newton solver must be one of {SOLVERS}, got {self.solver!r}")
        if not isinstance(self.search, str) or self.search not in LineSearch.names():
            raise InputError(f"newton search must be one of {', '.join(LineSearch.names())}, got {self.search!r}",
                             field="newton.search", value=self.search)
        if self.fallback not in ("definite", "projected"):
            raise InputError(f"newton fallback must be 'definite' or 'projected', got {self.fallback!r}",
                             field="newton.fallback", value=self.fallback)
        if self.precision not in PRECISIONS:
            raise InputError(f"newton precision must be one of {', '.join(PRECISIONS)}, got {self.precision!r}",
                             field="newton.precision", value=self.precision)
        if self.test not in TESTS:
            raise InputError(f"newton test must be one of {', '.join(TESTS)}, got {self.test!r}", field="newton.test",
                             value=self.test)
        for name in ("vtol", "contraction", "chords"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v <= 0:
                raise InputError(f"newton {name} must be a finite positive number, got {v!r}", field=f"newton.{name}",
                                 value=v)
        for name in ("lag", "krylov", "reuse"):
            v = getattr(self, name)
            if not (isinstance(v, bool) or (name != "reuse" and v == "auto")):
                raise InputError(f"newton {name} must be true or false{'' if name == 'reuse' else ' or auto'}, got "
                                 f"{v!r}", field=f"newton.{name}", value=v)
        c = self.armijo
        if isinstance(c, bool) or not isinstance(c, (int, float)) or not 0 < c < 0.5:
            raise InputError(f"newton armijo must lie in (0, 1/2), got {c!r}", field="newton.armijo", value=c)

    @classmethod
    def of(cls, value) -> NewtonSettings:
        """Settings from a NewtonSettings, a dict of its fields or None (the defaults); InputError otherwise."""
        if isinstance(value, cls):
            return value
        if value is None:
            return cls()
        if not isinstance(value, dict):
            raise InputError(f"newton settings must be a NewtonSettings or a dict, got {value!r}", field="newton",
                             value=value)
        known_keys(value, cls.__dataclass_fields__, "in the newton settings", field="newton")
        return cls(**value)
