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
the backend's unit: FE half as many elements a side. The grid, model and dt
come from :func:`validation.harness.backends.run_model`, as each case of a
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
import math
import re
import shutil
import sys
import time
import tomllib
from dataclasses import fields
from pathlib import Path

import ipctk
import numpy as np

import deformable
from deformable import scenes, tomlio
from deformable.backends.registry import Discretisation
from deformable.checks import extra, known_keys
from deformable.contact.clearance import clearance, require_clear
from deformable.dynamics import SCHEMES, Callback, EnergyMonitor, State, TimeStepper
from deformable.errors import InputError
from deformable.io import CheckpointWriter, XDMFWriter, frame_time, load_checkpoint, save_checkpoint
from deformable.io.folder import RunFolder, fresh, write_text
from deformable.io.render import FIELDS, render_series
from deformable.io.series import continuation
from deformable.limits import check_series
from deformable.physics.force_models import ForceModel
from validation.harness import drape
from validation.harness.backends import descriptor, run_model

__all__ = ["configure", "execute", "parse_grid", "parse_overrides", "scene_config", "scene_source", "sets_grid",
           "Run", "prepare", "resolve", "simulate",
           "RUN_KEYS", "DEFAULT_EVERY", "run_options", "backend_option", "force_model_option", "show_config_option",
           "print_config", "check_backend", "check_force_model", "option_fields"]

log = logging.getLogger(__name__)

#: keys of the [run] table of a resolved config
RUN_KEYS = ("backend", "scheme", "steps", "every", "version")
#: the default frame interval (s of simulated time)
DEFAULT_EVERY = 0.02
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


# -- options shared with the other commands ----------------------------------------------
def backend_option(parser, default=None, default_text="the scene file's [run] backend, else fd",
                   many: bool = False) -> None:
    """``--backend``, its choices (the registered backends) in its help."""
    names = Discretisation.names()
    choices = f"one of {', '.join(names)}" + (f", or several comma-separated (e.g. {','.join(names)})" if many else "")
    parser.add_argument("--backend", default=default, metavar="NAME" + (",..." if many else ""),
                        help=f"discretisation: {choices} (default: {default_text})")


def force_model_option(parser, default_text="the scene's, variational") -> None:
    """``--force-model``, its choices (the registered force models) in its help."""
    parser.add_argument("--force-model", default=None, metavar="MODEL",
                        help=f"force model: one of {', '.join(ForceModel.names())} (default: {default_text}); frozen "
                        "takes the scene keys alpha and beta")


def run_options(parser, sweep: bool = False) -> None:
    """The options ``deformable run`` and ``deformable sweep`` share: --backend, --force-model, --grid, --dt,
    --t-end (and, for run only, --scheme and --steps); :func:`option_fields` reads them."""
    if sweep:
        backend_option(parser, default="fd", default_text="fd", many=True)
    else:
        backend_option(parser)
    force_model_option(parser)
    if not sweep:  # (a sweep's cases step with the backend's default scheme: validation.harness.sweep)
        parser.add_argument("--scheme", default=None, choices=SCHEMES,
                            help="time-stepping scheme (default: the scene file's [run] scheme, else implicit-euler "
                            "for the variational model, semi-implicit for tpbf87 and frozen)")
    length = parser if sweep else parser.add_mutually_exclusive_group()
    if not sweep:
        length.add_argument("--steps", type=str, default=None,
                            help="run until this step number (default: run to t_end)")
    length.add_argument("--t-end", type=str, default=None, metavar="T",
                        help="run until this time (s), exactly (default: the scene's t_end)")
    parser.add_argument("--dt", type=str, default=None,
                        help="time step (s) (default: the scene's, or half the backend's stable step if smaller)")
    parser.add_argument("--grid", default=None, metavar="MxN",
                        help="node grid MxN (default: the scene's nodes on fd; on fe half as many elements a side, "
                        "e.g. 64x64 nodes -> 32x32 elements, 33x33 nodes)")


def show_config_option(parser) -> None:
    """``--show-config``: print the scene's config, field by field, and exit (:func:`print_config`)."""
    parser.add_argument("--show-config", action="store_true",
                        help="print every field of the scene's config (value after KEY=VALUE, the scene file and "
                        "the options; default; unit; meaning) and exit without running (default: off)")


