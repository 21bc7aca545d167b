r"""Study ``contact``: no penetration, friction's two regimes, the energy of an impact, the drape coefficient,
self-contact.

Six experiments on both backends (:mod:`deformable.contact`, the IPC barrier
of Li et al. 2020 with lagged smoothed Coulomb friction, under implicit Euler):

1. Clearance. The contact scenes ``floor``, ``sphere`` and ``drape`` on a
   small grid, and a fast drop (a sheet 1 cm above the floor moving down at
   5 m/s): :func:`deformable.clearance`, the smallest signed distance of every
   contact point to every obstacle, at every step. Expectation: > 0 always
   (the line search clips every Newton step to a safe fraction of the exact
   largest safe step, so no iterate can cross).
2. Inclined plane. A 20 cm sheet resting on a frictional plane (mu_f = 0.3)
   under gravity tilted by a, 1 degree either side of the friction angle
   atan(mu_f) and at 30 degrees; the plane analytic, and again as a triangle
   mesh of two triangles (its friction the IPC Toolkit's, triangle against
   triangle: :mod:`deformable.contact.meshpotential`), once split away from
   the sheet and once along a diagonal under it. Theory (Coulomb): below, it sticks (its
   speed over the second half of the run stays below the slip speed eps_v,
   the smoothing's creep); above, it slides with acceleration
   g (sin a - mu_f cos a). Expectation: the acceleration fitted over the
   second half of the run within 2% of that.
3. Energy of an impact. A sheet dropped 5 cm onto the frictionless floor
   without damping (gamma = 0), Newmark's average acceleration (energy
   conserving for a linear system) against implicit Euler (dissipative).
   Total energy E = elastic (13) + kinetic + barrier - (weight . x).
   Reported: the largest rise and fall of E over the run against the energy
   of the fall, m g h (the model's own weight times h); checked: implicit
   Euler's E never rises (it dissipates), Newmark's error falls with dt.
4. Drape. The Cusick drape test (:mod:`validation.harness.drape`) under refinement
   (FD 9, 17, 33 nodes a side; FE 4, 8, 16 elements a side at quick levels;
   four contact points per cell side, the scene's), each run to t = 1.5 s.
   Expectation: the changes between levels fall (reported with the observed
   order log2 of the ratio of successive changes), and FD and FE agree
   within 2% at the finest level.
5. Self-contact: no self-intersection at any step, the smallest
   self-distance, the energy of a frictionless self-impact and the cost
   (:mod:`validation.studies.selfcontact`).
6. Mesh obstacles: the ball's triangulation against the analytic ball, and
   a box moving through a hanging sheet at 5 m/s
   (:mod:`validation.studies.meshcontact`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import deformable as dm
from deformable import scenes
from deformable.geometry.surfaces import Plane
from deformable.solve.potential import flat
from validation.harness.backends import make_model
from validation.harness.orders import pairwise_orders
from validation.harness.study import Levels, Study, Table, nodes_at
from validation.studies.meshcontact import fill_mesh
from validation.studies.selfcontact import fill_self, one_thread

#: the backends every experiment runs on
BACKENDS = ("fd", "fe")
#: the sheet of the inclined-plane and drop experiments: a light cloth, no air damping
CLOTH = dict(mu=0.2, gamma=0.0, eta=np.full((2, 2), 20.0), xi=np.full((2, 2), 1e-5))
#: the coarsest grids (nodes a side)
COARSEST = {"fd": 9, "fe": 5}
#: the friction coefficient and the angles (degrees from the friction angle, and one far above) of the incline
FRICTION = 0.3
INCLINES = (-1.0, 1.0, 13.3)
#: clearance runs: (scene, t_end s, fields)
CLEARANCE_SCENES = (("floor", 0.25, dict(height=0.05)), ("sphere", 0.25, {}), ("drape", 0.25, {}))
#: Newmark's steps in the energy experiment (s)
NEWMARK_DT = (1e-3, 5e-4, 2.5e-4)
#: how long the drape runs (s)
DRAPE_T_END = 1.5


def _run(model, dt, t_end, X0=None, V0=None, scheme=None, watch=None):
    """Run model from X0, V0 to t_end; returns (RunResult, clearances per step, watch(state) per step). On one IPC
    Toolkit thread (a mesh floor's barrier, the sphere scene's self-contact): a rerun reads back the same report."""
    one_thread()
    stepper = dm.TimeStepper(model, dt, scheme=scheme)
    clear, seen = [], []

    def record(s):
        clear.append(dm.clearance(model, s.X, t=s.t))
        if watch is not None:
            seen.append(watch(stepper, s))

    X0 = model.initial_state() if X0 is None else X0
    record(stepper.start(X0, V0=V0))
    result = stepper.run(X0, V0=V0, t_end=t_end, trackers=[dm.Callback(record)])
    if result.status != "finished":
        raise RuntimeError(f"{model.scene.name} ({type(model).__name__}): {result.message}")
    return result, np.array(clear), seen


@dataclass(frozen=True)
class SceneCase:
    backend: str
    scene: str
    nodes: int
    t_end: float

    @property
    def label(self) -> str:
        return f"{self.scene} {self.backend.upper()} {self.nodes}x{self.nodes}"


def run_scene(case: SceneCase) -> dict:
    """A contact scene on a small grid: its smallest clearance over every step and contact point."""
    fields_ = dict(next(f for s, _, f in CLEARANCE_SCENES if s == case.scene))
    cfg = scenes.config(case.scene, nodes=(case.nodes, case.nodes), **fields_)
    model = dm.Simulation(cfg, case.backend, nodes=cfg.nodes, dt=cfg.dt).model
    result, clear, _ = _run(model, cfg.dt, case.t_end)
    return {"steps": result.steps, "clearance": float(clear.min()), "final": float(clear[-1])}


#: the floor z = 0 as a triangle mesh, a square 4 m a side of two triangles: "mesh" split along the diagonal
#: x + y = 0, away from the sheet (which lies in x, y > 0), "diagonal" along x = y, under it
FLOOR_MESHES = {
    "mesh": dict(vertices=((-2.0, -2.0, 0.0), (2.0, -2.0, 0.0), (2.0, 2.0, 0.0), (-2.0, 2.0, 0.0)),
                 faces=((0, 1, 3), (1, 2, 3))),
    "diagonal": dict(vertices=((-2.0, -2.0, 0.0), (2.0, -2.0, 0.0), (2.0, 2.0, 0.0), (-2.0, 2.0, 0.0)),
                     faces=((0, 1, 2), (0, 2, 3)))}
#: the floors of the incline: the analytic plane and the two meshes, as the incline's table names them
FLOORS = {"plane": "", "mesh": ", mesh floor", "diagonal": ", mesh floor, its diagonal under the sheet"}


def drop_scene(nodes: int, height: float, friction: float = 0.0, direction=(0.0, 0.0, -1.0),
               floor: str = "plane") -> dm.Scene:
    """A 20 cm cloth, flat and horizontal at ``height`` above the floor z = 0, under gravity along ``direction``;
    the floor the analytic half-space (``floor`` "plane") or a triangle mesh (:data:`FLOOR_MESHES`)."""
    sheet = dm.Sheet(size=(0.2, 0.2), nodes=(nodes, nodes), initial=Plane(origin=(0.0, 0.0, height)))
    ground = dm.HalfSpace() if floor == "plane" else dm.MeshObstacle(**FLOOR_MESHES[floor])
    return dm.Scene(sheet, dm.Material(**CLOTH), forces=[dm.Gravity(9.81, direction=direction)],
                    obstacles=[ground], contact=dm.Contact(distance=1e-3, friction=friction),
                    force_model="variational", name="drop")


@dataclass(frozen=True)
class DropCase:
    backend: str
    nodes: int
    speed: float

    @property
    def label(self) -> str:
        return f"drop at {self.speed:g} m/s {self.backend.upper()} {self.nodes}x{self.nodes}"


def run_fast_drop(case: DropCase) -> dict:
    """A sheet 1 cm above the floor moving down at ``speed`` (m/s): smallest clearance, and where it ends."""
    model = make_model(drop_scene(case.nodes, 0.01), case.backend)
    X0 = model.initial_state()
    V0 = np.zeros_like(X0)
    V0[model.value_dofs, 2] = -case.speed
    result, clear, _ = _run(model, 2e-3, 0.05, X0, V0)
    return {"steps": result.steps, "clearance": float(clear.min()), "final": float(clear[-1])}


def run_clearance(case) -> dict:
    """A SceneCase or a DropCase."""
    return run_scene(case) if isinstance(case, SceneCase) else run_fast_drop(case)


@dataclass(frozen=True)
class InclineCase:
    backend: str
    nodes: int
    degrees: float
    friction: float
    t_end: float = 0.4
    floor: str = "plane"


def run_incline(case: InclineCase) -> dict:
    """A sheet resting on a plane tilted by ``degrees`` (gravity tilted instead): its mean motion down the slope."""
    a = math.radians(case.degrees)
    g = 9.81
    model = make_model(drop_scene(case.nodes, 1e-4, case.friction, (math.sin(a), 0.0, -math.cos(a)), case.floor),
                       case.backend)
    nodes = np.asarray(model.value_dofs)
    t_end = case.t_end
    result, clear, seen = _run(model, 2e-3, t_end, watch=lambda st, s: (s.t, np.mean(s.X[nodes, 0]),
                                                                       np.mean(s.V[nodes, 0])))
    t, x, v = np.array(seen).T
    late = t >= 0.5 * t_end
    return {"acceleration": float(2 * np.polyfit(t[late], x[late], 2)[0]), "theory": g * (math.sin(a) - case.friction
            * math.cos(a)), "speed": float(np.max(np.abs(v[late]))), "slip": model.scene.contact.slip,
            "clearance": float(clear.min())}


@dataclass(frozen=True)
class EnergyCase:
    backend: str
    nodes: int
    scheme: str
    dt: float = 2e-3


def run_energy(case: EnergyCase) -> dict:
    """A frictionless undamped drop of 5 cm: the total energy's largest rise and fall, in units of m g h."""
    height = 0.05
    model = make_model(drop_scene(case.nodes, height), case.backend)

    def total(stepper, s):
        fl = stepper._scheme.flat
        x = flat(s.X)
        return (model.energy(s.X).total + model.kinetic_energy(s.V) + fl.contact.energy(x) - fl.load(s.t) @ x)

    result, clear, E = _run(model, case.dt, 0.25, scheme=case.scheme, watch=total)
    E = np.array(E)
    mgh = -float(np.sum(model.load(model.initial_state(), 0.0)[:, 2])) * height  # the model's own weight
    return {"rise": float(np.max(E - E[0]) / mgh), "fall": float(np.max(E[0] - E) / mgh),
            "end": float((E[-1] - E[0]) / mgh), "clearance": float(clear.min())}


