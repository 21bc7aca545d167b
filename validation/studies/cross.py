r"""Study ``cross``: FD against FE on the same dynamic scenes, and each one's self-convergence.

Both backends run the same scene (same node grid, same dt, same force model
tpbf87) on three or more grids with refinement ratio r = 2. At the nodes of
the coarsest grid (common to every level; FD values there are exact, FE
values are its nodal degrees of freedom or sampled) and at several times the
positions r, the metric G_ij (eq. 4) and the curvature B_ij (eq. 8) are
recorded. Reported:

- the FD-FE difference per level, max over points, times and components;
- each backend's self-convergence: e_k = max |f_k - f_{k+1}| between
  consecutive grids and its observed order;
- for scalar outputs phi (a free-edge position component, G11 and B22 at the
  centre, at the end time), Richardson extrapolation and Roache's grid
  convergence index on the three finest grids f1 (fine), f2, f3:
  eps21 = f2 - f1, eps32 = f3 - f2, p = ln|eps32/eps21| / ln r,
  phi_ext = f1 + (f1 - f2)/(r^p - 1), GCI_12 = Fs |eps21/f1| / (r^p - 1),
  GCI_23 = Fs |eps32/f2| / (r^p - 1), Fs = 1.25, and the asymptotic-range
  ratio GCI_23 / (r^p GCI_12), which should be near 1. With p observed on the
  same three grids that ratio is f1/f2 identically, so it is also given with
  the theoretical order p_th (where it equals (f1/f2) |eps32/eps21| / r^p_th,
  i.e. (f1/f2) r^(p - p_th)): that is the informative asymptotic-range check.

Theory. FD with the paper's pointwise weighting is first order at free edges
(docs/design.md: the natural-boundary rows are a half-cell flux balance), so its
positions converge at order 1 and so does the FD-FE difference, in the
asymptotic range. Gravity switched on at t = 0 sends a front from the pinned
edge through the sheet, so the quick grids (5, 9, 17 nodes) are not in that
range: the check is that the FD-FE difference shrinks at every refinement;
the observed orders and the GCI asymptotic ratios are reported as findings. B is not
checked: with xi = 0, and under tpbf87 even with xi > 0 about a flat rest
state (no linear bending stiffness, docs/design.md), nothing controls curvature at
the grid scale, so B at the nodes need not converge (reported). FE positions
are not given a checked order here: the tpbf87 force is lagged in time and
the corners where a pinned edge meets a free one are singular, so the
observed FE order is reported as a finding.

Scenes are the registered ``hanging`` (a cloth pinned at its two top
corners, falling from horizontal: point supports of a membrane are singular
in the continuum, which slows both backends below their smooth orders) and ``flag`` (pole edge pinned, coils on
the free corners swinging at 4 Hz, wind) of :mod:`deformable.scenes`, on n x n nodes. One dt serves every level
of a scene: half the FE stretching bound on the finest grid (the consistent
Hermite mass makes FE's bound 0.21 of FD's), so the levels differ in space
only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import deformable as dm
from deformable import scenes
from validation.harness.backends import make_model
from validation.harness.orders import fit_order
from validation.harness.study import Figure, Levels, Line, Panel, Study, Table, nodes_at

#: the paper's force and weights (section 5: xi = 0, eta_12 = xi_12 = 0)
PAPER = dict(force_model="tpbf87", shear=0.0, xi=0.0)
#: per scene: the flag's coils swing at 4 Hz, as this study was first measured. The shipped flag swings at 6 Hz
#: (a wave shorter than the flag, issue 13); its 1.1 m wave is not resolved by the coarse levels: measured, the
#: largest FD-FE position difference at the common points over t = 0.1-0.4 s grows from 0.073 m on 5 x 5
#: nodes to 0.129 m on 9 x 9.
EXTRA = {"hanging": {}, "flag": dict(frequency=4.0)}
COARSEST = 5
COMMON = 5  # common points: COMMON x COMMON nodes, shared by every grid
T_END = 0.4
SAMPLES = (0.1, 0.2, 0.3, 0.4)
FS = 1.25


def scene(name: str, nodes: int) -> dm.Scene:
    """The registered scene ``name`` ("hanging" | "flag", :mod:`deformable.scenes`) on nodes x nodes, as the paper
    has it: its force (14), eta_12 = xi_12 = 0 and xi = 0."""
    return scenes.SCENES[name](nodes=(nodes, nodes), **PAPER, **EXTRA[name])


def step(name: str, finest: int) -> float:
    """One dt for every level: half the FE stretching bound on the finest grid (one significant digit)."""
    return float(f"{0.5 * make_model(scene(name, finest), 'fe').stable_step():.1g}")


#: scalar outputs: name -> (scene, quantity, parameter point, component)
SCALARS = {
    "hanging": [("z of the free-edge midpoint", "r", (0.5, 0.0), (2,)),
                ("y of the free-edge midpoint", "r", (0.5, 0.0), (1,)),
                ("G22 at the centre", "G", (0.5, 0.5), (1, 1))],
    "flag": [("z of the free corner (1, 0)", "r", (1.0, 0.0), (2,)),
             ("y of the free corner (1, 0)", "r", (1.0, 0.0), (1,)),
             ("G11 at the centre", "G", (0.5, 0.5), (0, 0))],
}


@dataclass(frozen=True)
class Case:
    backend: str
    scene: str
    nodes: int
    dt: float


def run_case(case: Case) -> dict:
    """Positions, G and B at the coarsest grid's nodes at the sample times: arrays (T, P, ...)."""
    sc = scene(case.scene, case.nodes)
    model = make_model(sc, case.backend)
    L1, L2 = sc.sheet.size
    a1, a2 = np.meshgrid(np.linspace(0.0, L1, COMMON), np.linspace(0.0, L2, COMMON), indexing="ij")
    pts = np.stack([a1.ravel(), a2.ravel()], axis=1)
    stepper = dm.TimeStepper(model, dt=case.dt)
    X = model.initial_state()
    out = {"r": [], "G": [], "B": []}
    marks = {int(round(t / case.dt)) for t in SAMPLES}
    status = "finished"
    try:
        for state in stepper.iterate(X, int(round(T_END / case.dt))):
            if state.step in marks:
                s = model.sample(state.X, pts)
                out["r"].append(s.r)
                out["G"].append(s.G)
                out["B"].append(s.B)
    except dm.DivergenceError as err:
        status = str(err)
    return {"h": model.spacing[0], "status": status, **{k: np.array(v) for k, v in out.items()}}


