r"""``deformable bench``: what a time step costs, against the linear algebra it cannot avoid, in one run.

Two tables, each row measured in a process of its own (so that its peak
memory, the process's maximum resident set, is its own):

Semi-implicit rows (the paper's eq. (22)-(27)). The ``hanging`` scene under
the paper's force and weights (tpbf87, eta_12 = xi_12 = 0, so K(r) is refilled
every step, eq. (20); xi = 1e-6) is stepped K times at half the backend's own
stable step. :attr:`deformable.TimeStepper.timings` splits the
step into assembly (K(r) and A_t), factorisation and solve. The references,
in the same run: one factorisation of the same matrix

    A_t = K(r_t) + M/dt^2 + C/(2 dt)        (25)

reduced to the free degrees of freedom, and one solve with 3 right-hand sides
(x, y, z), by ``scipy.sparse.linalg.splu`` with its default options (COLAMD),
and by the stepper's own solver (:mod:`deformable.algebra.solvers`). The ratio step /
(factor + solve) says what the step costs beyond the linear algebra.

Implicit rows (the energy-consistent model). The ``curtain`` scene as it
ships (variational, implicit Euler at its dt of 5 ms), stepped K times after
one warm-up step at the start of the draw: Newton iterations and factorisations per step, ms per
iteration, the ratio of an iteration to one factorisation and solve of its
own Newton matrix with the same solver, and the ratio of the step to the
semi-implicit step of the same scene and grid under the paper's force (at its
own stable dt). FD rows are given in nodes a side, FE rows in elements a side.

Scene rows (opt-in: ``--scenes``). Shipped scenes as they ship (the
energy-consistent model, implicit Euler at the scene's dt) run for
``--scene-time`` seconds of motion from their initial state on FD
``--scene-fd`` nodes and FE ``--scene-fe`` elements a side: the wall time,
steps, Newton iterations, factorisations and definite fallbacks per step
(unknowns: every degree of freedom, held ones too, as in the contact rows).
They measure what the 2 s budgets of the scenes and the iterations per step
of a whole run are about, where the implicit rows time a few steps.

Contact rows (issue 14). The ``sphere`` scene with the cloth starting half
the barrier's activation distance above the ball (in contact from the first
step), stepped ``--contact-steps`` times (default 40, 0.2 s) after one
warm-up step, against the same scene and start with the obstacle removed (a
free fall): ms per step, Newton iterations per step, ms per iteration, and
the ratios. The window is long enough for the cloth to drape: its first
steps, with only the middle of the cloth on the ball, are the cheapest
(measured at FD 64 x 64: 2.40 Newton iterations a step over the first 5,
4.55 over the first 40). The issue's target is a step ratio of at most 2 at
64 x 64 FD nodes.
"""

from __future__ import annotations

import csv
import logging
import math
import multiprocessing as mp
import resource
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from deformable import scenes
from deformable.algebra.solvers import make_solver
from deformable.dynamics import TimeStepper
from deformable.errors import InputError
from deformable.solve.potential import flat
from validation.harness.backends import descriptor, make_model
from validation.harness.report import markdown_table

__all__ = ["configure", "execute", "BenchRow", "ImplicitRow", "ContactRow", "bench_one", "bench_implicit",
           "bench_contact", "format_table", "format_implicit", "format_contact", "SceneRow", "bench_scene",
           "format_scenes"]

log = logging.getLogger(__name__)
#: the semi-implicit rows' dt (s), where the backend's half stable step is not smaller
SEMI_IMPLICIT_DT = 1e-3

