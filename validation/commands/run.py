r"""``deformable run``: run a scene, write an XDMF time series, pictures and checkpoints.

::

    deformable run SCENE|FILE.toml [--backend fd|fe] [--steps N | --t-end T] [--dt DT]
                   [--grid MxN] [--out DIR] [--render] [--every K] [--field NAME]
                   [--checkpoint-every K] [--resume FILE]

The scene is a name of :data:`deformable.scenes.SCENES` or a TOML file
(``scene = "curtain"`` plus fields; :func:`deformable.scenes.read_toml`); the
command-line values --grid and --dt override it last. The resolved config is
written as ``<out>/<scene>.toml``.

The time stepping is eq. (22)-(27) (:class:`deformable.TimeStepper`); the
output is written as the run goes (:mod:`deformable.output`), so a killed run
keeps its frames. ``--steps N`` means: run until step N (a resumed run ends at
the same step as the uninterrupted one); ``--t-end T`` likewise ends at time T.

Checkpoints (``--checkpoint-every K``) hold X, V, t, step, the constraint
reference X0 and the scene config; ``--resume FILE`` rebuilds the scene from
the checkpoint and continues, bit-identical to an uninterrupted run. A diverging
run stops at the step that diverged, keeps its frames and writes a checkpoint
of the last good state (``<scene>-diverged.npz``); the command then exits 1.

Bad input (unknown scene or key, malformed grid, dt <= 0, an output folder that
cannot be written, a resume file that does not fit) is reported in one line on
stderr with exit code 2 before anything is written.
"""

from __future__ import annotations

import logging
import math
import re
import sys
import time
from pathlib import Path

from deformable import scenes
from deformable.contact import clearance, require_outside
from deformable.dynamics import Callback, EnergyMonitor, State, TimeStepper
from deformable.dynamics.stepper import round_down
from deformable.output import CheckpointWriter, XDMFWriter, load_checkpoint, save_checkpoint
from deformable.output.render import FIELDS, render_series
from deformable.scene import FORCE_MODELS
from validation.harness.backends import BACKENDS, make_model
from validation.harness.report import writable_folder

__all__ = ["configure", "execute", "parse_grid", "scene_config", "Run", "prepare", "simulate"]

log = logging.getLogger(__name__)


class _Error(ValueError):
    """Bad input: the command line prints it as one line and exits with code 2."""


def configure(parser) -> None:
    """Arguments of ``deformable run``."""
    parser.add_argument("scene", metavar="SCENE|FILE.toml",
                        help=f"a scene name ({', '.join(scenes.SCENES)}) or a TOML scene file")
    parser.add_argument("--backend", default="fd", help="fd (finite differences) or fe (finite elements)")
    parser.add_argument("--force-model", default=None, metavar="MODEL",
                        help=f"{', '.join(FORCE_MODELS)} (default: the scene's, tpbf87); variational steps "
                        "by implicit Euler (Newton), stable for large xi")
    length = parser.add_mutually_exclusive_group()
    length.add_argument("--steps", type=str, default=None, help="run until this step number")
    length.add_argument("--t-end", type=str, default=None, help="run until this time (s; default: the scene's)")
    parser.add_argument("--dt", type=str, default=None, help="time step (s; default: the scene's)")
    parser.add_argument("--grid", default=None, help="node grid MxN (default: the scene's, 32x32)")
    parser.add_argument("--out", default=None, help="output folder (default: runs/<scene>)")
    parser.add_argument("--render", action="store_true", help="render PNG frames and a GIF (pyvista, offscreen)")
    parser.add_argument("--every", type=str, default=None,
                        help="write a frame every K steps (default: every 1/50 s of simulated time)")
    parser.add_argument("--field", default="speed", help=f"field that colours the frames: {', '.join(FIELDS)}")
    parser.add_argument("--checkpoint-every", type=str, default=None, help="write a checkpoint every K steps")
    parser.add_argument("--resume", default=None, help="continue from a checkpoint file (.npz)")


# -- parsing -------------------------------------------------------------------------
def parse_grid(text: str) -> tuple[int, int]:
    """``"MxN"`` -> (M, N); ValueError unless two integers >= 3."""
    m = re.fullmatch(r"\s*(\d+)\s*[xX]\s*(\d+)\s*", str(text))
    if not m:
        raise _Error(f"malformed grid {text!r}: expected MxN, e.g. 32x32")
    M, N = int(m.group(1)), int(m.group(2))
    if min(M, N) < 3:
        raise _Error(f"grid {text!r} needs at least 3 nodes a side")
    return M, N