def print_config(cfg: scenes.SceneConfig) -> int:
    """Print the aligned table of a config's fields (:func:`deformable.scenes.config_table`); 0."""
    print("\n".join(scenes.config_table(cfg)))
    return 0


def _registered(family, name, field: str) -> str:
    """``name`` if ``family`` (a registry) knows it; else its lookup's InputError, prefixed by the field."""
    try:
        family.lookup(name)
    except InputError as err:
        raise InputError(f"{field}: {err}", field=field, value=name) from None
    return name


def check_backend(name, field: str = "--backend") -> str:
    """``name`` if it is a registered backend; else InputError naming the field, the value and the choices."""
    return _registered(Discretisation, name, field)


def check_force_model(name, field: str = "--force-model") -> str:
    """``name`` if it is a registered force model; else InputError naming the field, the value and the choices."""
    return _registered(ForceModel, name, field)


def option_fields(args, dt=None, t_end: bool = True) -> dict:
    """The scene fields the shared options set (--grid: nodes, --dt, --t-end, --force-model), checked;
    ``dt`` the checked --dt where the caller has it; ``t_end`` False leaves --t-end out (a run's length, which
    :func:`prepare` sets)."""
    out = {}
    if getattr(args, "grid", None) is not None:
        out["nodes"] = parse_grid(args.grid)
    dt = dt if dt is not None else positive("dt", getattr(args, "dt", None))
    if dt is not None:
        out["dt"] = dt
    end = positive("t-end", getattr(args, "t_end", None)) if t_end else None
    if end is not None:
        out["t_end"] = end
    if getattr(args, "force_model", None) is not None:
        out["force_model"] = check_force_model(args.force_model)
    return out


# -- parsing -------------------------------------------------------------------------
#: a node grid as text: MxN, or a TOML array [M, N] (as a scene file and the resolved config write it)
GRID = re.compile(r"\s*(\d+)\s*[xX]\s*(\d+)\s*|\s*\[\s*(\d+)\s*,\s*(\d+)\s*,?\s*\]\s*")


def parse_grid(text: str, field: str = "--grid", square: bool = False) -> tuple[int, int]:
    """A node grid (M, N) from ``"MxN"`` or ``"[M, N]"``; with ``square`` (the KEY=VALUE form of run and sweep,
    ``nodes=...``) also ``"N"`` for N x N. The one grid grammar of the commands. InputError naming ``field``
    unless two integers >= 3."""
    text = str(text)
    m = GRID.fullmatch(text) or (re.fullmatch(r"\s*(\d+)\s*", text) if square else None)
    if not m:
        raise InputError(f"{field}: malformed grid {text!r}: expected MxN or [M, N], e.g. 32x32"
                         + (" (or N for NxN)" if square else ""), field=field, value=text)
    numbers = [int(g) for g in m.groups() if g is not None]
    M, N = numbers if len(numbers) == 2 else numbers * 2
    if min(M, N) < 3:
        raise InputError(f"{field}: grid {text!r} needs at least 3 nodes a side", field=field, value=text)
    return M, N


def parse_overrides(items) -> dict:
    """``["eta=25", "nodes=16x16", "force_model=frozen"]`` -> a dict of scene fields.

    Values are TOML, a bare word is text; ``nodes`` is a grid, ``MxN``, ``[M, N]`` or ``N`` (:func:`parse_grid`,
    as ``deformable sweep`` reads it). InputError for an item without ``=``, a malformed grid or a key given
    twice; unknown keys are refused by the scene's config.
    """
    out = {}
    for item in items:
        key, sep, text = str(item).partition("=")
        key = key.strip()
        if not sep or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", key):
            raise InputError(f"expected KEY=VALUE, e.g. eta=25, got {item!r}", field="KEY=VALUE", value=item)
        if key in out:
            raise InputError(f"scene field {key} is given twice on the command line", field=key, value=text)
        if key == "nodes":
            out[key] = parse_grid(text, field=key, square=True)
            continue
        try:
            value = tomllib.loads(f"v = {text}")["v"]
        except tomllib.TOMLDecodeError:
            value = text.strip()  # a bare word: a string (force_model=frozen)
        out[key] = tuple(value) if isinstance(value, list) else value
    return out


def scene_config(scene: str, **overrides) -> scenes.SceneConfig:
    """The config of a scene name or a TOML scene file (``*.toml``), with overrides; InputError naming what is wrong."""
    if scene.endswith(".toml"):
        return scenes.read_toml(scene, **overrides)
    return scenes.config(scene, **overrides)


