r"""The semi-implicit rows of ``deformable bench``: the paper's eq. (22)-(27) against the linear algebra it cannot
avoid.

The ``hanging`` scene under the paper's force and weights (tpbf87, eta_12 =
xi_12 = 0, so K(r) is refilled every step, eq. (20); xi = 1e-6) is stepped K
times at half the backend's own stable step.
:attr:`deformable.TimeStepper.timings` splits the step into assembly (K(r)
and A_t), factorisation and solve. The references, in the same run: one
factorisation of the same matrix

    A_t = K(r_t) + M/dt^2 + C/(2 dt)        (25)

reduced to the free degrees of freedom, and one solve with 3 right-hand sides
(x, y, z), by ``scipy.sparse.linalg.splu`` with its default options (COLAMD),
and by the stepper's own solver (:mod:`deformable.algebra.solvers`). The ratio
step / (factor + solve) says what the step costs beyond the linear algebra.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from deformable import scenes
from deformable.algebra.solvers import make_solver
from deformable.dynamics import TimeStepper
from deformable.session import Simulation
from validation.harness.report import markdown_table

from .measure import direct_solve_time, peak_memory

__all__ = ["SEMI_IMPLICIT_DT", "BenchRow", "hanging_model", "bench_one", "format_table"]

#: the semi-implicit rows' dt (s), where the backend's half stable step is not smaller
SEMI_IMPLICIT_DT = 1e-3


@dataclass(frozen=True)
class BenchRow:
    """One semi-implicit line of the table; times in seconds per step, memory in MB."""

    backend: str
    nodes: str
    ndof: int
    free: int
    solver: str
    assembly: float
    factorisation: float
    solve: float
    step: float
    direct_factor: float
    direct_solve: float
    same_factor: float
    same_solve: float
    peak_mb: float

    @property
    def ratio(self) -> float:
        """step / (factor + solve) of the reference (default splu options)."""
        return self.step / (self.direct_factor + self.direct_solve)

    @property
    def same_ratio(self) -> float:
        """step / (factor + solve) with the stepper's own solver."""
        return self.step / (self.same_factor + self.same_solve)


def hanging_model(backend: str, n: int):
    """The semi-implicit rows' model on an n x n grid, and its step (s)."""
    # the paper's force and weights (xi > 0 so that K's bending stencil carries values; its pattern always has it)
    cfg = scenes.config("hanging", nodes=(n, n), xi=1e-6, shear=0.0, force_model="tpbf87", dt=SEMI_IMPLICIT_DT)
    # a step that keeps the scene on the stable side of the backend's own stretching bound at every size
    sim = Simulation(cfg, backend, nodes=cfg.nodes)
    return sim.model, sim.config.dt


def bench_one(backend: str, n: int, steps: int, solver: str = "auto") -> BenchRow:
    """Time ``steps`` semi-implicit steps of the hanging scene on an n x n grid, and the references."""
    model, dt = hanging_model(backend, n)
    stepper = TimeStepper(model, dt, solver=solver)
    # a generic deformed start, so that every alpha_ij, beta_ij is non-zero and the
    # reference matrix has the same non-zero pattern as the stepper's
    X0 = model.initial_state()
    L1, L2 = model.scene.sheet.size
    a = np.asarray(model.discretize(lambda a1, a2: np.stack(
        [0 * a1, 0 * a1, 0.05 * np.sin(np.pi * a1 / L1 + 0.3) * np.sin(2 * np.pi * a2 / L2 + 0.7)], axis=-1)))
    state = stepper.start(X0 + a)
    state = stepper.step(state)  # warm-up: builds the reduced-system pattern once
    for k in stepper.timings:
        stepper.timings[k] = 0.0
    t0 = time.perf_counter()
    for _ in range(steps):
        state = stepper.step(state)
    wall = (time.perf_counter() - t0) / steps
    tm = {k: v / steps for k, v in stepper.timings.items()}
    X = state.X
    A = (model.stiffness(X) + model.mass() / dt**2 + model.damping() / (2 * dt)).tocsr()
    free = np.setdiff1d(np.arange(A.shape[0]), np.asarray(model.fixed_dofs()[0], dtype=np.int64))
    Aff = sp.csc_matrix(A[free][:, free])
    rhs = (model.load(X, 0.0) + model.mass() / dt**2 @ X)[free]
    f, s = direct_solve_time(Aff, rhs)
    own = make_solver(solver)
    f2, s2 = direct_solve_time(Aff, rhs, own)
    return BenchRow(backend, f"{n}x{n}", model.ndof, free.size, own.name, tm["assembly"], tm["factorisation"],
                    tm["solve"], wall, f, s, f2, s2, peak_memory())


def format_table(rows) -> str:
    """A markdown table of semi-implicit rows (times in ms)."""
    return markdown_table(
        ("backend", "grid", "ndof", "free", "solver", "assembly ms", "factorisation ms", "solve ms", "step ms",
         "splu factor ms", "splu solve ms", "step / (factor+solve)", "step / same with its solver", "peak MB"),
        [(r.backend, r.nodes, r.ndof, r.free, r.solver, *(f"{1e3 * t:.2f}" for t in (
            r.assembly, r.factorisation, r.solve, r.step, r.direct_factor, r.direct_solve)),
          f"{r.ratio:.2f}", f"{r.same_ratio:.2f}", f"{r.peak_mb:.0f}") for r in rows])
