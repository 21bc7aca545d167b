r"""The rate rows of ``deformable bench`` (opt-in: ``--rates``): simulated seconds per CPU second, and what the
Newton solve's tolerance costs in accuracy.

Each row runs a shipped scene (the energy-consistent model, implicit Euler at the
scene's dt) for ``t_end`` seconds of motion from its initial state, on FD n nodes
or FE n elements a side, under one of two Newton settings
(:class:`deformable.solve.newton.NewtonSettings`):

- "defaults": the settings as they ship (the step test where no obstacle is,
  the force test under contact);
- "before-step-test": the settings before issue 27's step test (main at commit ce6e554) (:data:`BEFORE`: the force
  test at rtol 1e-3, a factorisation every solve, direct solves, the whole
  matrix's definite fallback).

Both are held to the same two references, run once per scene and grid with a
tight solve (:data:`TIGHT`, the force test at rtol 1e-9): the same scene at dt
(the *Newton error* of a row is the largest distance of a node from it at
``t_end``) and at dt / 2 (their distance is the *time error*, the size of what
implicit Euler's step leaves, against which the Newton error is judged).
``error_ratio`` is the Newton error over the time error.

CPU seconds are ``time.process_time`` of the run in a forked process of its own,
every thread pool held to one thread (MKL, OpenBLAS, the Hessian's blocks): on a
shared two-core machine wall time is noise and CPU time is not. The references'
runs are not timed.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from validation.harness.report import markdown_table

from .measure import grid_label, in_own_process
from .scenes import SceneRow, run_scene

__all__ = ["RateRow", "BEFORE", "TIGHT", "bench_rates", "format_rates"]

#: the Newton settings before issue 27's step test (main at commit ce6e554)
BEFORE = dict(test="force", lag=False, krylov=False, fallback="definite", rtol=1e-3)
#: the reference solve: the force test at a tolerance far below any step's Newton error
TIGHT = dict(test="force", lag=False, rtol=1e-9)
#: the settings of a row, by name
SETTINGS = {"defaults": {}, "before-step-test": BEFORE}


@dataclass(frozen=True)
class RateRow(SceneRow):
    """One rate line: a scene row (:class:`validation.benches.scenes.SceneRow`) under named Newton settings, with
    its rate and errors; times in seconds, lengths in m."""

    settings: str
    rate: float  # simulated seconds per CPU second
    newton_error: float  # max |X - X_tight| over the nodes at t_end
    time_error: float  # max |X_tight(dt) - X_tight(dt / 2)| at t_end
    error_ratio: float  # newton_error / time_error


def _distance(a, b) -> float:
    """The largest distance between the nodes of two runs ((SceneRow, X) each) at their end (nan unless both
    finished)."""
    if a[0].status != "finished" or b[0].status != "finished":
        return float("nan")
    return float(np.max(np.linalg.norm(a[1] - b[1], axis=-1)))


def bench_rates(scene: str, backend: str, n: int, t_end: float, settings=("defaults", "before-step-test"),
                progress=print, references: bool = True) -> list[RateRow]:
    """The rows of one scene and grid: each of ``settings`` timed, against the two tight references (module
    docstring; ``references=False``: none, the errors nan); each run in a process of its own."""
    say = progress or (lambda *_, **__: None)
    tight = (None, None)
    time_error = float("nan")
    if references:
        say(f"rates: {scene} {backend} {n}x{n}, {t_end:g} s: the tight references at dt and dt/2", flush=True)
        tight = in_own_process(run_scene, scene, backend, n, t_end, TIGHT, 1.0, True)
        half = in_own_process(run_scene, scene, backend, n, t_end, TIGHT, 0.5, True)
        time_error = _distance(tight, half)
    rows = []
    for name in settings:
        say(f"rates: {scene} {backend} {n}x{n}, {t_end:g} s under {name}", flush=True)
        run = in_own_process(run_scene, scene, backend, n, t_end, SETTINGS[name], 1.0, True)
        r, error = run[0], _distance(run, tight) if references else float("nan")
        rows.append(RateRow(**asdict(r), settings=name, rate=r.t_reached / r.cpu if r.cpu > 0 else float("nan"),
                            newton_error=error, time_error=time_error,
                            error_ratio=error / time_error if time_error > 0 else float("nan")))
    return rows


def speedups(rows) -> dict:
    """(scene, backend, grid) -> the defaults' rate over before-step-test's, where both finished."""
    by = {(r.scene, r.backend, r.grid, r.settings): r for r in rows}
    out = {}
    for (scene, backend, grid, name), r in by.items():
        old = by.get((scene, backend, grid, "before-step-test"))
        if name == "defaults" and old is not None and r.status == old.status == "finished":
            out[scene, backend, grid] = r.rate / old.rate
    return out


def format_rates(rows) -> str:
    """A markdown table of rate rows, with each grid's speedup of the defaults over before-step-test's settings."""
    up = speedups(rows)
    return markdown_table(
        ("scene", "backend", "grid", "unknowns", "dt (ms)", "settings", "status", "t reached (s)", "steps", "CPU (s)",
         "sim s / CPU s", "speedup", "Newton / step", "factorisations / step", "fallbacks / step",
         "Newton error (m)", "dt vs dt/2 (m)", "Newton / time error"),
        [(r.scene, r.backend, grid_label(r), r.unknowns, f"{1e3 * r.dt:g}", r.settings, r.status, f"{r.t_reached:g}",
          r.steps, f"{r.cpu:.1f}", f"{r.rate:.4g}",
          f"{up[r.scene, r.backend, r.grid]:.2f}" if r.settings == "defaults" and (r.scene, r.backend, r.grid) in up
          else "", f"{r.newton_per_step:.2f}", f"{r.factorisations_per_step:.2f}", f"{r.fallbacks_per_step:.2f}",
          f"{r.newton_error:.3g}", f"{r.time_error:.3g}", f"{r.error_ratio:.3g}") for r in rows])


def _find(rows, scene, backend, grid, settings="defaults"):
    return next((r for r in rows if (r.scene, r.backend, r.grid, r.settings) == (scene, backend, grid, settings)),
                None)


def verdicts(rows, peers=()) -> list[str]:
    """The speed and accuracy targets of the implicit step (docs/design.md, "Newton's convergence test"), each a
    line computed from this run's rows: what was measured, its number, the target and "met" or "NOT met" (or
    "not measured in this run" where its rows are absent)."""
    up, out = speedups(rows), []

    def line(what, value, target, ok):
        out.append(f"{what}: {value} (target {target}): {'met' if ok else 'NOT met'}")

    for grid, target in (("64x64", 2.0), ("256x256", 3.0)):
        key = ("curtain", "fd", grid)
        if key in up:
            line(f"curtain FD {grid} nodes, {_find(rows, *key).t_end:g} s, defaults' rate over before-step-test's",
                 f"{up[key]:.2f}x", f">= {target:g}x", up[key] >= target)
        else:
            out.append(f"curtain FD {grid} nodes: not measured in this run")
    r = _find(rows, "curtain", "fd", "256x256")
    if r is not None:  # the fine grid's price (docs/design.md, "The price of a step")
        line(f"curtain FD 256x256 nodes, {r.t_reached:g} of {r.t_end:g} s under defaults, CPU per simulated second "
             f"(peak memory {r.peak_mb:.0f} MB)", f"{r.cpu / r.t_reached / 60:.1f} min" if r.t_reached > 0 else "nan",
             "<= 10 min", bool(r.status == "finished" and r.t_reached > 0 and r.cpu / r.t_reached <= 600))
    for scene in ("curtain", "flag", "sphere"):
        r = _find(rows, scene, "fd", "64x64")
        if r is None:
            out.append(f"{scene} FD 64x64 Newton error: not measured in this run")
            continue
        line(f"{scene} FD 64x64, {r.t_end:g} s, Newton error over dt vs dt/2 ({r.newton_error:.3g} m over "
             f"{r.time_error:.3g} m)", f"{100 * r.error_ratio:.2f} %", "<= 10 %",
             bool(r.status == "finished" and r.error_ratio <= 0.1))
    r = _find(rows, "flag", "fd", "64x64")
    if r is not None:
        line(f"flag FD 64x64, {r.t_end:g} s, Newton iterations a step", f"{r.newton_per_step:.2f}", "<= 2.5",
             bool(r.status == "finished" and r.newton_per_step <= 2.5))
    fe, fd = _find(rows, "curtain", "fe", "32x32"), _find(rows, "curtain", "fd", "64x64")
    if fe is not None and fd is not None:
        ratio = (fe.cpu / fe.t_reached) / (fd.cpu / fd.t_reached)
        line("curtain FE 32x32 elements (its default grid) over FD 64x64 nodes, CPU per simulated second",
             f"{ratio:.2f}x", "<= 3x", bool(fe.status == fd.status == "finished" and ratio <= 3))
    ours = _find(rows, "hanging", "fd", "64x64")
    by = {p.solver: p for p in peers if p.status == "ok"}
    if ours is not None and by:
        if "vbd" in by:
            line("hanging FD 64x64, defaults' rate over newton VBD's", f"{ours.rate / by['vbd'].rate:.3g}x",
                 "> 1x", ours.rate > by["vbd"].rate)
        if "style3d" in by:
            line("hanging FD 64x64, defaults' rate over newton Style3D's", f"{ours.rate / by['style3d'].rate:.3g}x",
                 ">= 0.5x", ours.rate >= 0.5 * by["style3d"].rate)
    elif peers:
        out.append("peers: " + "; ".join(f"{p.solver} {p.status}" for p in peers))
    return out