def configure(parser) -> None:
    """Arguments of ``deformable bench``."""
    parser.add_argument("--backend", default="fd", help="fd, fe or all (default: fd)")
    parser.add_argument("--sizes", default="32,64,128,256", help="semi-implicit rows: grid sizes n, n x n nodes "
                        "(default: 32,64,128,256)")
    parser.add_argument("--steps", default="5", help="timed steps per semi-implicit and implicit row, after one "
                        "warm-up step (default: 5)")
    # the row lists below run as given, whatever --backend says; unset, a backend --backend takes has its default
    parser.add_argument("--implicit-fd", default=None, metavar="N,...",
                        help="implicit rows, FD: nodes a side (default with --backend fd or all: 32,64,128); '' for "
                        "none")
    parser.add_argument("--implicit-fe", default=None, metavar="N,...",
                        help="implicit rows, FE: elements a side (default with --backend fe or all: 16,32,64); '' "
                        "for none")
    parser.add_argument("--contact-fd", default=None, metavar="N,...",
                        help="contact rows (the sphere scene with and without its ball), FD: nodes a side "
                        "(default with --backend fd or all: 64); '' for none")
    parser.add_argument("--contact-fe", default=None, metavar="N,...",
                        help="contact rows, FE: elements a side (default: none)")
    parser.add_argument("--contact-steps", default="40", metavar="K",
                        help="contact rows: timed steps after one warm-up, long enough for the cloth to drape over "
                        "the ball (default: 40)")
    parser.add_argument("--scenes", default="", metavar="NAME,...",
                        help="scene rows: shipped scenes run for --scene-time s, e.g. curtain,flag (default: none)")
    parser.add_argument("--scene-fd", default=None, metavar="N,...",
                        help="scene rows, FD: nodes a side (default with --backend fd or all: 64); '' for none")
    parser.add_argument("--scene-fe", default=None, metavar="N,...",
                        help="scene rows, FE: elements a side (default with --backend fe or all: 32); '' for none")
    parser.add_argument("--scene-time", default="2", metavar="T",
                        help="scene rows: seconds of motion (default: 2)")
    parser.add_argument("--solver", default="auto", help="linear solver: auto, superlu or pardiso (default: auto)")
    parser.add_argument("--out", default=None, help="folder for bench.csv, bench_implicit.csv, bench_contact.csv "
                        "and bench_scenes.csv (default: reports/bench)")


def _peak_memory() -> float:
    """This process's maximum resident set (MB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _in_own_process(fn, *args):
    """fn(*args) in a forked process of its own (its peak memory is its own); returns its result."""
    ctx = mp.get_context("fork")
    with ctx.Pool(1) as pool:
        return pool.apply(fn, args)


# -- semi-implicit rows ------------------------------------------------------------------
@dataclass(frozen=True)
class BenchRow:
    """One semi-implicit line of the table; times in seconds per step, memory in MB."""

    backend: str
    nodes: str
    ndof: int
    free: int
    solver: str
    assembly: float
    factorisation: float
    solve: float
    step: float
    direct_factor: float
    direct_solve: float
    same_factor: float
    same_solve: float
    peak_mb: float

    @property
    def ratio(self) -> float:
        """step / (factor + solve) of the reference (default splu options)."""
        return self.step / (self.direct_factor + self.direct_solve)

    @property
    def same_ratio(self) -> float:
        """step / (factor + solve) with the stepper's own solver."""
        return self.step / (self.same_factor + self.same_solve)


def _model(backend: str, n: int):
    # the paper's force and weights (xi > 0 so that K's bending stencil carries values; its pattern always has it)
    cfg = scenes.config("hanging", nodes=(n, n), xi=1e-6, shear=0.0, force_model="tpbf87", dt=SEMI_IMPLICIT_DT)
    model = make_model(scenes.build(cfg), backend)
    # a step that keeps the scene on the stable side of the backend's own stretching bound at every size
    return model, min(cfg.dt, 0.5 * model.stable_step())


def _best(fn, repeats: int = 3) -> float:
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def direct_solve_time(A, rhs, solver=None, repeats: int = 3) -> tuple[float, float]:
    """Best of ``repeats`` of one factorisation of A and one solve of rhs: (factor s, solve s).

    ``solver``: one of :mod:`deformable.algebra.solvers` (default: ``splu`` with SciPy's default options).
    """
    if solver is None:
        lu = spla.splu(sp.csc_matrix(A))
        return _best(lambda: spla.splu(sp.csc_matrix(A)), repeats), _best(lambda: lu.solve(rhs), repeats)
    solver.factor(A)
    return _best(lambda: solver.factor(A), repeats), _best(lambda: solver.solve(rhs), repeats)


