r"""The matched-accuracy rows of ``deformable bench`` (with ``--peers``): CPU seconds per simulated second of the
64 x 64 hanging cloth at a matched accuracy, this project's implicit Euler against newton's VBD and Style3D.

The peer rows (:mod:`.peers`) and the rate rows (:mod:`.rates`) time each
solver at one budget: newton's example settings, this project's default Newton
settings. A budget says nothing of how accurately a step is solved (neither
peer has a convergence test), so a faster row may only be a sloppier one. Here
each solver is swept over its own accuracy knobs at a given time step, each
run gives a point (error, CPU seconds per simulated second), and the solvers
are compared at the same error: what each pays to solve its own time step to a
given accuracy.

The cloth. The project's ``hanging`` scene on FD 64 x 64 nodes (implicit Euler,
the variational model, built as :func:`validation.benches.scenes.run_scene`
builds it, but at the dt asked rather than the scene's 5 ms) and the same cloth
as :mod:`.peers` builds it for newton's VBD and Style3D (the mapping of the
parameters is that module's docstring), from rest, for ``t_end`` = 0.1 s, at
two steps: dt = 1/60 s and dt = 1/600 s. For the peers dt is the substep: one
substep a frame of 1/60 s, or ten (VBD's own example setting).

The error. At t_end, the RMS over all nodes (particles) of the distance to the
same solver's own most converged run at the same dt, over the cloth's size (1
m). Never against each other: the three discretise different energies (the
peers' membrane and bending energies are not eq. 13), so their distance is the
models' difference, not a solver's error; and never against another dt, since
the time discretisation's error is not what a solver's knobs buy. The short
horizon is what makes a reference possible: over a whole second the hanging
cloth is too sensitive to be one (two of this project's runs at the force
tolerance 1e-10, differing only in Newton's iteration cap, end 1.45 % of the
cloth's size apart), over 0.1 s it is well posed. Each reference is checked by
a somewhat less converged run of its own (:data:`SWEEPS`, role "check"), whose
error is the reference's own resolution: a level far below it is not resolved.

- ours: the reference is a tight Newton solve, the force test at rtol 1e-10 (at
  most 500 iterations a step), checked by rtol 1e-8; the sweep runs the step
  test (the default) at vtol 1, 1e-1, 1e-2, 1e-3 m/s and the force test at rtol
  1e-2, 1e-3, 1e-4, each also with ``lag=True`` (a factorisation kept across
  steps, which applies under the step test only:
  :class:`deformable.solve.settings.NewtonSettings`);
- VBD: iterations a substep; the reference 300, checked by 200, at dt = 1/600 s.
  At one substep a frame (dt = 1/60 s) VBD converges slowly, as a local
  (block Gauss-Seidel) method does on the slow modes of a stiff membrane
  (measured while choosing these: 300 iterations end 5.4e-4 of the cloth's
  size from 200, 3000 end 6.2e-4 from 2000), so there the reference runs 10000,
  checked by 6000, and the sweep goes on from 100 to 3000; 1 to 100 at both;
- Style3D: non-linear x PCG iterations a substep; the reference 100 x 100,
  checked by 70 x 70, at dt = 1/600 s. At 1/60 s the non-linear iterations are
  what converge slowly, not the PCG ones (300 x 100 ended 2.2e-5 from 300 x 300,
  100 x 300 7.4e-4 like 100 x 100), so there 600 x 100, checked by 400 x 100,
  and the sweep goes on to 300 x 100; 1 x 10 to 50 x 50 at both
  (:data:`REFERENCES`, :data:`PEER_SWEEPS`).

The peers compute in single precision (Warp's ``vec3``), ours in double: a
peer's error has a floor of its own, near float32's resolution of positions of
order 1 m (about 1e-7) and above it where round-off stalls the iterations.

Matching a level. A solver's points at a dt (its references' checks included,
the reference itself excluded: its error is zero by construction) form a
work-precision curve, taken as its front: the points that no other point beats
in both error and cost, by cost. The cost at a level L is read off that front
by interpolation in log-log between the two points bracketing L (log cost
linear in log error), the same way for every solver; where the cheapest point
already meets L, its cost (no extrapolation); where no point meets L, "never",
with the best error reached. The cheapest measured point meeting L is given
beside it (its setting and cost).

CPU time. ``time.process_time`` of the timed run only: the model's building and
one warm-up step (ours; numba loads its compiled kernels) or frame (the peers:
Warp compiles or loads its kernels, VBD captures a graph) are not timed; each
run in a forked process of its own (:func:`.measure.in_own_process`), held to
one thread (:func:`.measure.one_thread`). Warp's ``cpu`` device runs a launch's
threads serially on the calling thread. On a shared machine CPU time is the
measure, not wall time.

The verdicts. For each dt and peer: ours and the peer at 1e-3
(:data:`VERDICT_LEVEL`), "met" when ours costs at most the peer's CPU seconds
per simulated second; where a solver never reaches 1e-3, both at the finest
level both reach, said so. Every number is this run's.

Outputs (:func:`bench_accuracy`): ``bench_accuracy.csv`` (a row per solver, dt
and setting), ``bench_accuracy_levels.csv`` (the matched levels),
``bench_accuracy.png`` (the work-precision curves, a panel per dt) and
``bench_accuracy.md`` (the verdicts and both tables). newton and warp are
imported only in the peers' own processes: without them every peer row says so
in its status and ours still runs.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from deformable import scenes
from deformable.dynamics import TimeStepper
from deformable.session import Simulation
from validation.harness.report import markdown_table

from . import peers
from .measure import in_own_process, one_thread, scene_config, write_csv

__all__ = ["AccuracyRow", "LevelMatch", "Run", "Setting", "SWEEPS", "REFERENCES", "PEER_SWEEPS", "LABELS", "LEVELS",
           "DTS", "T_END", "VERDICT_LEVEL", "bench_accuracy", "measure_accuracy", "run_ours", "run_newton_peer",
           "front", "match_level", "matched_levels", "verdicts", "format_accuracy", "format_levels", "plot_accuracy",
           "write_accuracy", "substeps_of"]

#: simulated time (s) of every run
T_END = 0.1
#: the time steps (s): ours, and the peers' substep
DTS = (1 / 60, 1 / 600)
#: the accuracy levels matched (RMS distance over the cloth's size)
LEVELS = (1e-2, 1e-3, 1e-4)
#: the level of the verdicts
VERDICT_LEVEL = 1e-3
#: nodes (particles) a side
NODES = 64
#: a reference's check differing by more than this fraction of a level leaves that level unresolved (a caution)
RESOLVED = 0.1


@dataclass(frozen=True)
class Setting:
    """One run of a solver's sweep: its name, its role ("reference", "check" or "sweep"), its knobs (ours: the
    fields of :class:`deformable.solve.settings.NewtonSettings`; VBD: ``iterations``; Style3D: ``iterations`` and
    ``linear_iterations``) and the dts (s) it runs at (None: every dt)."""

    name: str
    role: str
    knobs: dict = field(default_factory=dict)
    dts: tuple | None = None

    def runs_at(self, dt: float) -> bool:
        """It runs at dt (s)."""
        return self.dts is None or any(math.isclose(dt, d, rel_tol=1e-9) for d in self.dts)


def _ours() -> tuple[Setting, ...]:
    """Ours: the tight reference, its check, the step and force tests each with and without ``lag``."""
    out = [Setting("force rtol 1e-10", "reference", dict(test="force", rtol=1e-10, max_iter=500)),
           Setting("force rtol 1e-8", "check", dict(test="force", rtol=1e-8, max_iter=500))]
    for lag in (False, True):
        tail = " lag" if lag else ""
        out += [Setting(f"step vtol {v:g}{tail}", "sweep", dict(test="step", vtol=v, lag=lag))
                for v in (1.0, 1e-1, 1e-2, 1e-3)]
        out += [Setting(f"force rtol {r:g}{tail}", "sweep", dict(test="force", rtol=r, lag=lag))
                for r in (1e-2, 1e-3, 1e-4)]
    return tuple(out)


#: the peers' (reference, check) at each of :data:`DTS`: VBD's iterations, Style3D's (non-linear, PCG) iterations a
#: substep (module docstring: at one substep a frame both converge slowly)
REFERENCES = {"vbd": {DTS[0]: (10000, 6000), DTS[1]: (300, 200)},
              "style3d": {DTS[0]: ((600, 100), (400, 100)), DTS[1]: ((100, 100), (70, 70))}}
#: the peers' sweeps: at every dt, and further at dt = 1/60 s
PEER_SWEEPS = {"vbd": ((1, 2, 5, 10, 20, 50, 100), (200, 500, 1000, 2000, 3000)),
               "style3d": (((1, 10), (2, 10), (5, 10), (10, 10), (20, 20), (50, 50)),
                           ((100, 50), (200, 50), (300, 100)))}


def _peer(solver: str) -> tuple[Setting, ...]:
    """A peer's settings: its references and checks (:data:`REFERENCES`) and its sweep (:data:`PEER_SWEEPS`)."""
    every, large = PEER_SWEEPS[solver]
    runs = [(k, role, (dt,)) for dt, pair in REFERENCES[solver].items()
            for k, role in zip(pair, ("reference", "check"))]
    runs += [(k, "sweep", None) for k in every] + [(k, "sweep", (DTS[0],)) for k in large]
    if solver == "vbd":
        return tuple(Setting(f"{k} iteration{'s' if k != 1 else ''}", role, dict(iterations=k), dts)
                     for k, role, dts in runs)
    return tuple(Setting(f"{k} x {m}", role, dict(iterations=k, linear_iterations=m), dts)
                 for (k, m), role, dts in runs)