def gci(f1: float, f2: float, f3: float, r: float = 2.0, p_theory: float | None = None) -> dict:
    """Richardson extrapolation and Roache's GCI from three grids (f1 finest), refinement ratio r."""
    e21, e32 = f2 - f1, f3 - f2
    with np.errstate(divide="ignore", invalid="ignore"):
        p = float(np.log(abs(e32 / e21)) / np.log(r)) if e21 != 0 and e32 != 0 else np.nan
    out = {"p": p, "oscillatory": bool(e21 * e32 < 0)}
    if np.isfinite(p) and p > 0:
        out["extrapolated"] = f1 + (f1 - f2) / (r**p - 1)
        out["gci_12"] = FS * abs(e21 / f1) / (r**p - 1)
        out["gci_23"] = FS * abs(e32 / f2) / (r**p - 1)
        out["asymptotic"] = out["gci_23"] / (r**p * out["gci_12"])
    if p_theory is not None and e21 != 0:
        g12 = FS * abs(e21 / f1) / (r**p_theory - 1)
        g23 = FS * abs(e32 / f2) / (r**p_theory - 1)
        out["gci_12_theory"] = g12
        out["asymptotic_theory"] = g23 / (r**p_theory * g12)
    return out


def fill(res, levels: int, runner) -> None:
    """Run the cross study over ``levels`` grids (5, 9, 17, ... nodes a side)."""
    nodes = [nodes_at(k, COARSEST) for k in range(levels)]
    dt = {s: step(s, nodes[-1]) for s in SCALARS}
    cases = [Case(b, s, n, dt[s]) for s in SCALARS for b in ("fd", "fe") for n in nodes]
    raw = runner.map(run_case, cases, desc="cross")
    res.config.update({
        "nodes": nodes, "dt": dt, "t_end": T_END, "sample_times": list(SAMPLES), "safety_factor": FS,
        "refinement_ratio": 2, "scenes": {s: scenes.to_toml(scenes.config(s, **PAPER, **EXTRA[s])) for s in SCALARS},
        "force_model": "tpbf87", "fd_weighting": "pointwise",
        "common_points": f"{COMMON} x {COMMON} nodes shared by every grid",
        "order_window": "theory -0.3/+0.3"})
    get = {(c.backend, c.scene, c.nodes): r for c, r in zip(cases, raw)}
    diff_rows, self_rows, gci_rows = [], [], []
    panels = []
    for s in SCALARS:
        for c, r in zip(cases, raw):
            if c.scene == s and r["status"] != "finished":
                res.check(f"{s}: {c.backend.upper()} at {c.nodes} nodes runs stably", "finished", r["status"], False)
        h = np.array([1.0 / (n - 1) for n in nodes])
        lines = []
        for q in ("r", "G", "B"):
            d = np.array([np.max(np.abs(get[("fd", s, n)][q] - get[("fe", s, n)][q])) for n in nodes])
            diff_rows.append((s, q, *d, fit_order(h, d) if np.all(d > 0) else np.nan))
            lines.append(Line(f"|FD - FE| of {q}", h, d))
            for b in ("fd", "fe"):
                e = np.array([np.max(np.abs(get[(b, s, nodes[k])][q] - get[(b, s, nodes[k + 1])][q]))
                              for k in range(levels - 1)])
                p = fit_order(h[:-1], e) if np.all(e > 0) else np.nan
                self_rows.append((s, b.upper(), q, *e, p))
                res.data[f"{s}|{b}|{q}|self"] = e.tolist()
                if b == "fd":
                    lines.append(Line(f"FD self-difference of {q}", h[:-1], e, "s--"))
                if q == "r":
                    res.findings.append(f"{s}: {b.upper()} positions self-converge at observed order {p:.2f} "
                                        f"(differences {', '.join(f'{v:.2e}' for v in e)}).")
            res.data[f"{s}|{q}|fd-fe"] = d.tolist()
            if q == "B":
                res.findings.append(f"{s}: B does not settle under refinement (FD-FE difference "
                                    f"{', '.join(f'{v:.2g}' for v in d)} 1/m): no bending stiffness controls the "
                                    "curvature at the grid scale (xi = 0; tpbf87 about a flat rest state has none "
                                    "at linear order anyway), so B is a grid-scale quantity here, not a "
                                    "converging one.")
            if q == "r":
                res.check(f"{s}: FD-FE difference of positions shrinks under refinement",
                          "decreasing at every refinement (both backends converge to one solution)",
                          ", ".join(f"{v:.2e}" for v in d) + f" (observed order {fit_order(h, d):.2f}, FD theory 1)",
                          np.all(np.diff(d) < 0))
        for label, q, point, comp in SCALARS[s]:
            idx = int(round(point[0] * (COMMON - 1))) * COMMON + int(round(point[1] * (COMMON - 1)))
            for b in ("fd", "fe"):
                f = [float(get[(b, s, n)][q][-1][idx][comp]) for n in nodes[-3:]][::-1]  # f1 finest
                g = gci(*f, p_theory=1.0 if b == "fd" else None)
                gci_rows.append((s, label, b.upper(), f[0], f[1], f[2], g["p"], g.get("extrapolated", np.nan),
                                 g.get("gci_12", np.nan), g.get("gci_23", np.nan), g.get("asymptotic", np.nan),
                                 g.get("asymptotic_theory", np.nan)))
                res.data[f"{s}|{label}|{b}|gci"] = g
        panels.append(Panel(f"{s}: FD-FE difference and FD self-convergence", "grid spacing h (parameter units)",
                             "max difference (r: m; G: -; B: 1/m)", tuple(lines), (1.0,)))
    res.tables.append(Table("fd_fe_difference", "FD-FE difference per level (max over the common points, the "
                            "sample times and the components)", ("scene", "quantity", *[f"{n} nodes" for n in nodes],
                                                                 "observed order"), diff_rows))
    res.tables.append(Table("self_convergence", "Self-convergence: max difference between consecutive grids",
                            ("scene", "backend", "quantity", *[f"{nodes[k]}-{nodes[k + 1]}" for k in range(levels - 1)],
                             "observed order"), self_rows))
    res.tables.append(Table("gci", "Richardson extrapolation and grid convergence index (three finest grids, r = 2, "
                            f"Fs = {FS}), at t = {T_END} s",
                            ("scene", "output", "backend", "f1 (fine)", "f2", "f3 (coarse)", "p observed",
                             "Richardson", "GCI_12", "GCI_23", "GCI_23/(r^p GCI_12)", "same with p_th = 1 (FD)"),
                            gci_rows,
                            note="With p observed on the same three grids GCI_23/(r^p GCI_12) = f1/f2 by "
                                 "construction; the last column uses FD's theoretical order 1 and equals "
                                 "(f1/f2) 2^(p - 1): near 1 in the asymptotic range."))
    res.figures.append(Figure("cross", "FD-FE differences (solid) and FD self-differences (dashed) under refinement",
                              tuple(panels)))


STUDY = Study('cross', 'FD against FE on the hanging and flag scenes: differences, self-convergence, Richardson and GCI',
              Levels(quick=3, full=4, minimum=3, maximum=5), fill)
