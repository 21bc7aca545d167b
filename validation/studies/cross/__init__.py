r"""Study ``cross``: FD against FE where it means something, and each at its best order.

Well-posed problems (:mod:`validation.studies.cross.problems`: the energy-consistent model, full weight
tensors, xi > 0, edges pinned or clamped, smooth loads), statics and motions, solved by both backends on
refined grids (:mod:`~validation.studies.cross.cases`). For r, G and B at fixed points
(:mod:`~validation.studies.cross.measure`: an L2 norm over the sheet and the max over the interior, the
largest over the loads or sample times):

1. the FD-FE difference at every level, which must shrink at every refinement at an observed order of at
   least 0.8 times the lower of the two backends' theoretical orders;
2. each backend's self-convergence (differences between consecutive levels, FD on one level more), its
   observed order next to the theoretical one and checked in the interior max, where no corner or edge
   layer limits it, against a window around it;
3. Richardson extrapolation and Roache's grid convergence index of scalar outputs (tip, centre, corner),
   with the asymptotic-range ratio at the theoretical order;
4. the cantilever's tip against the extensible elastica (FD within 3 % at 81 x 9 for P L^2 / EI = 1, 2,
   3), the time error of the motions' fixed step, and the work-precision of whole solves
   (:mod:`~validation.studies.cross.work`, its CPU times in run.md);
5. a finding, no check: the paper's force with xi = 0 on point-pinned and gusted scenes
   (:mod:`~validation.studies.cross.paper_force`), where G and B do not converge.

Theory (h the spacing; docs/design.md):

- FD (variational model, control-area weights, ghost-row clamp, each term of eq. (13) centred where its
  stencil is; its G and B carried to the nodes and interpolated bilinearly): r, G, B all O(h^2).
- FE (bicubic Hermite, conforming): r O(h^4), G O(h^3), B O(h^2) at points at a fixed position inside the
  elements (the probe's third points); the clamp holds the slope only. In the L2 norm over the sheet,
  corner singularities (a clamped or pinned edge meeting another edge at a right angle; Williams 1952,
  Blum and Rannacher 1980) may hold the FE orders lower: reported, not checked. On the cantilever the
  solution is close to a cubic along the strip, which the bicubics hold exactly: FE's r and G converge
  faster than theory says at most, so their window has no upper end.
- The motions run one fixed dt at every level (Newmark, second order in time): each compared pair is
  the same time-discrete problem, so the differences measure space alone; the time error itself (FD on
  the finest grid, dt against dt / 2) is reported beside the finest FD-FE difference.
"""

from __future__ import annotations

import numpy as np

from validation.harness.orders import fit_order, gci
from validation.harness.study import Figure, Levels, Line, Panel, Study, Table

from . import paper_force, problems
from .cases import DT, DYNAMICS, PROBLEMS, SAMPLE_TIMES, STATICS, T_END, Case, nodes, probe, run_case
from .convergence import NORMS, differences
from .measure import QUANTITIES, difference
from .work import GRIDS, cpu_to_reach, error_at, run_work, work_cases

#: theoretical orders by backend and quantity (module docstring)
THEORY = {"fd": {"r": 2.0, "G": 2.0, "B": 2.0}, "fe": {"r": 4.0, "G": 3.0, "B": 2.0}}
#: the window of a checked self-convergence order: [theory - below, theory + above]
WINDOW = (0.3, 0.5)
#: problems and quantities whose FE order has no upper end (module docstring)
UNBOUNDED = {("cantilever", "r"), ("cantilever", "G")}
#: the FD-FE difference must converge at least this fraction of the lower theoretical order
FRACTION = 0.8
#: the work-precision target on the clamped plate (relative error of the centre deflection)
TARGET = 1e-6
LABELS = {"cantilever": "cantilever (Sze, Liu and Lo)", "plate": "clamped plate, nonlinear",
          "hanging": "hanging sheet, pushed", "swing": "hanging sheet, released", "flag": "flag in a gust"}


def _grid(problem: str, level: int, backend: str = "fd") -> str:
    M, N = nodes(problem, level, backend)
    return f"{M}x{N}"


def _fmt(values) -> str:
    return ", ".join(f"{v:.2e}" for v in values)


