r"""``deformable sweep``: a scene run over the cartesian product of config values, one table.

::

    deformable sweep SCENE|FILE.toml KEY=V1,V2,... [KEY=START:STOP:NUM[:log] ...]
                     [--backend fd|fe|fd,fe] [--force-model M] [--grid MxN] [--dt DT] [--t-end T]
                     [--measure NAME,...] [--out DIR]
                     [--jobs N | --scheduler local:N|tcp://HOST:PORT|FILE]
                     [--max-cases N] [--fail-on-error] [--compare-serial]

Each ``KEY=...`` names a field of the scene's config (``dataclasses.fields``
of :func:`deformable.scenes.config`; a TOML scene file gives the base) and
its values: a comma-separated list, where an item may be a range
``START:STOP:NUM`` (NUM values, ends included, both finite; ``:log`` for
geometric spacing); a key given one value is a fixed override
(``nodes=12x12``, ``t_end=0.5``). The options ``--grid``, ``--dt``,
``--t-end`` and ``--force-model`` are ``deformable run``'s (the same
definitions and checks, :func:`validation.commands.run.run_options`): fixed
overrides of nodes, dt, t_end and force_model; a key given both as an option
and as ``KEY=...`` is refused. Every combination, on every backend of
``--backend``, is one run (:mod:`validation.harness.sweep`), through the
executor layer (:mod:`validation.harness.runner`): serial by default,
``--jobs N`` local processes, or Dask with ``--scheduler``. A grid is
``MxN``, ``[M, N]`` or ``N`` (as ``deformable run`` reads ``nodes=``); one not
set (no ``nodes``, no --grid, none in the scene file) is the scene's, taken in
each backend's unit as ``deformable run`` takes it (FE half as many elements a
side): a case runs the grid and model the run of its config would.

The cases are counted before any is built: a sweep of more than
``--max-cases`` (default 100 000), or a range of more values than that, is
refused in one line naming the count (``eta=1:2:100000 xi=0:1:100000``, 1e10
cases, is refused at once; it used to run out of memory building them).

Output (default ``sweeps/<scene>/``): ``sweep.csv``, ``sweep.md``,
``sweep.toml`` and, for two swept keys, the map ``sweep.png``; each case's
record in ``cases/``, written as it finishes. Run the same command again
and only the cases not stored yet run (a killed sweep continues where it
stopped). Progress (cases done, time left) goes to stderr.

A case that diverges, stops or stalls is a row with its status; so is a case
that fails (a value the scene refuses, a solver error, a worker process that
died each time it ran the case), with its message. A worker process that dies
(killed, out of memory) is replaced and its case runs again, up to 3 times, on
the pool as on Dask; the cases that had not started run as they would have.
Exit code: 0 when no case failed; 1 when some failed, said by the last line
(``sweep: N of M cases failed; ...`` on stderr), or with ``--fail-on-error``
when some case did not finish. Bad input (an unknown scene, key, backend or
measure, a value that is not a number, a malformed range or one with an end
that is not finite, a sweep above ``--max-cases``, a scheduler spec that is
neither local:N, an address nor a file, Dask missing) is one line on stderr
and exit code 2 before anything is written.

Ctrl-C (SIGINT to the terminal's process group) ends the sweep: the workers,
pool or Dask, ignore it and are stopped by this process, the cases finished
so far stay stored, and the one line ``interrupted`` goes to stderr, exit code
130. The same command continues the sweep.

``--compare-serial`` is a measurement: it runs every case (none taken from
the folder) on the chosen executor, then again serially in this process,
and reports both wall times, their ratio and whether every number agrees
bit for bit (exit code 1 if not).
"""

from __future__ import annotations

import json
import logging
import math
import re
import sys
import tempfile
import time
from dataclasses import fields
from pathlib import Path

import numpy as np

from deformable import scenes
from deformable.checks import count, known_keys
from deformable.errors import InputError, ResourceError
from validation.harness.report import writable_folder
from validation.harness.runner import Runner, counted, duration
from validation.harness.sweep import MAX_CASES, MEASURES, STATUSES, Sweep, plain, write_outputs

