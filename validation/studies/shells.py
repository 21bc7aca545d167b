r"""Study ``shells``: what a shell code is held to, beyond the flat benchmarks (issue 28).

Each part states its theory; every check is computed from the measurements.

1. *Weights that vary* (:mod:`validation.harness.manufactured`): the manufactured membrane with a full
   eta_ij(a1, a2), pinned at the manufactured shape. FD weighs each difference term at its own centre:
   second order; FE (bicubic Hermite): fourth order in the nodal values.
2. *The rolled cantilever* (:mod:`validation.harness.shells`): an end moment M = 2 pi EI / L rolls the strip
   into a full circle, its free end back at the clamp (Sze, Liu and Lo 2004, test 3.2).
   The tip's gap, over L: FE within 1e-3 at its finest grid and about fourth order; FD second order.
3. *The frozen clamped plate*: the ghost-row clamp under the paper's K(r) R = F: the centre deflection
   against Timoshenko's 0.00126 q a^4 / D (digits 0.00126531909 from a Richardson-extrapolated bicubic
   Hermite solution, tests/fdmodel/test_clamp.py), second order and within 1 % at 65 x 65 nodes.
4. *The buckled column* (arc length, :func:`deformable.equilibrium_path`): the straight clamped strip loses
   stability at Euler's load, and switched along its critical mode follows the elastica (Timoshenko and Gere
   1961, section 2.7): |P / P_cr - elastica| along the secondary branch.
5. *Symmetry* (FE): a quarter Koiter plate (nu = 0.3) with two symmetry edges has the whole plate's discrete
   solution, deflected about 1.5 h (nonlinear).
6. *The hinged roof* (Sze, Liu and Lo 2004, section 3.8, isotropic, h = 12.7; data and table sources in
   :mod:`validation.harness.shells`): a quarter on FE with two symmetry planes, Koiter's shell, the arc-length
   path through both limit points against the published path at every tabulated level: the load factor of
   our path at the tabulated deflection, its error relative to the tabulated load and to the peak load.
7. *The pull-out cylinder* (Sze, Liu and Lo 2004, section 3.5): an octant on FE with three symmetry planes,
   Koiter's shell, the arc-length path; w_A, -u_B, -u_C at every tabulated load against the published ones.

8. *The pinched cylinder over rigid diaphragms* (Sze, Liu and Lo 2004, section 3.6; full level): an octant on
   FE, the diaphragm holding the radial and circumferential displacements, three symmetry planes; -W_A and
   U_B at every tabulated load against the published ones.

The pinched semi-cylinder and the hemisphere of Sze, Liu and Lo are not in this study; see its findings.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import deformable as dm
from validation.harness import manufactured, shells
from validation.harness.backends import make_model
from validation.harness.orders import fit_order, pairwise_orders
from validation.harness.study import Figure, Levels, Line, Panel, Study, Table, order_check

#: the clamped square plate's centre deflection in q a^4 / D (tests/fdmodel/test_clamp.py)
CLAMPED_CENTRE = 0.00126531909
#: load steps of the rolled cantilever: a step turns the free end by 2 pi / steps (FD's B11 needs smaller ones)
ROLL_STEPS = {"fe": 16, "fd": 64}


@dataclass(frozen=True)
class Case:
    kind: str  # a key of RUNS
    backend: str
    nodes: int


def _weights(case: Case) -> dict:
    model = make_model(manufactured.scene(case.nodes), case.backend)
    X, _ = dm.equilibrium(model, model.initial_state(), tol=1e-9, check_stability=False)
    return {"error": manufactured.node_error(model, X)}


def _roll(case: Case) -> dict:
    model = make_model(shells.rolled_cantilever(case.nodes), case.backend)
    X, history = dm.equilibrium(model, model.initial_state(), tol=1e-10, load_steps=ROLL_STEPS[case.backend],
                                check_stability=False)
    return {"gap": shells.tip_gap(model, X), "iterations": len(history)}


def _frozen(case: Case) -> dict:
    n = case.nodes
    scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(n, n)), dm.Material(mu=1.0, alpha=0.0, beta=np.ones((2, 2))),
                     force_model="frozen", forces=[dm.BodyForce((0.0, 0.0, 1e-3))],
                     constraints=[dm.Clamp(["left", "right", "bottom", "top"])])
    model = make_model(scene, "fd")
    X, _ = dm.equilibrium(model, model.initial_state(), check_stability=False)
    return {"error": abs(model.grid(X)[n // 2, n // 2, 2] / (CLAMPED_CENTRE * 1e-3) - 1.0)}


def _column(case: Case) -> dict:
    model = make_model(shells.column(case.nodes), case.backend)
    straight = dm.equilibrium_path(model, model.initial_state(), length=0.05, psi=1.0, steps=5)
    path = dm.equilibrium_path(model, model.initial_state(), length=0.05, psi=1.0, steps=30, switch=True,
                               max_load=0.7)
    secondary = [p for p in path if p.branch == 1]
    deflection = [abs(float(model.grid(p.X)[-1, 1, 2])) for p in secondary]
    return {"straight_ratio": (2 * straight.loads).tolist(), "straight_negative": straight.negative.tolist(),
            "ratio": [2 * p.load for p in secondary], "deflection": deflection,
            "elastica": [shells.elastica_load(d) for d in deflection],
            "negative": [p.stability.negative for p in secondary]}


def _roof(case: Case) -> dict:
    model = make_model(shells.hinged_roof(case.nodes), "fe")
    corner = (shells.ROOF["R"] * shells.ROOF["theta"], shells.ROOF["L"] / 2)
    path = dm.equilibrium_path(model, model.initial_state(), length=1.0, steps=60)
    return {"w": (-path.displacement(model, corner)).tolist(), "load": path.loads.tolist(),
            "negative": path.negative.tolist(), "limits": path.limit_points()}


def _pullout(case: Case) -> dict:
    around, along = case.nodes, (case.nodes - 1) * 2 // 3 + 1  # elements about 3 : 2, as the octant's sides
    model = make_model(shells.pullout_cylinder(around, along), "fe")
    arc, half = shells.PULLOUT["R"] * np.pi / 2, shells.PULLOUT["L"] / 2
    path = dm.equilibrium_path(model, model.initial_state(), length=0.25, steps=120, max_load=1.0)
    return {"nodes": [around, along], "load": path.loads.tolist(),
            "wA": path.displacement(model, (arc, half), 2).tolist(),
            "uB": (-path.displacement(model, (0.0, half), 0)).tolist(),
            "uC": (-path.displacement(model, (0.0, 0.0), 0)).tolist()}


def _pinched(case: Case) -> dict:
    model = make_model(shells.pinched_cylinder(case.nodes), "fe")
    arc, half = shells.PINCHED["R"] * np.pi / 2, shells.PINCHED["L"] / 2
    path = dm.equilibrium_path(model, model.initial_state(), length=2.0, steps=200, max_load=1.0)
    return {"nodes": [case.nodes, case.nodes], "load": path.loads.tolist(),
            "wA": (-path.displacement(model, (arc, half), 2)).tolist(),
            "uB": path.displacement(model, (0.0, half), 0).tolist()}


def _at_levels(lam, series, levels) -> list:
    """The values of each of ``series`` where the load ``lam`` first reaches each of ``levels`` (linear between
    path points; as a load-controlled path meets the level), None for a level not reached."""
    out = []
    for lv in levels:
        k = int(np.argmax(lam >= lv)) if np.any(lam >= lv) else 0
        if k == 0:
            out.append(None)
            continue
        f = (lv - lam[k - 1]) / (lam[k] - lam[k - 1])
        out.append([(1 - f) * x[k - 1] + f * x[k] for x in series])
    return out


def _quarter(case: Case) -> dict:
    """The whole plate (8 x 8 elements) and its quarter (4 x 4) with two symmetry edges, Koiter at nu = 0.3."""
    E, nu, h, q = 1e6, 0.3, 0.01, 40.0
    unused = np.ones((2, 2))
    out = []
    for nodes, size, constraints in (((9, 9), (1.0, 1.0), [dm.Pin(["left", "right", "bottom", "top"])]),
                                     ((5, 5), (0.5, 0.5), [dm.Pin(["left", "bottom"]), dm.Symmetry("right", "x"),
                                                           dm.Symmetry("top", "y")])):
        scene = dm.Scene(dm.Sheet(size=size, nodes=nodes), dm.Material(mu=1.0, eta=unused, xi=unused),
                         force_model=dm.Koiter(E=E, nu=nu, h=h), forces=[dm.BodyForce((0.0, 0.0, q))],
                         constraints=constraints)
        model = make_model(scene, "fe")
        X, _ = dm.equilibrium(model, model.initial_state(), tol=1e-12, load_steps=2, check_stability=False)
        out.append(model.grid(X))
    whole, quarter = out
    return {"centre": float(whole[4, 4, 2]), "h": h,
            "difference": float(np.max(np.abs(quarter - whole[:5, :5])) / whole[4, 4, 2])}


#: kind of case -> the function that runs it
RUNS = {"weights": _weights, "roll": _roll, "frozen": _frozen, "column": _column, "symmetry": _quarter, "roof": _roof,
        "pullout": _pullout, "pinched": _pinched}


def run_case(case: Case) -> dict:
    return RUNS[case.kind](case)


def _grids(levels: int) -> dict:
    """The nodes a side of each part's runs at ``levels`` levels."""
    return {"weights": [8 * 2**k + 1 for k in range(levels)],  # 9, 17, 33, ...
            "roll_fe": [(8 * 2**k) + 1 for k in range(levels - 1)],
            "roll_fd": [16 * 2**k + 1 for k in range(levels - 1)],
            "frozen": [8 * 2**k + 1 for k in range(levels + 1)], "roof": [8 * 2**k + 1 for k in range(levels - 2)],
            "pullout": [25, 37][:levels - 2], "pinched": [33][:levels - 3]}


