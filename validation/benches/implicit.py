r"""The implicit rows of ``deformable bench``: a Newton iteration of the energy-consistent model against one
factorisation and solve of its own matrix.

The ``curtain`` scene as it ships (variational, implicit Euler at its dt of
5 ms), stepped K times after one warm-up step at the start of the draw:
Newton iterations and factorisations per step, ms per iteration, the ratio of
an iteration to one factorisation and solve of its own Newton matrix with the
same solver, and the ratio of the step to the semi-implicit step of the same
scene and grid under the paper's force (at its own stable dt). FD rows are
given in nodes a side, FE rows in elements a side.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from deformable import scenes
from deformable.algebra.solvers import make_solver
from deformable.dynamics import TimeStepper
from deformable.solve.potential import flat
from validation.harness.backends import make_model
from validation.harness.report import markdown_table

from .measure import direct_solve_time, grid_label, peak_memory, scene_config

__all__ = ["ImplicitRow", "bench_implicit", "format_implicit"]


@dataclass(frozen=True)
class ImplicitRow:
    """One implicit line: the variational curtain under implicit Euler; times in seconds, memory in MB."""

    backend: str
    grid: str
    unknowns: int
    solver: str
    dt: float
    newton_per_step: float
    factorisations_per_step: float
    step: float
    factor: float
    solve: float
    semi_implicit_step: float
    peak_mb: float

    @property
    def per_iteration(self) -> float:
        return self.step / self.newton_per_step

    @property
    def iteration_ratio(self) -> float:
        """One Newton iteration against one factorisation and solve of its own matrix (same solver)."""
        return self.per_iteration / (self.factor + self.solve)

    @property
    def step_ratio(self) -> float:
        """The implicit step against the semi-implicit step of the same scene and grid."""
        return self.step / self.semi_implicit_step


def bench_implicit(backend: str, n: int, steps: int, solver: str = "auto") -> ImplicitRow:
    """Time ``steps`` implicit-Euler steps of the variational curtain on n nodes (FD) or n elements (FE) a side."""
    cfg = scene_config("curtain", backend, n)
    model = make_model(scenes.build(cfg), backend)
    stepper = TimeStepper(model, cfg.dt, newton=dict(solver=solver))
    state = stepper.step(stepper.start(model.initial_state()))  # warm-up: patterns and analyses are built once
    t0 = time.perf_counter()
    for _ in range(steps):
        state = stepper.step(state)
    wall = (time.perf_counter() - t0) / steps
    reports = stepper.newton_reports[1:]
    dt = cfg.dt
    A = stepper.newton.newton_matrix(flat(state.X), 1 / dt**2, 1 / dt)
    own = make_solver(solver, definite=True)
    f, s = direct_solve_time(A, np.ones(A.shape[0]), own)
    # the paper's force on the same scene and grid, at its own stable step
    paper = make_model(scenes.build(cfg.replace(force_model="tpbf87")), backend)
    semi = TimeStepper(paper, min(scenes.config("curtain").dt, 0.5 * paper.stable_step()), solver=solver)
    sstate = semi.step(semi.start(paper.initial_state()))
    t1 = time.perf_counter()
    for _ in range(steps):
        sstate = semi.step(sstate)
    semi_step = (time.perf_counter() - t1) / steps
    return ImplicitRow(backend, f"{n}x{n}", A.shape[0], own.name, dt,
                       float(np.mean([r.iterations for r in reports])),
                       float(np.mean([r.factorisations for r in reports])), wall, f, s, semi_step, peak_memory())


def format_implicit(rows) -> str:
    """A markdown table of implicit rows (times in ms)."""
    return markdown_table(
        ("backend", "grid", "unknowns", "solver", "Newton iterations / step", "factorisations / step", "step ms",
         "ms / iteration", "factor+solve ms", "iteration / (factor+solve)", "step / semi-implicit step", "peak MB"),
        [(r.backend, grid_label(r), r.unknowns, r.solver, f"{r.newton_per_step:.2f}",
          f"{r.factorisations_per_step:.2f}",
          f"{1e3 * r.step:.1f}", f"{1e3 * r.per_iteration:.1f}", f"{1e3 * (r.factor + r.solve):.1f}",
          f"{r.iteration_ratio:.2f}", f"{r.step_ratio:.1f}", f"{r.peak_mb:.0f}") for r in rows])