@dataclass(frozen=True)
class DrapeCase:
    backend: str
    nodes: int
    t_end: float


def run_drape(case: DrapeCase) -> dict:
    """The drape scene on nodes x nodes, run to t_end: its drape coefficient and smallest clearance."""
    from deformable.contact.points import contact_points
    from validation.harness.drape import drape_coefficient

    cfg = scenes.config("drape", nodes=(case.nodes, case.nodes))
    model = dm.Simulation(cfg, case.backend, nodes=cfg.nodes, dt=cfg.dt).model
    result, clear, _ = _run(model, cfg.dt, case.t_end)
    return {"dc": drape_coefficient(model, result.state.X, cfg.table()), "clearance": float(clear.min()),
            "kinetic": float(model.kinetic_energy(result.state.V)), "points": contact_points(model).P}


def _report_clearance(res, runner) -> None:
    """1. Clearance: the contact scenes on small grids and the fast drop, each on both backends."""
    small = {"fd": 9, "fe": 5}
    cases = ([SceneCase(b, s, small[b], t) for s, t, _ in CLEARANCE_SCENES for b in BACKENDS]
             + [DropCase(b, small[b], 5.0) for b in BACKENDS])
    raw = runner.map(run_clearance, cases, desc="clearance")
    rows = [(c.label, r["steps"], r["clearance"], r["final"]) for c, r in zip(cases, raw)]
    res.check_all("clearance", "clearance > 0 at every step and contact point", {r[0]: r[2] > 0 for r in rows})
    res.tables.append(Table("clearance", "Smallest clearance over every step and contact point",
                            ("run", "steps", "smallest clearance (m)", "final clearance (m)"), rows))
    res.data["clearance"] = {r[0]: r[2] for r in rows}


