r"""``deformable view SCENE|FILE.toml [KEY=VALUE ...]``: the scene running in a window, its parameters as sliders.

The paper's macro group (mu, gamma, the force scale) and micro group (eta, xi) as sliders that change the
running simulation; the time, energies, largest stretch and the compatibility test (eq. (10)) shown live;
space pauses, ``r`` resets, ``g`` records a GIF (:mod:`validation.viewer`). In the window the simulation runs
in a thread of its own and the window draws the newest frame at its own rate; ``--frames N`` runs N frames in
turn in this thread instead (simulation, then drawing: deterministic). ``--offscreen --frames N --screenshot FILE``
runs N frames without a window (each rendered off screen), saves the last one and prints the frame rate against
real time and the CPU seconds of stepping and of drawing. Exit code 0, 1 when the run diverged, 2 on bad input
(one line).
"""

from __future__ import annotations

import sys
import time
from argparse import Namespace

from deformable.physics import kernels
from deformable.progress import COMPILING

from .run import positive, resolve

__all__ = ["configure", "execute"]


def configure(parser) -> None:
    parser.add_argument("scene", metavar="SCENE|FILE.toml", help="a scene name or a TOML scene file")
    parser.add_argument("overrides", metavar="KEY=VALUE", nargs="*", default=[],
                        help="set a field of the scene's config, e.g. nodes=[20,20] xi=1e-4 (default: none)")
    parser.add_argument("--backend", default=None, help="fd or fe (default: the scene file's, else fd)")
    parser.add_argument("--grid", default="20x20", help="node grid MxN (default: 20x20, light enough for real time)")
    parser.add_argument("--fps", default="30", help="frames a simulated second (default: 30)")
    parser.add_argument("--offscreen", action="store_true", help="render without a window (default: a window)")
    parser.add_argument("--frames", default=None, help="stop after this many frames, simulated and drawn in turn "
                        "(default: when the window closes, the simulation in a thread of its own)")
    parser.add_argument("--screenshot", default=None, metavar="FILE", help="save the last frame as PNG (default: none)")
    parser.add_argument("--gif", default=None, metavar="FILE", help="where the g key records (default: SCENE.gif)")


def execute(args) -> int:
    """``deformable view``: 0, or 1 when the simulation diverged."""
    from deformable.errors import InputError
    from validation.viewer import Session, Window

    fps = positive("fps", args.fps)
    frames = None if args.frames is None else positive("frames", args.frames, int)
    if args.offscreen and frames is None:
        raise InputError("--offscreen needs --frames N (how many frames to run without a window)", field="--frames",
                         value=None)
    sim, *_ = resolve(Namespace(scene=args.scene, overrides=args.overrides, backend=args.backend,
                           grid=args.grid, force_model=None, resume=None))
    cfg, backend = sim.config, sim.backend
    quiet = getattr(args, "quiet", False)
    if not quiet and not kernels.cached():  # before the session's first kernel call: what the silence is
        print(f"{time.strftime('%Y-%m-%d %H:%M:%S')} {cfg.scene}: {COMPILING}", file=sys.stderr, flush=True)
    window = Window(Session(cfg, backend), offscreen=args.offscreen, fps=fps, gif=args.gif)
    wall = window.run(frames, screenshot=args.screenshot, progress=None if quiet else cfg.scene)
    session = window.session
    if frames is not None and not quiet:
        simulated = session.state.t
        cpu = window.cpu
        print(f"{cfg.scene}: {frames} frames, {simulated:.3f} s simulated in {wall:.2f} s wall "
              f"({simulated / wall:.2f} x real time; CPU {cpu['steps']:.2f} s stepping, {cpu['render']:.2f} s "
              f"drawing); {session.status}" + (f"; screenshot {args.screenshot}" if args.screenshot else ""))
    return 0 if session.status == "running" else 1