def bench_one(backend: str, n: int, steps: int, solver: str = "auto") -> BenchRow:
    """Time ``steps`` semi-implicit steps of the hanging scene on an n x n grid, and the references."""
    model, dt = _model(backend, n)
    stepper = TimeStepper(model, dt, solver=solver)
    # a generic deformed start, so that every alpha_ij, beta_ij is non-zero and the
    # reference matrix has the same non-zero pattern as the stepper's
    X0 = model.initial_state()
    L1, L2 = model.scene.sheet.size
    a = np.asarray(model.discretize(lambda a1, a2: np.stack(
        [0 * a1, 0 * a1, 0.05 * np.sin(np.pi * a1 / L1 + 0.3) * np.sin(2 * np.pi * a2 / L2 + 0.7)], axis=-1)))
    state = stepper.start(X0 + a)
    state = stepper.step(state)  # warm-up: builds the reduced-system pattern once
    for k in stepper.timings:
        stepper.timings[k] = 0.0
    t0 = time.perf_counter()
    for _ in range(steps):
        state = stepper.step(state)
    wall = (time.perf_counter() - t0) / steps
    tm = {k: v / steps for k, v in stepper.timings.items()}
    X = state.X
    A = (model.stiffness(X) + model.mass() / dt**2 + model.damping() / (2 * dt)).tocsr()
    free = np.setdiff1d(np.arange(A.shape[0]), np.asarray(model.fixed_dofs()[0], dtype=np.int64))
    Aff = sp.csc_matrix(A[free][:, free])
    rhs = (model.load(X, 0.0) + model.mass() / dt**2 @ X)[free]
    f, s = direct_solve_time(Aff, rhs)
    own = make_solver(solver)
    f2, s2 = direct_solve_time(Aff, rhs, own)
    return BenchRow(backend, f"{n}x{n}", model.ndof, free.size, own.name, tm["assembly"], tm["factorisation"],
                    tm["solve"], wall, f, s, f2, s2, _peak_memory())


def format_table(rows) -> str:
    """A markdown table of semi-implicit rows (times in ms)."""
    return markdown_table(
        ("backend", "grid", "ndof", "free", "solver", "assembly ms", "factorisation ms", "solve ms", "step ms",
         "splu factor ms", "splu solve ms", "step / (factor+solve)", "step / same with its solver", "peak MB"),
        [(r.backend, r.nodes, r.ndof, r.free, r.solver, *(f"{1e3 * t:.2f}" for t in (
            r.assembly, r.factorisation, r.solve, r.step, r.direct_factor, r.direct_solve)),
          f"{r.ratio:.2f}", f"{r.same_ratio:.2f}", f"{r.peak_mb:.0f}") for r in rows])


# -- implicit rows -----------------------------------------------------------------------
@dataclass(frozen=True)
class ImplicitRow:
    """One implicit line: the variational curtain under implicit Euler; times in seconds, memory in MB."""

    backend: str
    grid: str
    unknowns: int
    solver: str
    dt: float
    newton_per_step: float
    factorisations_per_step: float
    step: float
    factor: float
    solve: float
    semi_implicit_step: float
    peak_mb: float

    @property
    def per_iteration(self) -> float:
        return self.step / self.newton_per_step

    @property
    def iteration_ratio(self) -> float:
        """One Newton iteration against one factorisation and solve of its own matrix (same solver)."""
        return self.per_iteration / (self.factor + self.solve)

    @property
    def step_ratio(self) -> float:
        """The implicit step against the semi-implicit step of the same scene and grid."""
        return self.step / self.semi_implicit_step


