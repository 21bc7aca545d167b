r"""The cases of the cross study: one problem, one backend, one grid (and, for the dynamics, one dt).

:func:`run_case` solves a case and returns r, G and B at the problem's probe points
(:mod:`validation.studies.cross.measure`) at its *samples* (the loads of the cantilever family, the one
static state of the plate and the hanging sheet, the sample times of a motion), and the scalar outputs of
the Richardson/GCI table.

Grids: level k of a problem has ``(c - 1) 2^k + 1`` nodes a side from its coarsest c (:data:`COARSEST`),
square cells. The cantilever's levels are FD's 41 x 5, 81 x 9, 161 x 17 (square cells along the strip);
FE takes the same nodes along the strip and 3 across: the solution is uniform across the width (nu = 0),
which the bicubics represent exactly on any grid across, so FE's levels refine along the strip, where
its error is.

Statics are solved by :func:`deformable.equilibrium` (Newton with a fresh factorisation each iteration,
:data:`~validation.studies.cross.problems.NEWTON`); the cantilever family by load continuation (each
load from the last one's equilibrium); the hanging sheet first under its weight, then pushed. Motions
start from a static equilibrium (the pushed hanging sheet; the flag in its steady wind) and run
:data:`T_END` seconds of Newmark steps of a fixed dt, Newton to a relative residual of 1e-9.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import deformable as dm
from validation.harness.backends import make_model

from . import problems as pb
from .measure import Probe, sample

__all__ = ["Case", "run_case", "COARSEST", "STATICS", "DYNAMICS", "PROBLEMS", "T_END", "DT", "SAMPLE_TIMES",
           "nodes", "probe"]

STATICS = ("cantilever", "plate", "hanging")
DYNAMICS = ("swing", "flag")
PROBLEMS = STATICS + DYNAMICS
#: nodes a side of the coarsest level (across the strip for the cantilever, along a2 for the flag)
COARSEST = {"cantilever": 5, "plate": 17, "hanging": 9, "swing": 9, "flag": 5}
#: the motions: their duration, fixed step and sample times (s)
T_END = 0.5
DT = 0.01
SAMPLE_TIMES = (0.125, 0.25, 0.375, 0.5)
#: Newmark's Newton tolerance (relative residual)
STEP_RTOL = 1e-9


@dataclass(frozen=True)
class Case:
    problem: str
    backend: str
    level: int
    dt: float = DT


def nodes(problem: str, level: int, backend: str = "fd") -> tuple[int, int]:
    """The node grid (M, N) of a problem's level (module docstring)."""
    n = (COARSEST[problem] - 1) * 2**level + 1
    if problem == "cantilever":
        return (10 * (n - 1) + 1, n if backend == "fd" else 3)
    if problem == "flag":
        return pb.flag(n).sheet.nodes
    return (n, n)


def probe(problem: str) -> Probe:
    """The fixed points of a problem: 4 x 4 Gauss points on every cell of its coarsest grid."""
    M, N = nodes(problem, 0)
    size = {"cantilever": (pb.CANTILEVER["L"], pb.CANTILEVER["b"]), "flag": pb.FLAG["size"]}.get(problem, (1.0, 1.0))
    return Probe.on_cells(size, (M - 1, N - 1))


def _scene(problem: str, grid: tuple[int, int], **kw) -> dm.Scene:
    if problem == "cantilever":
        return pb.cantilever(grid, **kw)
    builders = {"plate": pb.plate, "hanging": pb.hanging, "swing": pb.hanging, "flag": pb.flag}
    scene = builders[problem](grid[1], **kw)
    return scene if scene.sheet.nodes == grid else scene.with_nodes(grid)


def _equilibrium(model, X0):
    X, history = dm.equilibrium(model, X0, tol=1e-12, newton=pb.NEWTON)
    return X, len(history) - 1


def _static(case: Case, grid) -> tuple[list, dict, int]:
    """The samples, scalar outputs and Newton iterations of a static case."""
    pr, its = probe(case.problem), 0
    if case.problem == "cantilever":
        X, out, scalars = None, [], {}
        for load in pb.LOADS:
            model = make_model(_scene("cantilever", grid, load=load), case.backend)
            X, k = _equilibrium(model, model.initial_state() if X is None else X)
            its += k
            out.append(sample(model, X, pr))
            tip = model.sample(X, np.array([[pb.CANTILEVER["L"], pb.CANTILEVER["b"] / 2]])).r[0]
            scalars[f"tip x, P L^2/EI = {load:g}"], scalars[f"tip z, P L^2/EI = {load:g}"] = tip[0], tip[2]
        return out, scalars, its
    model = make_model(_scene(case.problem, grid), case.backend)
    X0 = model.initial_state()
    if case.problem == "hanging":  # its weight first: pushed from the unstressed state it has no lateral stiffness
        X0, its = _equilibrium(make_model(_scene("hanging", grid, stage="weight"), case.backend), X0)
    X, k = _equilibrium(model, X0)
    if case.problem == "plate":
        scalars = {"centre deflection w_c": model.sample(X, np.array([[0.5, 0.5]])).r[0, 2]}
    else:
        scalars = {"y of the bottom-edge midpoint": model.sample(X, np.array([[0.5, 0.0]])).r[0, 1]}
    return [sample(model, X, pr)], scalars, its + k


def _motion(case: Case, grid) -> tuple[list, dict, int]:
    """The samples at :data:`SAMPLE_TIMES`, the scalar outputs at the end and the Newton iterations of a motion."""
    if case.problem == "swing":
        m0 = make_model(_scene("hanging", grid, stage="weight"), case.backend)
        X0, its = _equilibrium(m0, m0.initial_state())
        X0, k = _equilibrium(make_model(_scene("hanging", grid), case.backend), X0)
        model = make_model(_scene("swing", grid, stage="released"), case.backend)
        where, what = np.array([[0.5, 0.0]]), "y of the bottom-edge midpoint"
    else:
        steady = make_model(_scene("flag", grid, stage="steady"), case.backend)
        X0, its = _equilibrium(steady, steady.initial_state())
        k = 0
        model = make_model(_scene("flag", grid), case.backend)
        where, what = np.array([[pb.FLAG["size"][0], pb.FLAG["size"][1] / 2]]), "y of the free edge's midpoint"
    pr = probe(case.problem)
    stepper = dm.TimeStepper(model, dt=case.dt, scheme="newmark", newton={"rtol": STEP_RTOL, "test": "force"})
    state, out = stepper.start(X0), []
    for t in SAMPLE_TIMES:  # each sample time is the end of a run, which its last step meets exactly
        for state in stepper.iterate(state, t_end=t):
            pass
        out.append(sample(model, state.X, pr))
    its += k + sum(r.iterations for r in stepper.newton_reports)
    return out, {f"{what} at t = {T_END:g} s": model.sample(state.X, where).r[0, 1]}, its


def run_case(case: Case) -> dict:
    """Solve a case: {"h": along-a1 spacing, "samples": [dict r, G, B], "scalars": {name: value}, "newton": its}."""
    grid = nodes(case.problem, case.level, case.backend)
    solve = _static if case.problem in STATICS else _motion
    samples, scalars, its = solve(case, grid)
    L1 = {"cantilever": pb.CANTILEVER["L"], "flag": pb.FLAG["size"][0]}.get(case.problem, 1.0)
    return {"h": L1 / (grid[0] - 1), "nodes": grid, "samples": samples, "scalars": scalars, "newton": its}
