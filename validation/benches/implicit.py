r"""The implicit rows of ``deformable bench``: a Newton step of the energy-consistent model against its floor.

The ``curtain`` scene as it ships (variational, implicit Euler at its dt of
5 ms) but without its self-contact (the floor is the elastic step's; the
self-contact rows, :mod:`.selfcontact`, price that), run from its start for
``--implicit-time`` seconds of motion after one warm-up step, on one thread
(:func:`.measure.one_thread`; CPU seconds, ``time.process_time``). Beside the
step, in the same process and in rounds spread over the run (:class:`FloorRounds`: the machine's speed
drifts over minutes, and the step and its floor must meet the same machine), the floor's parts, run in turn as a
bare Newton iteration runs them (each finds the caches as the others left
them; each part's median over the rounds): the energy, its gradient and its
Hessian into the Newton matrix's fixed pattern (the model's compiled kernels,
:meth:`model.energy`, :meth:`model.energy_gradient`,
:meth:`model.energy_elements` summed on their pattern), and one factorisation and one solve of the
step's own Newton matrix there with the step's own solver. The floor of a step
is what a Newton step cannot avoid: one Hessian and one factorisation, and a
solve and a gradient each iteration,

    floor (step) = hessian + factor + (Newton iterations a step) (solve + gradient),

the floor of an iteration the kernels and one factor+solve,

    floor (iteration) = energy + gradient + hessian + factor + solve,

and a row's ratios are the step over its floor and an iteration over its
floor. A step may fall below its floor where a factorisation serves more than
one step. Also the ratio of the step to the semi-implicit step of the same
scene and grid under the paper's force (at its own stable dt). FD rows are
given in nodes a side, FE rows in elements a side.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from deformable import scenes
from deformable.algebra.solvers import make_solver
from deformable.solve.directions import Directions
from deformable.solve.potential import flat
from deformable.solve.settings import NewtonReport
from deformable.session import Simulation
from validation.harness.report import markdown_table

from .measure import grid_label, one_thread, peak_memory, scene_config

__all__ = ["ImplicitRow", "FloorRounds", "bench_implicit", "format_implicit", "free_curtain", "FLOOR_ROUNDS"]

#: rounds of the floor's measurement spread over a row's run (and one before it)
FLOOR_ROUNDS = 10


@dataclass(frozen=True)
class ImplicitRow:
    """One implicit line: the variational curtain without self-contact under implicit Euler, against its floor; CPU
    seconds on one thread, memory in MB."""

    backend: str
    grid: str
    unknowns: int
    solver: str
    dt: float
    t_end: float
    steps: int
    newton_per_step: float
    factorisations_per_step: float
    step: float
    energy: float
    gradient: float
    hessian: float
    factor: float
    solve: float
    semi_implicit_step: float
    peak_mb: float

    @property
    def per_iteration(self) -> float:
        return self.step / self.newton_per_step

    @property
    def floor_step(self) -> float:
        """One Hessian and one factorisation a step, a solve and a gradient an iteration (module docstring)."""
        return self.hessian + self.factor + self.newton_per_step * (self.solve + self.gradient)

    @property
    def floor_iteration(self) -> float:
        """The kernels (energy, gradient, Hessian) and one factor+solve."""
        return self.energy + self.gradient + self.hessian + self.factor + self.solve

    @property
    def step_ratio(self) -> float:
        """The step against its floor."""
        return self.step / self.floor_step

    @property
    def iteration_ratio(self) -> float:
        """One Newton iteration against its floor."""
        return self.per_iteration / self.floor_iteration

    @property
    def semi_ratio(self) -> float:
        """The implicit step against the semi-implicit step of the same scene and grid."""
        return self.step / self.semi_implicit_step


class FloorRounds:
    """The floor's parts measured in rounds spread over a run, so that the step and its floor meet the same machine
    (its speed drifts by a quarter over minutes here): each round runs the kernels, a factorisation and a solve in
    turn at the run's current state, as a bare Newton iteration runs them (each finds the caches as the others left
    them), on a solver of its own; :meth:`parts` gives each part's median over the rounds (CPU seconds)."""

    def __init__(self, model, stepper, solver: str):
        self.model, self.stepper = model, stepper
        self.solver = make_solver(solver, definite=True, single=stepper.newton.solver.single)  # the step's precision
        newton = stepper.newton
        self.matrices = Directions(newton.problem, newton.settings)  # its own: the run's kept state is untouched
        self.seconds = []

    def round(self, X: np.ndarray) -> None:
        model, dt = self.model, self.stepper.dt_now
        A = self.matrices.matrix(flat(X), 1 / dt**2, 1 / dt, NewtonReport())
        elements = model.energy_elements(X)[1]  # the Hessian's kernels: element uppers summed on their pattern
        b = np.ones(A.shape[0])
        self.solver.factor(A)  # its analysis, outside the round
        calls = (lambda: model.energy(X), lambda: model.energy_gradient(X),
                 lambda: elements.collect(model.energy_elements(X)[0]), lambda: self.solver.factor(A),
                 lambda: self.solver.solve(b))
        seconds = []
        for call in calls:
            t0 = time.process_time()
            call()
            seconds.append(time.process_time() - t0)
        self.seconds.append(seconds)

    def parts(self) -> list[float]:
        return [float(v) for v in np.median(np.array(self.seconds), axis=0)]


