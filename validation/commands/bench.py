r"""``deformable bench``: the cost of one time step against one sparse direct solve.

For each backend and grid size the ``hanging`` scene (tpbf87, so K(r) is
refilled every step, eq. (20); xi = 1e-6 and a smooth initial bump so that every
entry of K's pattern carries a value) is stepped K times with the semi-implicit scheme
of eq. (22)-(27). :attr:`deformable.TimeStepper.timings` splits the step into
assembly (K(r) and A_t), factorisation and solve. In the same run, the
reference is one ``scipy.sparse.linalg.splu`` factorisation with default
options of the same matrix

    A_t = K(r_t) + M/dt^2 + C/(2 dt)        (25)

reduced to the free degrees of freedom, and one solve with 3 right-hand sides
(x, y, z). The ratio step / (factor + solve) says what the step costs beyond
the linear algebra it cannot avoid; issue 2's target for the FD backend is at
most 1.5 at 128 x 128 and 256 x 256. A second reference uses the stepper's own
SuperLU options (:data:`deformable.dynamics.semi_implicit.SPLU_OPTIONS`, a symmetric
ordering), so the second ratio isolates the cost of assembly and bookkeeping
from the choice of ordering.

The benchmark is written over the :class:`deformable.Backend` protocol; the FE
backend rows (``--backend fe``) step at FE's own stable step.
"""

from __future__ import annotations

import csv
import logging
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from deformable import scenes
from deformable.dynamics import TimeStepper
from deformable.dynamics.semi_implicit import SPLU_OPTIONS
from validation.harness.backends import make_model

__all__ = ["configure", "execute", "BenchRow", "bench_one", "format_table"]

log = logging.getLogger(__name__)


def configure(parser) -> None:
    """Arguments of ``deformable bench``."""
    parser.add_argument("--backend", default="fd", help="fd, fe or all")
    parser.add_argument("--sizes", default="32,64,128,256", help="comma-separated grid sizes n (n x n nodes)")
    parser.add_argument("--steps", default="5", help="timed steps per size (after one warm-up step)")
    parser.add_argument("--out", default=None, help="folder for bench.csv (default: reports/bench)")
    parser.add_argument("--variational-sizes", default="16,32", metavar="N,...",
                        help="grid sizes of the variational rows (implicit Euler, Newton); '' for none")


@dataclass(frozen=True)
class BenchRow:
    """One line of the table; times in seconds per step."""

    backend: str
    nodes: str
    ndof: int
    free: int
    assembly: float
    factorisation: float
    solve: float
    step: float
    direct_factor: float
    direct_solve: float
    same_factor: float
    same_solve: float

    @property
    def ratio(self) -> float:
        """step / (factor + solve) of the reference (default splu options)."""
        return self.step / (self.direct_factor + self.direct_solve)

    @property
    def same_ratio(self) -> float:
        """step / (factor + solve) with the stepper's own splu options."""
        return self.step / (self.same_factor + self.same_solve)


def _model(backend: str, n: int):
    # xi > 0 so that K's bending stencil carries values (its pattern always has it)
    cfg = scenes.config("hanging", nodes=(n, n), xi=1e-6)
    model = make_model(scenes.build(cfg), backend)
    # a step that keeps the scene on the stable side of the backend's own stretching bound at every size
    return model, min(cfg.dt, 0.5 * model.stable_step())


def direct_solve_time(model, X, dt: float, repeats: int = 3, **options) -> tuple[float, float, int]:
    """Best of ``repeats`` of one splu (default ``options``) of A_t on the free dofs, and one 3-rhs solve.

    Returns (factor seconds, solve seconds, number of free dofs). The free dofs
    are those of the x component (the hanging scene holds all three alike).
    """
    A = (model.stiffness(X) + model.mass() / dt**2 + model.damping() / (2 * dt)).tocsr()
    fixed = np.unique(np.asarray(model.fixed_dofs()[0], dtype=np.int64))
    free = np.setdiff1d(np.arange(A.shape[0]), fixed)
    Aff = sp.csc_matrix(A[free][:, free])
    rhs = np.asarray(model.load(X, 0.0))[free] + (model.mass() / dt**2 @ X)[free]
    best_f = best_s = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        lu = spla.splu(Aff, **options)
        t1 = time.perf_counter()
        lu.solve(rhs)
        t2 = time.perf_counter()
        best_f, best_s = min(best_f, t1 - t0), min(best_s, t2 - t1)
    return best_f, best_s, free.size


def bench_one(backend: str, n: int, steps: int) -> BenchRow:
    """Time ``steps`` steps of the hanging scene on an n x n grid, and the reference solve."""
    model, dt = _model(backend, n)
    stepper = TimeStepper(model, dt)
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
    f, s, nfree = direct_solve_time(model, state.X, dt)
    f2, s2, _ = direct_solve_time(model, state.X, dt, **SPLU_OPTIONS)
    return BenchRow(backend, f"{n}x{n}", model.ndof, nfree, tm["assembly"], tm["factorisation"], tm["solve"],
                    wall, f, s, f2, s2)


