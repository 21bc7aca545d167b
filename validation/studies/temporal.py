r"""Study ``time``: the temporal order of the stepper of eq. (22)-(27) by dt-refinement.

One scene (a sheet pinned along its top edge, falling across its plane under
gravity; mu = 1, gamma = 0.5, eta = 10, so that dt0 sits well inside both
backends' stretching bounds) on a fixed grid, run to t_end with dt = dt0 / 2^k. With no exact solution, the
self-differences e_k = max |X_k(t_end) - X_{k+1}(t_end)| (positions, all
nodes) give the observed order p = slope of log e_k against log dt_k.

Theory: the scheme lags K(r) and uses the backward difference V_t of
eq. (27); for one linear mode it damps by (1 + w^2 dt^2)^(-1/2) per step and
shifts the phase to atan(w dt) (docs/design.md): first order, p = 1.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import deformable as dm
from validation.harness.backends import make_model
from validation.harness.orders import fit_order, pairwise_orders
from validation.harness.study import Figure, Levels, Line, Panel, Study, Table, order_check


def scene(nodes: int) -> dm.Scene:
    """The hanging sheet of this study on nodes x nodes (module docstring)."""
    sheet = dm.Sheet(size=(1.0, 1.0), nodes=(nodes, nodes))
    return dm.Scene(sheet, dm.Material(mu=1.0, gamma=0.5, eta=10.0), forces=[dm.Gravity()],
                    constraints=[dm.Pin("top")], name="hanging (top edge)")

DT0 = 4e-3
T_END = 0.4
NODES = {"fd": 9, "fe": 5}


@dataclass(frozen=True)
class Case:
    backend: str
    dt: float


def run_case(case: Case) -> dict:
    sc = scene(NODES[case.backend])
    model = make_model(sc, case.backend)
    r = dm.TimeStepper(model, dt=case.dt).run(model.initial_state(), t_end=T_END)
    return {"status": r.status, "message": r.message, "grid": model.grid(r.state.X)}


def fill(res, levels: int, runner) -> None:
    """Run the time study with ``levels`` step sizes dt0 / 2^k (dt0 = 4 ms)."""
    dts = [DT0 / 2**k for k in range(levels)]
    cases = [Case(b, dt) for b in ("fd", "fe") for dt in dts]
    raw = runner.map(run_case, cases, desc="time")
    res.config.update({
        "scene": "sheet pinned along its top edge, gravity; mu 1, gamma 0.5, eta 10", "nodes": NODES, "dt": dts,
        "t_end": T_END,
        "order_window": "theory 1 -0.3/+0.3"})
    rows, lines = [], []
    for b in ("fd", "fe"):
        these = [r for c, r in zip(cases, raw) if c.backend == b]
        bad = [r["message"] for r in these if r["status"] != "finished"]
        if bad:
            res.check(f"{b.upper()} runs stably at every dt", "finished", bad[0], False)
            continue
        e = np.array([np.max(np.abs(these[k]["grid"] - these[k + 1]["grid"])) for k in range(levels - 1)])
        dt = np.array(dts[:-1])
        p = fit_order(dt, e)
        order_check(res, f"{b.upper()} ({NODES[b]} x {NODES[b]} nodes) temporal order of positions", p, 1.0)
        for d, ee, pp in zip(dt, e, [np.nan, *pairwise_orders(dt, e)]):
            rows.append((b.upper(), d, d / 2, ee, pp))
        lines.append(Line(f"{b.upper()} {NODES[b]}x{NODES[b]} (p = {p:.2f})", dt, e))
        res.data[b] = {"dt": dt.tolist(), "self_difference": e.tolist(), "order": p}
    res.tables.append(Table("time_orders", f"Self-differences of positions at t = {T_END} s",
                            ("backend", "dt (s)", "dt/2 (s)", "max |X(dt) - X(dt/2)| (m)", "pairwise order"), rows))
    res.figures.append(Figure("time", "Temporal self-convergence of the stepper",
                              (Panel("dt-refinement, hanging sheet", "time step dt (s)",
                                     "max |X(dt) - X(dt/2)| at t_end (m)", tuple(lines), (1.0,), "dt"),)))


STUDY = Study('time', 'temporal order of the semi-implicit stepper (eq. 22-27) by dt-refinement on the hanging sheet',
              Levels(quick=5, full=7, minimum=4, maximum=9), fill)