def fill(res, levels: int, runner) -> None:
    """The cross study on ``levels`` levels (FD on one more), the work-precision solves and the finding."""
    cases = [Case(p, b, k) for p in PROBLEMS for b in ("fd", "fe") for k in range(levels + (b == "fd"))]
    cases += [Case(p, "fd", levels, DT / 2) for p in DYNAMICS]  # the time error of the finest FD grid
    raw = dict(zip(cases, runner.map(run_case, cases, desc="cross")))
    wcases = work_cases(full=levels > 3)
    wraw = dict(zip(wcases, runner.map(run_work, wcases, desc="work-precision")))
    fcases = paper_force.cases(levels)
    fraw = dict(zip(fcases, runner.map(paper_force.run_force_case, fcases, desc="paper's force")))

    res.config.update({
        "problems": {p: {"nodes": {b: [_grid(p, k, b) for k in range(levels + (b == "fd"))] for b in ("fd", "fe")}}
                     for p in PROBLEMS},
        "cantilever": problems.CANTILEVER, "loads (P L^2/EI)": list(problems.LOADS), "plate": problems.PLATE,
        "linear plate": problems.LINEAR_PLATE, "flag": problems.FLAG,
        "motions": {"scheme": "newmark", "dt": DT, "t_end": T_END, "sample_times": list(SAMPLE_TIMES)},
        "theory": THEORY, "self-convergence window": f"theory -{WINDOW[0]}/+{WINDOW[1]} (interior max)",
        "FD-FE order": f">= {FRACTION} x the lower theoretical order",
        "work-precision grids": {p: {m: list(g if levels > 3 else g[:-1]) for m, g in methods.items()}
                                 for p, methods in GRIDS.items()},
        "force model": "variational (paper's force: the finding)", "fd weighting": "control-area (the default)"})

    diffs = {}
    for p in PROBLEMS:
        runs = {(c.backend, c.level): r for c, r in raw.items() if c.problem == p and c.dt == DT}
        diffs[p] = differences(runs, levels, probe(p))
    _cross_checks(res, diffs, levels)
    _self_convergence(res, diffs, levels)
    _richardson(res, raw, levels)
    _cantilever_tip(res, raw, levels)
    _time_error(res, raw, diffs, levels)
    _work_precision(res, wraw)
    paper_force.report(res, levels, fraw)
    _figure(res, diffs)


def _cross_checks(res, diffs, levels) -> None:
    rows = []
    for p, d in diffs.items():
        for q in QUANTITIES:
            need = FRACTION * min(THEORY["fd"][q], THEORY["fe"][q])
            parts, ok = [], True
            for norm in NORMS:
                v = d.cross[(q, norm)]
                p_obs = d.order(v)
                falls = bool(np.all(np.diff(v) < 0))
                ok &= falls and np.isfinite(p_obs) and p_obs >= need
                parts.append(f"{norm}: {_fmt(v)} (p = {p_obs:.2f})")
                rows.append((LABELS[p], q, norm, *v, p_obs, need))
                res.data[f"{p}|{q}|{norm}|fd-fe"] = v.tolist()
            res.check(f"{LABELS[p]}: FD-FE difference of {q}",
                      f"falls at every refinement, observed order >= {need:g} in both norms", "; ".join(parts), ok)
    res.tables.append(Table("fd_fe_difference", "FD-FE differences per level (largest over the loads or sample times)",
                            ("problem", "quantity", "norm", *[f"level {k}" for k in range(levels)], "observed order",
                             "required order"), rows,
                            note="Level k of each problem: the grids in the configuration. Orders: least-squares "
                                 "slope of log(difference) against log(h)."))


def _self_convergence(res, diffs, levels) -> None:
    rows = []
    for p, d in diffs.items():
        for b in ("fd", "fe"):
            parts, ok = [], True
            for q in QUANTITIES:
                th = THEORY[b][q]
                lo, hi = th - WINDOW[0], (np.inf if b == "fe" and (p, q) in UNBOUNDED else th + WINDOW[1])
                for norm in NORMS:
                    v = d.self[(b, q, norm)]
                    p_obs = d.order(v)
                    rows.append((LABELS[p], b.upper(), q, norm, *v, *([np.nan] * (levels - len(v))), p_obs, th))
                    res.data[f"{p}|{b}|{q}|{norm}|self"] = v.tolist()
                    if norm == "interior max":
                        ok &= bool(np.isfinite(p_obs) and lo <= p_obs <= hi)
                        parts.append(f"{q}: p = {p_obs:.2f} (window [{lo:.1f}, {hi:.1f}])")
            res.check(f"{LABELS[p]}: {b.upper()} self-convergence of r, G, B (interior max)",
                      f"orders {', '.join(f'{THEORY[b][q]:g}' for q in QUANTITIES)} within their windows",
                      "; ".join(parts), ok)
    res.tables.append(Table("self_convergence", "Self-convergence: differences between consecutive levels, observed "
                            "order next to theory",
                            ("problem", "backend", "quantity", "norm", *[f"{k}-{k + 1}" for k in range(levels)],
                             "observed order", "theoretical order"), rows,
                            note="FD runs one level more than FE. L2 orders of FE below theory come from corner "
                                 "singularities of the clamped and pinned edges (not checked)."))


