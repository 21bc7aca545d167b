r"""Study ``fabrics``: the Peirce cantilever test (ASTM D1388) run on the named fabrics, FD and FE.

The test (Peirce 1930, J. Textile Inst. 21, T377; ASTM D1388, option A): a strip of the fabric, here 2.5 cm
wide, held horizontally at one end (a :class:`~deformable.Clamp` on that edge) and hanging under its own
weight; the overhang l at which the chord from the clamp's edge to the tip falls 41.5 degrees below the
horizontal gives the bending length c = l / 2, and D = w g c^3. Each run here finds that l by a bracketed root
(scipy's brentq) of chord angle(l) - 41.5 degrees, each angle a static equilibrium of the strip
(:func:`deformable.equilibrium`, the variational force model, the fabric's :meth:`~deformable.Fabric.material`,
standard gravity), and compares c = l / 2 with the bending length of the preset, derived from its source's
bending stiffness (:mod:`deformable.physics.fabric_presets`): within 5 % on each backend, along the warp and
along the weft (paper, whose source gives one value, along one).

Along the warp the strip's long axis is a1 (the warp, clamped on the left edge: curvature B_11, the weight
xi_11 = D_warp / 2); along the weft a2 (clamped on the bottom edge: B_22, xi_22 = D_weft / 2). The chord
runs between the midpoints of the clamped and the free edge.

The rule against the exact elastica. The strip, inextensible, is the heavy elastica: with theta(s) the angle
below the horizontal at arc length s from the clamp and lengths in units of c = (D / (w g))^(1/3),
theta'' = -(L - s) cos(theta), theta(0) = 0, theta'(L) = 0, the tip at (int cos, int sin) (solved by
scipy's collocation, :func:`elastica_chord_angle`). At L = l / c = 2 its chord falls 41.487 degrees:
ASTM's 41.5 degrees is the exact elastica's to 0.02 % in c (the root L of 41.5 degrees is 2.00035).
Peirce's closed form c = l (cos(theta / 2) / (8 tan theta))^(1/3) (:func:`peirce_formula`), an
approximation, gives c = 0.5093 l at 41.5 degrees, 1.9 % above the exact elastica's l / 2; it gives
l / 2 at 42.94 degrees. So this study applies ASTM's rule (the root), not the inverted formula; the tables
give both against the exact elastica.

Measured (quick level: FD 21 and FE 9 nodes along, 3 across): every preset's c within 1 % of its source's on
both backends; FD 0.3 % to 0.5 % short (its clamp's ghost row, O(h^2): 0.07 % to 0.2 % on 41 nodes), FE within
0.25 %, but for one: the sweater's weft, 0.7 % short on FE at 9 and at 17 nodes alike, is the strip's stretch,
not the grid: its T = 6.5 N/m (2 c22, the softest) lets the strip lengthen under its weight, and with T and S
a hundred times stiffer the same run is 0.06 % long. The whole quick level takes about 8.5 s of CPU time (one
core), the full one (two levels) about 18 s.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_bvp
from scipy.optimize import brentq

import deformable as dm
from deformable.errors import ConvergenceError
from deformable.physics.fabric import Fabric, G
from deformable.physics.fabric_presets import lookup
from validation.harness.backends import make_model
from validation.harness.study import Levels, Study, Table, nodes_at

__all__ = ["PEIRCE_ANGLE", "STUDY", "TOLERANCE", "WIDTH", "Case", "chord_angle", "directions", "elastica_chord_angle",
           "peirce", "peirce_formula", "run_case", "strip"]

#: ASTM D1388's angle of the chord below the horizontal (deg) at which c = l / 2
PEIRCE_ANGLE = 41.5
#: the strip's width (m; ASTM D1388 cuts 25 mm)
WIDTH = 0.025
WIDTH_NODES = 3
#: nodes along the strip at level 0
COARSEST = {"fd": 21, "fe": 9}
#: the check: |c measured / c from the source - 1| at most this
TOLERANCE = 0.05
#: the direction -> (the clamped edge, the parameter axis the strip runs along)
DIRECTIONS = {"warp": ("left", 0), "weft": ("bottom", 1)}
#: the root's tolerance on l, relative to the source's c
XTOL = 1e-5
# SuperLU, as the variational study: the committed digits do not depend on the fast extra
NEWTON = {"solver": "superlu"}


def directions(name: str) -> tuple[str, ...]:
    """The directions the source of preset ``name`` gives a bending stiffness for: warp and weft, or one."""
    return ("warp",) if lookup(name).estimate else ("warp", "weft")


def strip(fabric: Fabric, overhang: float, direction: str, nodes: int, width_nodes: int = WIDTH_NODES) -> dm.Scene:
    """The cantilever: a strip ``overhang`` (m) long and :data:`WIDTH` wide along ``direction`` ("warp": a1,
    "weft": a2), clamped flat at its root, under standard gravity; ``nodes`` along it, ``width_nodes`` across."""
    edge, axis = DIRECTIONS[direction]
    size, grid = [WIDTH, WIDTH], [width_nodes, width_nodes]
    size[axis], grid[axis] = overhang, nodes
    return dm.Scene(dm.Sheet(size=tuple(size), nodes=tuple(grid)), fabric.material(), force_model="variational",
                    forces=[dm.Gravity(G)], constraints=[dm.Clamp(edge)], name=f"Peirce cantilever ({direction})")


def chord_angle(model, X, direction: str) -> float:
    """The angle (deg) below the horizontal of the chord from the clamped edge's midpoint to the free edge's."""
    R = model.grid(X)
    if DIRECTIONS[direction][1] == 1:
        R = np.swapaxes(R, 0, 1)
    d = R[-1].mean(axis=0) - R[0].mean(axis=0)
    return math.degrees(math.atan2(-d[2], math.hypot(d[0], d[1])))


def hanging(fabric: Fabric, overhang: float, direction: str, backend: str, nodes: int) -> tuple[float, int]:
    """The chord angle (deg) of the strip at equilibrium, and the Newton iterations it took. From the flat strip
    in one load step; in eight if Newton fails there (large deflection)."""
    model = make_model(strip(fabric, overhang, direction, nodes), backend)
    try:
        X, history = dm.equilibrium(model, model.initial_state(), newton=NEWTON, check_stability=False)
    except ConvergenceError:
        X, history = dm.equilibrium(model, model.initial_state(), newton=NEWTON, load_steps=8,
                                    check_stability=False)
    return chord_angle(model, X, direction), len(history) - 1


def peirce(fabric: Fabric, direction: str, backend: str, nodes: int, grow: float = 1.25) -> dict:
    """ASTM D1388 on the model: the overhang l (m) whose chord falls :data:`PEIRCE_ANGLE` degrees, by brentq on a
    bracket grown from l = 2 c (c the fabric's bending length) by factors ``grow``; c = l / 2.

    Returns a dict: ``overhang`` l and ``c`` (m), ``angle`` the chord's at l (deg), ``solves`` the equilibria
    solved, ``iterations`` their Newton iterations in all.
    """
    c0 = fabric.bending_length[DIRECTIONS[direction][1]]
    seen, its = {}, []

    def excess(overhang):
        if overhang not in seen:
            angle, n = hanging(fabric, overhang, direction, backend, nodes)
            seen[overhang] = angle - PEIRCE_ANGLE
            its.append(n)
        return seen[overhang]

    lo = hi = 2 * c0
    for _ in range(12):  # the chord's angle rises with the overhang
        if excess(lo) > 0:
            hi, lo = lo, lo / grow
        elif excess(hi) < 0:
            lo, hi = hi, hi * grow
        else:
            break
    else:
        raise ConvergenceError(f"Peirce test: the chord does not cross {PEIRCE_ANGLE} degrees for overhangs within "
                               f"a factor {grow**12:.3g} of twice the bending length {c0:.4g} m")
    overhang = brentq(excess, lo, hi, xtol=XTOL * c0, rtol=1e-10)
    return {"overhang": overhang, "c": overhang / 2, "angle": PEIRCE_ANGLE + excess(overhang), "solves": len(seen),
            "iterations": int(sum(its))}


def elastica_chord_angle(ratio: float) -> float:
    """The chord's angle (deg) below the horizontal of the inextensible heavy elastica of overhang ``ratio`` = l / c
    (module docstring), by collocation (scipy's solve_bvp, tolerance 1e-10)."""
    L = float(ratio)

    def rhs(s, y):  # y = (theta, theta', x, z)
        return np.vstack([y[1], -(L - s) * np.cos(y[0]), np.cos(y[0]), np.sin(y[0])])

    def bc(ya, yb):
        return np.array([ya[0], yb[1], ya[2], ya[3]])

    s = np.linspace(0.0, L, 201)
    guess = np.zeros((4, s.size))
    guess[2] = s
    sol = solve_bvp(rhs, bc, s, guess, tol=1e-10, max_nodes=200000)
    if not sol.success:
        raise ConvergenceError(f"heavy elastica at l / c = {ratio}: {sol.message}")
    return math.degrees(math.atan2(sol.y[3, -1], sol.y[2, -1]))


def peirce_formula(angle: float) -> float:
    """Peirce's closed form c / l = (cos(theta / 2) / (8 tan theta))^(1/3) at the chord angle theta (deg)."""
    t = math.radians(angle)
    return (math.cos(t / 2) / (8 * math.tan(t))) ** (1 / 3)


@dataclass(frozen=True)
class Case:
    preset: str
    direction: str
    backend: str
    nodes: int


def run_case(case: Case) -> dict:
    t0 = time.process_time()
    fabric = Fabric.preset(case.preset)
    out = peirce(fabric, case.direction, case.backend, case.nodes)
    out["source_c"] = fabric.bending_length[DIRECTIONS[case.direction][1]]
    out["cpu"] = time.process_time() - t0
    return out


def fill(res, levels: int, runner) -> None:
    """Run the Peirce test on every preset and direction, FD (21, 41, ... nodes along) and FE (9, 17, ...)."""
    grids = {b: [nodes_at(k, COARSEST[b]) for k in range(levels)] for b in ("fd", "fe")}
    cases = [Case(p, d, b, n) for p in Fabric.presets() for d in directions(p) for b in ("fd", "fe")
             for n in grids[b]]
    raw = runner.map(run_case, cases, desc="fabrics")
    res.config.update({
        "presets": list(Fabric.presets()), "width": WIDTH, "width_nodes": WIDTH_NODES, "nodes_along": grids,
        "angle_deg": PEIRCE_ANGLE, "g": G, "tolerance": TOLERANCE, "root_xtol_over_c": XTOL,
        "force_model": "variational", "start": "flat strip, one load step (eight if Newton fails)",
        "solver": NEWTON["solver"]})
    rows, timing, ok = [], [], {"fd": {}, "fe": {}}
    for c, r in zip(cases, raw):
        err = r["c"] / r["source_c"] - 1
        good = abs(err) <= TOLERANCE
        grid = f"{c.nodes} x {WIDTH_NODES}" if c.direction == "warp" else f"{WIDTH_NODES} x {c.nodes}"
        rows.append((c.preset, c.backend.upper(), c.direction, grid, 100 * r["source_c"], 100 * r["c"], err,
                     "pass" if good else "fail"))
        timing.append((c.preset, c.backend.upper(), c.direction, grid, r["solves"], r["iterations"], r["cpu"]))
        ok[c.backend][f"{c.preset} {c.direction} {grid}"] = good
        res.data.setdefault(c.backend, []).append({"preset": c.preset, "direction": c.direction, "nodes": c.nodes,
                                                   "source_c": r["source_c"], "c": r["c"],
                                                   "overhang": r["overhang"], "relative_error": err})
    for b in ("fd", "fe"):
        res.check_all(f"{b.upper()}: Peirce's bending length of every preset within {TOLERANCE:.0%} of its source's",
                      f"|c measured / c source - 1| <= {TOLERANCE:g} for every preset and direction", ok[b])
    res.tables.append(Table("peirce", "The cantilever test (ASTM D1388) on the presets: c = l / 2 at the overhang l "
                            f"whose chord falls {PEIRCE_ANGLE} degrees, against the source's c = (D / (w g))^(1/3)",
                            ("preset", "backend", "direction", "grid", "c from source (cm)", "c measured (cm)",
                             "relative error", "verdict"), rows,
                            note="grid: nodes along a1 x along a2; warp along a1, weft along a2."))
    res.tables.append(Table("timing", "Equilibria solved by each root, their Newton iterations, CPU time",
                            ("preset", "backend", "direction", "grid", "equilibria", "Newton iterations",
                             "CPU time (s)"), timing, volatile=True))
    res.run_findings.append(f"The study's cases took {sum(t[-1] for t in timing):.1f} s of CPU time in all.")
    _elastica(res)


def _elastica(res) -> None:
    """The rule against the exact elastica: a table over l / c, the root of 41.5 degrees, and a check."""
    ratios = (1.0, 1.5, 1.8, 2.0, 2.2, 2.5, 3.0)
    rows = []
    for L in ratios:
        a = elastica_chord_angle(L)
        rows.append((L, a, 1 / L, peirce_formula(a), peirce_formula(a) * L - 1))
    root = brentq(lambda L: elastica_chord_angle(L) - PEIRCE_ANGLE, 1.8, 2.2, xtol=1e-10)
    at_two = elastica_chord_angle(2.0)
    formula = peirce_formula(PEIRCE_ANGLE)
    res.tables.append(Table("elastica", "The inextensible heavy elastica: chord angle against the overhang in units "
                            "of c, and Peirce's closed form at that angle",
                            ("l / c", "chord angle (deg)", "exact c / l", "Peirce's formula c / l",
                             "formula's relative error"), rows))
    res.data["elastica"] = {"chord_angle_at_2c": at_two, "root_of_41_5_over_c": root,
                            "peirce_formula_c_over_l_at_41_5": formula}
    res.findings.append(
        f"The exact heavy elastica's chord falls {at_two:.3f} degrees at l = 2c; ASTM's {PEIRCE_ANGLE} degrees is "
        f"reached at l = {root:.5f} c, so the rule c = l / 2 is {root / 2 - 1:+.2e} off the exact c. Peirce's "
        f"closed form at {PEIRCE_ANGLE} degrees gives c = {formula:.4f} l, {2 * formula - 1:+.1%} from the exact "
        "elastica: the study applies the rule (the root), not the formula inverted.")
    res.check("ASTM's rule is the exact elastica's", f"the chord at l = 2c within 0.1 degree of {PEIRCE_ANGLE}",
              f"{at_two:.4f} degrees", abs(at_two - PEIRCE_ANGLE) <= 0.1)


STUDY = Study("fabrics", "the Peirce cantilever test (ASTM D1388) on the named fabrics, FD and FE: the bending length "
              "measured against the one derived from the source", Levels(quick=1, full=2, minimum=1, maximum=3), fill)
