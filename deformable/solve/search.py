"""Line searches of Newton's method: strategies beside the loop, registered by name.

Newton's loop (:class:`deformable.solve.newton.Newton`) computes a direction, lets the potential's direction filter
change and clip it (contact), and hands the search its candidates; the search returns the next iterate. A search is
built once per solve (it may keep state between iterations) with the potential phi, its gradient, the free degrees
of freedom and the Armijo constant c (``NewtonSettings(armijo=...)``, default 1e-4). A candidate is a direction over
the free degrees of freedom with its slope g . d < 0 (:class:`Candidate`); the first is the preferred one, the
second, if any, is produced only when the search asks for it (contact: Newton's own clipped direction, when the
solved contact normals fail to decrease phi).

- ``"watchdog"`` (:class:`Watchdog`, the default; Chamberlain, Powell, Lemarechal and Pedersen 1982, "The watchdog
  technique for forcing convergence in algorithms for constrained optimization", Math. Prog. Study 16): full Newton
  steps are taken even when phi grows, for at most :attr:`Watchdog.steps` steps in a row; if none brings a
  sufficient (Armijo) decrease against the last good point, the search goes back to that point and backtracks along
  its direction. phi is evaluated only to weigh a step: a full step whose residual meets the tolerance ends the
  solve without it. Newton keeps its quadratic convergence through the nonconvex stretches of elastica-like
  problems.
- ``"armijo"`` (:class:`Armijo`): monotone backtracking from every iterate, halving the step until ``phi(x + s d) <=
  phi(x) + c s g . d`` (Nocedal and Wright 2006, "Numerical Optimization", algorithm 3.1).

A search knows no contact: the directions it is given are safe as they are (clipped by the filter), and so is every
fraction of them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, ClassVar

import numpy as np

from ..errors import ConvergenceError
from ..registry import Registered

__all__ = ["LineSearch", "Watchdog", "Armijo", "Candidate", "WATCHDOG", "candidates", "spread"]

#: full Newton steps taken in a row without a sufficient decrease of the potential before the watchdog steps back
WATCHDOG = 6


@dataclass(frozen=True)
class Candidate:
    """A search direction over the free degrees of freedom, d (n_free,), and its slope g . d (< 0 for descent)."""

    d: np.ndarray
    slope: float


class LineSearch(Registered, family="line search"):
    """A line search for one Newton solve (module docstring).

    Parameters
    ----------
    phi, grad : callables of the flat x
        The potential and its gradient (3 ndof,).
    free : bool array (3 ndof,)
        The degrees of freedom that move.
    armijo : float
        The sufficient-decrease constant c of ``phi(x + d) <= phi(x) + c g . d``.
    label : str
        Named in the ConvergenceError of a failed search.
    """

    def __init__(self, phi: Callable, grad: Callable, free: np.ndarray, armijo: float = 1e-4,
                 label: str = "Newton"):
        self.phi, self.grad, self.free, self.c, self.label = phi, grad, free, armijo, label

    def step(self, x, first: Candidate, fallback: Callable[[], Candidate] | None, target: float, iteration: int,
             residual: float):
        """The next iterate from x and, when the search computed it, its free gradient (else None).

        ``first``: the preferred candidate; ``fallback()``: the next one, if any; ``target``: the residual (max-norm
        of the free gradient) at which Newton stops; ``residual``: the current one (for messages).
        """
        raise NotImplementedError

    def backtrack(self, x, f0: float, d: np.ndarray, slope: float, iteration: int, residual: float):
        """Armijo backtracking from x along the descent direction d (slope g . d < 0): the point and its phi.

        Halves the step from 1 until phi decreases sufficiently (at most 50 times); ConvergenceError otherwise.
        """
        step = 1.0
        for _ in range(50):
            xt = x.copy()
            xt[self.free] += step * d
            ft = self.phi(xt)
            if np.isfinite(ft) and ft <= f0 + self.c * step * slope:
                return xt, ft
            step *= 0.5
        raise ConvergenceError(f"{self.label}: line search failed at iteration {iteration} (residual {residual:.3e})",
                               [], x)


class Armijo(LineSearch):
    """Monotone backtracking from every iterate along the first candidate (module docstring)."""

    name = "armijo"
    rank = 1

    def step(self, x, first, fallback, target, iteration, residual):
        xt, _ = self.backtrack(x, self.phi(x), first.d, first.slope, iteration, residual)
        return xt, None


class Watchdog(LineSearch):
    """Full steps watched for a sufficient decrease, with a return to the last good point (module docstring).

    State between iterations: the reference (the last point of sufficient decrease, its phi when known, its
    direction and slope), phi at the current iterate when known, and the full steps left.
    """

    name = "watchdog"
    rank = 0
    #: full steps in a row without a sufficient decrease before the search steps back
    steps: ClassVar[int] = WATCHDOG

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.ref = None  # [x, phi or None, direction, slope]: the last sufficient decrease
        self.fx = None  # phi at the current iterate, when known
        self.relaxed = self.steps

    def step(self, x, first, fallback, target, iteration, residual):
        free, phi, grad, c = self.free, self.phi, self.grad, self.c
        new_ref = self.ref is None
        if new_ref:  # phi there is evaluated when a step is first weighed against it
            self.ref = [x, self.fx, first.d, first.slope]
        xt = gt = None
        if self.relaxed > 0:  # a full step, kept even if phi grows, for at most `steps` steps in a row
            d, slope = first.d, first.slope
            xt = x.copy()
            xt[free] += d
            gt = grad(xt)[free]
            weigh = not float(np.max(np.abs(gt))) <= target  # a step that converges needs no weighing
            ft = None
            if weigh and fallback is not None:  # the first candidate must gain on x itself, else the next one
                self.fx = phi(x) if self.fx is None else self.fx
                if new_ref:
                    self.ref[1] = self.fx
                ft = phi(xt)
                if not ft <= self.fx + c * slope:
                    other = fallback()
                    d, slope, ft = other.d, other.slope, None
                    if new_ref:
                        self.ref[2:] = [d, slope]
                    xt = x.copy()
                    xt[free] += d
                    gt = grad(xt)[free]
                    weigh = not float(np.max(np.abs(gt))) <= target
            if weigh:
                self.fx = phi(xt) if ft is None else ft
                if self.ref[1] is None:
                    self.ref[1] = phi(self.ref[0])
                if not np.isfinite(self.fx):
                    xt, gt, self.relaxed = None, None, 0
                elif self.fx <= self.ref[1] + c * self.ref[3]:
                    self.ref, self.relaxed = None, self.steps
                else:
                    self.relaxed -= 1
        if xt is None:  # back to the reference, and a monotone backtracking search along its direction
            xr, fr, dr, sr = self.ref
            xt, self.fx = self.backtrack(xr, phi(xr) if fr is None else fr, dr, sr, iteration, residual)
            self.ref = None
        return xt, gt


def spread(free, x, d) -> np.ndarray:
    """The free direction d (n_free,) as a flat vector like x (3 ndof,), zero on the held degrees of freedom."""
    dx = np.zeros_like(x)
    dx[free] = d
    return dx


def candidates(f, free, stiffness, x, g, d, slope, inertia: bool):
    """A line search's candidates: Newton's direction d (free) with its slope, or, with the potential's direction
    filter f, the filter's proposal (in time steps, ``inertia``; ``stiffness`` the Newton matrix's diagonal without
    the filter's Hessian) when it descends, each clipped to the filter's safe step, and Newton's own clipped
    direction as the fallback, computed only when asked for (:mod:`deformable.solve.newton`)."""
    if f is None:
        return Candidate(d, slope), None
    dx = spread(free, x, d)
    plain = None
    if inertia:  # the filter's 1-D models need the inertia's stiffness (none in equilibrium)
        proposed = f.propose(x, dx, stiffness)
        if proposed is not dx and float(g @ proposed[free]) < 0:
            plain = (dx, d, slope)
            dx, d, slope = proposed, proposed[free], float(g @ proposed[free])

    def clipped(dx, d, slope):
        alpha = f.max_step(x, dx)
        return Candidate(alpha * d, alpha * slope)

    return clipped(dx, d, slope), None if plain is None else (lambda: clipped(*plain))