def free_curtain(cfg):
    """The curtain of ``cfg`` without its self-contact (the scene's own contact with ``self_distance = 0``)."""
    return cfg.replace(contact={"self_distance": 0})


def bench_implicit(backend: str, n: int, t_end: float, solver: str = "auto") -> ImplicitRow:
    """The variational curtain without self-contact on n nodes (FD) or n elements (FE) a side for ``t_end`` seconds
    after one warm-up step, and its floor's parts in rounds over the run (module docstring); one thread."""
    one_thread()
    cfg = free_curtain(scene_config("curtain", backend, n))
    sim = Simulation(cfg, backend, nodes=cfg.nodes, dt=cfg.dt, stepping=dict(newton=dict(solver=solver)))
    model, stepper = sim.model, sim.stepper
    state = stepper.step(stepper.start(model.initial_state()))  # warm-up: kernels loaded, patterns and analyses built
    floor = FloorRounds(model, stepper, solver)
    floor.round(state.X)
    total = round(t_end / cfg.dt)
    every = max(1, total // FLOOR_ROUNDS)
    steps, step = 0, 0.0
    while state.t < t_end - 1e-9 * cfg.dt:
        c0 = time.process_time()
        state = stepper.step(state)
        step += time.process_time() - c0
        steps += 1
        if steps % every == 0:
            floor.round(state.X)
    step /= steps
    reports = stepper.newton_reports[1:]
    parts = floor.parts()
    # the paper's force on the same scene and grid, at its own stable step
    paper = Simulation(cfg.replace(force_model="tpbf87", dt=scenes.config("curtain").dt), backend, nodes=cfg.nodes,
                       stepping=dict(solver=solver))  # at the curtain's dt, within half the paper's stable step
    semi = paper.stepper
    sstate = semi.step(semi.start(paper.X0))
    c1 = time.process_time()
    for _ in range(5):
        sstate = semi.step(sstate)
    semi_step = (time.process_time() - c1) / 5
    unknowns = int(np.count_nonzero(stepper.newton.problem.free))
    return ImplicitRow(backend, f"{n}x{n}", unknowns, floor.solver.name, cfg.dt, t_end, steps,
                       float(np.mean([r.iterations for r in reports])),
                       float(np.mean([r.factorisations for r in reports])), step, *parts, semi_step, peak_memory())


def format_implicit(rows) -> str:
    """A markdown table of implicit rows (CPU ms on one thread)."""
    return markdown_table(
        ("backend", "grid", "unknowns", "solver", "steps", "Newton / step", "factorisations / step", "step ms",
         "energy ms", "gradient ms", "Hessian ms", "factor ms", "solve ms", "floor / step ms", "step / floor",
         "iteration / floor", "step / semi-implicit step", "peak MB"),
        [(r.backend, grid_label(r), r.unknowns, r.solver, r.steps, f"{r.newton_per_step:.2f}",
          f"{r.factorisations_per_step:.2f}", f"{1e3 * r.step:.2f}", f"{1e3 * r.energy:.3f}",
          f"{1e3 * r.gradient:.3f}", f"{1e3 * r.hessian:.3f}", f"{1e3 * r.factor:.3f}", f"{1e3 * r.solve:.3f}",
          f"{1e3 * r.floor_step:.2f}", f"{r.step_ratio:.2f}", f"{r.iteration_ratio:.2f}", f"{r.semi_ratio:.1f}",
          f"{r.peak_mb:.0f}") for r in rows])