#: solver -> its settings: the reference first, then its check, then the sweep
SWEEPS = {"ours": _ours(), "vbd": _peer("vbd"), "style3d": _peer("style3d")}
#: solver -> its name in tables and verdicts
LABELS = {"ours": "ours (FD implicit Euler)", "vbd": "newton VBD", "style3d": "newton Style3D"}
_SHORT = {"ours": "ours", "vbd": "VBD", "style3d": "Style3D"}


@dataclass(frozen=True)
class Run:
    """One measured run: CPU seconds of its timed part, simulated seconds, time steps (substeps), iterations a step,
    its final positions (m; None unless it ended) and its status ("ok", or why not)."""

    cpu: float
    t_end: float
    steps: int
    iterations: float
    X: np.ndarray | None
    status: str


@dataclass(frozen=True)
class AccuracyRow:
    """One run of a solver's sweep on the hanging cloth: its cost and error at t_end; times in seconds."""

    solver: str
    setting: str
    role: str  # "reference", "check" or "sweep"
    nodes: str
    dt: float  # s: ours a time step, the peers' substep
    t_end: float  # s simulated
    steps: int  # time steps (substeps)
    iterations: float  # a step: Newton's (ours), VBD's or Style3D's non-linear ones (the knob)
    cpu: float  # s, the timed run
    cpu_per_sim_s: float  # CPU s per simulated s
    error: float  # RMS distance to the solver's reference at t_end over the cloth's size (0 for the reference)
    status: str  # "ok", or why not