def bench_implicit(backend: str, n: int, steps: int, solver: str = "auto") -> ImplicitRow:
    """Time ``steps`` implicit-Euler steps of the variational curtain on n nodes (FD) or n elements (FE) a side."""
    cfg = _config("curtain", backend, n)
    model = make_model(scenes.build(cfg), backend)
    stepper = TimeStepper(model, cfg.dt, newton=dict(solver=solver))
    state = stepper.step(stepper.start(model.initial_state()))  # warm-up: patterns and analyses are built once
    t0 = time.perf_counter()
    for _ in range(steps):
        state = stepper.step(state)
    wall = (time.perf_counter() - t0) / steps
    reports = stepper.newton_reports[1:]
    dt = cfg.dt
    A = stepper.newton.newton_matrix(flat(state.X), 1 / dt**2, 1 / dt)
    own = make_solver(solver, definite=True)
    f, s = direct_solve_time(A, np.ones(A.shape[0]), own)
    # the paper's force on the same scene and grid, at its own stable step
    paper = make_model(scenes.build(cfg.replace(force_model="tpbf87")), backend)
    semi = TimeStepper(paper, min(scenes.config("curtain").dt, 0.5 * paper.stable_step()), solver=solver)
    sstate = semi.step(semi.start(paper.initial_state()))
    t1 = time.perf_counter()
    for _ in range(steps):
        sstate = semi.step(sstate)
    semi_step = (time.perf_counter() - t1) / steps
    return ImplicitRow(backend, f"{n}x{n}", A.shape[0], own.name, dt,
                       float(np.mean([r.iterations for r in reports])),
                       float(np.mean([r.factorisations for r in reports])), wall, f, s, semi_step, _peak_memory())


def format_implicit(rows) -> str:
    """A markdown table of implicit rows (times in ms)."""
    return markdown_table(
        ("backend", "grid", "unknowns", "solver", "Newton iterations / step", "factorisations / step", "step ms",
         "ms / iteration", "factor+solve ms", "iteration / (factor+solve)", "step / semi-implicit step", "peak MB"),
        [(r.backend, _grid(r), r.unknowns, r.solver, f"{r.newton_per_step:.2f}", f"{r.factorisations_per_step:.2f}",
          f"{1e3 * r.step:.1f}", f"{1e3 * r.per_iteration:.1f}", f"{1e3 * (r.factor + r.solve):.1f}",
          f"{r.iteration_ratio:.2f}", f"{r.step_ratio:.1f}", f"{r.peak_mb:.0f}") for r in rows])


def _config(scene: str, backend: str, n: int):
    """A shipped scene's config on n nodes (FD) or n elements (FE) a side: the unit of the implicit, scene and
    contact rows."""
    nodes = descriptor(backend).nodes(n)
    return scenes.config(scene, nodes=(nodes, nodes))


def _grid(r) -> str:
    """A row's grid with its unit: nodes a side (FD) or elements a side (FE)."""
    return f"{r.grid}{' nodes' if descriptor(r.backend).grid == 'nodes' else ' el.'}"


# -- scene rows --------------------------------------------------------------------------
@dataclass(frozen=True)
class SceneRow:
    """One scene line: a shipped scene run from its initial state; times in seconds, memory in MB."""

    scene: str
    backend: str
    grid: str
    unknowns: int
    dt: float
    t_end: float
    status: str
    t_reached: float
    steps: int
    wall: float
    newton_per_step: float
    factorisations_per_step: float
    fallbacks_per_step: float
    peak_mb: float


def bench_scene(scene: str, backend: str, n: int, t_end: float, solver: str = "auto") -> SceneRow:
    """Run a shipped scene (energy-consistent, implicit Euler at its own dt, as every scene ships) for t_end seconds
    on n nodes (FD) or n elements (FE) a side."""
    cfg = _config(scene, backend, n)
    model = make_model(scenes.build(cfg), backend)
    stepper = TimeStepper(model, cfg.dt, newton=dict(solver=solver))
    t0 = time.perf_counter()
    result = stepper.run(model.initial_state(), t_end=t_end)
    wall = time.perf_counter() - t0
    reports = stepper.newton_reports

    def per_step(name):
        return float(np.mean([getattr(r, name) for r in reports]))

    return SceneRow(scene, backend, f"{n}x{n}", 3 * model.ndof, cfg.dt, t_end, result.status, result.state.t,
                    result.steps, wall, per_step("iterations"), per_step("factorisations"), per_step("fallbacks"),
                    _peak_memory())


def format_scenes(rows) -> str:
    """A markdown table of scene rows."""
    return markdown_table(
        ("scene", "backend", "grid", "unknowns", "dt (ms)", "status", "t reached (s)", "steps", "wall (s)",
         "Newton / step", "factorisations / step", "definite fallbacks / step", "peak MB"),
        [(r.scene, r.backend, _grid(r), r.unknowns, f"{1e3 * r.dt:g}", r.status, f"{r.t_reached:g}", r.steps,
          f"{r.wall:.1f}", f"{r.newton_per_step:.2f}", f"{r.factorisations_per_step:.2f}",
          f"{r.fallbacks_per_step:.2f}", f"{r.peak_mb:.0f}") for r in rows])


