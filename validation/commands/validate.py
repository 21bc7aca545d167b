r"""``deformable validate``: run validation studies and write their reports.

::

    deformable validate [STUDY ...] [--quick | --full] [--levels K] [--surfaces S,...] [--out DIR]
                        [--jobs N | --scheduler local:N|tcp://HOST:PORT|FILE]

Runs the registered studies (:data:`validation.studies.STUDIES`; when none is
named, every one whose ``in_default`` is true, at the quick levels), each on
a shared :class:`Runner` (the executor layer: the independent cases run
serially, on a process pool of N workers, or on Dask with ``--scheduler
local:N | tcp://HOST:PORT | FILE``), and writes each
study's report folder as soon as that study has finished, then the index.
Unknown studies, surfaces or level counts end in one line on stderr and exit
code 2 (a ValueError, turned into that by :mod:`validation.commands`). The exit
code is 1 when any check failed, 0 otherwise.
"""

from __future__ import annotations

import logging
import os
import time

from deformable.checks import count
from deformable.errors import InputError
from validation.harness.report import writable_folder, write_index, write_study
from validation.harness.runner import Runner
from validation.studies import STUDIES, get_study

__all__ = ["configure", "execute", "run"]

log = logging.getLogger(__name__)


def configure(parser) -> None:
    """Add the arguments of ``deformable validate`` to an argparse parser."""
    parser.add_argument("studies", nargs="*", metavar="STUDY",
                        help="studies to run (default: all but the long ones, "
                        f"{', '.join(n for n, s in STUDIES.items() if not s.in_default) or 'none'}): "
                        f"{', '.join(STUDIES)}")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--quick", dest="mode", action="store_const", const="quick",
                      help="quick levels (default; every study in under two minutes in all)")
    mode.add_argument("--full", dest="mode", action="store_const", const="full", help="fine levels (default: off)")
    parser.set_defaults(mode="quick")
    parser.add_argument("--levels", type=int, default=None, metavar="K",
                        help="number of refinement levels (overrides --quick/--full; each study states its range) "
                        "(default: the mode's)")
    parser.add_argument("--surfaces", default=None, metavar="S,...",
                        help="comma-separated analytic surfaces for the studies that take them (default: each "
                        "study's own)")
    parser.add_argument("--out", default="reports", metavar="DIR", help="output folder (default: reports)")
    executor_options(parser)


def executor_options(parser) -> None:
    """``--jobs N`` | ``--scheduler SPEC``, and ``--oversubscribe``: where the cases run (validate, sweep)."""
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--jobs", type=int, default=1, metavar="N",
                       help=f"local worker processes, at most the {os.cpu_count() or 1} cores (default: 1)")
    where.add_argument("--scheduler", default=None, metavar="SPEC",
                       help="run the cases on Dask: local:N (a LocalCluster of N workers), tcp://HOST:PORT (a running "
                       "scheduler) or a scheduler file; needs pip install \".[distributed]\" (default: none, local "
                       "processes)")
    parser.add_argument("--oversubscribe", action="store_true",
                        help="allow --jobs above the number of cores (default: off)")


def check_jobs(jobs, oversubscribe: bool = False) -> int:
    """``jobs`` as an int in [1, cores] (any positive count when ``oversubscribe``); InputError otherwise."""
    cores = os.cpu_count() or 1
    jobs = count("--jobs", jobs)
    if jobs > cores and not oversubscribe:
        raise InputError(f"--jobs {jobs} exceeds the {cores} cores of this machine; give --oversubscribe to start more "
                         "workers than cores", field="--jobs", value=jobs)
    return jobs


def run(names=(), mode: str = "quick", levels: int | None = None, surfaces=None, out="reports", jobs: int = 1,
        progress: bool = True, oversubscribe: bool = False, scheduler: str | None = None, finished=None):
    """Run studies and write their reports; returns the list of StudyResult.

    ``finished(result)`` is called as each study's report has been written (``deformable validate`` prints
    its line then, so that a log shows each study as it ends). ``progress``: the cases of each study, a bar
    on a terminal and timestamped lines elsewhere (:class:`deformable.progress.Progress`), on stderr.

    ``jobs`` local processes (at most the number of cores unless ``oversubscribe``), or ``scheduler``
    (:class:`~validation.harness.runner.Runner`) for Dask. All arguments are checked before anything runs
    (InputError, a ValueError, otherwise).
    """
    from validation.harness import surfaces as sf

    jobs = check_jobs(jobs, oversubscribe)
    studies = [get_study(n) for n in (names or [n for n, s in STUDIES.items() if s.in_default])]
    counts = [s.levels.resolve(s.name, mode, levels) for s in studies]
    if surfaces is not None:
        surfaces = [s.strip() for s in surfaces.split(",")] if isinstance(surfaces, str) else list(surfaces)
        if not surfaces or not all(surfaces):
            raise InputError("--surfaces needs at least one surface name")
        for s in surfaces:
            sf.get(s)
    runner = Runner(jobs, progress=progress, scheduler=scheduler)
    writable_folder(out)
    results = []
    with runner:
        for st, k in zip(studies, counts):
            t0 = time.perf_counter()
            res = st.run(k, runner=runner, surfaces=surfaces)
            res.wall_time = time.perf_counter() - t0
            res.config = {"levels": k, "mode": mode if levels is None else "custom", **res.config}
            write_study(res, out)
            log.info("study %s: %d passed, %d failed in %.1f s", st.name, res.passed, res.failed, res.wall_time)
            results.append(res)
            if finished is not None:
                finished(res)
    write_index(out, STUDIES)
    return results


def execute(args) -> int:
    """Entry point of ``deformable validate``: 0 if every check passed, 1 otherwise."""
    t0 = time.perf_counter()
    quiet = getattr(args, "quiet", False)

    def finished(r):
        if not quiet:
            print(f"{r.study:14s} {r.passed:4d} passed {r.failed:3d} failed  {r.wall_time:6.1f} s", flush=True)

    results = run(args.studies, args.mode, args.levels, args.surfaces, args.out, args.jobs, progress=not quiet,
                  oversubscribe=args.oversubscribe, scheduler=args.scheduler, finished=finished)
    passed = sum(r.passed for r in results)
    failed = sum(r.failed for r in results)
    print(f"{passed} checks passed, {failed} failed in {time.perf_counter() - t0:.1f} s; reports in {args.out}/")
    return 0 if failed == 0 else 1
