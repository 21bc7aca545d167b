r"""``deformable bench``: what a time step costs, against the linear algebra it cannot avoid, in one run.

Tables of rows, each measured in a process of its own (so that its peak memory,
the process's maximum resident set, is its own), one bench module each
(:mod:`validation.benches`): the semi-implicit rows (the paper's eq. (22)-(27)
against its factorisation and solve), the implicit rows (a Newton iteration of
the energy-consistent curtain against one factorisation and solve of its own
matrix), the contact rows (the sphere scene with and without its ball) and,
when asked for, the scene rows (shipped scenes for seconds of motion). The
command parses its arguments, refuses bad ones in one line before any work,
and writes each table's CSV beside printing it.
"""

from __future__ import annotations

import math
from pathlib import Path

from deformable import scenes
from deformable.algebra.solvers import make_solver
from deformable.errors import InputError
from validation.benches import (
    bench_contact,
    bench_implicit,
    bench_one,
    bench_scene,
    format_contact,
    format_implicit,
    format_scenes,
    format_table,
)
from validation.benches.measure import emit, in_own_process
from validation.benches.rates import SETTINGS as RATE_SETTINGS
from validation.benches.selfcontact import bench_self, format_self

__all__ = ["configure", "execute"]


def configure(parser) -> None:
    """Arguments of ``deformable bench``, table by table."""
    _table_arguments(parser)
    _bar_and_scene_arguments(parser)
    _rate_arguments(parser)
    _realtime_arguments(parser)
    parser.add_argument("--solver", default="auto", help="linear solver: auto, superlu or pardiso (default: auto)")
    parser.add_argument("--out", default=None, help="folder for bench.csv, bench_implicit.csv, bench_contact.csv, "
                        "bench_self.csv, bench_bar.csv, bench_scenes.csv, bench_rates.csv, bench_peers.csv, "
                        "bench_accuracy.csv, bench_accuracy_levels.csv and bench_realtime.csv (default: reports/bench)")


def _table_arguments(parser) -> None:
    """The semi-implicit, implicit, contact and self-contact rows' arguments (and --backend)."""
    parser.add_argument("--backend", default="fd", help="fd, fe or all (default: fd)")
    parser.add_argument("--sizes", default="32,64,128,256", help="semi-implicit rows: grid sizes n, n x n nodes "
                        "(default: 32,64,128,256)")
    parser.add_argument("--steps", default="5", help="timed steps per semi-implicit row, after one warm-up step "
                        "(default: 5)")
    # the row lists below run as given, whatever --backend says; unset, a backend --backend takes has its default
    parser.add_argument("--implicit-fd", default=None, metavar="N,...",
                        help="implicit rows (a Newton step of the curtain against its floor), FD: nodes a side "
                        "(default with --backend fd or all: 20,64,128); '' for none")
    parser.add_argument("--implicit-fe", default=None, metavar="N,...",
                        help="implicit rows, FE: elements a side (default with --backend fe or all: 16,32); '' "
                        "for none")
    parser.add_argument("--implicit-time", default="2", metavar="T",
                        help="implicit rows: seconds of the curtain's motion timed, after one warm-up step "
                        "(default: 2, its whole run)")
    parser.add_argument("--contact-fd", default=None, metavar="N,...",
                        help="contact rows (the sphere scene with and without its ball), FD: nodes a side "
                        "(default with --backend fd or all: 64); '' for none")
    parser.add_argument("--contact-fe", default=None, metavar="N,...",
                        help="contact rows, FE: elements a side (default: none)")
    parser.add_argument("--contact-steps", default="40", metavar="K",
                        help="contact rows: timed steps after one warm-up, long enough for the cloth to drape over "
                        "the ball (default: 40)")
    parser.add_argument("--self-fd", default=None, metavar="N,...",
                        help="self-contact rows (the curtain with its self-contact against without), FD: nodes a side "
                        "(default with --backend fd or all: 32,64); '' for none")
    parser.add_argument("--self-fe", default=None, metavar="N,...",
                        help="self-contact rows, FE: elements a side (default: none)")
    parser.add_argument("--self-time", default="2", metavar="T",
                        help="self-contact rows: seconds of the curtain's motion (default: 2, its whole run)")