# -- contact rows ------------------------------------------------------------------------
@dataclass(frozen=True)
class ContactRow:
    """One contact line: the sphere scene with its ball against without; times in seconds, memory in MB."""

    backend: str
    grid: str
    unknowns: int
    contact_points: int
    steps: int
    newton_contact: float
    newton_free: float
    step_contact: float
    step_free: float
    peak_mb: float

    @property
    def step_ratio(self) -> float:
        """The step with contact against the step without the obstacle."""
        return self.step_contact / self.step_free

    @property
    def iteration_ratio(self) -> float:
        """A Newton iteration with contact against one without."""
        return (self.step_contact / self.newton_contact) / (self.step_free / self.newton_free)


def _timed_steps(model, dt: float, steps: int, solver: str) -> tuple[float, float]:
    """(s per step, Newton iterations per step) of ``steps`` implicit-Euler steps after one warm-up step."""
    stepper = TimeStepper(model, dt, newton=dict(solver=solver))
    state = stepper.step(stepper.start(model.initial_state()))
    t0 = time.perf_counter()
    for _ in range(steps):
        state = stepper.step(state)
    wall = (time.perf_counter() - t0) / steps
    return wall, float(np.mean([r.iterations for r in stepper.newton_reports[1:]]))


def bench_contact(backend: str, n: int, steps: int, solver: str = "auto") -> ContactRow:
    """Time ``steps`` steps of the sphere scene in contact, and of the same scene without its ball."""
    import dataclasses

    from deformable.contact.points import contact_points

    base = _config("sphere", backend, n)
    cfg = base.replace(gap=0.5 * base.contact.distance)
    scene = scenes.build(cfg)
    model = make_model(scene, backend)
    with_ball, it_ball = _timed_steps(model, cfg.dt, steps, solver)
    free = make_model(dataclasses.replace(scene, obstacles=(), contact=None), backend)
    without, it_free = _timed_steps(free, cfg.dt, steps, solver)
    return ContactRow(backend, f"{n}x{n}", 3 * model.ndof, contact_points(model).P, steps, it_ball, it_free,
                      with_ball, without, _peak_memory())


def format_contact(rows) -> str:
    """A markdown table of contact rows (times in ms)."""
    return markdown_table(
        ("backend", "grid", "unknowns", "contact points", "steps", "Newton / step, ball", "Newton / step, none",
         "step ms, ball", "step ms, none", "step ratio", "iteration ratio", "peak MB"),
        [(r.backend, _grid(r), r.unknowns, r.contact_points, r.steps, f"{r.newton_contact:.2f}",
          f"{r.newton_free:.2f}", f"{1e3 * r.step_contact:.1f}", f"{1e3 * r.step_free:.1f}", f"{r.step_ratio:.2f}",
          f"{r.iteration_ratio:.2f}", f"{r.peak_mb:.0f}") for r in rows])


# -- the command -------------------------------------------------------------------------
def _sizes(text, flag: str, allow_empty: bool = False) -> list[int]:
    """Comma-separated grid sizes, each at least 3; ValueError naming ``flag`` otherwise."""
    try:
        sizes = [int(s) for s in str(text).split(",") if s.strip()]
    except ValueError:
        raise InputError(f"{flag} must be comma-separated integers, got {text!r}") from None
    if (not sizes and not allow_empty) or (sizes and min(sizes) < 3):
        raise InputError(f"{flag} needs grid sizes of at least 3, got {text!r}")
    return sizes


#: the grids of the implicit, contact and scene rows of a backend that --backend takes, unless given
ROW_DEFAULTS = {"implicit": {"fd": "32,64,128", "fe": "16,32,64"}, "contact": {"fd": "64", "fe": ""},
                "scene": {"fd": "64", "fe": "32"}}


def _row_sizes(args, kind: str, backends) -> dict:
    """The grids of one kind of row by backend: as given (whatever --backend says), else the default of a backend
    that --backend takes, else none."""
    out = {}
    for b in ("fd", "fe"):
        given = getattr(args, f"{kind}_{b}")
        text = given if given is not None else ROW_DEFAULTS[kind][b] if b in backends else ""
        out[b] = _sizes(text, f"--{kind}-{b}", allow_empty=True)
    return out


