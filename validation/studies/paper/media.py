r"""The README's pictures of the scenes (section 5, Figs 3-8, and the contact scenes): an animation and a still of
each, regenerable.

    python -m validation.studies.paper.media [--out docs/scenes] [--nodes N] [--frames K] [SCENE ...]

Each scene of :mod:`deformable.scenes` runs as shipped (its own model,
parameters, grid, t_end and dt) on the FD backend, on its own grid (the curtain
family on the grids that resolve their fabrics' folds, denim 64 x 64,
jacket-polyester 80 x 80, paper 48 x 48: deformable.scenes.curtain; the coil
121 x 9); ``--nodes N`` runs every scene on N
nodes along a1 instead, its grid's aspect kept (N x N for a square one). It
writes ``<scene>.gif`` and ``<scene>.png``, drawn by :mod:`deformable.io.render`:

- the sheet scenes (``hanging``, the curtains, ``paper``): K + 1 frames from
  t = 0 to t_end, the surface shaded and coloured by its coordinate out of the
  rest plane (y, or z for ``hanging``), with a colour bar and the time on each
  frame and the curtain's rod drawn in (:func:`.pictures.animation`); the still
  is the last frame (:func:`.pictures.render`);
- ``flag``: its coils swing at ``frequency`` (6 Hz), so K + 1 frames over its
  2 s would sample a period about 2.6 times and could not show a wave
  travelling from the pole to the free edge. Its animation is the last
  :data:`FLAG_PERIODS` periods of the run (the swing at full amplitude, long
  after its ramp) at no fewer than :data:`FLAG_FRAMES_A_PERIOD` frames a period
  (every :func:`flag_sampling` steps; 16.7 a period at the shipped 5 ms step),
  played at 12 frames a second: 8 times slower than the flag moves. The still
  is a strip of :data:`FLAG_PHASES` phases of the last period side by side
  (:func:`phase_frames`; the first panel's time written, the others' phase
  after it), one camera and colour range for all, in which a crest (red) or
  trough (blue) moves towards the free edge from panel to panel.
  ``--frames`` does not apply to it; the pole is drawn in;
- the contact scenes (``sphere``, ``drape``, ``coil``): K + 1 frames from
  t = 0 to t_end (the first state at or after each frame's time: their step
  adapts), coloured by the height z over its range in the second half of the
  run (the start above it saturates: the coil's folds get the whole range,
  not 1/15 of it), the obstacles in grey
  (:func:`.pictures.contact_images`): the camera on the sheet's bounding box
  over the run, so that the sheet fills the picture, and the floor drawn
  only just around the sheet's footprint (not a floor around a few pixels of
  ribbon); the still is the last frame framed and coloured on itself alone
  (the coil's folded ribbon close up, the drape's lobes).

A run that does not finish writes nothing for its scene and makes the command
exit 1; a bad argument is one line on stderr, exit code 2, nothing written.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from deformable import scenes

from .cases import Case, fields, run_case
from .pictures import animation, contact_images, render, rest_axis
from .renders import decorations

__all__ = ["FRAMES", "MEDIA_SCENES", "CONTACT_SCENES", "FLAG_FRAMES_A_PERIOD", "FLAG_PERIODS", "FLAG_PHASES",
           "flag_sampling", "phase_frames", "scene_nodes", "scene_run", "contact_run", "scene_media", "write_atomic",
           "main"]

#: frames of an animation after the first (t = 0)
FRAMES = 30
#: the contact scenes: drawn among their obstacles (:func:`contact_run`, :func:`.pictures.contact_images`)
CONTACT_SCENES = ("sphere", "drape", "coil")
#: the scenes drawn by default: the README's table
MEDIA_SCENES = ("hanging", "curtain", "curtain-silky", "paper", "flag") + CONTACT_SCENES
#: the flag's animation has at least this many frames a period of its coils' swing (``frequency``) ...
FLAG_FRAMES_A_PERIOD = 12
#: ... over this many periods at the end of its run
FLAG_PERIODS = 2
#: the flag's still: this many phases of its last period side by side
FLAG_PHASES = 5
#: the view of a contact scene (z up): the coil's loops lie in the x-z plane, so from its side
CONTACT_VIEW = {"coil": (0.3, -1.0, 0.45), "drape": (0.6, -1.0, 0.9), "sphere": (0.6, -1.0, 0.55)}


def flag_sampling(cfg, dt: float) -> tuple[int, float]:
    """(every, t_from): the flag's animation takes a frame every ``every`` steps of ``dt`` (s) from ``t_from`` (s)
    to its t_end, the last :data:`FLAG_PERIODS` periods of its swing at ``cfg.frequency`` (Hz) sampled at least
    :data:`FLAG_FRAMES_A_PERIOD` times a period. ValueError when a step is too long for that or the run shorter
    than the periods."""
    period = 1.0 / cfg.frequency
    every = int(math.floor(period / (FLAG_FRAMES_A_PERIOD * dt) * (1 + 1e-9)))
    if every < 1:
        raise ValueError(f"the flag's step {dt:g} s is too long for {FLAG_FRAMES_A_PERIOD} frames a period at "
                         f"{cfg.frequency:g} Hz (it gives {period / dt:.3g})")
    t_from = cfg.t_end - FLAG_PERIODS * period
    if t_from < 0:
        raise ValueError(f"the flag's run ({cfg.t_end:g} s) is shorter than {FLAG_PERIODS} periods at "
                         f"{cfg.frequency:g} Hz")
    return every, t_from


def phase_frames(frames: list, frequency: float, t_end: float, phases: int = FLAG_PHASES) -> list:
    """Of ``frames`` (t, ...), the one nearest each of ``phases`` phases k / phases (k = 0, ..., phases - 1) of
    the last period before ``t_end`` at ``frequency`` (Hz)."""
    period = 1.0 / frequency
    times = np.array([f[0] for f in frames])
    return [frames[int(np.argmin(np.abs(times - (t_end - period + k * period / phases))))] for k in range(phases)]


def scene_nodes(scene: str, nodes: int | None = None) -> tuple[int, int]:
    """The grid a scene is drawn on: its own, or ``nodes`` along a1 with its aspect kept (at least 3 across)."""
    M, N = scenes.config(scene).nodes
    if nodes is None:
        return M, N
    return nodes, max(3, int(round((N - 1) * (nodes - 1) / (M - 1))) + 1)


def scene_run(scene: str, nodes: int, frames: int = FRAMES) -> dict:
    """The scene's FD run on ``nodes`` x ``nodes``: ``frames`` + 1 animation frames (the flag's: its last
    :data:`FLAG_PERIODS` periods by :func:`flag_sampling`), the last one kept as a still. A contact scene:
    :func:`contact_run`."""
    if scene in CONTACT_SCENES:
        return contact_run(scene, scene_nodes(scene, nodes), frames)
    cfg = scenes.config(scene)
    steps = int(round(cfg.t_end / cfg.dt))
    t_from = 0.0
    if scene == "flag":
        every, t_from = flag_sampling(cfg, cfg.dt)
    else:
        every = max(1, steps // frames)
    run = run_case(Case("scene", scene, "fd", nodes, fields(), t_end=cfg.t_end, times=(cfg.t_end,), every=every))
    if scene == "flag":
        run["frames"] = [f for f in run["frames"] if f[0] >= t_from - 1e-9]
    return run


def contact_run(scene: str, nodes: tuple[int, int], frames: int = FRAMES) -> dict:
    """A contact scene's FD run as ``deformable run`` steps it (its own step, adapting), on ``nodes`` (M, N):
    ``frames`` + 1 frames (t, points (M', N', 3)), the first state at or after each of ``frames`` + 1 times
    from 0 to t_end, with its ``obstacles`` and ``cell`` (m, the longest cell diagonal at the start) for the
    pictures."""
    import deformable as dm

    from .cases import render_points

    t0 = time.perf_counter()
    cfg = scenes.config(scene, nodes=tuple(nodes))
    sim = dm.Simulation(cfg, "fd", nodes=cfg.nodes)
    model = sim.model
    pending = list(np.linspace(0.0, cfg.t_end, frames + 1))
    rec = []

    def watch(state):
        if pending and state.t >= pending[0] - 1e-9:
            rec.append((state.t, render_points(model, state.X, refine=2 if min(nodes) < 40 else 1)))
            while pending and state.t >= pending[0] - 1e-9:
                pending.pop(0)

    X0 = model.initial_state()
    grid = model.grid(X0)
    cell = float(max(np.linalg.norm(grid[1:, 1:] - grid[:-1, :-1], axis=-1).max(),
                     np.linalg.norm(grid[1:, :-1] - grid[:-1, 1:], axis=-1).max()))
    watch(dm.State(t=0.0, X=X0, V=np.zeros_like(X0)))
    result = sim.run(t_end=cfg.t_end, trackers=[dm.Callback(watch)])
    if rec and result.state.t > rec[-1][0] + 1e-9 and result.status == "finished":
        rec.append((result.state.t, render_points(model, result.state.X, refine=2 if min(nodes) < 40 else 1)))
    return dict(status=result.status, t=result.state.t, steps=result.steps, frames=rec,
                renders={rec[-1][0]: rec[-1][1]}, obstacles=model.scene.obstacles, cell=cell, nodes=tuple(nodes),
                wall=time.perf_counter() - t0)


def scene_media(scene: str, run: dict, nodes) -> tuple[bytes, bytes]:
    """(GIF, PNG) of a scene from its run (:func:`scene_run`); ``nodes``: its grid, n or (M, N), for the label."""
    from deformable.io.render import gif_bytes, png_bytes

    M, N = (nodes, nodes) if np.ndim(nodes) == 0 else nodes
    label = f"{scene}, FD {M}x{N}"
    if "obstacles" in run:
        view = CONTACT_VIEW.get(scene, (0.8, -1.0, 0.6))
        frames = [(label, t, pts) for t, pts in run["frames"]]
        images = contact_images(frames, run["obstacles"], direction=view, cell=run["cell"], colour_from=0.5 * run["t"])
        still, = contact_images(frames[-1:], run["obstacles"], direction=view, cell=run["cell"])
        return gif_bytes(images), png_bytes(still)
    lines = decorations(scene)
    axis = rest_axis(run["frames"][0][1])  # the colour: the coordinate out of the rest plane
    frames = [(label, t, pts) for t, pts in run["frames"]]
    if scene == "flag":
        cfg = scenes.config(scene)
        axis = 1  # the flag's rest plane is x-z; the window's first frame is not at rest
        strip = phase_frames(run["frames"], cfg.frequency, run["t"])
        n = len(strip)  # the first panel's time, the others' phase after it (no time: the labels stay apart)
        row = [(label, t, pts) if k == 0 else (f"+{k}/{n} period", None, pts) for k, (t, pts) in enumerate(strip)]
        still = render([row], size=(260, 240), lines=lines, axis=axis)
        return animation(frames, lines=lines, axis=axis), still
    (t_last, last), = run["renders"].items()
    still = render([[(label, t_last, last)]], size=(360, 320), lines=lines, axis=axis)
    return animation(frames, lines=lines, axis=axis), still


def write_atomic(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file in the same folder (no half-written file)."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.chmod(tmp, 0o644)  # mkstemp makes it private
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _positive_int(name: str, text: str, least: int) -> int:
    try:
        value = int(text)
    except ValueError:
        value = None
    if value is None or value < least:
        raise ValueError(f"--{name} must be a whole number >= {least}, got {text!r}")
    return value


def main(argv=None) -> int:
    """The command line (module docstring); returns the exit code."""
    parser = argparse.ArgumentParser(prog="python -m validation.studies.paper.media",
                                     description="Animations and stills of the scenes for the README.")
    parser.add_argument("scenes", nargs="*", metavar="SCENE", help=f"default: {' '.join(MEDIA_SCENES)}")
    parser.add_argument("--out", default="docs/scenes", help="output folder (default: docs/scenes)")
    parser.add_argument("--nodes", default=None, help="FD nodes a side (default: each scene's own grid)")
    parser.add_argument("--frames", default=str(FRAMES), help=f"frames after t = 0 (default: {FRAMES})")
    args = parser.parse_args(argv)
    try:
        nodes = None if args.nodes is None else _positive_int("nodes", args.nodes, 3)
        frames = _positive_int("frames", args.frames, 1)
        names = args.scenes or list(MEDIA_SCENES)
        for name in names:
            scenes.config(name)  # an unknown name: ValueError naming it
        out = Path(args.out)
        if not out.is_dir():
            raise ValueError(f"--out {str(out)!r} is not a folder")
    except ValueError as err:
        print(f"media: {err}", file=sys.stderr)
        return 2
    failed = []
    for name in names:
        n = nodes or scenes.config(name).nodes[0]
        run = scene_run(name, n, frames)
        if run["status"] != "finished":
            print(f"{name}: the run stopped at t = {run['t']:.3g} s ({run['status']}); nothing written",
                  file=sys.stderr)
            failed.append(name)
            continue
        gif, png = scene_media(name, run, run.get("nodes", n))
        write_atomic(out / f"{name}.gif", gif)
        write_atomic(out / f"{name}.png", png)
        print(f"{name}: {run['steps']} steps in {run['wall']:.0f} s; {out / name}.gif ({len(gif) / 1e3:.0f} kB, "
              f"{len(run['frames'])} frames), {out / name}.png ({len(png) / 1e3:.0f} kB)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
