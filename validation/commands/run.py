r"""``deformable run``: run a scene, write an XDMF time series, pictures and checkpoints.

::

    deformable run SCENE|FILE.toml [KEY=VALUE ...] [--backend fd|fe] [--force-model M] [--scheme S]
                   [--steps N | --t-end T] [--dt DT] [--grid MxN] [--out DIR] [--overwrite]
                   [--render] [--every SECONDS] [--field NAME] [--checkpoint-every K] [--resume FILE]
                   [--compress | --no-compress] [--show-config]

The scene is a name of :data:`deformable.scenes.SCENES` or a TOML file
(``scene = "curtain"`` plus fields; :func:`deformable.scenes.read_toml`).
``KEY=VALUE`` sets any field of the scene's config (``eta=25``,
``nodes=16x16``, ``force_model=frozen``; values are TOML, a bare word is a
string; the grid ``nodes`` is ``MxN``, ``[M, N]`` or ``N``, read as
``deformable sweep`` reads it: :func:`parse_grid`); the options --grid, --dt,
--force-model override last (their definitions, :func:`run_options`, are
shared with ``deformable sweep``). A grid not set (by ``nodes=``, --grid, the
scene file or the checkpoint) is the scene's, written in FD's nodes, taken in
the backend's unit: FE half as many elements a side. The grid, model, dt and
the run itself come from :class:`deformable.Simulation`, as each case of a
sweep takes them: the same scene and backend give the same grid.
``--show-config`` prints every field of the resolved config (value, default,
unit, meaning: the config classes' docstrings, :mod:`deformable.scenes.fields`)
and exits without running. ``--compress`` / ``--no-compress`` gzip the series'
HDF5 datasets or not (default: above 32 x 32 nodes; :class:`deformable.io.XDMFWriter`).

Reproducible runs. The resolved config is written beside the results as
``<out>/<scene>.toml``: every scene field (with ``t_end`` the time the run
was asked to end at, or steps x dt after --steps, and ``dt`` the step it took), and a ``[run]`` table with
the backend, the scheme, the number of steps when --steps was given, the frame
interval and the package version. ``deformable run <out>/<scene>.toml``
reproduces the run bit for bit (its ``[run]`` table gives the backend and the
scheme; options on the command line still override).

Output folders. The default ``--out`` is ``runs/<scene>``, or ``runs/<scene>-2``, ...
when that already holds results. A run never mixes with another run's
results (:mod:`deformable.io.folder`): an ``--out`` holding them is refused
unless ``--overwrite`` is given (they are then removed first), and a lock keeps
two runs out of one folder.

The time stepping is eq. (22)-(27) (:class:`deformable.TimeStepper`); the
output is written as the run goes (:mod:`deformable.io`), so a killed run
keeps its frames. ``--steps N`` means: run until step N (a resumed run ends at
the same step as the uninterrupted one); ``--t-end T`` likewise ends at time T,
exactly (the last step is shortened where T is not a whole number of steps).
``--every S`` writes a frame every S seconds of simulated time (the first step
at or past each multiple of S), so the frames do not depend on the backend's dt.

Checkpoints (``--checkpoint-every K``) hold X, V, A, t, step, the constraint
reference X0, the resolved config and the controller's memory (the adapted
step: :meth:`deformable.TimeStepper.memory`); ``--resume FILE`` continues from
one, bit-identical to an uninterrupted run, also one whose implicit step
adapted. Any difference between the scene (file, ``KEY=VALUE``, options) and
the checkpoint's config is refused, naming the field (the scene may be left
out: the checkpoint's is taken). The resumed run continues the series
``<scene>.xdmf`` of the checkpoint's folder (by default its ``--out``; another
folder gets a copy of it first), dropping its frames after the checkpoint, so
the series equals the uninterrupted run's frame by frame, ``displacement``
measured from the original start. A series that ends before the checkpoint
(cut back by a resume from an earlier one) is refused, naming the last step it
reaches; the checkpoints later than the one resumed from are removed when the
resumed run starts (their frames are gone). The summary line gives the
smallest, median and largest step taken where they differ from the requested
dt. A diverging run stops at the step that diverged, keeps its frames and
writes a checkpoint of the last good state (``<scene>-diverged.npz``); the
command then exits 1.

Bad input (unknown scene or key, malformed grid, dt <= 0, an output folder that
cannot be written or holds another run's results, a resume file that is damaged
or does not fit) is reported in one line on stderr with exit code 2 before
anything is written.
"""

