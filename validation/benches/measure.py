r"""How a bench measures: in a process of its own (its peak memory is its own), the best of a few repeats of a
factorisation and solve, a few timed steps after a warm-up, a shipped scene on a grid of the backend's own unit; and
how a bench's rows are printed and written (a markdown table, a CSV).

Times are wall-clock seconds (``time.perf_counter``) on a machine the bench has to itself, or, where the machine
is shared (two cores, other work beside), CPU seconds (``time.process_time``) with every thread pool held to one
thread (:func:`one_thread`); memory is the process's maximum resident set (MB).
"""

from __future__ import annotations

import csv
import multiprocessing as mp
import os
import resource
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from deformable import scenes
from deformable.dynamics import TimeStepper
from validation.harness.backends import descriptor

__all__ = ["peak_memory", "in_own_process", "one_thread", "best_of", "direct_solve_time", "scene_config", "WORKLOADS",
           "grid_label", "timed_steps", "write_csv", "emit"]


def peak_memory() -> float:
    """This process's maximum resident set (MB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def in_own_process(fn, *args):
    """fn(*args) in a forked process of its own (its peak memory is its own); returns its result."""
    ctx = mp.get_context("fork")
    with ctx.Pool(1) as pool:
        return pool.apply(fn, args)


def one_thread() -> None:
    """Hold this process to one thread for good, so that its CPU time is one core's work: OpenMP, MKL (PARDISO)
    and OpenBLAS by their environment (read when each starts) and by threadpoolctl (those already loaded), the
    Hessian's blocks (:func:`deformable.physics.integrand.hessian_threads` reads OMP_NUM_THREADS) and the IPC
    Toolkit's TBB threads. Meant for a row's own forked process (:func:`in_own_process`)."""
    import ipctk
    from threadpoolctl import threadpool_limits

    for name in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS", "NUMBA_NUM_THREADS"):
        os.environ[name] = "1"
    threadpool_limits(1)
    ipctk.set_num_threads(1)


def best_of(fn, repeats: int = 3) -> float:
    """The best wall time (s) of ``repeats`` calls of fn."""
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def direct_solve_time(A, rhs, solver=None, repeats: int = 3) -> tuple[float, float]:
    """Best of ``repeats`` of one factorisation of A and one solve of rhs: (factor s, solve s).

    ``solver``: one of :mod:`deformable.algebra.solvers` (default: ``splu`` with SciPy's default options).
    """
    if solver is None:
        lu = spla.splu(sp.csc_matrix(A))
        return best_of(lambda: spla.splu(sp.csc_matrix(A)), repeats), best_of(lambda: lu.solve(rhs), repeats)
    solver.factor(A)
    return best_of(lambda: solver.factor(A), repeats), best_of(lambda: solver.solve(rhs), repeats)


#: what a bench row runs stays what it measured when a scene's defaults change: the curtain rows run the curtain of
#: issue 44 (an isotropic sheet, mu 0.2 kg/m^2, eta 20 N/m, xi 1e-4 N m), shipped since in denim
WORKLOADS = {"curtain": dict(fabric="", mu=0.2, eta=20.0, xi=1e-4, shear=1.0)}


def scene_config(scene: str, backend: str, n: int):
    """A shipped scene's config on n nodes (FD) or n elements (FE) a side, with its :data:`WORKLOADS` fields: the
    unit of the implicit, scene and contact rows."""
    nodes = descriptor(backend).nodes(n)
    return scenes.config(scene, nodes=(nodes, nodes), **WORKLOADS.get(scene, {}))


def grid_label(r) -> str:
    """A row's grid with its unit: nodes a side (FD) or elements a side (FE)."""
    return f"{r.grid}{' nodes' if descriptor(r.backend).grid == 'nodes' else ' el.'}"


def timed_steps(model, dt: float, steps: int, solver: str, probe=None) -> tuple:
    """(s per step, Newton iterations per step) of ``steps`` implicit-Euler steps after one warm-up step; with
    ``probe``, a function of the stepper, also what it returns of the timed steps, called before and after them:
    (before, after) -> after minus before, key by key (a dict of seconds)."""
    stepper = TimeStepper(model, dt, newton=dict(solver=solver))
    state = stepper.step(stepper.start(model.initial_state()))
    before = dict(probe(stepper)) if probe is not None else None
    t0 = time.perf_counter()
    for _ in range(steps):
        state = stepper.step(state)
    wall = (time.perf_counter() - t0) / steps
    iterations = float(np.mean([r.iterations for r in stepper.newton_reports[1:]]))
    if probe is None:
        return wall, iterations
    return wall, iterations, {k: v - before.get(k, 0.0) for k, v in probe(stepper).items()}


def write_csv(path: Path, rows, extra=()) -> None:
    """The rows (dataclasses) and their ``extra`` (name, function of a row) columns as a CSV at ``path``."""
    with path.open("w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(list(asdict(rows[0]).keys()) + [name for name, _ in extra])
        for r in rows:
            writer.writerow(list(asdict(r).values()) + [f"{fn(r):.6g}" for _, fn in extra])


def emit(path: Path, rows, table, extra=()) -> None:
    """Print the rows' markdown table and write them to the CSV at ``path``; nothing for no rows."""
    if rows:
        print(table(rows))
        write_csv(path, rows, extra)
        print(f"wrote {path}")
