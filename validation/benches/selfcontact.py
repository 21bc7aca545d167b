r"""The self-contact rows of ``deformable bench``: the shipped curtain's step with its self-contact against without.

The ``curtain`` as it ships (variational, implicit Euler at its dt of 5 ms, its
self-contact: a barrier within 4 mm beyond a fabric 1 mm thick) and the same
curtain with ``self_distance = 0`` (no self-contact), each run from its start
for ``--self-time`` seconds of motion after one warm-up step, in one process held
to one thread (CPU seconds, ``time.process_time``): the CPU per step of each,
their ratio, the Newton iterations and factorisations a step, and the steps
rejected (retried shorter). The self-contact's own work goes through the IPC
Toolkit on the broad phase of each step (:mod:`deformable.contact.trianglebarrier`):
``broad_phases`` counts them a step (one, and another where an iterate leaves the
motion it was built for), ``bounded`` the share of collision-free steps a
conservative bound settled without CCD.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from deformable.session import Simulation
from validation.harness.report import markdown_table

from .implicit import free_curtain
from .measure import grid_label, one_thread, peak_memory, scene_config

__all__ = ["SelfRow", "bench_self", "format_self"]


@dataclass(frozen=True)
class SelfRow:
    """One self-contact line: the curtain with its self-contact and without; CPU seconds on one thread."""

    backend: str
    grid: str
    unknowns: int
    t_end: float
    step_self: float  # CPU s per step with self-contact
    step_free: float  # CPU s per step without
    newton_self: float
    newton_free: float
    factorisations_self: float
    factorisations_free: float
    rejected_self: int
    rejected_free: int
    broad_phases: float  # the self-contact's broad phases a step
    bounded: float  # share of collision-free steps settled by the conservative bound
    peak_mb: float

    @property
    def ratio(self) -> float:
        """The step with self-contact against the step without."""
        return self.step_self / self.step_free


def _run(cfg, backend: str, t_end: float):
    """Run a curtain config from its start for t_end s after one warm-up step: (stepper, CPU s per step)."""
    sim = Simulation(cfg, backend, nodes=cfg.nodes, dt=cfg.dt)
    model, stepper = sim.model, sim.stepper
    state = stepper.step(stepper.start(model.initial_state()))
    steps, c0 = 0, time.process_time()
    while state.t < t_end - 1e-9 * cfg.dt:
        state = stepper.step(state)
        steps += 1
    return stepper, (time.process_time() - c0) / steps


def bench_self(backend: str, n: int, t_end: float) -> SelfRow:
    """The curtain on n nodes (FD) or n elements (FE) a side, with its self-contact and without, for t_end s each
    (module docstring); one thread."""
    one_thread()
    cfg = scene_config("curtain", backend, n)
    free, step_free = _run(free_curtain(cfg), backend, t_end)
    own, step_self = _run(cfg, backend, t_end)
    sheet = own.newton.problem.contact.sheet
    steps = len(own.newton_reports)

    def mean(stepper, name):
        return float(np.mean([getattr(r, name) for r in stepper.newton_reports[1:]]))

    calls = max(1, sheet.bounded + sheet.ccd_calls)
    return SelfRow(backend, f"{n}x{n}", int(np.count_nonzero(own.newton.problem.free)), t_end, step_self, step_free,
                   mean(own, "iterations"), mean(free, "iterations"), mean(own, "factorisations"),
                   mean(free, "factorisations"), own.rejected, free.rejected, sheet.broad_phases / steps,
                   sheet.bounded / calls, peak_memory())


def format_self(rows) -> str:
    """A markdown table of self-contact rows (CPU ms on one thread)."""
    return markdown_table(
        ("backend", "grid", "unknowns", "t (s)", "step ms, self-contact", "step ms, none", "ratio",
         "Newton / step, self / none", "factorisations / step, self / none", "rejected, self / none",
         "broad phases / step", "CCD settled by the bound", "peak MB"),
        [(r.backend, grid_label(r), r.unknowns, f"{r.t_end:g}", f"{1e3 * r.step_self:.1f}", f"{1e3 * r.step_free:.1f}",
          f"{r.ratio:.2f}", f"{r.newton_self:.2f} / {r.newton_free:.2f}",
          f"{r.factorisations_self:.2f} / {r.factorisations_free:.2f}", f"{r.rejected_self} / {r.rejected_free}",
          f"{r.broad_phases:.2f}", f"{100 * r.bounded:.0f} %", f"{r.peak_mb:.0f}") for r in rows])