from __future__ import annotations

import argparse
import logging
import sys
import time

import numpy as np
from pathlib import Path

import deformable
from deformable import scenes
from deformable.checks import extra, known_keys
from deformable.errors import InputError
from deformable.io import frame_time, load_checkpoint
from deformable.io.folder import fresh
from deformable.io.render import FIELDS, render_series
from deformable.session import DEFAULT_EVERY, Simulation
from validation.harness import drape

from .options import (backend_option, check_backend, check_force_model, force_model_option, option_fields,
                      parse_grid, parse_overrides, positive, print_config, run_options, scene_config, scene_source,
                      sets_grid, show_config_option)

__all__ = ["configure", "execute", "prepare", "resolve", "RUN_KEYS", "DEFAULT_EVERY",
           # the options the commands share (validation.commands.options), as they were imported from here
           "parse_grid", "parse_overrides", "scene_config", "scene_source", "sets_grid", "run_options",
           "backend_option", "force_model_option", "show_config_option", "print_config", "check_backend",
           "check_force_model", "option_fields", "positive"]

log = logging.getLogger(__name__)

#: keys of the [run] table of a resolved config
RUN_KEYS = ("backend", "scheme", "steps", "every", "version")
#: a line on a run's final state, by scene: what the scene measures (the drape coefficient)
MEASURES = {"drape": drape.final_line}


def configure(parser) -> None:
    """Arguments of ``deformable run``."""
    parser.add_argument("scene", metavar="SCENE|FILE.toml", nargs="?", default=None,
                        help=f"a scene name ({', '.join(scenes.SCENES)}) or a TOML scene file, e.g. a run's resolved "
                        "config (default with --resume: the checkpoint's scene)")
    parser.add_argument("overrides", metavar="KEY=VALUE", nargs="*", default=[],
                        help="set a field of the scene's config, e.g. eta=25 nodes=16x16 force_model=frozen "
                        "(values are TOML; default: none)")
    run_options(parser)
    parser.add_argument("--out", default=None,
                        help="output folder (default: runs/<scene>, or runs/<scene>-2, ... if that holds results; "
                        "with --resume: the checkpoint's folder)")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace another run's results in --out (default: refuse such a folder)")
    parser.add_argument("--render", action="store_true",
                        help="render PNG frames and a GIF (pyvista, offscreen) (default: off)")
    parser.add_argument("--every", type=str, default=None,
                        help=f"write a frame every this many seconds of simulated time (default: {DEFAULT_EVERY})")
    parser.add_argument("--field", default="speed", help=f"field that colours the frames: {', '.join(FIELDS)}")
    parser.add_argument("--checkpoint-every", type=str, default=None,
                        help="write a checkpoint every K steps (default: none)")
    parser.add_argument("--resume", default=None, help="continue from a checkpoint file (.npz) (default: none)")
    parser.add_argument("--compress", action=argparse.BooleanOptionalAction, default=None,
                        help="gzip the series' HDF5 datasets (default: automatic, on above 32 x 32 nodes)")
    show_config_option(parser)


def _table(text: str | None, source: str) -> dict:
    """The [run] table of a scene file, its keys checked."""
    if text is None:
        return {}
    table = scenes.run_table(text, source)
    known_keys(table, RUN_KEYS, f"in the [run] table of {source!r}")
    if table.get("version", deformable.__version__) != deformable.__version__:
        log.warning("%s was written by deformable %s, this is %s: the numbers may differ", source,
                    table["version"], deformable.__version__)
    return table


