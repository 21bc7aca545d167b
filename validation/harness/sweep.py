r"""Parameter sweeps: the cartesian product of scene-config values, each case one run.

A :class:`Sweep` is a base scene config (:mod:`deformable.scenes`), axes
``key = (v1, v2, ...)`` over the config's fields and one or more backends.
Its cases are counted (:attr:`Sweep.count`, the backends times the values of
every axis) when it is made, before any is built: a product above
``max_cases`` (default :data:`MAX_CASES`, 100 000) is refused with a
:class:`~deformable.errors.ResourceError` naming the count (a sweep of 1e10
cases used to build them until memory ran out).
Every combination is a :class:`SweepCase`, run by :func:`run_case`: the grid,
scene and model of the config on its backend by
:class:`deformable.Simulation` (the path ``deformable run``
takes), and :class:`deformable.TimeStepper` from the initial state to the
config's t_end (eq. (22)-(27) for the tpbf87 and frozen force models, implicit
Euler for the variational one), at the config's dt, or on a backend whose
stretching bound is tighter at half that bound
(:func:`deformable.dynamics.dt.within_stable`) unless dt was given. A grid
not set (no ``nodes`` axis, no ``nodes`` in the scene file) is the scene's,
written in FD's nodes, taken in the backend's unit
(:meth:`deformable.backends.Discretisation.scene_nodes`: FE half as many elements a
side), as ``deformable run`` takes it; a case's fields hold the grid it runs.

Each case gives one row: its status (``finished``, ``diverged`` when the
divergence guard stopped it, ``stopped``, ``stalled`` when an implicit step
found no dt, ``failed`` when the case raised: a value the scene refuses, a
solver error; the message says why), the time reached, the final elastic
energy of eq. (13) (J), the largest edge stretch and node speed over the run,
its wall time, and the measures asked for (:data:`MEASURES`).

Cases are independent and go through a :class:`~validation.harness.runner.Runner`
(serial, process pool or Dask). A case whose worker process died runs again on
a new worker (the pool and Dask alike, up to 3 times); a case given up after
that is a ``failed`` row, its message starting ``worker:``, and the cases that
had not started run as they would have. An interrupted sweep (Ctrl-C) stores
what finished and nothing for the others. Each finished case is stored at once as
``OUT/cases/<key>.json`` (written to a temporary name and renamed, so a kill
never leaves half a file), the key a digest of the scene, the full resolved
config and the backend. A sweep started again in the same folder takes the
cases stored there whose status is final (finished, diverged, stopped,
stalled) and that hold the measures asked for, and runs only the others
(failed cases run again); a sweep extended by new values runs only the new
combinations.

Outputs (:func:`write_outputs`): ``sweep.csv`` (full precision), ``sweep.md``
(the table and what it means), ``sweep.toml`` (the resolved base config) and,
when exactly two keys take more than one value, ``sweep.png``: a map of the
statuses over those two keys (one panel per backend), like the paper study's
stability maps.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import logging
import math
import os
import re
import time
from contextlib import closing, contextmanager
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from deformable import checks, scenes
from deformable.dynamics.trackers import DivergenceGuard, Tracker
from deformable.errors import InputError, ResourceError
from deformable.physics.force_models import ForceModel
from deformable.scenes.config import force_model_table

from deformable.session import Simulation

from .backends import descriptor
from .report import csv_text, markdown_table
from .runner import counted
from .study import Table

__all__ = ["FINAL", "plain", "MAX_CASES", "MEASURES", "STATUSES", "Extremes", "Sweep", "SweepCase", "load_records",
           "map_png", "run_case", "save_record", "write_outputs"]

log = logging.getLogger(__name__)

#: every status a row can have; FINAL ones are kept by a restarted sweep, "failed" cases run again
STATUSES = ("finished", "diverged", "stopped", "stalled", "failed")
FINAL = ("finished", "diverged", "stopped", "stalled")
#: the most cases a sweep may have unless it says otherwise (``--max-cases``)
MAX_CASES = 100_000


# -- measures --------------------------------------------------------------------------
def _energy_part(part):
    return lambda model, state, X0: float(getattr(model.energy(state.X), part))


def _largest_metric(model, state, X0) -> float:
    G, _ = model.tensors(state.X)
    return float(max(G[0, 0].max(), G[1, 1].max()))


def _largest_curvature(model, state, X0) -> float:
    _, B = model.tensors(state.X)
    return float(np.abs(B).max())


def _displacement(model, state, X0) -> float:
    return float(np.max(np.linalg.norm(model.grid(state.X) - model.grid(X0), axis=-1)))


#: ``--measure`` names: (column header, fn(model, final State, X0) -> float), all at the end of the run
MEASURES = {
    "kinetic": ("kinetic energy (J)", lambda model, state, X0: float(model.kinetic_energy(state.V))),
    "stretching": ("stretching energy (J)", _energy_part("stretching")),
    "bending": ("bending energy (J)", _energy_part("bending")),
    "metric": ("max G_ii", _largest_metric),
    "curvature": ("max |B_ij| (1/m)", _largest_curvature),
    "displacement": ("max displacement (m)", _displacement),
}


class Extremes(Tracker):
    """The largest edge stretch and node speed of a run, watched every step.

    ``stretch``: the longest grid edge between neighbouring nodes over its parameter length h_i
    (1 = unstretched for the scenes' flat rest shapes); ``speed``: the largest node speed (m/s).
    """

    def initialize(self, state, stepper, steps):
        super().initialize(state, stepper, steps)
        self.h = stepper.model.spacing
        self.stretch = self.speed = 0.0
        self.handle(state)

    def handle(self, state):
        model = self.stepper.model
        e1, e2 = DivergenceGuard._edges(model.grid(state.X))
        self.stretch = max(self.stretch, float(e1.max()) / self.h[0], float(e2.max()) / self.h[1])
        self.speed = max(self.speed, float(np.max(np.linalg.norm(state.V[model.value_dofs], axis=1))))


# -- cases -----------------------------------------------------------------------------
@dataclass(frozen=True)
class SweepCase:
    """One run of a sweep.

    scene : the scene's registry name
    fields : ((key, value), ...) every field of its config but ``scene``, sorted: the whole resolved config
    backend : "fd" | "fe"
    measures : names of :data:`MEASURES` to compute
    dt_given : dt was asked for, so it is kept even on a backend with a tighter bound
    """

    scene: str
    fields: tuple
    backend: str
    measures: tuple = ()
    dt_given: bool = False

    @property
    def key(self) -> str:
        """A digest of what determines the run (not the measures): the name of its stored result."""
        text = json.dumps([self.scene, [[k, v] for k, v in self.fields], self.backend, self.dt_given],
                          default=plain)
        return hashlib.sha1(text.encode()).hexdigest()[:16]

    @property
    def cost(self) -> float:
        """A rough cost (steps times nodes times the backend's cost per node, FE 4) to start long cases first."""
        f = dict(self.fields)
        try:
            return f["t_end"] / f["dt"] * f["nodes"][0] * f["nodes"][1] * descriptor(self.backend).cost
        except (KeyError, TypeError, ZeroDivisionError, IndexError, InputError):
            return 0.0


def plain(value):
    """A field's value that JSON does not hold, as the scene file writes it (for a case's key): the table of the
    contact settings, an obstacle or a force model with parameters; anything else its repr."""
    if isinstance(value, ForceModel):
        return force_model_table(value)
    table = getattr(value, "table", None)
    return table() if callable(table) else repr(value)


@contextmanager
def _divergence_expected():
    """Silence the stepper's warning on a diverged run: in a sweep that is an outcome, tabulated."""
    logger = logging.getLogger("deformable.dynamics.stepper")
    level = logger.level
    logger.setLevel(logging.ERROR)
    try:
        yield
    finally:
        logger.setLevel(level)


def run_case(case: SweepCase) -> dict:
    """Run one case; returns its record (a JSON-ready dict). Never raises: an error is a "failed" record.

    The record holds ``key``, ``scene``, ``backend``, ``fields``, ``status``, ``message``, ``t`` (s
    reached), ``steps``, ``dt`` (s), ``energy`` (J, eq. 13 at the last good state), ``max_stretch``,
    ``max_speed`` (m/s), ``measures`` {name: value}, ``wall`` (s) and ``state_sha1`` (a digest of the
    final positions, to compare runs bit for bit).
    """
    t0 = time.perf_counter()
    record = {"key": case.key, "scene": case.scene, "backend": case.backend, "fields": dict(case.fields)}
    try:
        cfg = scenes.config(case.scene, **dict(case.fields))
        sim = Simulation(cfg, case.backend, nodes=cfg.nodes, dt=cfg.dt if case.dt_given else None)
        model, dt, X0 = sim.model, sim.config.dt, sim.X0
        extremes = Extremes()
        with _divergence_expected():
            result = sim.run(t_end=cfg.t_end, trackers=[extremes])
        state = result.state
        energy = model.energy(state.X)
        record.update(status=result.status, message=result.message, t=float(state.t), steps=int(result.steps),
                      dt=float(dt), energy=float(energy.stretching + energy.bending),
                      max_stretch=extremes.stretch, max_speed=extremes.speed,
                      measures={m: MEASURES[m][1](model, state, X0) for m in case.measures},
                      state_sha1=hashlib.sha1(np.ascontiguousarray(state.X).tobytes()).hexdigest())
    except Exception as err:  # noqa: BLE001 - a case's failure is a row of the table, not the end of the sweep
        record.update(status="failed", message=_one_line(err))
    record["wall"] = time.perf_counter() - t0
    return record


def _one_line(err: BaseException) -> str:
    text = " ".join(str(err).split())
    return f"{type(err).__name__}: {text}" if text else type(err).__name__


# -- the sweep -------------------------------------------------------------------------
@dataclass(frozen=True)
class Sweep:
    """A base config, axes and backends; :meth:`cases` is their cartesian product.

    base : the scene config every case starts from (defaults, or a scene file)
    axes : ((key, values), ...) in the order given; an axis of one value is a fixed override
    backends : ("fd",), ("fe",) or both
    measures : names of :data:`MEASURES`
    max_cases : the most cases allowed; more raise ResourceError (one line naming the count) on construction
    grid_set : the base's grid was set (a scene file's ``nodes``): every backend takes it as is, as a ``nodes``
    axis is; otherwise each backend takes the scene's grid in its own unit (:meth:`deformable.backends.Discretisation.scene_nodes`)
    """

    base: scenes.SceneConfig
    axes: tuple
    backends: tuple = ("fd",)
    measures: tuple = ()
    max_cases: int = MAX_CASES
    grid_set: bool = False

    def __post_init__(self):
        checks.count("--max-cases", self.max_cases)
        if self.count > self.max_cases:
            sizes = " x ".join([counted(len(self.backends), "backend"),
                                *(f"{len(v)} {k}" for k, v in self.axes if len(v) > 1)])
            raise ResourceError(f"a sweep of {self.base.scene} with {self.count} cases ({sizes}) is more than "
                                f"--max-cases {self.max_cases}; sweep fewer values, or raise --max-cases",
                                field="--max-cases", value=self.count)
        axes = dict(self.axes)
        fabrics = axes.get("fabric", (self.base.fabric,))
        swept = sorted(set(axes) & set(self.base.FABRIC_FIELDS))
        if swept and any(fabrics):
            named = ", ".join(repr(f) for f in fabrics if f)
            raise InputError(f"sweep key {swept[0]}: the fabric {named} sets mu, eta, xi and shear; add fabric=\"\" "
                             f"to sweep {swept[0]} on its values", field=swept[0], value=str(axes[swept[0]])[:60])

    @property
    def count(self) -> int:
        """The number of cases: the backends times the number of values of every axis, counted without building any."""
        return len(self.backends) * math.prod(len(v) for _, v in self.axes)

    @property
    def swept(self) -> tuple[str, ...]:
        """The keys that take more than one value (the table's and the map's columns)."""
        return tuple(k for k, v in self.axes if len(v) > 1)

    @property
    def fixed(self) -> dict:
        """The keys given one value: overrides of the base config."""
        return {k: v[0] for k, v in self.axes if len(v) == 1}

    def cases(self) -> list[SweepCase]:
        """Every combination, backends first, then the axes in order (the last one fastest); each case's
        ``nodes`` the grid its backend runs (:meth:`deformable.backends.Discretisation.scene_nodes`)."""
        base = {f.name: getattr(self.base, f.name) for f in fields(self.base) if f.name != "scene"}
        dt_given = "dt" in dict(self.axes)
        grid_set = self.grid_set or "nodes" in dict(self.axes)
        out = []
        for backend in self.backends:
            own = base if grid_set else dict(base, nodes=descriptor(backend).scene_nodes(self.base.nodes))
            for combo in itertools.product(*(v for _, v in self.axes)):
                merged = self.base.stated(dict(own, **dict(zip((k for k, _ in self.axes), combo))))
                out.append(SweepCase(self.base.scene, tuple(sorted(merged.items())), backend, self.measures,
                                     dt_given))
        return out

    def run(self, runner, out, reuse: bool = True) -> tuple[list[dict], int]:
        """Run the cases not stored in ``out`` yet on ``runner``; returns (records in case order, cases run).

        Each record is stored in ``out/cases`` as it arrives. ``reuse=False`` runs every case. A case the
        runner gave up because its worker died each time is a ``failed`` record (message ``worker: ...``);
        an interrupt (KeyboardInterrupt) leaves the cases not finished unrecorded.
        """
        cases = self.cases()
        records = load_records(out, cases, self.measures) if reuse else {}
        todo = sorted((c for c in cases if c.key not in records), key=lambda c: -c.cost)
        if records:
            log.info("sweep: %d of %d cases already in %s", len(records), len(cases), out)
        with closing(runner.completed(run_case, todo, desc=f"sweep {self.base.scene}")) as outcomes:
            for i, record, error in outcomes:
                if error is not None:  # its worker died, every time (run_case never raises): it runs again next time
                    case = todo[i]
                    record = {"key": case.key, "scene": case.scene, "backend": case.backend,
                              "fields": dict(case.fields), "status": "failed",
                              "message": f"worker: {_one_line(error)}", "wall": float("nan")}
                save_record(out, record)
                records[record["key"]] = record
        return [records[c.key] for c in cases], len(todo)

    # -- the table ----------------------------------------------------------------------
    def columns(self) -> tuple[str, ...]:
        return ("backend", *self.swept, "status", "t (s)", "steps", "dt (s)", "energy (J)", "max stretch",
                "max speed (m/s)", "wall (s)", *(MEASURES[m][0] for m in self.measures), "message")

    def row(self, case: SweepCase, record: dict) -> tuple:
        fields_ = dict(case.fields)
        nan = float("nan")

        def get(name):
            return nan if record.get(name) is None else record[name]
        measures = record.get("measures") or {}
        return (case.backend, *(_cell(fields_[k]) for k in self.swept), record["status"], get("t"),
                record.get("steps", ""), get("dt"), get("energy"), get("max_stretch"), get("max_speed"),
                get("wall"), *(measures.get(m, nan) for m in self.measures),
                record.get("message", "") if record["status"] != "finished" else "")

    def table(self, records: list[dict]) -> Table:
        rows = [self.row(c, r) for c, r in zip(self.cases(), records)]
        return Table("sweep", f"Sweep of {self.base.scene}", self.columns(), rows)


def _cell(value):
    return "x".join(f"{v:g}" for v in value) if isinstance(value, tuple) else value


# -- storage ---------------------------------------------------------------------------
def _atomic_write(path: Path, data: str | bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file in the same folder and a rename."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with open(tmp, "wb" if isinstance(data, bytes) else "w") as f:
            f.write(data)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def save_record(out, record: dict) -> Path:
    """Store one case's record as ``out/cases/<key>.json`` (atomically)."""
    path = Path(out) / "cases" / f"{record['key']}.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    _atomic_write(path, json.dumps(record, indent=1, sort_keys=True, default=plain) + "\n")
    return path


def load_records(out, cases, measures=()) -> dict[str, dict]:
    """The stored records of ``cases`` that a restarted sweep keeps: final status, every measure asked for."""
    kept = {}
    for case in cases:
        path = Path(out) / "cases" / f"{case.key}.json"
        if not path.is_file():
            continue
        try:
            record = json.loads(path.read_text())
        except (OSError, ValueError):
            log.warning("sweep: unreadable %s; the case runs again", path)
            continue
        if record.get("key") == case.key and record.get("status") in FINAL \
                and all(m in (record.get("measures") or {}) for m in measures):
            kept[case.key] = record
    return kept


# -- outputs ---------------------------------------------------------------------------
_MARK = {"finished": ("o", "tab:green"), "stopped": ("s", "tab:blue"), "stalled": ("D", "tab:orange"),
         "diverged": ("x", "tab:red"), "failed": ("*", "0.3")}


def axis_label(cls, key: str) -> str:
    """An axis label of a swept key of config class ``cls``: the key, its meaning and unit as the config's
    docstring gives them (:func:`deformable.scenes.fields.field_docs`, the one place fields are documented)."""
    doc = scenes.field_docs(cls).get(key)
    if doc is None:
        return key
    meaning = re.split(r"[,;:]", doc.meaning)[0].strip()
    label = f"{key}, {meaning[:1].lower()}{meaning[1:]}"
    return label if doc.unit in ("", "-") else f"{label} ({doc.unit})"


def map_png(sweep: Sweep, records: list[dict]) -> bytes:
    """The statuses over the two swept keys, one panel per backend (categorical axes: one column per value)."""
    import io

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    (kx, vx), (ky, vy) = [(k, v) for k, v in sweep.axes if len(v) > 1]
    panels = len(sweep.backends)
    fig, axes = plt.subplots(1, panels, figsize=(max(4.0, 0.35 * len(vx) + 2.5) * panels,
                                                 max(3.4, 0.3 * len(vy) + 2.0)), squeeze=False)
    for ax, backend in zip(axes[0], sweep.backends):
        points = {s: [] for s in _MARK}
        for case, record in zip(sweep.cases(), records):
            if case.backend == backend:
                f = dict(case.fields)
                points[record["status"]].append((vx.index(f[kx]), vy.index(f[ky])))
        for status, (marker, colour) in _MARK.items():
            if points[status]:
                x, y = zip(*points[status])
                ax.scatter(x, y, marker=marker, color=colour, s=40, label=status, zorder=3)
        for axis, key, values in ((ax.xaxis, kx, vx), (ax.yaxis, ky, vy)):
            step = max(1, math.ceil(len(values) / 12))
            axis.set_ticks(range(0, len(values), step))
            axis.set_ticklabels([f"{v:.3g}" if isinstance(v, float) else str(_cell(v))
                                 for v in values[::step]], fontsize=7)
        ax.set_xlabel(axis_label(type(sweep.base), kx), fontsize=8)
        ax.set_ylabel(axis_label(type(sweep.base), ky), fontsize=8)
        ax.set_xlim(-0.5, len(vx) - 0.5)
        ax.set_ylim(-0.5, len(vy) - 0.5)
        ax.set_title(f"{sweep.base.scene}, {backend}", fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80)
    plt.close(fig)
    return buf.getvalue()


_COLUMNS_NOTE = (
    "status: finished (reached t_end), diverged (the divergence guard stopped the run: non-finite, a grid "
    "edge stretched tenfold, or a displacement above 100 sheet diagonals), stopped, stalled (an implicit step "
    "found no dt), failed (the case raised: see its message). t: time reached (s); energy: the elastic energy "
    "of eq. (13), stretching + bending, at the last good state (J); max stretch: the longest grid edge over its "
    "parameter length, over the whole run (1 = unstretched); max speed: the largest node speed over the run "
    "(m/s); wall: the case's wall time (s), model building included. Measures are taken at the last good state.")


def write_outputs(out, sweep: Sweep, records: list[dict], command: str = "", summary: str = "") -> list[Path]:
    """Write ``sweep.csv``, ``sweep.md``, ``sweep.toml`` and (two swept keys) ``sweep.png`` in ``out``."""
    out = Path(out)
    table = sweep.table(records)
    counts = {s: sum(r["status"] == s for r in records) for s in STATUSES}
    written = []
    png = None
    if len(sweep.swept) == 2:
        png = out / "sweep.png"
        _atomic_write(png, map_png(sweep, records))
        written.append(png)
    fixed = ", ".join(f"{k} = {_cell(v)}" for k, v in sweep.fixed.items()) or "none"
    axes = ", ".join(f"{k} ({len(v)} values)" for k, v in sweep.axes if len(v) > 1) or "none"
    lines = [f"# Sweep of {sweep.base.scene}", ""]
    if command:
        lines += [f"`{command}`", ""]
    lines += [f"{counted(len(records))} on {', '.join(sweep.backends)}: "
              + ", ".join(f"{n} {s}" for s, n in counts.items() if n) + ".", ""]
    if summary:
        lines += [summary, ""]
    lines += [f"Swept: {axes}. Fixed: {fixed}. The rest of the config is `sweep.toml`.", "",
              _COLUMNS_NOTE, "", markdown_table(table.columns, table.rows), ""]
    if png is not None:
        lines += [f"![statuses over {' and '.join(sweep.swept)}](sweep.png)", ""]
    for name, text in (("sweep.csv", csv_text(table)), ("sweep.md", "\n".join(lines)),
                       ("sweep.toml", scenes.to_toml(sweep.base))):
        _atomic_write(out / name, text)
        written.append(out / name)
    return written