def _cases(grids: dict) -> list[Case]:
    """Every run of the study, part by part."""
    return ([Case("weights", "fd", n) for n in grids["weights"]]
            + [Case("weights", "fe", n) for n in grids["weights"][:2]]
            + [Case("roll", "fe", n) for n in grids["roll_fe"]] + [Case("roll", "fd", n) for n in grids["roll_fd"]]
            + [Case("frozen", "fd", n) for n in grids["frozen"]]
            + [Case("column", "fe", 17), Case("column", "fd", 33), Case("symmetry", "fe", 9)]
            + [Case("roof", "fe", n) for n in grids["roof"]] + [Case("pullout", "fe", n) for n in grids["pullout"]]
            + [Case("pinched", "fe", n) for n in grids["pinched"]])


def _report_weights(res, raw: dict, grids: dict, levels: int) -> tuple[list, Panel]:
    """1. Weights that vary: FD's and FE's node errors under refinement; (table rows, FD's panel)."""
    rows = []
    for b, theory, n_levels, bound in (("fd", 2, levels, 3e-4), ("fe", 4, 2, 2e-6)):
        nodes = grids["weights"][:n_levels]
        h = 1.0 / (np.array(nodes) - 1)
        e = np.array([raw[Case("weights", b, n)]["error"] for n in nodes])
        p = fit_order(h, e)
        order_check(res, f"varying weights, manufactured membrane, {b.upper()} node error (m)", p, theory,
                    finest=e[-1], bound=bound)
        rows += [("weights", b.upper(), n, ee, pp) for n, ee, pp in zip(nodes, e, [np.nan, *pairwise_orders(h, e)])]
        res.data[f"weights_{b}"] = {"nodes": nodes, "error": e.tolist(), "order": p}
        if b == "fd":
            panel = Panel("manufactured membrane, varying eta_ij", "grid spacing h (m)", "largest node error (m)",
                          (Line(f"FD (p = {p:.2f})", h, e),), (2.0,))
    return rows, panel