def _bar_and_scene_arguments(parser) -> None:
    """The curtain bar's and the scene rows' arguments."""
    parser.add_argument("--bar", action="store_true",
                        help="the curtain bar: the shipped curtain on --bar-grid nodes for --bar-time s in "
                        "fixed-matrix SuperLU factor+solves per simulated second, with its Newton error against dt vs "
                        "dt/2 (default: off)")
    parser.add_argument("--bar-grid", default="48", metavar="N", help="the curtain bar: FD nodes a side (default: 48)")
    parser.add_argument("--bar-time", default="0.5", metavar="T",
                        help="the curtain bar: seconds of motion (default: 0.5)")
    parser.add_argument("--scenes", default="", metavar="NAME,...",
                        help="scene rows: shipped scenes run for --scene-time s, e.g. curtain,flag (default: none)")
    parser.add_argument("--scene-fd", default=None, metavar="N,...",
                        help="scene rows, FD: nodes a side (default with --backend fd or all: 64); '' for none")
    parser.add_argument("--scene-fe", default=None, metavar="N,...",
                        help="scene rows, FE: elements a side (default with --backend fe or all: 32); '' for none")
    parser.add_argument("--scene-time", default="2", metavar="T",
                        help="scene rows: seconds of motion (default: 2)")


def _rate_arguments(parser) -> None:
    """The rate rows' and the peer rows' arguments."""
    parser.add_argument("--rates", action="store_true",
                        help="rate rows: simulated s per CPU s (one thread) of --rates-scenes for --rates-time s under "
                        "the default Newton settings and under those from before issue 27's step test (the force test "
                        "at rtol 1e-3, a factorisation every solve), with the Newton error of each against a tight "
                        "solve and the dt vs dt/2 difference (minutes to hours; default: off)")
    parser.add_argument("--rates-scenes", default="curtain,flag,sphere", metavar="NAME,...",
                        help="rate rows: the scenes (default: curtain,flag,sphere)")
    parser.add_argument("--rates-fd", default="32,64,128", metavar="N,...",
                        help="rate rows, FD: nodes a side (default: 32,64,128); '' for none")
    parser.add_argument("--rates-fe", default="16,32", metavar="N,...",
                        help="rate rows, FE: elements a side (default: 16,32); '' for none")
    parser.add_argument("--rates-curtain-fd", default="256", metavar="N,...",
                        help="rate rows, the curtain alone, FD: further nodes a side (default: 256); '' for none")
    parser.add_argument("--rates-settings", default="defaults,before-step-test", metavar="NAME,...",
                        help="rate rows: the Newton settings timed: defaults (as shipped) and/or before-step-test "
                        "(the settings from before issue 27's step test: the force test at rtol 1e-3, a "
                        "factorisation every solve) (default: both)")
    parser.add_argument("--no-rates-references", dest="rates_references", action="store_false",
                        help="rate rows: no tight references (the Newton and time errors not measured; hours saved at "
                        "FD 256)")
    parser.add_argument("--rates-time", default="2", metavar="T",
                        help="rate and peer rows: seconds of motion (default: 2)")
    parser.add_argument("--peers", action="store_true",
                        help="peer rows: newton's VBD and Style3D (pip install '.[peers]') on the 64 x 64 "
                        "hanging cloth at their example budgets, beside this project's hanging cloth on FD 64 x 64 "
                        "nodes, and the three at matched accuracy over 0.1 s (dt 1/60 and 1/600 s, each swept against "
                        "its own most converged run: bench_accuracy.md, .csv, _levels.csv, .png; about 40 minutes) "
                        "(default: off)")