def _richardson(res, raw, levels) -> None:
    rows = []
    for p in PROBLEMS:
        for b in ("fd", "fe"):
            count = levels + (b == "fd")
            runs = [raw[Case(p, b, k)] for k in range(count)]
            for name in runs[0]["scalars"]:
                f1, f2, f3 = (runs[k]["scalars"][name] for k in (count - 1, count - 2, count - 3))
                g = gci(f1, f2, f3, p_theory=THEORY[b]["r"])
                extra = (g.get(k, np.nan) for k in ("extrapolated", "gci_12", "asymptotic", "asymptotic_theory"))
                rows.append((LABELS[p], name, b.upper(), f1, f2, f3, g["p"], THEORY[b]["r"], *extra))
                res.data[f"{p}|{name}|{b}|gci"] = g
                if b == "fd" and not name.startswith("tip x"):
                    ratio = g.get("asymptotic_theory", np.nan)
                    res.check(f"{LABELS[p]}: FD {name}, asymptotic range",
                              "GCI_23 / (r^2 GCI_12) within [0.8, 1.25] (Roache's check at the theoretical order 2)",
                              f"{ratio:.3f} (p observed {g['p']:.2f})", bool(0.8 <= ratio <= 1.25))
    res.tables.append(Table("richardson_gci", "Richardson extrapolation and grid convergence index (three finest grids "
                            "of each backend, r = 2, Fs = 1.25)",
                            ("problem", "output", "backend", "f1 (fine)", "f2", "f3 (coarse)", "p observed",
                             "p theory", "Richardson", "GCI_12", "GCI_23/(r^p GCI_12), p observed",
                             "same at p theory"), rows,
                            note="With p observed on the same three grids the first ratio is f1/f2 by construction; "
                                 "the last column, at the theoretical order, is the informative asymptotic-range "
                                 "check (near 1). FE's outputs converge near round-off on these grids."))


def _cantilever_tip(res, raw, levels) -> None:
    rows, items, falling = [], {}, {}
    L = problems.CANTILEVER["L"]
    for load in problems.LOADS:
        x, z = problems.elastica_tip(load)
        errs = []
        for k in range(levels + 1):
            r = raw[Case("cantilever", "fd", k)]["scalars"]
            xt, zt = r[f"tip x, P L^2/EI = {load:g}"], r[f"tip z, P L^2/EI = {load:g}"]
            e = max(abs(xt - x) / (L - x), abs(zt - z) / abs(z))  # relative errors of u and w
            errs.append(e)
            rows.append((load, _grid("cantilever", k), (L - xt) / L, -zt / L, (L - x) / L, -z / L, e))
        falling[load] = errs
        if load <= 3:
            items[f"P L^2/EI = {load:g}"] = errs[1] <= 0.03 and bool(np.all(np.diff(errs) < 0))
    res.check_all("cantilever: FD tip within 3 % at 81x9 nodes, falling under refinement (P L^2/EI = 1, 2, 3)",
                  "relative error of u and w <= 3 % at 81x9, smaller at every finer grid", items)
    res.findings.append("Cantilever, FD with default settings: relative tip errors (larger of u and w) at "
                        + "; ".join(f"P L^2/EI = {ld:g}: " + ", ".join(
                            f"{_grid('cantilever', k)} {e:.1e}" for k, e in enumerate(errs))
                                    for ld, errs in falling.items()) + ".")
    res.tables.append(Table("cantilever_tip", "Cantilever: FD tip against the extensible elastica of the model",
                            ("P L^2/EI", "FD nodes", "-u/L", "w/L", "reference -u/L", "reference w/L",
                             "relative error"), rows,
                            note="Reference: the extensible elastica of the model's own energy (problems.py); the "
                                 "inextensible elastica of the literature differs by the axial strain, about 3e-5."))


