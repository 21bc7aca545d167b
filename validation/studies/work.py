r"""Study ``work``: a work-precision diagram, the error of B against CPU time, FD against FE.

For the generic Monge patch, each backend builds its model on an n x n grid,
discretises the surface and evaluates B (eq. 19 for FD at the nodes, eq. 8
for FE at the 4 x 4 Gauss points). Work is the CPU time (process time, s) of
those three steps, the best of three repetitions; precision is the max error
of B against the closed form (FD: interior nodes; FE: Gauss points).

Expectations: the cost grows like the number of nodes, h^-2, so the error
falls like (CPU time)^(-p/2): FD (p = 1) slope -1/2, FE (p = 2 for B11, B22)
slope -1, once the fixed costs are amortised. The checked statement is that
each backend's error falls with every increase of work; the slopes and the
cross-over are reported as findings of the run, and the table and the
diagram are volatile (timings depend on the machine and the moment): they go
to run.md, run_work.csv and run_work_precision.png, so that a rerun leaves the
committed report as it was. results.json keeps the grids and the errors.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

import deformable as dm
from validation.harness import surfaces as sf
from validation.harness.backends import make_model
from validation.harness.orders import fit_order
from validation.harness.study import Figure, Levels, Line, Panel, Study, Table, nodes_at

COARSEST = {"fd": 9, "fe": 5}
SURFACE = "monge"


@dataclass(frozen=True)
class Case:
    backend: str
    nodes: int


def run_case(case: Case) -> dict:
    s = sf.get(SURFACE)
    best = np.inf
    for _ in range(3):
        t0 = time.process_time()
        sc = dm.Scene(dm.Sheet(size=s.size, nodes=(case.nodes, case.nodes), rest=s), dm.Material(eta=1.0, xi=1.0))
        model = make_model(sc, case.backend)
        _, B = model.tensors(model.initial_state())
        best = min(best, time.process_time() - t0)
    err = np.abs(B - s.B(*model.points))
    if case.backend == "fd":  # interior nodes: the boundary rows are one-sided
        err = err[:, :, 1:-1, 1:-1]
    return {"h": model.spacing[0], "cpu": max(best, 1e-6), "error": float(err.max())}


def fill(res, levels: int, runner) -> None:
    """Run the work study over ``levels`` grids (FD 9, 17, ...; FE 5, 9, ... nodes a side)."""
    cases = [Case(b, nodes_at(k, COARSEST[b])) for b in ("fd", "fe") for k in range(levels)]
    raw = runner.map(run_case, cases, desc="work")
    res.config.update({
        "surface": SURFACE, "nodes": {b: [nodes_at(k, COARSEST[b]) for k in range(levels)] for b in ("fd", "fe")},
        "timing": "process time of model build + discretisation + tensors, best of 3"})
    rows, lines, timings = [], [], {}
    for b in ("fd", "fe"):
        these = [r for c, r in zip(cases, raw) if c.backend == b]
        cpu = np.array([r["cpu"] for r in these])
        err = np.array([r["error"] for r in these])
        slope = fit_order(cpu, err)
        res.check(f"{b.upper()}: the error of B falls as the grid is refined", "decreasing error at every level",
                  ", ".join(f"{e:.2e}" for e in err), np.all(np.diff(err) < 0))
        res.run_findings.append(f"{b.upper()}: error ~ CPU^{slope:.2f} over these levels (expected "
                                f"-{0.5 if b == 'fd' else 1} once fixed costs are amortised).")
        for c, r in zip([c for c in cases if c.backend == b], these):
            rows.append((b.upper(), c.nodes, r["h"], r["cpu"], r["error"]))
        lines.append(Line(f"{b.upper()} (B {'interior nodes' if b == 'fd' else '4x4 Gauss points'})", cpu, err))
        res.data[b] = {"h": [r["h"] for r in these], "error": err.tolist()}
        timings[b] = cpu
    fd_best = res.data["fd"]["error"][-1]
    cheaper = [c for c, e in zip(timings["fe"], res.data["fe"]["error"]) if e <= fd_best]
    res.run_findings.append(f"FE reaches FD's finest B error ({fd_best:.2e}) at {min(cheaper):.3g} s of CPU time "
                            f"against FD's {timings['fd'][-1]:.3g} s." if cheaper else
                            "FE does not reach FD's finest B error on these levels.")
    res.tables.append(Table("work", "CPU time and B error", ("backend", "nodes a side", "h", "CPU time (s)",
                                                             "max error of B (1/m)"), rows, volatile=True))
    res.figures.append(Figure("work_precision", "Work-precision: max error of B against CPU time",
                              (Panel(f"B on the {SURFACE} patch", "CPU time (s)", "max error of B (1/m)",
                                     tuple(lines), (-0.5, -1.0), "t"),), volatile=True))


STUDY = Study('work', 'work-precision: max error of B against CPU time, FD against FE (generic Monge patch)',
              Levels(quick=4, full=6, minimum=3, maximum=7), fill)