@dataclass(frozen=True)
class LevelMatch:
    """What a solver pays at dt for an error level: CPU s per simulated s read off its front (nan: never)."""

    solver: str
    dt: float  # s
    level: float  # RMS distance over the cloth's size
    cpu_per_sim_s: float  # interpolated on the front (module docstring); nan where never reached
    best: float  # the least error of its points (nan: none)
    cheapest: str  # the cheapest measured setting meeting the level ("" if none)
    cheapest_cpu_per_sim_s: float  # its CPU s per simulated s
    how: str  # "interpolated between A and B", "cheapest point", "never: best X" or why there are no points

    @property
    def met(self) -> bool:
        """The level is reached."""
        return math.isfinite(self.cpu_per_sim_s)


def substeps_of(dt: float, frame_dt: float = 1.0 / peers.FPS) -> int:
    """The peers' substeps a frame of ``frame_dt`` s (newton's 1/60 s) for a substep of dt s; ValueError unless dt
    divides the frame."""
    k = round(frame_dt / dt)
    if k < 1 or abs(k * dt - frame_dt) > 1e-9 * frame_dt:
        raise ValueError(f"dt = {dt:g} s does not divide the peers' frame of {frame_dt:g} s")
    return k


def run_ours(nodes: int, dt: float, t_end: float, newton: dict) -> Run:
    """The project's hanging cloth on FD nodes x nodes, implicit Euler at dt (s) under the Newton settings
    ``newton`` for t_end (s), in this process: the model built and one warm-up step taken untimed, then the run
    from rest timed (CPU seconds)."""
    cfg = scene_config("hanging", "fd", nodes)
    model = Simulation(cfg, "fd", nodes=cfg.nodes, dt=dt).model
    warm = TimeStepper(model, dt, newton=newton)
    warm.step(warm.start(model.initial_state()))  # numba's kernels loaded, the model's caches filled
    stepper = TimeStepper(model, dt, newton=newton)
    c0 = time.process_time()
    result = stepper.run(model.initial_state(), t_end=t_end)
    cpu = time.process_time() - c0
    X = np.asarray(result.state.X, dtype=float)
    reports = stepper.newton_reports
    iterations = float(np.mean([r.iterations for r in reports])) if reports else math.nan
    if result.status != "finished" or not np.isfinite(X).all():
        return Run(cpu, result.state.t, result.steps, iterations, None,
                   f"{result.status}: {' '.join(result.message.split())[:120]}")
    status = "ok" if not stepper.rejected else f"ok ({stepper.rejected} steps retried at a smaller dt)"
    return Run(cpu, result.state.t, result.steps, iterations, X, status)