def _report_roll(res, raw: dict, grids: dict, levels: int) -> tuple[list, Panel]:
    """2. The rolled cantilever: the tip's gap under refinement on FE and FD; (table rows, panel)."""
    rows, lines = [], []
    for b, theory, window in (("fe", 4, (0.7, 1.0)), ("fd", 2, (0.3, 0.5))):
        nodes = grids[f"roll_{b}"]
        h = 1.0 / (np.array(nodes) - 1)
        gap = np.array([raw[Case("roll", b, n)]["gap"] for n in nodes])
        p = float(pairwise_orders(h, gap)[-1])
        if b == "fe":
            res.check("rolled cantilever, FE: the tip back at the clamp", "gap <= 1e-3 L at the finest grid",
                      f"gap {gap[-1]:.2e} L at {nodes[-1]} nodes", gap[-1] <= 1e-3)
        order_check(res, f"rolled cantilever, {b.upper()} tip gap / L", p, theory, window=window)
        rows += [("roll", b.upper(), n, g, pp) for n, g, pp in zip(nodes, gap, [np.nan, *pairwise_orders(h, gap)])]
        res.data[f"roll_{b}"] = {"nodes": nodes, "gap": gap.tolist(), "order": p}
        lines.append(Line(f"{b.upper()} (p = {p:.2f})", h, gap))
    return rows, Panel("cantilever rolled by M = 2 pi EI / L", "grid spacing h (m)", "tip gap / L", tuple(lines),
                       (2.0, 4.0))