def _report_incline(res, runner) -> None:
    """2. The inclined plane: stick below the friction angle, slide above it, on each floor of :data:`FLOORS`."""
    angle = math.degrees(math.atan(FRICTION))
    inc = [InclineCase(b, 5, angle + d, FRICTION, floor=f) for f in FLOORS for b in BACKENDS for d in INCLINES]
    raw = runner.map(run_incline, inc, desc="incline")
    rows, stick, slide = [], {f: {} for f in FLOORS}, {f: {} for f in FLOORS}
    for c, r in zip(inc, raw):
        label = f"{c.backend.upper()}{FLOORS[c.floor]} a = {c.degrees:.2f} deg"
        rows.append((label, r["theory"], r["acceleration"], r["speed"], r["clearance"]))
        if r["theory"] < 0:
            stick[c.floor][label] = r["speed"] < r["slip"] and r["clearance"] > 0
        else:
            slide[c.floor][label] = abs(r["acceleration"] - r["theory"]) <= 0.02 * r["theory"] and r["clearance"] > 0
    for f, what in FLOORS.items():
        on = what or " on the analytic plane"
        res.check_all(f"incline{on}: sticks below the friction angle", f"speed below the slip speed below "
                      f"atan({FRICTION}) = {angle:.2f} deg", stick[f])
        res.check_all(f"incline{on}: slides above it", "acceleration within 2% of g (sin a - mu cos a)", slide[f])
    near = [(c.backend.upper(), c.degrees, r["theory"], r["acceleration"]) for c, r in zip(inc, raw)
            if c.floor == "diagonal" and 0 < r["theory"] < 1.0]  # just above the friction angle
    res.findings.append(
        "Friction against a mesh is Coulomb's where the sheet slides over the inside of a triangle: on the floor "
        "split away from the sheet the accelerations match g (sin a - mu cos a) as on the analytic plane. Where an "
        "edge of the mesh lies in the flat under the sliding sheet (the floor split along its diagonal under it), "
        "the IPC barrier of the sheet's edges against that edge adds to the faces' on either side, so the sheet "
        "rides over a ridge as it slides: 1 degree above the friction angle "
        + ", ".join(f"{b} {acc:.4g} against {th:.4g} m/s^2" for b, _, th, acc in near)
        + ", an effective friction coefficient of "
        + ", ".join(f"{FRICTION + (th - acc) / (9.81 * math.cos(math.radians(deg))):.4f}" for _, deg, th, acc in near)
        + f" for mu_f = {FRICTION}.")
    res.tables.append(Table("incline", f"A sheet on an inclined plane, mu_f = {FRICTION}",
                            ("run", "g (sin a - mu cos a) (m/s^2)", "fitted acceleration (m/s^2)",
                             "largest speed, 2nd half (m/s)",
                             "smallest clearance (m)"), rows))
    res.data["incline"] = [dict(zip(("run", "theory", "acceleration", "speed", "clearance"), r)) for r in rows]