def scene_source(scene: str) -> tuple[str | None, str]:
    """(the text of a scene file, its name) or (None, a scene name)."""
    if not scene.endswith(".toml"):
        return None, scene
    return tomlio.read_text(scene, field="scene"), scene


def sets_grid(text: str | None, source: str) -> bool:
    """Whether a scene file's text (None for a scene name: no) sets the grid, ``nodes``: a grid so set is taken as
    is on every backend (:func:`validation.harness.backends.run_grid`)."""
    return text is not None and "nodes" in tomlio.loads(text, source)


def positive(name: str, text, kind=float):
    if text is None:
        return None
    try:
        value = kind(text)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"--{name} must be a positive {'integer' if kind is int else 'number'}, got {text!r}",
                     field=f"--{name}", value=text) from None
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"--{name} must be positive, got {text!r}", field=f"--{name}", value=text)
    return value


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


def _differences(a: scenes.SceneConfig, b: scenes.SceneConfig, skip=("t_end",)) -> list[str]:
    """The fields (but ``skip``) in which two configs differ, as 'name = a vs b'."""
    if a.scene != b.scene:
        return [f"scene = {a.scene!r} vs {b.scene!r}"]
    return [f"{f.name} = {getattr(a, f.name)!r} vs {getattr(b, f.name)!r}" for f in fields(a)
            if f.name not in skip and getattr(a, f.name) != getattr(b, f.name)]


class Run:
    """A prepared run: everything checked, nothing written yet.

    Attributes: ``config`` (the resolved scene config), ``settings`` (the [run] table), ``scene``, ``model``,
    ``stepper``, ``X0`` (constraint reference, (ndof, 3)), ``start`` (State or None: a resume point),
    ``steps`` / ``t_end`` (where to stop; one is None), ``every`` (frame interval, s), ``folder``
    (a :class:`RunFolder`), ``out`` (its path), ``series`` (a series to continue, or None), ``backend``.
    """


def resolve(args, dt: float | None = None):
    """The scene config, its [run] table, the fields set on the command line, the checkpoint (or None), the
    backend's name, the Scene and the model of ``args`` (scene, overrides, backend, grid, force_model,
    resume); ``dt`` the checked --dt. InputError on bad input; nothing written."""
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

    checkpoint = None
    if args.resume is not None:
        checkpoint = load_checkpoint(args.resume, t0=0.0)  # the command's runs start at t = 0
    if args.scene is None and checkpoint is None:
        raise InputError("name a scene or a scene file (or --resume a checkpoint)", field="scene", value=None)
    text, source = (scene_source(args.scene) if args.scene is not None
                    else (checkpoint["config"], f"the checkpoint {args.resume}"))
    table = _table(text, source)
    fields_ = {**overrides, **cli}
    cfg = (scenes.read_toml_text(text, source=source, **fields_) if text is not None
           else scenes.config(source, **fields_))
    backend = args.backend or table.get("backend") or (checkpoint["backend"] if checkpoint else "fd")
    check_backend(backend, "--backend" if args.backend else f"backend (the [run] table of {source})")
    given = "nodes" in fields_ or sets_grid(text, source) or checkpoint is not None
    asked = cfg
    cfg, scene, model = run_model(cfg, backend, nodes=cfg.nodes if given else None,
                                  dt=cfg.dt if "dt" in fields_ else None)
    if cfg.nodes != asked.nodes:  # the scene's grid is FD's: FE takes half as many elements a side
        log.info("%dx%d nodes (%dx%d %s) for the %s backend: the scene's %dx%d taken in its own unit (--grid "
                 "sets it)", *cfg.nodes, cfg.nodes[0] - 1, cfg.nodes[1] - 1, descriptor(backend).grid, backend,
                 *asked.nodes)
    # the scenes' default dt is the FD one; a backend with a tighter stretching bound gets its own.
    # The bound comes from lagging alpha (eq. 25): the frozen and variational models have none (inf).
    bound = model.stable_step()
    if cfg.dt != asked.dt:
        log.info("dt = %g s for the %s backend (half its stretching bound %.3g s)", cfg.dt, backend, bound)
    if cfg.dt > bound:
        log.warning("dt = %g s exceeds the %s backend's stretching stability bound %.3g s "
                    "(docs/design.md, 'Time stepping'): expect divergence", cfg.dt, backend, bound)
    return cfg, table, fields_, checkpoint, backend, scene, model