def _time_error(res, raw, diffs, levels) -> None:
    rows = []
    for p in DYNAMICS:
        a, b = raw[Case(p, "fd", levels)], raw[Case(p, "fd", levels, DT / 2)]
        pr = probe(p)
        for q in QUANTITIES:
            t_err = max(difference(x[q], y[q], pr)[0] for x, y in zip(a["samples"], b["samples"]))
            rows.append((LABELS[p], q, _grid(p, levels), DT, t_err, diffs[p].cross[(q, "L2")][-1]))
        mine = rows[-3:]
        above = [q for q, row in zip(QUANTITIES, mine) if row[4] > row[5]]
        res.findings.append(
            f"{LABELS[p]}: dt = {DT:g} s against dt / 2 on FD's finest grid differs by "
            + ", ".join(f"{q} {row[4]:.1e} (finest FD-FE difference {row[5]:.1e})" for q, row in zip(QUANTITIES, mine))
            + " in L2. Every compared pair shares that time error (one dt at every level), so the differences "
            "measure space; " + (f"against the continuum, {' and '.join(above)} at this dt are limited by the time "
                                 "step, not the grid." if above else "the time error is below them all."))
    res.tables.append(Table("time_error", "The motions' time error: FD on its finest grid, dt against dt / 2 (L2, "
                            "largest over the sample times)",
                            ("problem", "quantity", "FD nodes", "dt (s)", "|q(dt) - q(dt/2)|",
                             "FD-FE difference at the finest common level"), rows))


def _work_precision(res, wraw) -> None:
    series = {}
    for c, r in wraw.items():
        series.setdefault((c.problem, c.method), []).append((c.nodes, r))
    rows, lines = [], {"plate": [], "cantilever": []}
    for (p, m), runs in series.items():
        cpu = np.array([r["cpu"] for _, r in runs])
        err = np.array([r["error"] for _, r in runs])
        for n, r in runs:
            rows.append((p, m.upper() if len(m) == 2 else m.capitalize(), n, r["unknowns"], r["cpu"], r["error"]))
        lines[p].append(Line(m.upper() if len(m) == 2 else m.capitalize(), cpu, err))
        res.data[f"work|{p}|{m}"] = {"nodes": [n for n, _ in runs], "error": err.tolist(),
                                     "unknowns": [r["unknowns"] for _, r in runs]}
    res.tables.append(Table("work_precision", "Work-precision: CPU time of whole solves against the relative error",
                            ("problem", "method", "nodes a side (along)", "unknowns", "CPU time (s)", "relative error"),
                            rows, volatile=True))
    work = (Panel("linear clamped plate, centre deflection", "CPU time (s)", "relative error (1)",
                  tuple(lines["plate"])),
            Panel("cantilever, P L^2/EI = 2, tip deflection", "CPU time (s)", "relative error (1)",
                  tuple(lines["cantilever"])))
    res.figures.append(Figure("work_precision", "Work-precision of whole solves: relative error against CPU time",
                              work, volatile=True))

    def get(p, m):
        runs = series[(p, m)]
        return (np.array([r["cpu"] for _, r in runs]), np.array([r["error"] for _, r in runs]),
                [n for n, _ in runs])

    # FD on the linear plate: second order, within 1 % at 65 x 65
    cpu, err, ns = get("plate", "fd")
    h = 1.0 / (np.array(ns) - 1.0)
    p_fd = fit_order(h, err)
    at65 = err[ns.index(65)] if 65 in ns else np.nan
    res.check("linear clamped plate: FD centre deflection (Timoshenko's 0.00126 q a^4 / D)",
              "order 2 (window [1.7, 2.3]), within 1 % at 65x65",
              f"p = {p_fd:.2f}; relative errors {_fmt(err)} on {', '.join(str(n) for n in ns)} nodes a side",
              bool(1.7 <= p_fd <= 2.3 and at65 <= 0.01))
    # FE against FD and Morley
    fe_cpu, fe_err, fe_n = get("plate", "fe")
    t_fe = cpu_to_reach(fe_cpu, fe_err, TARGET)
    t_fd = cpu_to_reach(cpu, err, TARGET)
    tail = slice(-3, None)  # FD's measured work-precision slope on its three finest solves, extrapolated
    slope = np.polyfit(np.log(cpu[tail]), np.log(err[tail]), 1)
    t_fd_extrapolated = float(np.exp((np.log(TARGET) - slope[1]) / slope[0])) if slope[0] < 0 else np.inf
    fe_reach = next((n for n, e in zip(fe_n, fe_err) if e <= TARGET), None)
    ratio = (t_fd if np.isfinite(t_fd) else t_fd_extrapolated) / t_fe if np.isfinite(t_fe) else np.nan
    res.check(f"linear clamped plate: FE reaches a relative error of {TARGET:g} at 10x less CPU than FD",
              "FE's CPU time to the target at most a tenth of FD's (or FD does not reach it)",
              (f"FE reaches it with {fe_reach}x{fe_reach} nodes; " if fe_reach else "FE does not reach it; ")
              + (f"FD's finest solve ({ns[-1]}x{ns[-1]}) stops at {err[-1]:.1e}" if not np.isfinite(t_fd)
                 else "FD reaches it too") + " (CPU times in run.md)",
              bool(np.isfinite(t_fe) and (not np.isfinite(t_fd) or ratio >= 10)))
    mo_cpu, mo_err, _ = get("plate", "morley")
    behind = [n for c, e, n in zip(fe_cpu, fe_err, fe_n)
              if np.isfinite(error_at(mo_cpu, mo_err, c)) and e >= error_at(mo_cpu, mo_err, c)]
    compared = [n for c, n in zip(fe_cpu, fe_n) if np.isfinite(error_at(mo_cpu, mo_err, c))]
    res.check("linear clamped plate: FE ahead of scikit-fem's Morley element at equal CPU time",
              "FE's error below Morley's (interpolated at the same CPU time) at every FE solve within Morley's range",
              "ahead at every compared solve" if compared and not behind
              else ("no FE solve inside Morley's CPU range" if not compared
                    else f"behind at {', '.join(map(str, behind))} nodes"), bool(compared) and not behind)
    ar_cpu, ar_err, ar_n = get("plate", "argyris")
    ar_reach = next((n for n, e in zip(ar_n, ar_err) if e <= TARGET), None)
    reach = {name: (f"with {n}x{n} nodes" if n else "not on these grids") for name, n in (("FE", fe_reach),
                                                                                         ("Argyris", ar_reach))}
    res.findings.append(f"Linear clamped plate: FE reaches {TARGET:g} {reach['FE']}, scikit-fem's Argyris quintic "
                        f"{reach['Argyris']} (deflection errors O(h^4) and O(h^6) for smooth solutions); Morley and FD "
                        "(O(h^2)) do not reach it on these grids.")
    t_ar = cpu_to_reach(ar_cpu, ar_err, TARGET)
    res.tables.append(Table("work_targets", f"CPU time to reach a relative error of {TARGET:g} on the linear clamped "
                            "plate (log-log interpolation between measured solves; FD extrapolated along its measured "
                            "slope)",
                            ("method", "CPU time (s)", "how"),
                            [("FE", t_fe, "interpolated"), ("Argyris", t_ar, "interpolated"),
                             ("FD", t_fd if np.isfinite(t_fd) else t_fd_extrapolated,
                              "interpolated" if np.isfinite(t_fd) else f"extrapolated (error ~ CPU^{slope[0]:.2f})"),
                             ("FD / FE", ratio, "ratio")], volatile=True))