def resolve(args, dt: float | None = None):
    """The run ``args`` ask for (scene, overrides, backend, grid, force_model, resume, scheme), not yet prepared:
    (its :class:`deformable.Simulation`, the scene file's [run] table, the fields set on the command line, the
    checkpoint or None); ``dt`` the checked --dt. InputError on bad input; nothing written."""
    items = list(args.overrides)
    if args.scene is not None and "=" in args.scene and not args.scene.endswith(".toml"):
        items.insert(0, args.scene)  # deformable run --resume CK eta=2: no scene, overrides only
        args.scene = None
    overrides = parse_overrides(items)
    cli = option_fields(args, dt, t_end=False)
    for key in set(cli) & set(overrides):
        if cli[key] != overrides[key]:
            raise InputError(f"scene field {key} is {overrides[key]!r} as KEY=VALUE but {cli[key]!r} as an option",
                             field=key, value=overrides[key])
    resume = getattr(args, "resume", None)
    checkpoint = load_checkpoint(resume, t0=0.0) if resume is not None else None  # the command's runs start at 0
    if args.scene is None and checkpoint is None:
        raise InputError("name a scene or a scene file (or --resume a checkpoint)", field="scene", value=None)
    text, source = (scene_source(args.scene) if args.scene is not None
                    else (checkpoint["config"], f"the checkpoint {resume}"))
    table = _table(text, source)
    fields_ = {**overrides, **cli}
    cfg = (scenes.read_toml_text(text, source=source, **fields_) if text is not None
           else scenes.config(source, **fields_))
    backend = args.backend or table.get("backend") or (checkpoint["backend"] if checkpoint else "fd")
    check_backend(backend, "--backend" if args.backend else f"backend (the [run] table of {source})")
    given = "nodes" in fields_ or sets_grid(text, source) or checkpoint is not None
    sim = Simulation(cfg, backend, nodes=cfg.nodes if given else None, dt=cfg.dt if "dt" in fields_ else None,
                     scheme=getattr(args, "scheme", None) or table.get("scheme"),
                     overwrite=getattr(args, "overwrite", False))
    _explain(sim)
    return sim, table, fields_, checkpoint


def _explain(sim: Simulation) -> None:
    """Log where the run's grid or step is not the scene's, and warn where the step passes the stable one."""
    cfg, asked, backend = sim.config, sim.asked, sim.backend
    if cfg.nodes != asked.nodes:  # the scene's grid is FD's: FE takes half as many elements a side
        log.info("%dx%d nodes (%dx%d %s) for the %s backend: the scene's %dx%d taken in its own unit (--grid "
                 "sets it)", *cfg.nodes, cfg.nodes[0] - 1, cfg.nodes[1] - 1, sim.descriptor.grid, backend,
                 *asked.nodes)
    # the scenes' default dt is the FD one; a backend with a tighter stretching bound gets its own.
    # The bound comes from lagging alpha (eq. 25): the frozen and variational models have none (inf).
    bound = sim.model.stable_step()
    if cfg.dt != asked.dt:
        log.info("dt = %g s for the %s backend (half its stretching bound %.3g s)", cfg.dt, backend, bound)
    if cfg.dt > bound:
        log.warning("dt = %g s exceeds the %s backend's stretching stability bound %.3g s "
                    "(docs/design.md, 'Time stepping'): expect divergence", cfg.dt, backend, bound)


def _length(table, fields_, steps, t_end):
    """--steps, else a resolved config's [run] steps (a run given --steps) where neither --t-end nor t_end=
    is set."""
    if steps is None and t_end is None and "steps" in table and "t_end" not in fields_:
        return positive("steps", table["steps"], int)
    return steps


def prepare(args) -> Simulation:
    """The run ``args`` ask for, every input checked and the output folder with it: a prepared
    :class:`deformable.Simulation` (:meth:`~deformable.Simulation.prepare`). InputError on bad input; nothing
    written."""
    if args.field not in FIELDS:
        raise InputError(f"unknown field {args.field!r}; choose one of {', '.join(FIELDS)}", field="--field",
                         value=args.field)
    if args.render:  # pyvista missing: one line saying how to install it, before anything is written
        extra("pyvista", "render", "deformable run --render")
    dt, steps = positive("dt", args.dt), positive("steps", args.steps, int)
    t_end, every = positive("t-end", args.t_end), positive("every", args.every)
    ck_every = positive("checkpoint-every", args.checkpoint_every, int)
    sim, table, fields_, checkpoint = resolve(args, dt)
    if checkpoint is not None:
        sim.resume(args.resume, checkpoint)
        sim.out = Path(args.out) if args.out else Path(args.resume).resolve().parent
    else:
        sim.out = Path(args.out) if args.out else fresh(Path("runs") / sim.config.scene)
    every = every if every is not None else positive("every", table.get("every", DEFAULT_EVERY))
    return sim.prepare(t_end=t_end, steps=_length(table, fields_, steps, t_end), every=every, checkpoint_every=ck_every,
                       compress=getattr(args, "compress", None))