def prepare(args) -> Run:
    """Check all input and build the model; raises InputError (a ValueError) on bad input, writes nothing."""
    run = Run()
    if args.field not in FIELDS:
        raise InputError(f"unknown field {args.field!r}; choose one of {', '.join(FIELDS)}", field="--field",
                     value=args.field)
    if args.render:  # pyvista missing: one line saying how to install it, before anything is written
        extra("pyvista", "render", "deformable run --render")
    dt = positive("dt", args.dt)
    steps = positive("steps", args.steps, int)
    t_end = positive("t-end", args.t_end)
    every = positive("every", args.every)
    ck_every = positive("checkpoint-every", args.checkpoint_every, int)
    cfg, table, fields_, checkpoint, backend, scene, model = resolve(args, dt)
    stepper = TimeStepper(model, cfg.dt, scheme=args.scheme or table.get("scheme"))

    if checkpoint is not None:
        _fits(args.resume, checkpoint, cfg, backend, stepper)
        X0 = checkpoint["X0"]
        if checkpoint["memory"] is not None:  # the adapted step and the rest of the controller's memory
            try:
                stepper.restore(checkpoint["memory"])
            except InputError as err:
                raise InputError(f"resume file {str(args.resume)!r}: {err}", field="resume",
                                 value=args.resume) from None
        elif stepper.adaptive:
            log.warning("%s holds no controller memory (an earlier version wrote it): the resumed run starts at "
                        "dt = %g s and differs from the uninterrupted one wherever its step adapted", args.resume,
                        cfg.dt)
        run.start = State(t=checkpoint["t"], X=checkpoint["X"], V=checkpoint["V"], step=checkpoint["step"],
                          A=checkpoint["A"])
    else:
        X0 = model.initial_state()
        run.start = None
    if scene.obstacles:  # a start inside an obstacle cannot be stepped: refused before anything is written
        try:
            require_clear(model, X0 if run.start is None else run.start.X, "the start",
                            0.0 if run.start is None else run.start.t)
        except ValueError as err:
            raise InputError(str(err)) from None
    t_now = 0.0 if run.start is None else run.start.t
    cfg, run.steps, run.t_end, steps = _length(cfg, table, fields_, steps, t_end, checkpoint)
    stepper.length(t_now, steps=run.steps, t_end=run.t_end)  # a bad length or one beyond the cap, before any work
    run.every = every if every is not None else positive("every", table.get("every", DEFAULT_EVERY))
    run.ck_every = ck_every
    if ck_every or args.resume is not None:
        # a run that checkpoints or resumes is resumed bit for bit: the IPC Toolkit's sums over the contact pairs
        # (self-contact, mesh obstacles) run in a varying order on more than one thread and move the last digits
        # (measured: a resumed mesh-obstacle run ended 6.5e-16 m off in one of three); one thread costs the sphere
        # scene 18 % of its wall time (FD 32 x 32, 0.6 s: 32.0 s against 27.2 s)
        ipctk.set_num_threads(1)
    run.render, run.field = args.render, args.field
    run.compress = getattr(args, "compress", None)
    run.config, run.scene, run.model, run.stepper, run.X0, run.backend = cfg, scene, model, stepper, X0, backend
    run.settings = dict(backend=backend, scheme=stepper.scheme, steps=steps, every=run.every,
                        version=deformable.__version__)
    _folder(run, args, checkpoint)
    span = (run.t_end - t_now) if run.t_end is not None else run.steps * cfg.dt  # adaptive steps are at most dt
    check_series(run.out / f"{cfg.scene}.xdmf", cfg.nodes, int(math.ceil(span / run.every)) + 2)
    return run