def format_table(rows) -> str:
    """A markdown table of bench rows (times in ms)."""
    head = ("| backend | grid | ndof | free | assembly ms | factorisation ms | solve ms | step ms "
            "| splu factor ms | splu solve ms | step / (factor+solve) | step / same, stepper's options |")
    lines = [head, "|" + "---|" * 12]
    for r in rows:
        lines.append(f"| {r.backend} | {r.nodes} | {r.ndof} | {r.free} | {1e3 * r.assembly:.2f} | "
                     f"{1e3 * r.factorisation:.2f} | {1e3 * r.solve:.2f} | {1e3 * r.step:.2f} | "
                     f"{1e3 * r.direct_factor:.2f} | {1e3 * r.direct_solve:.2f} | {r.ratio:.2f} "
                     f"| {r.same_ratio:.2f} |")
    return "\n".join(lines)


def _sizes(text, flag: str, allow_empty: bool = False) -> list[int]:
    """Comma-separated grid sizes, each at least 3; ValueError naming ``flag`` otherwise."""
    try:
        sizes = [int(s) for s in str(text).split(",") if s.strip()]
    except ValueError:
        raise ValueError(f"{flag} must be comma-separated integers, got {text!r}") from None
    if (not sizes and not allow_empty) or (sizes and min(sizes) < 3):
        raise ValueError(f"{flag} needs grid sizes of at least 3, got {text!r}")
    return sizes


def _parse(args):
    backends = {"fd": ["fd"], "fe": ["fe"], "all": ["fd", "fe"]}.get(args.backend)
    if backends is None:
        raise ValueError(f"unknown backend {args.backend!r}; choose fd, fe or all")
    sizes = _sizes(args.sizes, "--sizes")
    try:
        steps = int(args.steps)
    except ValueError:
        raise ValueError(f"--steps must be a positive integer, got {args.steps!r}") from None
    if steps < 1:
        raise ValueError(f"--steps must be a positive integer, got {args.steps!r}")
    return backends, sizes, steps


def execute(args) -> int:
    """``deformable bench``: print the table and write bench.csv."""
    from validation.harness.report import writable_folder

    backends, sizes, steps = _parse(args)
    vsizes = _sizes(args.variational_sizes, "--variational-sizes", allow_empty=True)
    out = writable_folder(Path(args.out) if args.out else Path("reports") / "bench")
    rows = []
    for backend in backends:
        for n in sizes:
            rows.append(bench_one(backend, n, steps))
            log.info("%s", rows[-1])
    print(format_table(rows))
    with (out / "bench.csv").open("w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(list(asdict(rows[0]).keys()) + ["ratio", "same_ratio"])
        for r in rows:
            writer.writerow(list(asdict(r).values()) + [f"{r.ratio:.4f}", f"{r.same_ratio:.4f}"])
    print(f"wrote {out / 'bench.csv'}")
    if vsizes:
        vrows = [bench_variational(b, n, steps) for b in backends for n in vsizes]
        print(format_variational(vrows))
        with (out / "bench_variational.csv").open("w", newline="") as fh:
            writer = csv.writer(fh)
            writer.writerow(list(asdict(vrows[0]).keys()))
            writer.writerows(list(asdict(r).values()) for r in vrows)
        print(f"wrote {out / 'bench_variational.csv'}")
    return 0


@dataclass(frozen=True)
class VariationalRow:
    """One variational row: implicit-Euler steps solved by Newton; times in seconds."""

    backend: str
    nodes: str
    unknowns: int
    dt: float
    newton_per_step: float
    step: float

    @property
    def per_iteration(self) -> float:
        return self.step / self.newton_per_step


def bench_variational(backend: str, n: int, steps: int) -> VariationalRow:
    """Time ``steps`` implicit-Euler steps of the hanging scene under the variational model (xi = 1e-3)."""
    cfg = scenes.config("hanging", nodes=(n, n), xi=1e-3, force_model="variational")
    model = make_model(scenes.build(cfg), backend)
    dt = 5e-3
    stepper = TimeStepper(model, dt)
    state = stepper.step(stepper.start(model.initial_state()))  # warm-up
    t0 = time.perf_counter()
    for _ in range(steps):
        state = stepper.step(state)
    wall = (time.perf_counter() - t0) / steps
    newton = float(np.mean([r.iterations for r in stepper.newton_reports[1:]]))
    return VariationalRow(backend, f"{n}x{n}", 3 * model.ndof, dt, newton, wall)


def format_variational(rows) -> str:
    """A markdown table of variational rows (times in ms)."""
    lines = ["| backend | grid | unknowns | dt s | Newton iterations / step | step ms | ms / iteration |",
             "|" + "---|" * 7]
    for r in rows:
        lines.append(f"| {r.backend} | {r.nodes} | {r.unknowns} | {r.dt:g} | {r.newton_per_step:.2f} | "
                     f"{1e3 * r.step:.1f} | {1e3 * r.per_iteration:.1f} |")
    return "\n".join(lines)