def _report_frozen(res, raw: dict, grids: dict, levels: int) -> tuple[list, Panel]:
    """3. The frozen clamped plate: the centre deflection against Timoshenko's; (table rows, panel)."""
    nodes = grids["frozen"]
    h = 1.0 / (np.array(nodes) - 1)
    e = np.array([raw[Case("frozen", "fd", n)]["error"] for n in nodes])
    p = fit_order(h, e)
    at65 = e[nodes.index(65)] if 65 in nodes else None
    order_check(res, "frozen clamped plate, FD centre deflection against Timoshenko", p, 2,
                finest=e[-1], bound=1e-2 if nodes[-1] >= 65 else 1.0)
    if at65 is not None:
        res.check("frozen clamped plate within 1 % at 65 x 65 nodes", "relative error <= 1e-2",
                  f"{at65:.2e}", at65 <= 1e-2)
    rows = [("frozen plate", "FD", n, ee, pp) for n, ee, pp in zip(nodes, e, [np.nan, *pairwise_orders(h, e)])]
    res.data["frozen"] = {"nodes": nodes, "error": e.tolist(), "order": p}
    return rows, Panel("frozen clamped plate (ghost-row clamp)", "grid spacing h (m)", "relative error of w_c",
                       (Line(f"FD (p = {p:.2f})", h, e),), (2.0,))


def _report_column(res, raw: dict) -> None:
    """4. The buckled column: the straight path's loss of stability and the switched branch against the elastica."""
    crows = []
    for b, n, bound in (("fe", 17, 2e-3), ("fd", 33, 7e-3)):
        r = raw[Case("column", b, n)]
        ratio, neg = np.array(r["straight_ratio"]), np.array(r["straight_negative"])
        res.check_all(f"column, {b.upper()} {n} nodes: the straight path loses stability at Euler's load",
                      "no negative eigenvalue below 0.99 P_cr, one above 1.01 P_cr",
                      {f"P/P_cr = {x:.2f}": (k == 0 if x < 0.99 else k == 1) for x, k in zip(ratio, neg)
                       if x < 0.99 or x > 1.01})
        dev = np.abs(np.array(r["ratio"]) - np.array(r["elastica"]))
        res.check(f"column, {b.upper()} {n} nodes: the switched branch follows the elastica",
                  f"max |P/P_cr - elastica| <= {bound:g} over the branch, reaching delta / L > 0.5, all stable",
                  f"{dev.max():.2e} over {dev.size} points, delta / L up to {max(r['deflection']):.2f}, "
                  f"{sum(k == 0 for k in r['negative'])} of {len(r['negative'])} stable",
                  dev.size > 10 and dev.max() <= bound and max(r["deflection"]) > 0.5 and not any(r["negative"]))
        crows += [(b.upper(), n, d, x, el)
                  for d, x, el in zip(r["deflection"][::5], r["ratio"][::5], r["elastica"][::5])]
        res.data[f"column_{b}"] = r
    res.tables.append(Table("column", "The switched branch of the clamped column against the elastica (every "
                            "fifth point)", ("backend", "nodes", "tip deflection / L", "P / P_cr", "elastica P / P_cr"),
                            crows))


