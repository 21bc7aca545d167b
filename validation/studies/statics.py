r"""Study ``statics``: Navier's centre deflection of the frozen-beta plate under a uniform load.

The frozen model with alpha = 0 and constant beta (section 3.2) on
[0, L1] x [0, L2], all edges pinned (simply supported: w = 0 and, naturally,
w_nn = 0), under a uniform transverse load q (N/m^2):

    beta (w_1111 + w_2222) = q.

(No w_1122 term: beta_12 = 0, the paper's choice.) Navier's double sine
series, q = sum_{j,k odd} 16 q / (pi^2 j k) sin(j pi a1/L1) sin(k pi a2/L2),
gives at the centre

    w_c = sum_{j,k odd} 16 q sin(j pi/2) sin(k pi/2) / (pi^6 beta j k (j^4/L1^4 + k^4/L2^4)),

summed here to j, k < 4000 (tail below 1e-13 relative).

Theory. FD: the sine modes are exact discrete eigenvectors with eigenvalues
(k pi/L)^4 (1 + O(h^2)) and the pointwise load's discrete sine coefficients
differ from the continuous ones by O(h^2): second order. FE (bicubic
Hermite, k = 3, fourth-order operator m = 2): the L2 error of w is
O(h^{k+1}) = O(h^4), and point values converge at that order.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as spla

import deformable as dm
from validation.harness.backends import make_model
from validation.harness.orders import fit_order, pairwise_orders
from validation.harness.study import Figure, Levels, Line, Panel, Study, Table, nodes_at, order_check

L1, L2, BETA, Q = 1.0, 0.8, 0.02, 1e-3
COARSEST = {"fd": 9, "fe": 5}
THEORY = {"fd": 2, "fe": 4}


def navier_centre(beta: float = BETA, q: float = Q, L1: float = L1, L2: float = L2, terms: int = 4000) -> float:
    """Centre deflection (m) of beta (w_1111 + w_2222) = q, simply supported, by Navier's series."""
    j = np.arange(1, terms, 2, dtype=float)
    sj = np.where((j // 2) % 2 == 0, 1.0, -1.0)  # sin(j pi / 2) for odd j
    J, K = np.meshgrid(j, j, indexing="ij")
    terms_ = np.outer(sj, sj) / (J * K * (J**4 / L1**4 + K**4 / L2**4))
    return float(16 * q / (np.pi**6 * beta) * terms_.sum())


def scene(nodes: int) -> dm.Scene:
    sheet = dm.Sheet(size=(L1, L2), nodes=(nodes, nodes))
    return dm.Scene(sheet, dm.Material(mu=1.0, alpha=0.0, beta=BETA), force_model="frozen",
                    forces=[dm.BodyForce(f=(0.0, 0.0, Q))], constraints=[dm.Pin(["left", "right", "bottom", "top"])])


@dataclass(frozen=True)
class Case:
    backend: str
    nodes: int


def solve(backend: str, nodes: int):
    """The static transverse deflection: (model, X) with X (ndof, 3), z column solved."""
    sc = scene(nodes)
    model = make_model(sc, backend)
    X = model.initial_state()
    free = np.setdiff1d(np.arange(model.ndof), model.fixed_dofs()[2])
    K = model.stiffness(X).tocsc()[free][:, free]
    F = model.load(X, 0.0)[free, 2]
    X[free, 2] = spla.spsolve(K, F)
    return model, X


def run_case(case: Case) -> dict:
    model, X = solve(case.backend, case.nodes)
    w = float(model.sample(X, np.array([[L1 / 2, L2 / 2]])).r[0, 2])
    return {"h": model.spacing[0], "w": w}


def fill(res, levels: int, runner) -> None:
    """Run the statics study over ``levels`` levels (FD 9, 17, ... nodes a side; FE 5, 9, ...)."""
    cases = [Case(b, nodes_at(k, COARSEST[b])) for b in ("fd", "fe") for k in range(levels)]
    raw = runner.map(run_case, cases, desc="statics")
    exact = navier_centre()
    res.config.update({
        "size": [L1, L2], "beta": BETA, "q": Q, "constraints": "all four edges pinned",
        "nodes": {b: [nodes_at(k, COARSEST[b]) for k in range(levels)] for b in ("fd", "fe")},
        "navier_centre_deflection": exact, "order_window": "theory -0.3/+0.3; finest relative error <= 1e-2"})
    rows, lines = [], []
    for b in ("fd", "fe"):
        these = [r for c, r in zip(cases, raw) if c.backend == b]
        h = np.array([r["h"] for r in these])
        w = np.array([r["w"] for r in these])
        err = np.abs(w - exact) / abs(exact)
        p = fit_order(h, err)
        order_check(res, f"{b.upper()} centre deflection, relative error", p, THEORY[b], finest=err[-1], bound=1e-2)
        for hh, ww, ee, pp in zip(h, w, err, [np.nan, *pairwise_orders(h, err)]):
            rows.append((b.upper(), round(L1 / hh) + 1, hh, ww, exact, ee, pp))
        lines.append(Line(f"{b.upper()} (p = {p:.2f})", h, err))
        res.data[b] = {"h": h.tolist(), "w": w.tolist(), "relative_error": err.tolist(), "order": p}
    res.tables.append(Table("deflection", "Centre deflection against Navier's series",
                            ("backend", "nodes a side", "h", "w_c (m)", "Navier w_c (m)", "relative error",
                             "pairwise order"), rows))
    res.figures.append(Figure("deflection", "Relative error of the centre deflection against Navier's series",
                              (Panel("Navier plate, centre deflection", "grid spacing / element size h "
                                     "(parameter units)", "relative error of w_c", tuple(lines), (2.0, 4.0)),)))


STUDY = Study('statics', 'Navier centre deflection of the frozen-beta plate, simply supported, uniform load',
              Levels(quick=4, full=6, minimum=3, maximum=7), fill)