from .run import check_backend, option_fields, parse_grid, run_options, scene_config, scene_source, sets_grid
from .validate import check_jobs, executor_options

__all__ = ["configure", "execute", "fixed_options", "parse_axis", "parse_sweep"]

log = logging.getLogger(__name__)


def configure(parser) -> None:
    """Arguments of ``deformable sweep``."""
    parser.add_argument("scene", metavar="SCENE|FILE.toml",
                        help=f"a scene name ({', '.join(scenes.SCENES)}) or a TOML scene file")
    parser.add_argument("values", nargs="*", metavar="KEY=VALUES",
                        help="a config field and its values: V1,V2,... and/or ranges START:STOP:NUM[:log]; "
                        "one value is a fixed override (e.g. nodes=16x16 t_end=0.5)")
    run_options(parser, sweep=True)  # --backend (a list), --force-model, --t-end, --dt, --grid: as run takes them
    parser.add_argument("--measure", default=None, metavar="NAME,...",
                        help=f"extra columns, at the end of each run: {', '.join(MEASURES)} (default: none)")
    parser.add_argument("--out", default=None, metavar="DIR", help="output folder (default: sweeps/<scene>)")
    executor_options(parser)
    parser.add_argument("--max-cases", type=int, default=MAX_CASES, metavar="N",
                        help="refuse a sweep of more than N cases, counted before any is built (default: %(default)s)")
    parser.add_argument("--fail-on-error", action="store_true",
                        help="exit 1 also when a case diverged, stopped or stalled (a failed case always exits 1)")
    parser.add_argument("--compare-serial", action="store_true",
                        help="measure: run every case on the executor and then serially; report both wall times "
                        "and whether the numbers agree bit for bit")