def _report_symmetry(res, raw: dict) -> None:
    """5. Symmetry: the quarter plate against the whole."""
    s = raw[Case("symmetry", "fe", 9)]
    res.check("symmetry planes: the quarter plate is the whole plate (FE, Koiter nu = 0.3)",
              "every node within 1e-9 of the centre deflection, deflected beyond h",
              f"{s['difference']:.1e} of w_c = {s['centre'] / s['h']:.2f} h",
              s["difference"] <= 1e-9 and s["centre"] > s["h"])
    res.data["symmetry"] = s


def _report_roof(res, raw: dict, grids: dict) -> None:
    """6. The hinged roof against Sze, Liu and Lo (2004): the limit points and the path at every tabulated level."""
    table = shells.ROOF_TABLE[1:]
    peak = float(table[:int(np.argmax(np.diff(table[:, 0]) < 0)) + 1, 0].max())  # the first limit load
    runs = {n: raw[Case("roof", "fe", n)] for n in grids["roof"]}
    finest = max(runs)
    r = runs[finest]
    w, lam = np.array(r["w"]), np.array(r["load"])
    reached = table[:, 1] <= w.max()
    ours = np.interp(table[reached, 1], w, lam) if np.all(np.diff(w) > 0) else np.full(reached.sum(), np.nan)
    rel = np.abs(ours - table[reached, 0]) / table[reached, 0]
    of_peak = np.abs(ours - table[reached, 0]) / peak
    limits = r["limits"]
    neg = np.array(r["negative"])
    between = neg[limits[0] + 1:limits[1]] if len(limits) >= 2 else np.array([])
    before = sorted(set(neg[:limits[0]].tolist())) if limits else []
    res.check("hinged roof: the path passes both limit points (FE, arc length)",
              "a maximum and then a minimum of the load, one negative eigenvalue between them, none before",
              f"limit points at P/P_max = {', '.join(f'{lam[k]:.4f}' for k in limits[:2])}; negative eigenvalues "
              f"between: {sorted(set(between.tolist()))}, before: {before}",
              len(limits) >= 2 and between.size > 0 and np.all(between == 1) and np.all(neg[:limits[0]] == 0))
    res.check_all(f"hinged roof within 2 % of the published path at every tabulated level (FE {finest} nodes)",
                  "|P/P_max - table| <= 2 % of the tabulated load, at each tabulated deflection -W_C",
                  {f"-W_C = {wr:g}": e <= 0.02 for wr, e in zip(table[reached, 1], rel)} if reached.all() else {})
    res.tables.append(Table("roof", f"Hinged roof, isotropic, h = 12.7: the published path (Sze, Liu and Lo 2004, "
                            f"read from MBDyn's sze38_ref_a.dat) against ours (FE {finest} x {finest} nodes, a "
                            "quarter)", ("-W_C (mm)", "published P/P_max", "ours", "error / published",
                                         "error / peak"),
                            [(wr, lr, o, e, q) for (lr, wr), o, e, q in zip(table[reached], ours, rel, of_peak)]))
    res.data["roof"] = {"runs": runs, "error_relative": rel.tolist(), "error_of_peak": of_peak.tolist()}
    if len(runs) > 1:
        coarse = runs[min(runs)]
        diff = np.max(np.abs(np.interp(table[reached, 1], np.array(coarse["w"]), np.array(coarse["load"])) - ours))
        res.findings.append(f"Hinged roof: {min(runs)} and {finest} nodes a side differ by at most {diff:.4f} "
                            "in P/P_max at the tabulated deflections.")
    res.findings.append(
        f"Hinged roof: the largest difference from the published path is {rel.max():.1%} of the tabulated load "
        f"(at -W_C = {table[reached, 1][int(np.argmax(rel))]:g}) and {of_peak.max():.1%} of the peak load; at the "
        f"first tabulated level (-W_C = {table[0, 1]:g}, the linear range) it is {rel[0]:.1%}, our path the "
        f"{'stiffer' if ours[0] > table[0, 0] else 'softer'}. The published path is ABAQUS's S4R (a shear-deformable "
        "element, on Sze's mesh), ours Koiter's shell; the full level runs a second grid, "
        "which shows whether the difference is this discretisation's.")


@dataclass(frozen=True)
class Published:
    """A path of Sze, Liu and Lo (2004) read from MBDyn's table ``where``: the loads and the displacements ``names``
    of our runs (``label`` in the report) at each."""

    title: str
    table: np.ndarray
    names: tuple[str, ...]
    label: tuple[str, ...]
    where: str