def _steps_line(stepper, dt: float) -> str:
    """What the steps of this run were: "dt = 5 s", or, where they differ, their smallest, median and largest."""
    taken = stepper.steps_taken
    if taken.size == 0 or np.allclose(taken, dt, rtol=1e-9, atol=0):
        return f"dt = {dt:g} s"
    low, mid, high = np.min(taken), np.median(taken), np.max(taken)
    return f"dt {low:.3g} to {high:.3g} s, median {mid:.3g} s, over the {taken.size} steps taken; requested {dt:g} s"


def execute(args) -> int:
    """``deformable run``: returns 0 when the run finished, 1 when it diverged."""
    quiet = getattr(args, "quiet", False)
    if getattr(args, "show_config", False):  # the config the run would take, field by field; no run
        sim, table, fields_, _ = resolve(args, positive("dt", args.dt))
        t_end = positive("t-end", args.t_end)
        steps = _length(table, fields_, positive("steps", args.steps, int), t_end)
        return print_config(_shown(sim, steps, t_end))
    sim = prepare(args)
    cfg = sim.config
    if not quiet:  # the paper's two parameter groups and what they imply (deformable params)
        print("\n".join(scenes.parameters(cfg, sim.model, sim.backend).lines()), flush=True)
    t0 = time.perf_counter()
    result = sim.run(progress=False if quiet else cfg.scene)
    wall = time.perf_counter() - t0
    if result.status == "diverged":
        print(f"{cfg.scene}: {result.message}; kept {sim.series.frames} frames in {sim.series.path}, "
              f"last good state (t = {result.state.t:.6g} s) in {sim.checkpoints[-1]}", file=sys.stderr)
    if args.render:
        pngs = render_series(sim.series.path, sim.out / "frames", field=args.field, progress=not quiet,
                             title=f"{cfg.scene} ({sim.backend}, {cfg.nodes[0]}x{cfg.nodes[1]})",
                             obstacles=sim.scene.obstacles)
        if pngs and not quiet:
            print(f"rendered {len(pngs) - 1} frames and {pngs[-1]}")
    if not quiet:
        _summary(sim, result, wall)
    return 0 if result.status != "diverged" else 1


def _shown(sim: Simulation, steps, t_end):
    """The config ``--show-config`` prints: the run's, its t_end where the run would stop."""
    if steps is not None:
        return sim.config.replace(t_end=frame_time(steps * sim.config.dt))
    return sim.config.replace(t_end=t_end) if t_end is not None else sim.config


def _summary(sim: Simulation, result, wall: float) -> None:
    """The run's closing lines: status, steps, energies, frames; the clearance and the scene's measure."""
    cfg, model = sim.config, sim.model
    e, kinetic = model.energy(result.state.X), model.kinetic_energy(result.state.V)
    print(f"{cfg.scene}: {result.status}, {result.steps} steps to t = {result.state.t:.6g} s "
          f"({_steps_line(sim.stepper, cfg.dt)}, {cfg.nodes[0]}x{cfg.nodes[1]} {sim.backend}, "
          f"{sim.stepper.scheme}) in {wall:.1f} s wall; energy: stretching {e.stretching:.4g} J, bending "
          f"{e.bending:.4g} J, kinetic {kinetic:.4g} J; {sim.series.frames} frames in {sim.series.path}")
    if sim.clearances:
        print(f"{cfg.scene}: smallest clearance over {len(sim.clearances)} steps {min(sim.clearances):.3g} m "
              f"(final {sim.clearances[-1]:.3g} m)")
    if cfg.scene in MEASURES:
        print(f"{cfg.scene}: {MEASURES[cfg.scene](cfg, model, result.state.X)}")
