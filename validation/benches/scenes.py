r"""The scene rows of ``deformable bench`` (opt-in: ``--scenes``): shipped scenes run for seconds of motion.

Shipped scenes as they ship (the energy-consistent model, implicit Euler at
the scene's dt) run for ``--scene-time`` seconds of motion from their
initial state on FD ``--scene-fd`` nodes and FE ``--scene-fe`` elements a
side: the wall time, steps, Newton iterations, factorisations and definite
fallbacks per step (unknowns: every degree of freedom, held ones too, as in
the contact rows). They measure what the 2 s budgets of the scenes and the
iterations per step of a whole run are about, where the implicit rows time a
few steps.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from deformable.session import Simulation
from validation.harness.report import markdown_table

from .measure import grid_label, one_thread as hold_one_thread, peak_memory, scene_config

__all__ = ["SceneRow", "bench_scene", "run_scene", "format_scenes"]


@dataclass(frozen=True)
class SceneRow:
    """One scene line: a shipped scene run from its initial state; times in seconds, memory in MB."""

    scene: str
    backend: str
    grid: str
    unknowns: int
    dt: float
    t_end: float
    status: str
    t_reached: float
    steps: int
    wall: float
    cpu: float
    newton_per_step: float
    factorisations_per_step: float
    fallbacks_per_step: float
    peak_mb: float


def run_scene(scene: str, backend: str, n: int, t_end: float, newton: dict | None = None, dt_factor: float = 1.0,
              one_thread: bool = False):
    """Run a shipped scene (energy-consistent, implicit Euler at ``dt_factor`` times its own dt) for t_end seconds
    on n nodes (FD) or n elements (FE) a side, in this process: (its SceneRow, the final positions (ndof, 3)).
    ``one_thread``: every thread pool held to one thread for good (:func:`.measure.one_thread`: MKL, OpenBLAS, the
    Hessian's blocks, the IPC Toolkit's TBB threads; before, TBB's were not, and their time counted)."""
    cfg = scene_config(scene, backend, n)
    sim = Simulation(cfg, backend, nodes=cfg.nodes, dt=cfg.dt * dt_factor, stepping=dict(newton=newton))
    model, stepper = sim.model, sim.stepper
    if one_thread:  # for good: the rows that ask run in a process of their own
        hold_one_thread()
    t0, c0 = time.perf_counter(), time.process_time()
    result = stepper.run(model.initial_state(), t_end=t_end)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    reports = stepper.newton_reports

    def per_step(name):
        return float(np.mean([getattr(r, name) for r in reports])) if reports else float("nan")

    row = SceneRow(scene, backend, f"{n}x{n}", 3 * model.ndof, stepper.dt, t_end, result.status, result.state.t,
                   result.steps, wall, cpu, per_step("iterations"), per_step("factorisations"), per_step("fallbacks"),
                   peak_memory())
    return row, np.asarray(result.state.X)


def bench_scene(scene: str, backend: str, n: int, t_end: float, solver: str = "auto") -> SceneRow:
    """Run a shipped scene (energy-consistent, implicit Euler at its own dt, as every scene ships) for t_end seconds
    on n nodes (FD) or n elements (FE) a side."""
    return run_scene(scene, backend, n, t_end, dict(solver=solver))[0]


def format_scenes(rows) -> str:
    """A markdown table of scene rows."""
    return markdown_table(
        ("scene", "backend", "grid", "unknowns", "dt (ms)", "status", "t reached (s)", "steps", "wall (s)", "CPU (s)",
         "Newton / step", "factorisations / step", "definite fallbacks / step", "peak MB"),
        [(r.scene, r.backend, grid_label(r), r.unknowns, f"{1e3 * r.dt:g}", r.status, f"{r.t_reached:g}", r.steps,
          f"{r.wall:.1f}", f"{r.cpu:.1f}", f"{r.newton_per_step:.2f}", f"{r.factorisations_per_step:.2f}",
          f"{r.fallbacks_per_step:.2f}", f"{r.peak_mb:.0f}") for r in rows])