def _figure(res, diffs) -> None:
    panels = {}
    for p, d in diffs.items():
        lines = []
        for q, style in zip(QUANTITIES, ("o-", "s-", "^-")):
            lines.append(Line(f"|FD - FE| of {q}", d.h[: len(d.cross[(q, 'L2')])], d.cross[(q, "L2")], style))
            v = d.self[("fd", q, "L2")]
            lines.append(Line(f"FD self-difference of {q}", d.h[: len(v)], v, style[0] + "--"))
        panels[p] = Panel(LABELS[p], "grid spacing h (m)", "L2 difference (r: m^2; G: m; B: 1)", tuple(lines), (2.0,))
    for name, which in (("cross_statics", STATICS), ("cross_motions", DYNAMICS)):
        drawn = tuple(panels[p] for p in which)
        res.figures.append(Figure(name, f"{'Statics' if name.endswith('statics') else 'Motions'}: FD-FE differences "
                                  "(solid) and FD self-differences (dashed), L2 over the sheet", drawn))


#: not in the default run of ``deformable validate`` (every study there in under two minutes): its quick levels
#: take about 4 minutes of CPU on two cores (FE motions on 33 x 33 nodes, FD on 65 x 65); run it by name
STUDY = Study("cross", "FD against FE on well-posed problems (variational model, xi > 0, held edges): r, G, B "
              "differences, self-convergence, Richardson/GCI, work-precision; the paper's force as a finding",
              Levels(quick=3, full=4, minimum=3, maximum=5), fill, in_default=False)