def _length(cfg, table, fields_, steps, t_end, checkpoint):
    """Where the run stops: (the config with its t_end, the steps left or None, the end time or None, the
    requested step number or None), from --steps / --t-end, else the file's [run] steps, else the config's t_end;
    InputError when the start (the checkpoint's, else t = 0) is already there."""
    t_now = 0.0 if checkpoint is None else checkpoint["t"]
    step_now = 0 if checkpoint is None else checkpoint["step"]
    if steps is None and t_end is None and "steps" in table and "t_end" not in fields_:
        steps = positive("steps", table["steps"], int)  # a resolved config of a run given --steps
    if steps is not None:
        if steps <= step_now:
            raise InputError(f"the run already stands at step {step_now} (t = {t_now:.6g} s); nothing to do until step "
                         f"{steps}", field="--steps", value=steps)
        return cfg.replace(t_end=frame_time(steps * cfg.dt)), steps - step_now, None, steps  # at the requested dt
    t_end = t_end if t_end is not None else cfg.t_end
    if not t_end > t_now * (1 + 1e-12):
        raise InputError(f"the run already stands at t = {t_now:.6g} s (step {step_now}); nothing to do until "
                     f"t = {t_end:.6g} s", field="--t-end", value=t_end)
    return cfg.replace(t_end=t_end), None, t_end, steps


def _fits(path, checkpoint, cfg, backend, stepper) -> None:
    """InputError naming the first field in which the run asked for differs from the checkpoint's."""
    base = scenes.read_toml_text(checkpoint["config"], source=path)
    diff = _differences(cfg, base)
    if checkpoint["backend"] != backend:
        diff.insert(0, f"backend = {backend!r} vs {checkpoint['backend']!r}")
    scheme = scenes.run_table(checkpoint["config"], path).get("scheme")
    if scheme is not None and scheme != stepper.scheme:
        diff.append(f"scheme = {stepper.scheme!r} vs {scheme!r}")
    if checkpoint["dt"] != cfg.dt:
        diff.append(f"dt = {cfg.dt!r} vs {checkpoint['dt']!r}")
    if diff:
        more = f" (and {len(diff) - 1} more)" if len(diff) > 1 else ""
        raise InputError(f"resume file {str(path)!r} does not fit the run asked for: {diff[0]} (asked for vs the "
                     f"checkpoint's){more}", field=diff[0].split(" =")[0], value=path)
    X = checkpoint["X"]
    if X.shape != (stepper.model.ndof, 3):
        raise InputError(f"resume file {str(path)!r} holds states of shape {X.shape}, the scene has "
                     f"({stepper.model.ndof}, 3)", field="resume", value=path)


def _folder(run: Run, args, checkpoint) -> None:
    """The output folder (checked, not yet claimed) and the series a resumed run continues."""
    cfg = run.config
    run.series = None
    if checkpoint is not None:
        home = Path(args.resume).resolve().parent
        out = Path(args.out) if args.out else home
        source = home / f"{cfg.scene}.xdmf"

        def own(folder):  # the checkpoint's own folder, whose config is the run's (but for t_end)
            path = Path(folder) / f"{cfg.scene}.toml"
            try:
                mine = scenes.read_toml(path)
                theirs = scenes.run_table(path.read_text(), str(path)).get("backend", run.backend)
            except (InputError, OSError):
                return False
            return not _differences(mine, cfg) and theirs == run.backend

        if source.is_file() and own(home):
            run.series = source
            continuation(source, run.start.step, run.start.t, run.every)  # a series with a hole is refused
        elif source.is_file():
            log.warning("the series %s is not this run's (its config differs): the resumed run starts a new series",
                        source)
        run.folder = RunFolder(out, overwrite=args.overwrite, own=own)
    else:
        out = Path(args.out) if args.out else fresh(Path("runs") / cfg.scene)
        run.folder = RunFolder(out, overwrite=args.overwrite)
    run.folder.check()
    run.out = run.folder.path


def _abandon(folder: Path, scene: str, step: int) -> None:
    """Remove the checkpoints in ``folder`` later than ``step``: the run resumed from ``step`` replaces them.

    Their series is cut back to ``step``; resumed from, they would leave a hole in it (a diverged run's last
    good state likewise).
    """
    later = [p for k, p in CheckpointWriter.found(folder, f"{scene}-checkpoint").items() if k > step]
    diverged = folder / f"{scene}-diverged.npz"
    if diverged.is_file():
        try:
            if load_checkpoint(diverged)["step"] > step:
                later.append(diverged)
        except InputError:
            pass  # not a checkpoint this run can read: left alone
    for path in later:
        path.unlink(missing_ok=True)
    if later:
        log.warning("removed %d checkpoints later than step %d (%s), of the run this one replaces from there",
                    len(later), step, ", ".join(p.name for p in later[:3]) + (" ..." if len(later) > 3 else ""))