def scene_config(scene: str, **overrides) -> scenes.SceneConfig:
    """The config of a scene name or a TOML scene file (``*.toml``), with overrides; ValueError naming what is wrong."""
    if scene.endswith(".toml"):
        return scenes.read_toml(scene, **overrides)
    return scenes.config(scene, **overrides)


def _positive(name: str, text, kind=float):
    if text is None:
        return None
    try:
        value = kind(text)
    except (TypeError, ValueError):
        raise _Error(f"--{name} must be a positive {'integer' if kind is int else 'number'}, got {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise _Error(f"--{name} must be positive, got {text!r}")
    return value


class Run:
    """A prepared run: everything checked, nothing written yet.

    Attributes: ``config`` (the resolved scene config), ``scene``, ``model``,
    ``stepper``, ``X0`` (constraint reference, (ndof, 3)), ``start`` (State or
    None: a resume point), ``steps`` (to run), ``every``, ``out`` (folder),
    ``stem`` (file name stem), ``backend``.
    """


def prepare(args) -> Run:
    """Check all input and build the model; raises _Error (a ValueError) on bad input."""
    run = Run()
    backend = args.backend
    if backend not in BACKENDS:
        raise _Error(f"unknown backend {backend!r}; choose one of {', '.join(BACKENDS)}")
    if args.field not in FIELDS:
        raise _Error(f"unknown field {args.field!r}; choose one of {', '.join(FIELDS)}")
    dt = _positive("dt", args.dt)
    steps = _positive("steps", args.steps, int)
    t_end = _positive("t-end", args.t_end)
    every = _positive("every", args.every, int)
    ck_every = _positive("checkpoint-every", args.checkpoint_every, int)
    overrides = {}
    if args.grid is not None:
        overrides["nodes"] = parse_grid(args.grid)
    if dt is not None:
        overrides["dt"] = dt
    if args.force_model is not None:
        if args.force_model not in FORCE_MODELS:
            raise _Error(f"unknown force model {args.force_model!r}; choose one of {', '.join(FORCE_MODELS)}")
        overrides["force_model"] = args.force_model

    checkpoint = None
    if args.resume is not None:
        checkpoint = load_checkpoint(args.resume)
        base = scenes.read_toml_text(checkpoint["config"], source=args.resume)
        given = scene_config(args.scene)
        if given.scene != base.scene:
            raise _Error(f"resume file {args.resume!r} holds scene {base.scene!r}, not {given.scene!r}")
        if checkpoint["backend"] != backend:
            raise _Error(f"resume file {args.resume!r} was written by backend {checkpoint['backend']!r}, "
                         f"not {backend!r}")
        for key, value in overrides.items():
            if getattr(base, key) != value:
                raise _Error(f"resume file {args.resume!r} has {key} = {getattr(base, key)!r}, "
                             f"but {value!r} was asked for")
        cfg = base
    else:
        cfg = scene_config(args.scene, **overrides)
    scene = scenes.build(cfg)
    model = make_model(scene, backend)
    # the scenes' default dt is the FD one; a backend with a tighter stretching bound gets its own.
    # The bound comes from lagging alpha (eq. 25): the frozen and variational models have none (inf).
    bound = model.stable_step()
    if dt is None and checkpoint is None and cfg.dt > 0.5 * bound:
        cfg = cfg.replace(dt=round_down(0.5 * bound))
        log.info("dt = %g s for the %s backend (half its stretching bound %.3g s)", cfg.dt, backend, bound)
    if cfg.dt > bound:
        log.warning("dt = %g s exceeds the %s backend's stretching stability bound %.3g s "
                    "(docs/design.md, 'Time stepping'): expect divergence", cfg.dt, backend, bound)
    stepper = TimeStepper(model, cfg.dt)
    if checkpoint is not None:
        X0, X, V = checkpoint["X0"], checkpoint["X"], checkpoint["V"]
        if X.shape != (model.ndof, 3) or X0.shape != X.shape or V.shape != X.shape:
            raise _Error(f"resume file {args.resume!r} holds states of shape {X.shape}, "
                         f"the scene has ({model.ndof}, 3)")
        if checkpoint["dt"] != cfg.dt:
            raise _Error(f"resume file {args.resume!r} was written with dt = {checkpoint['dt']!r}, "
                         f"the scene has {cfg.dt!r}")
        A = checkpoint["A"]
        if A is not None and A.shape != X.shape:
            raise _Error(f"resume file {args.resume!r} holds accelerations of shape {A.shape}, the scene has "
                         f"({model.ndof}, 3)")
        run.start = State(t=checkpoint["t"], X=X, V=V, step=checkpoint["step"], A=A)
    else:
        X0 = model.initial_state()
        run.start = None
    if scene.obstacles:  # a start inside an obstacle cannot be stepped: refused before anything is written
        try:
            require_outside(model, X0 if run.start is None else run.start.X, "the start")
        except ValueError as err:
            raise _Error(str(err)) from None
    t_now = 0.0 if run.start is None else run.start.t
    step_now = 0 if run.start is None else run.start.step
    if steps is not None:
        target = steps
    else:
        target = int(round((t_end if t_end is not None else cfg.t_end) / cfg.dt))
    if target <= step_now:
        raise _Error(f"the run already stands at step {step_now} (t = {t_now:.6g} s); "
                     f"nothing to do until step {target}")
    run.steps = target - step_now
    run.every = every if every is not None else max(1, int(round(0.02 / cfg.dt)))
    run.ck_every = ck_every
    run.render, run.field = args.render, args.field
    run.config, run.scene, run.model, run.stepper, run.X0, run.backend = cfg, scene, model, stepper, X0, backend
    run.out = writable_folder(Path(args.out) if args.out else Path("runs") / cfg.scene)
    run.stem = cfg.scene if run.start is None else f"{cfg.scene}-from-{step_now:07d}"
    return run


def simulate(run: Run, progress: bool = False):
    """Run a prepared run; returns (RunResult, XDMFWriter, list of written checkpoints)."""
    cfg = run.config
    config_text = scenes.to_toml(cfg)
    (run.out / f"{cfg.scene}.toml").write_text(config_text)
    meta = dict(scene=cfg.scene, config=config_text, backend=run.backend, dt=cfg.dt, nodes=cfg.nodes)
    writer = XDMFWriter(run.out / f"{run.stem}.xdmf", every=run.every)
    energy = EnergyMonitor(every=run.every)
    trackers = [writer, energy]
    run.clearance = []  # with obstacles: the clearance after every step (m)
    if run.scene.obstacles:
        trackers.append(Callback(lambda s: run.clearance.append(clearance(run.model, s.X))))
    ckpt = None
    if run.ck_every:
        ckpt = CheckpointWriter(run.out, f"{cfg.scene}-checkpoint", run.ck_every, run.X0, **meta)
        trackers.append(ckpt)
    result = run.stepper.run(run.X0, steps=run.steps, trackers=trackers, progress=progress, resume=run.start)
    written = list(ckpt.written) if ckpt else []
    if result.status == "diverged":
        written.append(save_checkpoint(run.out / f"{cfg.scene}-diverged.npz", result.state, run.X0, **meta))
    return result, writer, energy, written


def execute(args) -> int:
    """``deformable run``: returns 0 when the run finished, 1 when it diverged."""
    run = prepare(args)
    t0 = time.perf_counter()
    result, writer, energy, written = simulate(run, progress=True)
    e = run.model.energy(result.state.X)
    kinetic = run.model.kinetic_energy(result.state.V)
    wall = time.perf_counter() - t0
    cfg = run.config
    if result.status == "diverged":
        print(f"{cfg.scene}: {result.message}; kept {writer.frames} frames in {writer.path}, "
              f"last good state (t = {result.state.t:.6g} s) in {written[-1]}", file=sys.stderr)
    if run.render:
        pngs = render_series(writer.path, run.out / "frames", field=run.field,
                             title=f"{cfg.scene} ({run.backend}, {cfg.nodes[0]}x{cfg.nodes[1]})",
                             obstacles=run.scene.obstacles)
        if pngs:
            print(f"rendered {len(pngs) - 1} frames and {pngs[-1]}")
    print(f"{cfg.scene}: {result.status}, {result.steps} steps to t = {result.state.t:.6g} s "
          f"(dt = {cfg.dt:g} s, {cfg.nodes[0]}x{cfg.nodes[1]} {run.backend}) in {wall:.1f} s wall; "
          f"energy: stretching {e.stretching:.4g} J, bending {e.bending:.4g} J, kinetic {kinetic:.4g} J; "
          f"{writer.frames} frames in {writer.path}")
    if run.clearance:
        print(f"{cfg.scene}: smallest clearance over {len(run.clearance)} steps {min(run.clearance):.3g} m "
              f"(final {run.clearance[-1]:.3g} m)")
    report = scenes.SCENES[cfg.scene].report
    if report is not None:
        print(f"{cfg.scene}: {report(cfg, run.model, result.state.X)}")
    return 0 if result.status != "diverged" else 1