#: 7. the pull-out cylinder and 8. the pinched cylinder: kind of run -> its published path
PUBLISHED = {"pullout": Published("pull-out cylinder", shells.PULLOUT_TABLE[1:], ("wA", "uB", "uC"),
                                  ("w_A", "-u_B", "-u_C"), "sze35_ref.dat"),
             "pinched": Published("pinched cylinder over rigid diaphragms", shells.PINCHED_TABLE[1:], ("wA", "uB"),
                                  ("-W_A", "U_B"), "sze36_ref.dat")}


def _report_published(res, raw: dict, grids: dict, kind: str) -> None:
    """7. and 8.: each run of ``kind`` against its published path at every tabulated load."""
    pub = PUBLISHED[kind]
    table, label = pub.table, pub.label
    for n in grids[kind]:
        r = raw[Case(kind, "fe", n)]
        ours = _at_levels(np.array(r["load"]), [np.array(r[q]) for q in pub.names], table[:, 0])
        errs, prow = {}, []
        for (lv, *ref), o in zip(table, ours):
            if o is None:
                continue
            e = [abs(x - v) / abs(v) for x, v in zip(o, ref)]
            errs[f"P/P_max = {lv:g}"] = max(e) <= 0.02
            prow.append((lv, *[x for pair in zip(ref, o) for x in pair], max(e)))
        nodes = "x".join(map(str, r["nodes"]))
        res.check_all(f"{pub.title} within 2 % of the published {', '.join(label)} at every tabulated load "
                      f"(FE {nodes} nodes)", f"|ours - table| <= 2 % of the table, each of the {len(label)}, "
                      "each level", errs if len(errs) == len(table) else {})
        res.tables.append(Table(f"{kind}_{nodes}", f"{pub.title.capitalize()} (Sze, Liu and Lo 2004, read from MBDyn's "
                                f"{pub.where}) against ours (FE {nodes} nodes, an octant)",
                                ("P/P_max", *[f"{q} {w}" for q in label for w in ("published", "ours")],
                                 "largest error / published"), prow))
        res.data[f"{kind}_{nodes}"] = r


def fill(res, levels: int, runner) -> None:
    """``levels`` refinement levels of each convergence part (3 quick)."""
    grids = _grids(levels)
    cases = _cases(grids)
    raw = dict(zip(cases, runner.map(run_case, cases, desc="shells")))
    res.config.update({"grids": grids, "roll_load_steps": ROLL_STEPS, "manufactured": {"A": manufactured.A,
                       "W": manufactured.W}, "strip": shells.ROLL})
    parts = [report(res, raw, grids, levels) for report in (_report_weights, _report_roll, _report_frozen)]
    res.tables.append(Table("convergence", "Errors under refinement (pairwise orders)",
                            ("problem", "backend", "nodes along", "error", "pairwise order"),
                            [row for rows, _ in parts for row in rows],
                            note="weights: largest node distance to r* (m); roll: tip gap / L; frozen plate: "
                                 "relative error of the centre deflection."))
    _report_column(res, raw)
    _report_symmetry(res, raw)
    _report_roof(res, raw, grids)
    for kind in PUBLISHED:
        _report_published(res, raw, grids, kind)
    res.figures.append(Figure("convergence", "Errors under refinement", tuple(panel for _, panel in parts)))
    if not grids["pinched"]:
        res.findings.append("The pinched cylinder over rigid diaphragms runs at the full level only (an octant on FE "
                            "33 x 33 nodes, about 15 CPU minutes).")
    res.findings.append("Not here: the pinched semi-cylinder (Sze, Liu and Lo 2004, section 3.7; its table is MBDyn's "
                        "sze37_ref.dat, but no public source read states its boundary conditions) and the hemisphere "
                        "(section 3.4; MBDyn has no table, Elmer's has unlabelled columns); "
                        "validation/harness/shells.py says where each was looked for.")


STUDY = Study("shells", "Shells beyond the flat square: varying weights, end moments, the ghost-row clamp under "
              "K(r), arc length and branch switching, symmetry planes", Levels(quick=3, full=4, minimum=3, maximum=5),
              fill, in_default=False)