def _realtime_arguments(parser) -> None:
    """The real-time rows' arguments."""
    parser.add_argument("--realtime", default=None, metavar="SCENE",
                        help="the real-time rows alone (none of the tables above): a shipped scene stepped, its "
                        "readout taken and rendered off screen as `deformable view --offscreen` does, at 30 frames a "
                        "simulated second, for --t-end s on --grid nodes and each backend of --backend, in CPU s on "
                        "one thread; a row a run appended to bench_realtime.csv (default: off)")
    parser.add_argument("--grid", default="20x20", metavar="MxN",
                        help="real-time rows: the node grid, as deformable view's (default: 20x20)")
    parser.add_argument("--t-end", default="2", metavar="T",
                        help="real-time rows: seconds of motion (default: 2)")


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
ROW_DEFAULTS = {"implicit": {"fd": "20,64,128", "fe": "16,32"}, "contact": {"fd": "64", "fe": ""},
                "self": {"fd": "32,64", "fe": ""},
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
    t_end = _seconds(args.scene_time, "--scene-time")
    implicit_time = _seconds(args.implicit_time, "--implicit-time")
    self_rows = (_row_sizes(args, "self", backends), _seconds(args.self_time, "--self-time"))
    bar = (_positive_int(args.bar_grid, "--bar-grid"), _seconds(args.bar_time, "--bar-time")) if args.bar else None
    if bar is not None and bar[0] < 3:
        raise InputError(f"--bar-grid needs at least 3 nodes a side, got {args.bar_grid!r}")
    scene_grids = _row_sizes(args, "scene", backends)
    if names and not any(scene_grids.values()):
        raise InputError(f"--scenes {args.scenes!r} needs a grid: --scene-fd or --scene-fe")
    return backends, sizes, (implicit, implicit_time), contact, steps, (names, scene_grids, t_end), _rate_jobs(args), \
        self_rows, bar


def _seconds(text, flag: str) -> float:
    """A positive number of seconds; InputError naming ``flag`` otherwise."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"{flag} must be a positive number of seconds, got {text!r}")
    return value


def _rate_jobs(args) -> tuple:
    """The rate rows' (scene, backend, n), their seconds of motion, the settings timed and whether the tight
    references run; no rows without --rates (the hanging cloth on FD 64 with --peers)."""
    t_end = _seconds(args.rates_time, "--rates-time")
    jobs = []
    if args.rates:
        names = [name.strip() for name in str(args.rates_scenes).split(",") if name.strip()]
        for name in names:
            if name not in scenes.SCENES:
                raise InputError(f"--rates-scenes: unknown scene {name!r}; known: {', '.join(scenes.SCENES)}")
        fd, fe = (_sizes(getattr(args, f"rates_{b}"), f"--rates-{b}", allow_empty=True) for b in ("fd", "fe"))
        extra = _sizes(args.rates_curtain_fd, "--rates-curtain-fd", allow_empty=True)
        jobs = [(name, "fd", n) for name in names for n in fd] + [(name, "fe", n) for name in names for n in fe]
        jobs += [("curtain", "fd", n) for n in extra if ("curtain", "fd", n) not in jobs]
        if not jobs:
            raise InputError("--rates needs a scene and a grid: --rates-scenes with --rates-fd or --rates-fe")
    if args.peers and ("hanging", "fd", 64) not in jobs:
        jobs.append(("hanging", "fd", 64))
    settings = tuple(name.strip() for name in str(args.rates_settings).split(",") if name.strip())
    for name in settings:
        if name not in RATE_SETTINGS:
            raise InputError(f"--rates-settings: unknown settings {name!r}; known: {', '.join(RATE_SETTINGS)}")
    if not settings:
        raise InputError("--rates-settings needs at least one of " + ", ".join(RATE_SETTINGS))
    return jobs, t_end, settings, args.rates_references


def execute(args) -> int:
    """``deformable bench``: print the tables and write bench.csv (and bench_implicit.csv, bench_contact.csv,
    bench_scenes.csv for the rows asked for)."""
    from validation.harness.report import writable_folder

    parsed = _parse(args)
    if args.realtime is not None:  # the real-time rows alone
        return _realtime(args, parsed[0])
    backends, sizes, (implicit, implicit_time), contact, (steps, contact_steps), (names, scene_grids, t_end), rates, \
        (self_grids, self_time), bar = parsed
    out = writable_folder(Path(args.out) if args.out else Path("reports") / "bench")
    rows = [in_own_process(bench_one, b, n, steps, args.solver) for b in backends for n in sizes]
    emit(out / "bench.csv", rows, format_table,
          [("ratio", lambda r: r.ratio), ("same_ratio", lambda r: r.same_ratio)])
    irows = [in_own_process(bench_implicit, b, n, implicit_time, args.solver) for b in ("fd", "fe")
             for n in implicit[b]]
    emit(out / "bench_implicit.csv", irows, format_implicit,
          [("floor_step", lambda r: r.floor_step), ("floor_iteration", lambda r: r.floor_iteration),
           ("step_ratio", lambda r: r.step_ratio), ("iteration_ratio", lambda r: r.iteration_ratio),
           ("semi_ratio", lambda r: r.semi_ratio)])
    crows = [in_own_process(bench_contact, b, n, contact_steps, args.solver) for b in ("fd", "fe")
             for n in contact[b]]
    emit(out / "bench_contact.csv", crows, format_contact,
          [("step_ratio", lambda r: r.step_ratio), ("iteration_ratio", lambda r: r.iteration_ratio),
           ("self_ratio", lambda r: r.self_ratio), ("self_share", lambda r: r.self_share)])
    selfrows = []
    for b in ("fd", "fe"):
        for n in self_grids[b]:  # minutes each: say which one runs
            print(f"self-contact row: curtain {b} {n}x{n}, {self_time:g} s with and without", flush=True)
            selfrows.append(in_own_process(bench_self, b, n, self_time))
    emit(out / "bench_self.csv", selfrows, format_self, [("ratio", lambda r: r.ratio)])
    if bar is not None:
        from validation.benches.bar import bench_bar, format_bar

        print(f"the curtain bar: FD {bar[0]}x{bar[0]}, {bar[1]:g} s (three runs: the row and its tight references)",
              flush=True)
        emit(out / "bench_bar.csv", [bench_bar(*bar)], format_bar,
             [("bar", lambda r: r.bar), ("error_ratio", lambda r: r.error_ratio)])
    jobs = [(name, b, n) for name in names for b in ("fd", "fe") for n in scene_grids[b]]
    srows = []
    for k, (name, b, n) in enumerate(jobs, 1):  # minutes each: say which one runs
        print(f"scene {k} of {len(jobs)}: {name} {b} {n}x{n}, {t_end:g} s of motion", flush=True)
        srows.append(in_own_process(bench_scene, name, b, n, t_end, args.solver))
    emit(out / "bench_scenes.csv", srows, format_scenes)
    _rates(out, *rates, args.peers)
    return 0


def _rates(out: Path, jobs, t_end: float, settings, references: bool, peers: bool) -> None:
    """The rate rows, the peer rows and the verdicts computed from them (bench_rates.md)."""
    from validation.benches.peers import bench_peers, format_peers
    from validation.benches.rates import bench_rates, format_rates, verdicts

    rows = []
    for k, (name, b, n) in enumerate(jobs, 1):  # minutes to hours each: say which one runs
        print(f"rate rows {k} of {len(jobs)}", flush=True)
        rows += bench_rates(name, b, n, t_end, settings, references=references)
    emit(out / "bench_rates.csv", rows, format_rates)
    prows = []
    if peers:
        print(f"peer rows: newton's VBD and Style3D on the 64 x 64 hanging cloth, {t_end:g} s", flush=True)
        prows = in_own_process(bench_peers, 64, t_end)
        emit(out / "bench_peers.csv", prows, format_peers)
        from validation.benches.accuracy import T_END, bench_accuracy

        print(f"matched accuracy: ours, VBD and Style3D on the 64 x 64 hanging cloth over {T_END:g} s, each swept "
              "against its own most converged run (tens of minutes)", flush=True)
        bench_accuracy(out, progress=print)
    if rows:
        lines = verdicts(rows, prows)
        print("\n".join(lines))
        (out / "bench_rates.md").write_text("# Rates: the speed and accuracy targets, computed from this run\n\n"
                                            + "".join(f"- {line}\n" for line in lines))
        print(f"wrote {out / 'bench_rates.md'}")


def _realtime(args, backends) -> int:
    """The real-time rows (``--realtime``; :mod:`validation.benches.realtime`): SCENE on each of ``backends``, each
    in a process of its own, printed and appended to bench_realtime.csv. Bad input is refused before any work."""
    from deformable.checks import extra
    from validation.benches.realtime import bench_realtime, format_realtime, write_row
    from validation.commands.run import parse_grid
    from validation.harness.report import writable_folder

    name = str(args.realtime).strip()
    if name not in scenes.SCENES:
        raise InputError(f"--realtime: unknown scene {name!r}; known: {', '.join(scenes.SCENES)}")
    M, N = parse_grid(args.grid)  # (its message names --grid)
    try:
        scenes.build(scenes.config(name, nodes=(M, N)))  # a grid the scene refuses (its margins), in a millisecond
    except InputError as err:
        raise InputError(f"--grid: {err}") from None
    t_end = _seconds(args.t_end, "--t-end")
    extra("pyvista", "render", "deformable bench --realtime")  # missing: one line saying how to install it
    out = writable_folder(Path(args.out) if args.out else Path("reports") / "bench")
    path = out / "bench_realtime.csv"
    for k, b in enumerate(backends, 1):
        print(f"real-time row {k} of {len(backends)}: {name} {b} {M}x{N} nodes, {t_end:g} s of motion", flush=True)
        row, status = in_own_process(bench_realtime, name, b, f"{M}x{N}", t_end)
        print(format_realtime([row]))
        if status != "running":
            print(f"{name} {b}: {status} at t = {row.sim_seconds:.3f} s")
        appended = write_row(path, row)
        print(f"{'appended to' if appended else 'wrote'} {path}")
    return 0