def run_newton_peer(solver: str, nodes: int, dt: float, t_end: float, knobs: dict) -> Run:
    """A newton solver ("vbd", "style3d") on the same cloth at a substep of dt (s), frames of 1/60 s, for t_end
    (s) rounded up to whole frames, in this process (:func:`validation.benches.peers.run_peer`)."""
    r = peers.run_peer(solver, nodes, 1.0 / peers.FPS, substeps_of(dt), knobs["iterations"], t_end,
                       knobs.get("linear_iterations", 10))
    if r.q is None:
        return Run(r.cpu, r.t_end, 0, math.nan, None, r.status)
    if not np.isfinite(r.q).all():
        return Run(r.cpu, r.t_end, r.steps, float(knobs["iterations"]), None, "non-finite positions")
    return Run(r.cpu, r.t_end, r.steps, float(knobs["iterations"]), r.q, "ok")


def _measured(solver: str, nodes: int, dt: float, t_end: float, knobs: dict) -> Run:
    """One run, in a (forked) process held to one thread from its start."""
    one_thread()
    if solver == "ours":
        return run_ours(nodes, dt, t_end, knobs)
    return run_newton_peer(solver, nodes, dt, t_end, knobs)


def _at(settings, dt: float) -> list[Setting]:
    """The settings that run at dt, the reference first, then its check, then the sweep; ValueError without one
    reference."""
    out = sorted((s for s in settings if s.runs_at(dt)), key=lambda s: ("reference", "check", "sweep").index(s.role))
    if sum(s.role == "reference" for s in out) != 1:
        raise ValueError(f"dt = {dt:g} s needs one reference setting, got {[s.name for s in out]}")
    return out


def _rms(X, ref, size: float) -> float:
    """RMS over the nodes of the distance between two position arrays (n, 3), over ``size``."""
    return float(np.sqrt(np.mean(np.sum((np.asarray(X) - np.asarray(ref)) ** 2, axis=-1)))) / size


def measure_accuracy(nodes: int = NODES, t_end: float = T_END, dts=DTS, solvers=("ours", "vbd", "style3d"),
                     sweeps=None, progress=print) -> list[AccuracyRow]:
    """The rows: every setting of each solver's sweep (``sweeps``, default :data:`SWEEPS`) at each dt (s), each
    run in a process of its own, its error against the solver's reference at the same dt (module docstring).

    A solver whose reference does not run (newton missing, a failure) gives every one of its rows at that dt
    that status, without running them.
    """
    say = progress or (lambda *_, **__: None)
    sweeps = SWEEPS if sweeps is None else sweeps
    size = float(scenes.config("hanging", nodes=(nodes, nodes)).size[0])
    rows = []
    for solver in solvers:
        for dt in dts:
            settings = _at(sweeps[solver], dt)
            ref = None
            for k, s in enumerate(settings, 1):
                if ref is not None and ref.X is None:  # the reference did not run: neither does the rest
                    run = Run(math.nan, math.nan, 0, math.nan, None,
                              ref.status if ref.status == peers.MISSING else f"not run: the reference {ref.status}")
                else:
                    say(f"accuracy: {LABELS[solver]}, dt = {_dt_label(dt)}, {s.name} ({s.role}; {k} of "
                        f"{len(settings)})", flush=True)
                    run = in_own_process(_measured, solver, nodes, dt, t_end, s.knobs)
                if s.role == "reference":
                    ref = run
                error = _rms(run.X, ref.X, size) if run.X is not None and ref.X is not None else math.nan
                rows.append(AccuracyRow(solver, s.name, s.role, f"{nodes}x{nodes}", dt, run.t_end, run.steps,
                                        run.iterations, run.cpu, run.cpu / run.t_end if run.t_end > 0 else math.nan,
                                        error, run.status))
                if run.X is not None:
                    say(f"  CPU {run.cpu:.2f} s for {run.t_end:g} s, error {error:.3g}", flush=True)
                elif s.role == "reference" or ref.X is not None:
                    say(f"  {run.status}", flush=True)
    return rows