def _positive_int(text, flag: str) -> int:
    """A positive integer; InputError naming ``flag`` otherwise."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise InputError(f"{flag} must be a positive integer, got {text!r}")
    return value


def _parse(args):
    backends = {"fd": ["fd"], "fe": ["fe"], "all": ["fd", "fe"]}.get(args.backend)
    if backends is None:
        raise InputError(f"unknown backend {args.backend!r}; choose fd, fe or all")
    sizes = _sizes(args.sizes, "--sizes")
    implicit, contact = _row_sizes(args, "implicit", backends), _row_sizes(args, "contact", backends)
    steps = (_positive_int(args.steps, "--steps"), _positive_int(args.contact_steps, "--contact-steps"))
    make_solver(args.solver)  # a bad or missing solver is refused before any work
    names = [name.strip() for name in str(args.scenes).split(",") if name.strip()]
    for name in names:
        if name not in scenes.SCENES:
            raise InputError(f"--scenes: unknown scene {name!r}; known: {', '.join(scenes.SCENES)}")
    try:
        t_end = float(args.scene_time)
    except ValueError:
        t_end = math.nan
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"--scene-time must be a positive number of seconds, got {args.scene_time!r}")
    scene_grids = _row_sizes(args, "scene", backends)
    if names and not any(scene_grids.values()):
        raise InputError(f"--scenes {args.scenes!r} needs a grid: --scene-fd or --scene-fe")
    return backends, sizes, implicit, contact, steps, (names, scene_grids, t_end)


def _write(path: Path, rows, extra=()) -> None:
    with path.open("w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(list(asdict(rows[0]).keys()) + [name for name, _ in extra])
        for r in rows:
            writer.writerow(list(asdict(r).values()) + [f"{fn(r):.4f}" for _, fn in extra])


def _emit(path: Path, rows, table, extra=()) -> None:
    """Print the rows' markdown table and write them to the CSV at ``path``; nothing for no rows."""
    if rows:
        print(table(rows))
        _write(path, rows, extra)
        print(f"wrote {path}")


def execute(args) -> int:
    """``deformable bench``: print the tables and write bench.csv (and bench_implicit.csv, bench_contact.csv,
    bench_scenes.csv for the rows asked for)."""
    from validation.harness.report import writable_folder

    backends, sizes, implicit, contact, (steps, contact_steps), (names, scene_grids, t_end) = _parse(args)
    out = writable_folder(Path(args.out) if args.out else Path("reports") / "bench")
    rows = [_in_own_process(bench_one, b, n, steps, args.solver) for b in backends for n in sizes]
    _emit(out / "bench.csv", rows, format_table,
          [("ratio", lambda r: r.ratio), ("same_ratio", lambda r: r.same_ratio)])
    irows = [_in_own_process(bench_implicit, b, n, steps, args.solver) for b in ("fd", "fe") for n in implicit[b]]
    _emit(out / "bench_implicit.csv", irows, format_implicit,
          [("ms_per_iteration", lambda r: 1e3 * r.per_iteration), ("iteration_ratio", lambda r: r.iteration_ratio),
           ("step_ratio", lambda r: r.step_ratio)])
    crows = [_in_own_process(bench_contact, b, n, contact_steps, args.solver) for b in ("fd", "fe")
             for n in contact[b]]
    _emit(out / "bench_contact.csv", crows, format_contact,
          [("step_ratio", lambda r: r.step_ratio), ("iteration_ratio", lambda r: r.iteration_ratio)])
    jobs = [(name, b, n) for name in names for b in ("fd", "fe") for n in scene_grids[b]]
    srows = []
    for k, (name, b, n) in enumerate(jobs, 1):  # minutes each: say which one runs
        print(f"scene {k} of {len(jobs)}: {name} {b} {n}x{n}, {t_end:g} s of motion", flush=True)
        srows.append(_in_own_process(bench_scene, name, b, n, t_end, args.solver))
    _emit(out / "bench_scenes.csv", srows, format_scenes)
    return 0
