r"""The README's pictures of the scenes (section 5, Figs 3-8): an animation and a still of each, regenerable.

    python -m validation.studies.paper.media [--out docs/scenes] [--nodes N] [--frames K] [SCENE ...]

Each scene of :mod:`deformable.scenes` runs as shipped (its own model,
parameters, grid, t_end and dt) on the FD backend: 32 x 32 nodes, the curtain
family 64 x 64 (their folds at least 3 grid spacings wide there, see the paper
study's folds section); ``--nodes N`` runs every scene on N x N instead. It
writes ``<scene>.gif``, K + 1 frames from t = 0 to t_end (the
surface shaded and coloured by its coordinate out of the rest plane, y, or z for
``hanging``, with a colour bar and the time on each frame; the curtain's rod or
the flag's pole drawn in; :func:`.pictures.animation`, drawn by
:mod:`deformable.io.render`), and ``<scene>.png``, the last frame as a still
(:func:`.pictures.render`). A run
that does not finish writes nothing for its scene and makes the command exit
1; a bad argument is one line on stderr, exit code 2, nothing written.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

from deformable import scenes

from .cases import Case, fields, run_case
from .pictures import animation, render, rest_axis
from .renders import decorations

__all__ = ["FRAMES", "MEDIA_SCENES", "scene_run", "scene_media", "write_atomic", "main"]

#: frames of an animation after the first (t = 0)
FRAMES = 30
#: the scenes drawn by default: the README's table
MEDIA_SCENES = ("hanging", "curtain", "curtain-silky", "paper", "flag")


def scene_run(scene: str, nodes: int, frames: int = FRAMES) -> dict:
    """The scene's FD run with ``frames`` + 1 animation frames (and the last one kept as a still)."""
    cfg = scenes.config(scene)
    steps = int(round(cfg.t_end / cfg.dt))
    every = max(1, steps // frames)
    return run_case(Case("scene", scene, "fd", nodes, fields(), t_end=cfg.t_end, times=(cfg.t_end,), every=every))


def scene_media(scene: str, run: dict, nodes: int) -> tuple[bytes, bytes]:
    """(GIF, PNG) of a scene from its run (:func:`scene_run`)."""
    lines = decorations(scene)
    axis = rest_axis(run["frames"][0][1])  # the colour: the coordinate out of the rest plane
    frames = [(f"{scene}, FD {nodes}x{nodes}", t, pts) for t, pts in run["frames"]]
    (t_last, last), = run["renders"].items()
    still = render([[(f"{scene}, FD {nodes}x{nodes}", t_last, last)]], size=(360, 320), lines=lines, axis=axis)
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
        gif, png = scene_media(name, run, n)
        write_atomic(out / f"{name}.gif", gif)
        write_atomic(out / f"{name}.png", png)
        print(f"{name}: {run['steps']} steps in {run['wall']:.0f} s; {out / name}.gif ({len(gif) / 1e3:.0f} kB, "
              f"{len(run['frames'])} frames), {out / name}.png ({len(png) / 1e3:.0f} kB)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