def front(points) -> list[tuple]:
    """The work-precision front of (cost, error, name) points: those no other point beats in both, by cost (so by
    falling error); points with a non-finite or non-positive cost or a non-finite error left out."""
    ok = sorted((p for p in points if math.isfinite(p[0]) and p[0] > 0 and math.isfinite(p[1]) and p[1] >= 0),
                key=lambda p: (p[0], p[1]))
    out = []
    for p in ok:
        if not out or p[1] < out[-1][1]:
            out.append(p)
    return out


def match_level(points, level: float) -> tuple[float, float, str, float, str]:
    """(cost at ``level``, best error, cheapest setting meeting it, its cost, how) of (cost, error, name) points:
    log-log interpolation on their front between the two points bracketing the level; the cheapest point's cost
    where it meets the level already; nan and "never: best X" where none does (module docstring)."""
    f = front(points)
    if not f:
        return math.nan, math.nan, "", math.nan, "no points"
    best = f[-1][1]
    i = next((i for i, p in enumerate(f) if p[1] <= level), None)
    if i is None:
        return math.nan, best, "", math.nan, f"never: best {best:.3g}"
    c1, e1, name = f[i]
    if i == 0:
        return c1, best, name, c1, "cheapest point"
    c0, e0, name0 = f[i - 1]
    if e1 <= 0:  # an error of zero has no logarithm: the point meeting the level
        return c1, best, name, c1, f"{name} (error 0)"
    u = (math.log(level) - math.log(e0)) / (math.log(e1) - math.log(e0))
    cost = math.exp(math.log(c0) + u * (math.log(c1) - math.log(c0)))
    return cost, best, name, c1, f"interpolated between {name0} and {name}"


def _points(rows, solver: str, dt: float) -> list[tuple]:
    """The (cost, error, setting) points of a solver at dt: its runs that ended, the reference excluded."""
    return [(r.cpu_per_sim_s, r.error, r.setting) for r in rows
            if r.solver == solver and r.dt == dt and r.role != "reference" and r.status.startswith("ok")
            and math.isfinite(r.error)]


def _keys(rows) -> list[tuple[str, float]]:
    """(solver, dt) pairs of the rows, in their order."""
    return list(dict.fromkeys((r.solver, r.dt) for r in rows))


def matched_levels(rows, levels=LEVELS) -> list[LevelMatch]:
    """Each solver's cost at each dt and level (:func:`match_level` on its points)."""
    out = []
    for solver, dt in _keys(rows):
        points = _points(rows, solver, dt)
        for level in levels:
            cost, best, cheapest, cheapest_cost, how = match_level(points, level)
            if not points:
                how = next(r.status for r in rows if r.solver == solver and r.dt == dt)
            out.append(LevelMatch(solver, dt, level, cost, best, cheapest, cheapest_cost, how))
    return out


def _dt_label(dt: float) -> str:
    """dt as 1/k s where k is a whole number, else in s."""
    k = 1.0 / dt
    return f"1/{round(k)} s" if abs(k - round(k)) < 1e-6 * k else f"{dt:g} s"


def _check(rows, solver: str, dt: float) -> tuple[float, str]:
    """(error, setting) of a solver's reference check at dt (nan, "" where none ended)."""
    r = next((r for r in rows if r.solver == solver and r.dt == dt and r.role == "check"
              and r.status.startswith("ok")), None)
    return (r.error, r.setting) if r is not None else (math.nan, "")