def _report_energy(res, runner) -> None:
    """3. The energy of an impact: implicit Euler dissipates, Newmark's error falls with dt."""
    en = ([EnergyCase(b, 5, "implicit-euler") for b in BACKENDS]
          + [EnergyCase(b, 5, "newmark", dt) for b in BACKENDS for dt in NEWMARK_DT])
    raw = runner.map(run_energy, en, desc="energy")
    rows = [(f"{c.backend.upper()} {c.scheme}", c.dt, r["rise"], r["fall"], r["end"], r["clearance"])
            for c, r in zip(en, raw)]
    res.check_all("energy: implicit Euler dissipates", "E never rises (1e-9 m g h)",
                  {r[0]: r[2] <= 1e-9 and r[5] > 0 for r in rows if "euler" in r[0]})
    for b in BACKENDS:
        rise = [r[2] for r in rows if r[0] == f"{b.upper()} newmark"]
        res.check(f"energy: {b.upper()} Newmark's energy error falls with dt", "largest rise of E falls as dt halves",
                  ", ".join(f"{v:.3g}" for v in rise), len(rise) >= 2 and np.all(np.diff(rise) < 0))
    res.check_all("energy: clearance", "clearance > 0 at every step", {f"{r[0]} dt {r[1]:g}": r[5] > 0 for r in rows})
    res.findings.append("The barrier is far stiffer at impact than at rest, and an impact at 1 m/s crosses the 1 mm "
                        "activation distance within a step: implicit Euler absorbs the fall's whole energy (an "
                        "inelastic landing, its numerical dissipation), Newmark's trapezoidal rule gains energy at "
                        "impact (it conserves energy only for quadratic potentials), an error that falls with dt but "
                        "is still a multiple of m g h at dt = 0.25 ms. Contact runs use implicit Euler.")
    res.tables.append(Table("energy", "Frictionless undamped drop of 5 cm: total energy E against m g h",
                            ("run", "dt (s)", "largest rise / mgh", "largest fall / mgh", "end - start / mgh",
                             "smallest clearance (m)"), rows))
    res.data["energy"] = [dict(zip(("run", "dt", "rise", "fall", "end", "clearance"), r)) for r in rows]


