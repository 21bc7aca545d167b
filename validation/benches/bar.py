r"""The curtain bar of ``deformable bench --bar``: the shipped curtain's cost in units of a fixed matrix's direct solve.

The ``curtain`` as it ships (variational, implicit Euler at its dt of 5 ms, its
self-contact) on FD ``--bar-grid`` nodes a side (48) for ``--bar-time`` seconds
(0.5), its CPU seconds per simulated second on one thread (a rate row of
:mod:`.rates`, under the default Newton settings), divided by the CPU seconds of
one SuperLU factorisation and one solve of a fixed matrix of the same size, in
the same run: the curtain's Newton matrix at its initial state (its free block,
the size of every system the run solves), factorised with the project's
symmetric ordering (:data:`deformable.algebra.solvers.SPLU_OPTIONS`), the least
of a few repeats. The quotient, *factor+solves per simulated second*, does not
depend on how fast the machine is. Beside it, the row's Newton error against the
time discretisation's (:mod:`.rates`: the largest node distance at the end from a
tight solve at dt, over the distance between tight solves at dt and dt / 2).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from deformable.algebra.solvers import SuperLU
from deformable.solve.potential import flat
from deformable.session import Simulation
from validation.harness.report import markdown_table

from .measure import in_own_process, one_thread, scene_config
from .rates import bench_rates

__all__ = ["BarRow", "bench_bar", "fixed_solve", "format_bar"]


@dataclass(frozen=True)
class BarRow:
    """The curtain bar: CPU seconds, the unit (one SuperLU factor+solve of a same-size fixed matrix), their
    quotient per simulated second, and the Newton error against the time error (m)."""

    grid: str
    unknowns: int
    t_end: float
    status: str
    steps: int
    cpu: float  # CPU s of the run, one thread
    unit: float  # CPU s of one SuperLU factorisation and solve of the same-size fixed matrix
    newton_error: float
    time_error: float

    @property
    def bar(self) -> float:
        """Fixed-matrix factor+solves per simulated second."""
        return self.cpu / self.t_end / self.unit

    @property
    def error_ratio(self) -> float:
        return self.newton_error / self.time_error if self.time_error > 0 else float("nan")


def fixed_solve(n: int, repeats: int = 5) -> tuple[float, int]:
    """CPU seconds (the least of ``repeats``) of one SuperLU factorisation and solve of the curtain's Newton matrix
    at its initial state on FD n x n nodes, and its size; one thread."""
    one_thread()
    cfg = scene_config("curtain", "fd", n)
    sim = Simulation(cfg, "fd", nodes=cfg.nodes, dt=cfg.dt)
    model, stepper = sim.model, sim.stepper
    A = stepper.newton.newton_matrix(flat(model.initial_state()), 1 / cfg.dt**2, 1 / cfg.dt)
    b, lu = np.ones(A.shape[0]), SuperLU()
    best = np.inf
    for _ in range(repeats):
        t0 = time.process_time()
        lu.factor(A).solve(b)
        best = min(best, time.process_time() - t0)
    return float(best), A.shape[0]


def bench_bar(n: int = 48, t_end: float = 0.5, progress=print) -> BarRow:
    """The curtain bar on FD n x n nodes over t_end s (module docstring); each run in a process of its own."""
    row = bench_rates("curtain", "fd", n, t_end, settings=("defaults",), progress=progress)[0]
    unit, size = in_own_process(fixed_solve, n)
    return BarRow(f"{n}x{n}", size, row.t_reached, row.status, row.steps, row.cpu, unit, row.newton_error,
                  row.time_error)


def format_bar(rows) -> str:
    return markdown_table(
        ("grid", "unknowns", "t (s)", "status", "steps", "CPU (s)", "SuperLU factor+solve (ms)",
         "factor+solves / simulated s", "Newton error (m)", "dt vs dt/2 (m)", "Newton / time error"),
        [(f"{r.grid} nodes", r.unknowns, f"{r.t_end:g}", r.status, r.steps, f"{r.cpu:.2f}", f"{1e3 * r.unit:.2f}",
          f"{r.bar:.1f}", f"{r.newton_error:.3g}", f"{r.time_error:.3g}", f"{100 * r.error_ratio:.2f} %")
         for r in rows])
