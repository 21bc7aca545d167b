r"""The real-time row of ``deformable bench --realtime SCENE``: how far ``deformable view`` is from the clock.

A row runs a shipped scene as ``deformable view SCENE --offscreen --frames N`` runs it, through the same
:class:`validation.viewer.Window`: a frame every 1 / :data:`validation.viewer.FPS` s of simulated time, each
stepped (the scene's shipped settings: its dt, the default Newton settings, its self-contact), then its readout
taken, its mesh, colours and text updated and rendered off screen. The grid is the view's (nodes a side, default
20 x 20). The window's opening (the GL context and its shaders: one render of the initial state) is not timed,
as the scene's build is not; everything a frame does is.

CPU seconds (``time.process_time``) in a forked process of its own held to one thread
(:func:`validation.benches.measure.one_thread`, and Mesa's software rasteriser, llvmpipe, to the calling thread):
on a shared machine wall time is noise. ``cpu_steps`` is the stepping, ``cpu_render`` the rest of the frames (the
readout, the updates, the rendering), and

    realtime_factor = sim_seconds / (cpu_steps + cpu_render),

the simulated seconds one core computes and draws in a CPU second: 1 or more, the view keeps up with the clock
on one core; with two cores (the interactive window steps in a thread of its own beside the drawing) the bound is
sim_seconds / max(cpu_steps, cpu_render). Each run appends its row to ``bench_realtime.csv`` (a table of rows
over runs: ``--realtime curtain`` then ``--realtime flag`` leave two).
"""

from __future__ import annotations

import csv
import logging
import math
import os
from argparse import Namespace
from dataclasses import astuple, dataclass, fields
from pathlib import Path

from validation.harness.report import markdown_table

from .measure import one_thread

__all__ = ["COLUMNS", "RealtimeRow", "bench_realtime", "cells", "format_realtime", "write_row"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class RealtimeRow:
    """One real-time line: a scene run and drawn as ``deformable view --offscreen`` does; times in CPU seconds."""

    scene: str
    backend: str
    grid: str  # nodes a side, MxN (the view's --grid)
    sim_seconds: float  # simulated seconds (s)
    cpu_steps: float  # CPU seconds stepping
    cpu_render: float  # CPU seconds of the rest of the frames: readout, updates, off-screen rendering
    realtime_factor: float  # sim_seconds / (cpu_steps + cpu_render)


#: the CSV's columns
COLUMNS = tuple(f.name for f in fields(RealtimeRow))


def bench_realtime(scene: str, backend: str, grid: str, t_end: float, fps: float | None = None):
    """Run ``scene`` on ``backend`` and the node ``grid`` ("MxN") for ``t_end`` s as ``deformable view --offscreen``
    does, in this process held to one thread for good (call it through
    :func:`validation.benches.measure.in_own_process`): (its RealtimeRow, the run's status: "running" unless it
    diverged or stalled, which ends the frames)."""
    one_thread()
    os.environ["LP_NUM_THREADS"] = "0"  # Mesa's llvmpipe rasterises in the calling thread (read as GL starts)
    from validation.commands.run import resolve
    from validation.viewer import FPS, Session, Window

    fps = FPS if fps is None else fps
    sim, *_ = resolve(Namespace(scene=scene, overrides=[], backend=backend, grid=grid,
                           force_model=None, resume=None))
    cfg, backend = sim.config, sim.backend
    window = Window(Session(cfg, backend), offscreen=True, fps=fps)
    try:
        window.show()  # the window's opening: its context and shaders, on the initial state (not timed)
        frames = max(1, math.ceil(t_end * fps - 1e-9))
        for _ in range(frames):
            window.frame()
            if window.session.status != "running":
                break
    finally:
        window.plotter.close()
    sim, steps, render = window.session.state.t, window.cpu["steps"], window.cpu["render"]
    M, N = cfg.nodes
    row = RealtimeRow(scene=scene, backend=backend, grid=f"{M}x{N}", sim_seconds=float(sim), cpu_steps=steps,
                      cpu_render=render, realtime_factor=sim / (steps + render))
    return row, window.session.status


def cells(row: RealtimeRow) -> list[str]:
    """The row's cells as written and printed: text as is, numbers to 6 significant digits."""
    return [v if isinstance(v, str) else f"{v:.6g}" for v in astuple(row)]


def format_realtime(rows) -> str:
    """A markdown table of real-time rows, the CSV's columns and cells."""
    return markdown_table(COLUMNS, [cells(r) for r in rows])


def write_row(path: Path, row: RealtimeRow) -> bool:
    """Append ``row`` to the CSV at ``path`` when its header is :data:`COLUMNS`; else (no file, or other columns)
    write the header and the row anew. Returns whether the row was appended."""
    path = Path(path)
    header = None
    if path.exists():
        with path.open(newline="") as fh:
            header = next(csv.reader(fh), None)
    append = header == list(COLUMNS)
    if header is not None and not append:
        log.warning("%s had other columns (%s): written anew", path, ", ".join(header))
    with path.open("a" if append else "w", newline="") as fh:
        writer = csv.writer(fh)
        if not append:
            writer.writerow(COLUMNS)
        writer.writerow(cells(row))
    return append