def verdicts(rows, level: float = VERDICT_LEVEL) -> list[str]:
    """For each dt, ours against each peer at ``level``: a line with both costs (CPU s per simulated s) and "met"
    where ours costs at most the peer's, "NOT met" otherwise; where either never reaches the level, both at the
    finest level both reach, said so; where a solver's cheapest setting already meets the level, said so (its cost
    there is an upper bound); a caution where a reference's check differs by more than :data:`RESOLVED` of the
    level compared. Every number is computed from the rows."""
    out = []
    for dt in dict.fromkeys(r.dt for r in rows):
        ours = _points(rows, "ours", dt)
        solvers = [s for s, d in _keys(rows) if d == dt and s != "ours"]
        if not ours:
            status = next((r.status for r in rows if r.solver == "ours" and r.dt == dt), "not measured in this run")
            out.append(f"dt = {_dt_label(dt)}: ours not measured: {status}")
            continue
        for peer in solvers:
            name, points = _SHORT.get(peer, peer), _points(rows, peer, dt)
            if not points:
                status = next(r.status for r in rows if r.solver == peer and r.dt == dt)
                out.append(f"dt = {_dt_label(dt)}: {LABELS.get(peer, peer)} not measured: {status}")
                continue
            best_ours, best_peer = front(ours)[-1][1], front(points)[-1][1]
            at, notes = level, []
            if best_peer > at:
                at = best_peer
                notes.append(f"{name} never reaches {level:g} (best {best_peer:.3g}): compared at {name}'s best level")
            if best_ours > at:
                at = best_ours
                notes.append(f"ours never reaches {level:g} (best {best_ours:.3g}): compared at ours' best level")
            x, y = match_level(ours, at)[0], match_level(points, at)[0]
            for who, its in (("ours", ours), (peer, points)):
                cheapest = front(its)[0]
                if cheapest[1] <= at:  # the cost at the level is an upper bound: no cheaper setting was tried
                    notes.append(f"the cheapest setting of {_SHORT.get(who, who)} ({cheapest[2]}) is already at "
                                 f"{cheapest[1]:.3g}")
                check, setting = _check(rows, who, dt)
                if check > RESOLVED * at:
                    notes.append(f"caution: {_SHORT.get(who, who)}'s reference differs from its check ({setting}) by "
                                 f"{check:.3g}, more than {RESOLVED:g} x the level")
            out.append(f"dt = {_dt_label(dt)}: ours at {at:.3g}: {x:.3g} CPU s per sim s; {LABELS.get(peer, peer)}: "
                       f"{y:.3g} ({'met' if x <= y else 'NOT met'}: ours <= {name}; {name} / ours = {y / x:.3g}x)"
                       + "".join(f"; {n}" for n in notes))
    return out


def format_accuracy(rows) -> str:
    """A markdown table of the accuracy rows."""
    return markdown_table(
        ("solver", "dt", "setting", "role", "grid", "steps", "iterations / step", "CPU (s)", "CPU s / sim s",
         "error (RMS / size)", "status"),
        [(LABELS.get(r.solver, r.solver), _dt_label(r.dt), r.setting, r.role, r.nodes, r.steps,
          f"{r.iterations:.3g}", f"{r.cpu:.3g}", f"{r.cpu_per_sim_s:.3g}",
          f"{r.error:.3g}" if r.role != "reference" else "(reference)", r.status) for r in rows])


def format_levels(matches) -> str:
    """A markdown table of the matched levels."""
    return markdown_table(
        ("solver", "dt", "level", "CPU s / sim s", "how", "cheapest point meeting it", "its CPU s / sim s"),
        [(LABELS.get(m.solver, m.solver), _dt_label(m.dt), f"{m.level:g}",
          f"{m.cpu_per_sim_s:.3g}" if m.met else f"never: best {m.best:.3g}" if math.isfinite(m.best) else "never",
          m.how if m.met or not m.how.startswith("never") else "", m.cheapest,
          f"{m.cheapest_cpu_per_sim_s:.3g}" if m.met else "") for m in matches])