# -- parsing ---------------------------------------------------------------------------
def _number(key: str, text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise InputError(f"sweep value of {key} must be a number, got {text!r}", field=key, value=text) from None


def _values(key: str, item: str, default, limit: int = MAX_CASES) -> list:
    """One comma-separated item of ``key=...``: a value, or a range ``start:stop:num[:log]`` of a number field.

    A range needs finite ends and at most ``limit`` values (``--max-cases``), checked before they are made.
    """
    item = item.strip()
    if isinstance(default, tuple):
        if len(default) != 2:  # the obstacles: tables, not a pair of numbers
            raise InputError(f"a sweep cannot vary {key}: its value is a list of tables, not a number or a pair; "
                             "set it in a scene file", field=key, value=item)
        if all(isinstance(v, int) for v in default):  # the node grid: MxN, [M, N], or N for N x N
            return [parse_grid(item, field=key, square=True)]
        parts = re.split(r"\s*[xX]\s*", item)
        if len(parts) > 2 or not all(parts):
            raise InputError(f"sweep value of {key} must be AxB or A (for AxA), got {item!r}", field=key, value=item)
        pair = [_number(key, p) for p in parts]
        return [tuple(pair if len(pair) == 2 else pair * 2)]
    if isinstance(default, str):
        if item in ("", '""', "''") and key == "fabric":  # no named fabric: the config's own mu, eta, xi, shear
            return [""]
        if not item:
            raise InputError(f"sweep value of {key} is empty", field=key, value=item)
        return [item]
    if ":" not in item:
        return [_number(key, item)]
    parts = item.split(":")
    log_spaced = len(parts) == 4 and parts[3] == "log"
    if len(parts) != 3 and not log_spaced:
        raise InputError(f"sweep range of {key} must be START:STOP:NUM or START:STOP:NUM:log, got {item!r}",
                         field=key, value=item)
    start, stop = _number(key, parts[0]), _number(key, parts[1])
    if not (parts[2].isascii() and parts[2].isdigit()) or int(parts[2]) < 2:
        raise InputError(f"sweep range {key}={item} needs NUM >= 2 values, got {parts[2]!r}", field=key, value=item)
    for end, text in ((start, parts[0]), (stop, parts[1])):
        if not math.isfinite(end):
            raise InputError(f"sweep range {key}={item}: START and STOP must be finite, got {text!r}",
                             field=key, value=item)
    if log_spaced and not (start > 0 and stop > 0):
        raise InputError(f"sweep range {key}={item}: a log range needs START and STOP > 0", field=key, value=item)
    num = int(parts[2])
    if num > limit:
        raise ResourceError(f"sweep range {key}={item} has {num} values, more than --max-cases {limit}",
                            field=key, value=item)
    if not log_spaced and not math.isfinite(stop - start):  # finite ends, but their step would overflow
        raise InputError(f"sweep range {key}={item} spans more than a float can hold", field=key, value=item)
    spaced = np.geomspace if log_spaced else np.linspace
    return [float(v) for v in spaced(start, stop, num)]


def parse_axis(base, text: str, limit: int = MAX_CASES) -> tuple[str, tuple]:
    """``"key=v1,v2,start:stop:num,..."`` -> (key, values) for the config ``base``; InputError on bad input.

    Values are typed by the field's default: numbers; ``MxN``, ``[M, N]`` or ``N`` for the node grid
    (:func:`validation.commands.run.parse_grid`, as ``deformable run`` reads ``nodes=``); ``AxB``
    (or ``A``) for the other pairs (size, rest_metric); text for the others (force_model); a value
    given twice counts once. A range has finite ends and at most ``limit`` values. Whether the scene
    accepts a value is decided by each case (a refused one is a failed row).
    """
    key, sep, rest = str(text).partition("=")
    key = key.strip()
    if not sep or not key:
        raise InputError(f"sweep values must be KEY=V1,V2,... or KEY=START:STOP:NUM, got {text!r}", value=text)
    if key == "scene":
        raise InputError("the scene itself is not a sweep key: run one sweep per scene", field=key)
    known_keys([key], sorted(f.name for f in fields(base)), f"for scene {base.scene!r}")
    default = getattr(base, key)
    items = re.split(r",(?![^\[]*\])", rest)  # commas between values, not inside a grid's [M, N]
    values = dict.fromkeys(v for item in items for v in _values(key, item, default, limit))
    return key, tuple(values)


def _names(text: str, check) -> tuple[str, ...]:
    """The comma-separated names of ``text``, each once, each passed through ``check`` (InputError when unknown)."""
    names = tuple(dict.fromkeys(n.strip() for n in str(text).split(",")))
    for n in names:
        check(n)
    return names


def _measure(name: str) -> str:
    if name not in MEASURES:
        raise InputError(f"--measure: unknown measure {name!r}; choose from {', '.join(MEASURES)}", field="measure",
                         value=name)
    return name


#: the scene field each shared option of run sets, and the option
OPTIONS = {"nodes": "--grid", "dt": "--dt", "t_end": "--t-end", "force_model": "--force-model"}


def _given(args, key: str):
    """What the command line gave the option that sets scene field ``key`` (its text)."""
    return getattr(args, OPTIONS[key][2:].replace("-", "_"))


def fixed_options(args, items) -> dict:
    """The scene fields set by run's options (--grid, --dt, --t-end, --force-model), checked as run checks them;
    InputError (one line) when one of them is also a KEY=VALUES item."""
    given = option_fields(args)
    keys = {str(item).partition("=")[0].strip() for item in items}
    for key in given:
        if key in keys:
            raise InputError(f"sweep key {key} is also given as the option {OPTIONS[key]}; give it one way",
                             field=key, value=_given(args, key))
    return given


def parse_sweep(base, items, backends: str = "fd", measures: str | None = None, max_cases: int = MAX_CASES,
                fixed: dict | None = None, grid_set: bool = False) -> Sweep:
    """The :class:`Sweep` of command-line text: ``items`` like ``"eta=10,20"``, ``backends`` like ``"fd,fe"``;
    ``fixed`` the fields the options set (:func:`fixed_options`), axes of one value after the items';
    ``grid_set`` the base's grid was set by its scene file (:attr:`Sweep.grid_set`).

    Raises InputError (one line naming the key and value) on bad input, and ResourceError (naming the count)
    for a sweep of more than ``max_cases`` cases, counted before any is built.
    """
    limit = count("--max-cases", max_cases)
    axes = [parse_axis(base, item, limit) for item in items]
    axes += [(key, (value,)) for key, value in (fixed or {}).items()]
    keys = [k for k, _ in axes]
    twice = [k for k in dict.fromkeys(keys) if keys.count(k) > 1]
    if twice:
        raise InputError(f"sweep key {twice[0]!r} is given twice; list all its values in one KEY=V1,V2,...",
                         field=twice[0])
    return Sweep(base, tuple(axes), _names(backends, check_backend), _names(measures, _measure) if measures else (),
                 max_cases=limit, grid_set=grid_set)


# -- the command -----------------------------------------------------------------------
def _numbers(record: dict) -> str:
    """Everything a case computed, wall time aside, as text (to compare runs bit for bit)."""
    return json.dumps({k: v for k, v in record.items() if k != "wall"}, sort_keys=True, default=plain)


def _case_time(records) -> float:
    """The cases' own wall times added up (s); a case lost with its worker has none."""
    return sum(r["wall"] for r in records if math.isfinite(r["wall"]))


def execute(args) -> int:
    """``deformable sweep``: 0; 1 when a case failed, with --fail-on-error when one did not finish, or when
    --compare-serial found the numbers differ (the last line on stderr says which)."""
    base = scene_config(args.scene)
    fixed = fixed_options(args, args.values)
    sweep = parse_sweep(base, args.values, args.backend, args.measure, args.max_cases, fixed=fixed,
                        grid_set=sets_grid(*scene_source(args.scene)))
    runner = Runner(check_jobs(args.jobs, args.oversubscribe), progress=not getattr(args, "quiet", False),
                    scheduler=args.scheduler, progress_after=0.0)  # a line as each case is stored
    out = writable_folder(Path(args.out) if args.out else Path("sweeps") / base.scene)
    options = [[OPTIONS[k], _given(args, k)] for k in fixed]
    command = " ".join(["deformable sweep", args.scene, *args.values, "--backend", ",".join(sweep.backends)]
                       + [w for pair in options for w in pair]
                       + (["--measure", ",".join(sweep.measures)] if sweep.measures else []))
    total = sweep.count
    t0 = time.perf_counter()
    with runner:  # a LocalCluster starts here: its start is part of the wall time, its shutdown is not
        records, ran = sweep.run(runner, out, reuse=not args.compare_serial)
        wall = time.perf_counter() - t0
        where = runner.describe()
    summary = (f"{counted(ran)} run {where} in {duration(wall)}; {total - ran} taken from earlier runs in this "
               f"folder; the cases' own wall times add up to {duration(_case_time(records))}.")
    differ = False
    if args.compare_serial:
        with tempfile.TemporaryDirectory(dir=out, prefix=".serial-") as tmp, Runner(1, progress=True) as serial:
            t1 = time.perf_counter()
            alone, _ = sweep.run(serial, tmp, reuse=False)
            serial_wall = time.perf_counter() - t1
        differ = any(_numbers(a) != _numbers(b) for a, b in zip(records, alone))
        summary += (f" Compared with a serial run of the same {counted(total)}: {duration(serial_wall)} serially, "
                    f"{wall:.2f} s / {serial_wall:.2f} s = {wall / serial_wall:.3f} of its wall time "
                    f"(starting the workers included); numbers {'DIFFER' if differ else 'bit-identical'}.")
    write_outputs(out, sweep, records, command=command, summary=summary)
    statuses = [r["status"] for r in records]
    counts = ", ".join(f"{statuses.count(s)} {s}" for s in STATUSES if s in statuses)
    print(f"{base.scene}: {counted(total)} ({counts}). {summary} Table: {out / 'sweep.md'}")
    if differ:
        print("sweep: the executor's numbers differ from the serial run's", file=sys.stderr)
    unfinished = total - statuses.count("finished")
    failed = statuses.count("failed")
    if args.fail_on_error and unfinished:
        others = ", ".join(f"{statuses.count(s)} {s}" for s in STATUSES[1:] if s in statuses)
        print(f"sweep: {unfinished} of {total} cases did not finish ({others}; --fail-on-error)", file=sys.stderr)
    elif failed:
        print(f"sweep: {failed} of {counted(total)} failed; their messages are in {out / 'sweep.md'}",
              file=sys.stderr)
    return 1 if differ or failed or (args.fail_on_error and unfinished) else 0