def simulate(run: Run, progress: bool | str = False):
    """Run a prepared run; returns (RunResult, XDMFWriter, EnergyMonitor, list of written checkpoints).

    ``progress``: False, a name to start the progress lines with, or True for the scene's name."""
    cfg = run.config
    progress = cfg.scene if progress is True else progress
    with run.folder:
        config_text = scenes.to_toml(cfg, run.settings)
        write_text(run.out / f"{cfg.scene}.toml", config_text)
        meta = dict(scene=cfg.scene, config=config_text, backend=run.backend, dt=cfg.dt, nodes=cfg.nodes)
        path = run.out / f"{cfg.scene}.xdmf"
        if run.series is not None and run.series.resolve() != path.resolve():
            for src in (run.series, run.series.with_suffix(".h5")):
                shutil.copyfile(src, run.out / src.name)
        if run.start is not None:
            _abandon(run.out, cfg.scene, run.start.step)
        writer = XDMFWriter(path, interval=run.every, reference=run.X0, append=run.start is not None,
                            compress=run.compress)
        energy = EnergyMonitor(every=max(1, int(round(run.every / cfg.dt))))
        trackers = [writer, energy]
        run.clearance = []  # with obstacles: the clearance after every step (m)
        if run.scene.obstacles:
            trackers.append(Callback(lambda s: run.clearance.append(clearance(run.model, s.X, t=s.t))))
        ckpt = None
        if run.ck_every:
            ckpt = CheckpointWriter(run.out, f"{cfg.scene}-checkpoint", run.ck_every, run.X0, **meta)
            trackers.append(ckpt)
        try:
            result = run.stepper.run(run.X0, steps=run.steps, t_end=run.t_end, trackers=trackers, progress=progress,
                                     resume=run.start)
        finally:
            writer.close()
        written = list(ckpt.written) if ckpt else []
        if result.status == "diverged":
            written.append(save_checkpoint(run.out / f"{cfg.scene}-diverged.npz", result.state, run.X0,
                                           memory=run.stepper.memory(), **meta))
    return result, writer, energy, written


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
        cfg, table, fields_, checkpoint, *_ = resolve(args, positive("dt", args.dt))
        steps, t_end = positive("steps", args.steps, int), positive("t-end", args.t_end)
        return print_config(_length(cfg, table, fields_, steps, t_end, checkpoint)[0])
    run = prepare(args)
    if not quiet:  # the paper's two parameter groups and what they imply (deformable params)
        print("\n".join(scenes.parameters(run.config, run.model, run.backend).lines()), flush=True)
    t0 = time.perf_counter()
    result, writer, energy, written = simulate(run, progress=False if quiet else run.config.scene)
    e = run.model.energy(result.state.X)
    kinetic = run.model.kinetic_energy(result.state.V)
    wall = time.perf_counter() - t0
    cfg = run.config
    if result.status == "diverged":
        print(f"{cfg.scene}: {result.message}; kept {writer.frames} frames in {writer.path}, "
              f"last good state (t = {result.state.t:.6g} s) in {written[-1]}", file=sys.stderr)
    if run.render:
        pngs = render_series(writer.path, run.out / "frames", field=run.field, progress=not quiet,
                             title=f"{cfg.scene} ({run.backend}, {cfg.nodes[0]}x{cfg.nodes[1]})",
                             obstacles=run.scene.obstacles)
        if pngs and not quiet:
            print(f"rendered {len(pngs) - 1} frames and {pngs[-1]}")
    if not quiet:
        print(f"{cfg.scene}: {result.status}, {result.steps} steps to t = {result.state.t:.6g} s "
              f"({_steps_line(run.stepper, cfg.dt)}, {cfg.nodes[0]}x{cfg.nodes[1]} {run.backend}, "
              f"{run.stepper.scheme}) in "
              f"{wall:.1f} s wall; energy: stretching {e.stretching:.4g} J, bending {e.bending:.4g} J, kinetic "
              f"{kinetic:.4g} J; {writer.frames} frames in {writer.path}")
        if run.clearance:
            print(f"{cfg.scene}: smallest clearance over {len(run.clearance)} steps {min(run.clearance):.3g} m "
                  f"(final {run.clearance[-1]:.3g} m)")
        if cfg.scene in MEASURES:
            print(f"{cfg.scene}: {MEASURES[cfg.scene](cfg, run.model, result.state.X)}")
    return 0 if result.status != "diverged" else 1