def _report_drape(res, runner, levels: int) -> None:
    """4. The drape under refinement: the changes between levels fall, FD and FE agree at the finest."""
    dr = [DrapeCase(b, nodes_at(k, COARSEST[b]), DRAPE_T_END) for b in BACKENDS for k in range(levels)]
    raw = runner.map(run_drape, dr, desc="drape")
    rows, dcs, spacing = [], {}, {}
    for c, r in zip(dr, raw):
        rows.append((c.backend.upper(), c.nodes, r["points"], r["dc"], r["kinetic"], r["clearance"]))
        dcs.setdefault(c.backend, []).append(r["dc"])
        spacing.setdefault(c.backend, []).append(1.0 / (c.nodes - 1))
    orders = {}
    for b in BACKENDS:
        changes = np.abs(np.diff(dcs[b]))
        # observed order of the self-convergence: successive changes, each at the coarser of its two spacings
        with np.errstate(divide="ignore"):  # a change of exactly zero: an infinite order
            orders[b] = pairwise_orders(spacing[b][:-1], changes).tolist()
        res.check(f"drape: {b.upper()} converges", "changes between levels fall",
                  ", ".join(f"{d:.4f}" for d in changes) + " (observed order "
                  + ", ".join(f"{q:.1f}" for q in orders[b]) + ")",
                  changes.size >= 2 and np.all(np.diff(changes) < 0))
    fd, fe = dcs["fd"][-1], dcs["fe"][-1]
    res.check("drape: FD and FE agree", "within 2% at the finest level", f"FD {fd:.4f}, FE {fe:.4f}",
              abs(fd - fe) <= 0.02 * abs(fe))
    res.check_all("drape: clearance", "clearance > 0 at every step", {f"{r[0]} {r[1]}": r[5] > 0 for r in rows})
    res.tables.append(Table("drape", f"Cusick drape coefficient at t = {DRAPE_T_END} s",
                            ("backend", "nodes a side", "contact points", "drape coefficient", "kinetic energy (J)",
                             "smallest clearance (m)"), rows))
    res.data["drape"] = dcs
    res.data["drape_orders"] = orders


def fill(res, levels: int, runner) -> None:
    """The six experiments of the module docstring, in its order (the drape over ``levels`` levels)."""
    _report_clearance(res, runner)
    _report_incline(res, runner)
    _report_energy(res, runner)
    _report_drape(res, runner, levels)
    fill_self(res, runner)
    fill_mesh(res, runner)
    res.findings.append(
        "The drape coefficient depends on where the table's rim holds the cloth. With contact points only at the "
        "nodes (FD) or at h / 2 (FE), the cloth is held only where a contact point lands on the table, and the "
        "surface between that point and the next cuts the rim: the table is in effect smaller by up to the contact "
        "points' spacing, an error that does not fall smoothly with h. Measured with that sampling (t = 1.5 s, the "
        "shadow counted in pixels without extrapolation): FD "
        "0.885, 0.898, 0.923 at 9, 17, 33 nodes and 0.923 at 65 (166 s, by hand), FE 0.906, 0.901, 0.925 at 4, 8, "
        "16 elements: the changes grew from the first to the second pair on both backends. The drape scene now "
        "takes four contact points per cell side (Contact(samples=4)): the table above. FE's "
        "coarsest grid, 4 elements across a 30 cm cloth, is outside the asymptotic range whatever the sampling "
        "(0.906 with 2 or 4 points a side). The drape is not quite static at t = 1.5 s: on FD 65 nodes the "
        "coefficient moved by 4e-4 between t = 1.25 and 1.5 s (a slow swing of the corners, damped), the size "
        "of the finest changes; the convergence check compares every level at the same t. The observed orders "
        "(log2 of the ratio of successive changes) are not asymptotic orders where the last change has the other "
        "sign. The shadow's area is extrapolated from two rasters (validation.harness.drape): the raw 4096-pixel one "
        "was 2.4e-4 to 6.0e-4 too high, as much as the finest changes.")


STUDY = Study("contact", "contact: clearance, stick and slip on an incline, the energy of an impact, Cusick drape, "
              "self-contact, mesh obstacles",
              Levels(quick=3, full=4, minimum=3, maximum=5), fill, in_default=False)
