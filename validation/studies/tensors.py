r"""Study ``tensors``: errors of G_ij (eq. 4) and B_ij (eq. 8) of both backends on analytic surfaces.

Each backend discretises an analytic surface (FD: node values; FE: nodal
Hermite interpolation of r, r_1, r_2, r_12) and its G and B are compared with
the closed forms, component by component, in the max norm and the RMS norm
(root mean square over the point set, a discrete L2 norm normalised by the
number of points), where:

FD (eq. 18-19): G_ij = D_i+ r . D_j+ r, B_ij = n . D_ij r
  - at the nodes, interior (1 <= m <= M-2, 1 <= n <= N-2) and boundary apart;
    theory: every component first order (forward differences are centred at
    half-nodes; the normal uses forward differences; the boundary rows are
    one-sided or copied from the neighbour, also O(h));
  - at the point where each stencil is centred: G11 at (m + 1/2, n),
    G22 at (m, n + 1/2); theory: second order.
FE (bicubic Hermite, nodal interpolation; Q3 is complete to degree 3):
  - at the 4 x 4 Gauss points: G third order (r_i error O(h^3)); B11, B22
    second order (r_11, r_22 error O(h^2)); B12 third order: the interpolant
    is I1 I2 r and d12 (r - I1 I2 r) = d1 (1 - I1) d2 r + d1 I1 d2 (1 - I2) r
    is O(h^3) (a first derivative of a 1-D interpolation error);
  - at the 2 x 2 Gauss points: B third order (the second derivative of
    (s - s0)^2 (s - s1)^2 vanishes at the two Gauss points of each side);
  - at the nodes: r_i and r_12 are degrees of freedom, so G and B12 are exact
    to round-off; B11, B22 second order.

Orders are checked on the generic surfaces (saddle, monge, skew). The
plane, the cylinder by arc length, the latitude/longitude sphere, the torus
and the helicoid have a symmetry (a shift of one parameter is a rigid
motion) that makes errors vanish or superconverge: they are reported as
findings, with the reason (:data:`SYMMETRIC`). So are components that vanish to round-off on a
generic surface, and the structural exceptions listed in :data:`SPECIAL`,
each with its reason.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import deformable as dm
from validation.harness import surfaces as sf
from validation.harness.backends import make_model
from validation.harness.orders import fit_order
from validation.harness.study import Figure, Levels, Line, Panel, Study, Table, nodes_at, order_check

COMPONENTS = {"G11": ("G", 0, 0), "G12": ("G", 0, 1), "G22": ("G", 1, 1),
              "B11": ("B", 0, 0), "B12": ("B", 0, 1), "B22": ("B", 1, 1)}
#: surfaces whose symmetry makes errors vanish or superconverge: findings only
SYMMETRIC = {
    "plane": "linear in both parameters: every difference and every interpolant is exact",
    "cylinder": "arc-length parametrisation, invariant under shifts in a1 and linear in a2: the half-node shift of "
                "the forward differences costs nothing, so FD errors are O(h^2) (chord against arc) or vanish",
    "sphere": "a surface of revolution in the longitude a1: shifts in a1 are rigid rotations, so the components "
              "that depend only on the latitude lose their first-order error",
    "torus": "a surface of revolution in a1 (like the sphere): every quantity is invariant under shifts in a1, so "
             "the half-node shifts along a1 cost nothing and those components superconverge",
    "helicoid": "invariant under the screw motion a2 -> a2 + c and linear in a1: D1+ r and D11 r are exact and "
                "shifts along a2 are rigid motions, so errors vanish or superconverge",
}
#: (backend, location) -> (coarsest nodes a side, {component: theoretical order, None = exact})
THEORY = {
    ("fd", "nodes, interior"): {c: 1 for c in COMPONENTS},
    ("fd", "nodes, boundary"): {c: 1 for c in COMPONENTS},
    ("fd", "stencil centres"): {"G11": 2, "G22": 2},
    ("fe", "Gauss 4x4"): {"G11": 3, "G12": 3, "G22": 3, "B11": 2, "B12": 3, "B22": 2},
    ("fe", "Gauss 2x2"): {"G11": 3, "G12": 3, "G22": 3, "B11": 3, "B12": 3, "B22": 3},
    ("fe", "nodes"): {"G11": None, "G12": None, "G22": None, "B11": 2, "B12": None, "B22": 2},
}
COARSEST = {"fd": 9, "fe": 9}
#: structural exceptions on generic surfaces: (surface, backend, component or "*") -> reason
SPECIAL = {
    ("saddle", "fe", "*"): "the saddle is a quadratic polynomial, which bicubic Hermite interpolation reproduces "
                           "exactly: all FE errors are round-off",
}

#: why an error vanishes on a generic surface: (surface, backend) -> reason
VANISH = {
    ("saddle", "fd"): "the saddle is quadratic, so a forward difference is the exact derivative at the half-node "
                      "and G11, G22 are exact at the stencil centres",
}


@dataclass(frozen=True)
class Case:
    """One discretisation: backend ("fd" | "fe"), surface name, nodes a side."""

    backend: str
    surface: str
    nodes: int


def _errors(diff: np.ndarray) -> tuple[float, float]:
    """(max, RMS) of |diff| over all its entries."""
    a = np.abs(diff)
    return float(a.max()), float(np.sqrt(np.mean(a**2)))


def _component_errors(G, B, Gx, Bx, mask=None) -> dict[str, tuple[float, float]]:
    """Per component (max, RMS) errors; fields (2, 2, *pts), mask over pts."""
    out = {}
    for name, (T, i, j) in COMPONENTS.items():
        d = (G if T == "G" else B)[i, j] - (Gx if T == "G" else Bx)[i, j]
        out[name] = _errors(d if mask is None else d[mask])
    return out


def run_case(case: Case) -> dict:
    """Errors of one discretisation: {location: {component: (max, rms)}} and the spacing h."""
    s = sf.get(case.surface)
    sheet = dm.Sheet(size=s.size, nodes=(case.nodes, case.nodes), rest=s)
    scene = dm.Scene(sheet, dm.Material(eta=1.0, xi=1.0))
    out = {}
    model = make_model(scene, case.backend)
    X = model.initial_state()
    G, B = model.tensors(X)
    a1, a2 = model.points
    h1, h2 = model.spacing
    if case.backend == "fd":
        Gx, Bx = s.G(a1, a2), s.B(a1, a2)
        inner = np.zeros(a1.shape, bool)
        inner[1:-1, 1:-1] = True
        out["nodes, interior"] = _component_errors(G, B, Gx, Bx, inner)
        out["nodes, boundary"] = _component_errors(G, B, Gx, Bx, ~inner)
        out["stencil centres"] = {
            "G11": _errors((G[0, 0] - s.G(a1 + h1 / 2, a2)[0, 0])[:-1, :]),
            "G22": _errors((G[1, 1] - s.G(a1, a2 + h2 / 2)[1, 1])[:, :-1]),
        }
    else:
        out["Gauss 4x4"] = _component_errors(G, B, s.G(a1, a2), s.B(a1, a2))
        g = 0.5 + np.array([-1, 1]) / (2 * np.sqrt(3))
        M, N = sheet.nodes
        i, j = np.meshgrid(np.arange(M - 1), np.arange(N - 1), indexing="ij")
        pts = np.stack([((i[..., None, None] + g[:, None]) * h1 + 0 * g[None, :]).ravel(),
                        ((j[..., None, None] + g[None, :]) * h2 + 0 * g[:, None]).ravel()], axis=1)
        out["Gauss 2x2"] = _sampled(model, X, s, pts)
        n1, n2 = sheet.coordinates()
        out["nodes"] = _sampled(model, X, s, np.stack([n1.ravel(), n2.ravel()], axis=1))
    return {"h": h1, "errors": out}


def _sampled(model, X, s, pts) -> dict[str, tuple[float, float]]:
    smp = model.sample(X, pts)
    G, B = np.moveaxis(smp.G, 0, -1), np.moveaxis(smp.B, 0, -1)
    return _component_errors(G, B, s.G(pts[:, 0], pts[:, 1]), s.B(pts[:, 0], pts[:, 1]))


def _roundoff(errors) -> bool:
    """Errors at round-off level at every level (no order to fit)."""
    return bool(np.max(errors) < 1e-11)


def fill(res, levels: int, runner, surfaces=None) -> None:
    """The tensors study over ``levels`` refinement levels (9, 17, 33, ... nodes a side, both backends).

    ``surfaces``: surface names (default: every surface of :data:`validation.harness.surfaces.SURFACES`).
    """
    names = list(surfaces or sf.SURFACES)
    for n in names:
        sf.get(n)
    cases = [Case(b, n, nodes_at(k, COARSEST[b])) for b in ("fd", "fe") for n in names for k in range(levels)]
    raw = runner.map(run_case, cases, desc="tensors")
    res.config.update({"surfaces": names,
                       "nodes": {b: [nodes_at(k, COARSEST[b]) for k in range(levels)] for b in ("fd", "fe")},
                       "order_window": "theory -0.3/+0.3 on the max-norm order; finest max error <= 20 h^p",
                       "symmetric_surfaces": list(SYMMETRIC)})
    rows, series, data, vanish = [], {}, {}, {}
    for b in ("fd", "fe"):
        for name in names:
            these = [r for c, r in zip(cases, raw) if c.backend == b and c.surface == name]
            h = np.array([r["h"] for r in these])
            for (bb, loc), theory in THEORY.items():
                if bb != b:
                    continue
                for comp, p_th in theory.items():
                    emax = np.array([r["errors"][loc][comp][0] for r in these])
                    erms = np.array([r["errors"][loc][comp][1] for r in these])
                    key = f"{b}|{name}|{loc}|{comp}"
                    data[key] = {"h": h.tolist(), "max": emax.tolist(), "rms": erms.tolist()}
                    exact = _roundoff(emax)
                    p_max = np.nan if exact else fit_order(h, emax)
                    p_rms = np.nan if exact or _roundoff(erms) else fit_order(h, erms)
                    special = SPECIAL.get((name, b, comp)) or SPECIAL.get((name, b, "*"))
                    verdict = "checked"
                    label = f"{b.upper()} {name} {comp} at {loc}"
                    if p_th is None:
                        verdict = "check: exact"
                        res.check(label, "exact to round-off (degree of freedom)", f"max error {emax.max():.1e}",
                                  exact)
                    elif name in SYMMETRIC:
                        verdict = "finding (symmetric surface)"
                    elif exact:
                        verdict = "finding (exact to round-off)"
                        vanish.setdefault((b, name), []).append(f"{comp} ({loc})")
                    elif special:
                        verdict = "finding (structure)"
                        res.findings.append(f"{label}: observed order {p_max:.2f} (generic theory {p_th}); {special}.")
                    else:
                        order_check(res, label, p_max, p_th, finest=emax[-1], bound=20 * h[-1] ** p_th)
                    rows.append((b.upper(), name, loc, comp, "exact" if p_th is None else p_th,
                                 p_max, p_rms, emax[-1], erms[-1], verdict))
                    series[(b, name, loc, comp)] = (h, emax)
    for (b, name), where in vanish.items():
        special = SPECIAL.get((name, b, "*")) or VANISH.get((name, b))
        res.findings.append(f"{b.upper()} {name}: the error vanishes to round-off at every level for "
                            f"{', '.join(where)}" + (f"; {special}." if special else
                                                     " (the component is zero and the discretisation keeps it so)."))
    for name, why in SYMMETRIC.items():
        sub = [r for r in rows if r[1] == name and r[-1].startswith("finding (symmetric")]
        if not sub:
            continue
        exact = [f"{r[0]} {r[3]} ({r[2]})" for r in sub if not np.isfinite(r[5])]
        above = [f"{r[0]} {r[3]} ({r[2]}) p = {r[5]:.2f}" for r in sub if np.isfinite(r[5]) and r[5] > r[4] + 0.3]
        at = [r for r in sub if np.isfinite(r[5]) and r[5] <= r[4] + 0.3]
        res.findings.append(f"{name} (not checked; {why}): exact to round-off: {', '.join(exact) or 'none'}; "
                            f"above the generic order: {', '.join(above) or 'none'}; "
                            f"{len(at)} other components at their generic order.")
    res.tables.append(Table(
        "orders", "Observed orders (least-squares slope over all levels) against theory",
        ("backend", "surface", "location", "component", "theory", "p (max)", "p (RMS)", "finest max error",
         "finest RMS error", "verdict"), rows,
        note="p is blank where the error is round-off at every level. 'checked' rows are PASS/FAIL checks below."))
    res.data = data
    res.figures = _figures(series, names)


def _figures(series, names) -> list[Figure]:
    figs = []
    surf = "monge" if "monge" in names else names[0]
    comps = list(COMPONENTS)

    def lines(b, loc, which, fmt="{c}"):
        out = []
        for c in which:
            h, e = series.get((b, surf, loc, c), (None, None))
            if h is not None and not _roundoff(e):
                out.append(Line(fmt.format(c=c), h, e))
        return out

    figs.append(Figure("fd_nodes", f"FD errors at nodes on the {surf} surface (max norm); interior and boundary",
                       (Panel(f"FD interior nodes, {surf}", "grid spacing h (parameter units)",
                              "max error (G: dimensionless, B: 1/length)", tuple(lines("fd", "nodes, interior", comps)),
                              (1.0,)),
                        Panel(f"FD boundary nodes, {surf}", "grid spacing h (parameter units)",
                              "max error (G: dimensionless, B: 1/length)", tuple(lines("fd", "nodes, boundary", comps)),
                              (1.0,)))))
    figs.append(Figure("fd_centres", f"FD metric at nodes against the stencil centres on the {surf} surface",
                       (Panel(f"FD G11, G22, {surf}", "grid spacing h (parameter units)", "max error (dimensionless)",
                              tuple(lines("fd", "nodes, interior", ["G11", "G22"], "{c} at nodes")
                                    + lines("fd", "stencil centres", ["G11", "G22"], "{c} at stencil centre")),
                              (1.0, 2.0)),)))
    figs.append(Figure("fe", f"FE errors on the {surf} surface (max norm) at Gauss points and nodes",
                       (Panel(f"FE 4x4 Gauss points, {surf}", "element size h (parameter units)",
                              "max error (G: dimensionless, B: 1/length)", tuple(lines("fe", "Gauss 4x4", comps)),
                              (2.0, 3.0)),
                        Panel(f"FE 2x2 Gauss points and nodes, {surf}", "element size h (parameter units)",
                              "max error (G: dimensionless, B: 1/length)",
                              tuple(lines("fe", "Gauss 2x2", ["G11", "B11", "B12", "B22"], "{c} 2x2 Gauss")
                                    + lines("fe", "nodes", ["B11", "B22"], "{c} nodes")), (2.0, 3.0)))))
    generic = [n for n in names if n not in SYMMETRIC]
    fd_lines = [Line(n, *series[("fd", n, "nodes, interior", "B11")]) for n in generic
                if not _roundoff(series[("fd", n, "nodes, interior", "B11")][1])]
    fe_lines = [Line(n, *series[("fe", n, "Gauss 4x4", "B22")]) for n in generic
                if not _roundoff(series[("fe", n, "Gauss 4x4", "B22")][1])]
    figs.append(Figure("surfaces", "B errors on every generic surface: FD B11 at interior nodes, FE B22 at 4x4 Gauss "
                                   "points (components chosen non-zero on all of them)",
                       (Panel("FD B11, interior nodes", "grid spacing h (parameter units)", "max error (1/length)",
                              tuple(fd_lines), (1.0,)),
                        Panel("FE B22, 4x4 Gauss points", "element size h (parameter units)", "max error (1/length)",
                              tuple(fe_lines), (2.0,)))))
    return figs


# at least 4 levels: over 3 the slope of the skew surface's FE G22 at 4x4 Gauss points is 3.34, outside the
# window [2.7, 3.3] (the coarsest level, 9 nodes a side, is not yet in the asymptotic range)
STUDY = Study("tensors", "G_ij and B_ij errors of FD and FE on analytic surfaces; observed orders against theory",
              Levels(quick=4, full=6, minimum=4, maximum=8), fill, surfaces=True)