def plot_accuracy(rows, path: Path, levels=LEVELS, t_end: float | None = None) -> None:
    """The work-precision curves as a PNG: error against CPU s per simulated s, log-log, a panel per dt, each
    solver's points (open markers) and its front (a line), the levels dotted and each solver's cost at them marked
    (a diamond)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    dts = list(dict.fromkeys(r.dt for r in rows))
    t_end = t_end if t_end is not None else max((r.t_end for r in rows if math.isfinite(r.t_end)), default=T_END)
    fig, axes = plt.subplots(1, len(dts), figsize=(6.0 * len(dts), 4.8), dpi=90, squeeze=False)
    colours = {"ours": "C0", "vbd": "C1", "style3d": "C2"}
    for ax, dt in zip(axes[0], dts):
        for solver in dict.fromkeys(r.solver for r in rows if r.dt == dt):
            colour = colours.get(solver, "C3")
            points = [p for p in _points(rows, solver, dt) if p[1] > 0]
            f = [p for p in front(points) if p[1] > 0]
            if not f:
                ax.plot([], [], " ", label=f"{LABELS.get(solver, solver)}: no points")
                continue
            ax.loglog([p[0] for p in points], [p[1] for p in points], "o", mfc="none", color=colour, ms=5, alpha=0.7)
            ax.loglog([p[0] for p in f], [p[1] for p in f], "-", color=colour, lw=1.4, label=LABELS.get(solver, solver))
            for level in levels:
                cost = match_level(points, level)[0]
                if math.isfinite(cost):
                    ax.loglog([cost], [level], "D", color=colour, ms=5)
        for level in levels:
            ax.axhline(level, ls=":", color="0.4", lw=1)
            ax.annotate(f"{level:g}", (0.99, level), xycoords=("axes fraction", "data"), ha="right", va="bottom",
                        fontsize=8, color="0.3")
        ax.set_xlabel("CPU s per simulated s (one thread)")
        ax.set_ylabel(f"RMS distance to own reference / cloth size (1 m), t = {t_end:g} s")
        ax.set_title(f"hanging cloth, dt = {_dt_label(dt)} (peers: substep)", fontsize=10)
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=8, loc="best", framealpha=0.8)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def write_accuracy(out: Path, rows, levels=LEVELS, progress=print) -> list[str]:
    """Write the rows' CSV, the matched levels' CSV, the plot and the markdown (verdicts and both tables) into
    ``out``; print the tables and verdicts through ``progress``; return the verdict lines."""
    say = progress or (lambda *_, **__: None)
    out = Path(out)
    matches, lines = matched_levels(rows, levels), verdicts(rows)
    write_csv(out / "bench_accuracy.csv", rows)
    write_csv(out / "bench_accuracy_levels.csv", matches)
    plot_accuracy(rows, out / "bench_accuracy.png", levels)
    table, levels_table = format_accuracy(rows), format_levels(matches)
    (out / "bench_accuracy.md").write_text(
        "# Matched accuracy: the hanging cloth, computed from this run\n\n"
        "CPU seconds per simulated second at a matched error: the RMS distance at t_end to each solver's own most "
        "converged run at the same dt, over the cloth's size (validation/benches/accuracy.py). A level's cost is "
        "interpolated in log-log on each solver's work-precision front between the two points bracketing it.\n\n"
        "## Verdicts\n\n" + "".join(f"- {line}\n" for line in lines)
        + "\n## Matched levels\n\n" + levels_table + "\n\n## Runs\n\n" + table + "\n\n![work-precision]"
        "(bench_accuracy.png)\n")
    say(table)
    say(levels_table)
    say("\n".join(lines))
    say(f"wrote {out / 'bench_accuracy.csv'}, {out / 'bench_accuracy_levels.csv'}, {out / 'bench_accuracy.png'} "
        f"and {out / 'bench_accuracy.md'}")
    return lines


def bench_accuracy(out: Path, t_end: float = T_END, dts=DTS, progress=print, nodes: int = NODES,
                   solvers=("ours", "vbd", "style3d"), sweeps=None, levels=LEVELS) -> list[str]:
    """Measure the matched-accuracy rows (:func:`measure_accuracy`) and write them into ``out``
    (:func:`write_accuracy`): the verdict lines.

    Parameters
    ----------
    out : Path
        An existing writable folder.
    t_end : float
        Simulated time of every run (s).
    dts : tuple of float
        Ours' time steps and the peers' substeps (s); each must divide the peers' frame of 1/60 s.
    progress : callable or None
        Called with a line as each run starts and ends, then with the tables and verdicts; None: silent.
    nodes : int
        Nodes (particles) a side.
    solvers : tuple of str
        Of "ours", "vbd", "style3d".
    sweeps : dict, optional
        solver -> its settings (default :data:`SWEEPS`).
    levels : tuple of float
        The error levels matched (RMS distance over the cloth's size).
    """
    sweeps = SWEEPS if sweeps is None else sweeps
    for dt in dts:  # refused before any work
        substeps_of(dt)
        for solver in solvers:
            _at(sweeps[solver], dt)
    rows = measure_accuracy(nodes, t_end, dts, solvers, sweeps, progress)
    return write_accuracy(out, rows, levels, progress)
