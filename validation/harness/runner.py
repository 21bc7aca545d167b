r"""The executor layer: a case function mapped over independent cases, here or on workers.

Every study (``fill(res, levels, runner)``) and every sweep hands its cases to
a :class:`Runner`, which runs them

- serially in this process (the default),
- on a local process pool (``jobs=N``, ``deformable validate --jobs N``), or
- on Dask's distributed scheduler (``scheduler=...``, ``--scheduler``, the
  optional extra ``pip install ".[distributed]"``):

  ``"local:N"``
      a ``distributed.LocalCluster`` of N worker processes on this machine,
      one thread each (started on entering the runner, closed on leaving);
  ``"tcp://HOST:PORT"`` (any ``scheme://`` address)
      a running Dask scheduler (``dask scheduler`` with ``dask worker`` processes);
  a path to a scheduler file
      the JSON file that ``dask scheduler --scheduler-file``, ``dask-mpi`` or
      a ``dask-jobqueue`` job writes, naming the scheduler's address.

A case function must be a module-level function of an installed module (the
workers import it by name) and a case a picklable value (a frozen dataclass);
the case function's result comes back to this process.

:meth:`Runner.map` returns the results in the order of the cases and raises
the first error; :meth:`Runner.completed` yields ``(index, result, error)`` as
cases finish, so a caller can store each result at once (a sweep that is
killed keeps what it finished) and turn a failed case into a row.

Faults. A worker process that dies (killed, out of memory, a crash in
compiled code) is replaced and the case it ran runs again, up to
:data:`ALLOWED_FAILURES` (3) times: the :class:`Pool` does it as Dask's
scheduler does (``distributed.scheduler.allowed-failures``); then that case
alone is an error (``BrokenProcessPool`` on the pool, ``KilledWorker`` on
Dask). The other cases are not touched: a case that had not started is never
an error for it. A Ctrl-C, which a terminal sends to the whole process group,
reaches only this process: the pool's workers ignore SIGINT and a
LocalCluster's workers are started with it blocked; the KeyboardInterrupt
here ends the workers quietly on leaving ``with runner:`` (before, Dask's
workers printed 65-91 lines of tracebacks).

Determinism. A case is computed by the same code on the same inputs wherever
it runs, so the numbers are bit-identical serially, on the pool and on Dask
workers of the same machine (tests/validation/harness/test_runner.py). The
one thing that could differ between processes is the number of BLAS / MKL
threads of a reduction; Dask's workers run one (its ``pre-spawn-environ``),
and so do the pool's (:func:`_start_worker`). SuperLU is single-threaded,
and PARDISO runs in MKL's conditional numerical reproducibility mode
(:mod:`deformable.algebra.solvers`): without it a factorisation on one MKL thread
differs in the last bits from one on two (FE 6 x 6 nodes), so nothing is
pinned in this process. Dask sets its workers' variables
(``OMP_NUM_THREADS=1``, ``PYTHONHASHSEED``, ...) in this process to spawn
them; the runner sets this process's environment back.

Progress (``progress=True``): cases done out of all, the time elapsed and an
estimate of the time left (the mean time per finished case times the cases
left, so it counts the workers' parallelism): a tqdm bar on a terminal; on a
stream that is not one (a batch job's log), a timestamped line each tenth of
the cases and at least every 30 s while cases finish, from
``progress_after`` seconds on (default :data:`PROGRESS_AFTER`, 5 s; a sweep, whose cases are each stored
as they finish, gives 0: a line a stored case) (:class:`deformable.progress.Progress`).
"""

from __future__ import annotations

import logging
import os
import sys
from collections.abc import Callable, Iterable, Iterator
from contextlib import closing, contextmanager
from typing import Any

from deformable.progress import Progress, counted, duration

__all__ = ["ALLOWED_FAILURES", "DISTRIBUTED_HINT", "Pool", "Progress", "Runner", "counted", "duration",
           "parse_scheduler"]

log = logging.getLogger(__name__)

#: how to get the optional Dask dependency, said whenever --scheduler is asked for without it
DISTRIBUTED_HINT = 'pip install ".[distributed]" (Dask distributed) in the project folder'
#: seconds of a map before its first progress line off a terminal (a study of a few seconds says only its summary)
PROGRESS_AFTER = 5.0
#: seconds to wait for a remote scheduler to answer
CONNECT_TIMEOUT = 20
#: times a case runs again after its pool worker died (Dask's default distributed.scheduler.allowed-failures)
ALLOWED_FAILURES = 3


def parse_scheduler(spec: str) -> tuple[str, Any]:
    """``"local:N"`` -> ("local", N); ``"scheme://..."`` -> ("address", spec); an existing file -> ("file", path).

    Raises ValueError naming the bad spec (a zero or malformed worker count, a file that does not exist).
    """
    spec = str(spec).strip()
    if spec.startswith("local:"):
        count = spec[len("local:"):]
        if not count.isdigit() or int(count) < 1:
            raise ValueError(f"--scheduler local:N needs a positive number of workers N, got {spec!r}")
        return "local", int(count)
    if "://" in spec:
        if not spec.split("://", 1)[1]:
            raise ValueError(f"--scheduler address {spec!r} names no host; expected e.g. tcp://HOST:PORT")
        return "address", spec
    if os.path.isfile(spec):
        return "file", spec
    raise ValueError(f"--scheduler must be local:N, a scheduler address tcp://HOST:PORT or a scheduler file; "
                     f"{spec!r} is none of them (no such file)")


def _distributed():
    """The ``distributed`` module, or a ValueError saying how to install it."""
    try:
        import distributed
    except ImportError:
        raise ValueError(f"--scheduler needs Dask, which is not installed: {DISTRIBUTED_HINT}") from None
    return distributed


def _start_worker(parent: int | None) -> None:
    """Pool-worker initializer: a worker computes on one core, and ends with the process that made it.

    One core: OMP_NUM_THREADS = 1 (the Hessian's threads, :func:`deformable.physics.integrand.hessian_threads`, and
    MKL's in a worker that loads it later) and one thread for the BLAS and MKL this process has loaded already
    (threadpoolctl), as Dask's workers have; the pool has at most a worker per core. Without it each worker of
    ``--jobs 2`` ran two Hessian threads and two MKL threads on the machine's two cores.

    Ending with its parent: on Linux the kernel sends the worker SIGKILL when its parent (this process, or the
    forkserver, which ends with this process) dies: ``prctl(PR_SET_PDEATHSIG)``, so a killed run leaves no
    orphans. ``parent``: the expected parent's id, when known, to catch a parent that died before the
    request. Elsewhere nothing is done.
    """
    from threadpoolctl import threadpool_limits

    for name in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
        os.environ[name] = "1"
    threadpool_limits(1)
    if not sys.platform.startswith("linux"):
        return
    import ctypes
    import signal

    ctypes.CDLL(None).prctl(1, signal.SIGKILL)  # 1 = PR_SET_PDEATHSIG
    if parent is not None and os.getppid() != parent:
        os._exit(1)


def _serve(connection, parent: int | None) -> None:
    """A pool worker: run ``(fn, case)`` after ``(fn, case)`` read from ``connection``; send back (result, error).

    A Ctrl-C (SIGINT, sent by a terminal to the whole process group) is ignored: the parent handles it and ends
    the workers. The worker returns on None, or when the parent's end is closed.
    """
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _start_worker(parent)
    while True:
        try:
            task = connection.recv()
        except EOFError:
            return
        if task is None:
            return
        fn, case = task
        try:
            outcome = fn(case), None
        except Exception as err:  # noqa: BLE001 - handed to the caller, which raises it or tabulates it
            outcome = None, err
        try:
            connection.send(outcome)
        except Exception as err:  # noqa: BLE001 - a result or error that cannot be pickled
            connection.send((None, RuntimeError(f"the case's outcome cannot be sent back: {err}")))


@contextmanager
def _interrupts_blocked():
    """Block SIGINT in this thread meanwhile, and so in the threads it starts and the processes they start.

    A Dask LocalCluster started inside runs its event loop on a thread of its own, which spawns the workers,
    and restarts a worker that died: a mask of blocked signals is inherited by new threads and processes, so
    a Ctrl-C in a terminal (SIGINT to the whole process group) reaches only this process's main thread. The
    workers print nothing (they printed 65-91 lines of tracebacks); this process stops them on the way out.
    A Ctrl-C while blocked is handled when the block ends. multiprocessing's resource tracker is started first:
    starting it unblocks SIGINT in the thread that does (CPython bpo-33613), which would be Dask's.
    """
    import signal
    from multiprocessing import resource_tracker

    if not hasattr(signal, "pthread_sigmask"):  # not POSIX
        yield
        return
    resource_tracker.ensure_running()
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _restore_environ(saved: dict) -> None:
    """Set os.environ back to ``saved``: Dask's nanny sets its workers' variables here to spawn them, and leaves them."""
    for name in os.environ.keys() - saved.keys():
        del os.environ[name]
    os.environ.update({name: value for name, value in saved.items() if os.environ.get(name) != value})


def _death(exitcode: int | None) -> str:
    """How a process ended, in words: ``"killed by SIGKILL"``, ``"exit code 1"``."""
    import signal

    if exitcode is not None and exitcode < 0:
        try:
            return f"killed by {signal.Signals(-exitcode).name}"
        except ValueError:
            return f"killed by signal {-exitcode}"
    return f"exit code {exitcode}"


class Pool:
    """``jobs`` local worker processes, each running one case at a time; a worker that dies is replaced.

    A case whose worker died (killed, out of memory, a crash in compiled code) runs again on a new worker,
    up to :data:`ALLOWED_FAILURES` times, as on Dask (``distributed.scheduler.allowed-failures``); after that
    it is given up with a ``BrokenProcessPool`` error naming how its worker ended. The other cases are not
    touched: those running go on, those waiting start as they would have. (concurrent.futures'
    ProcessPoolExecutor, used before, failed every pending case when one worker died.)

    Workers are forked from this process, imports and all, which is fast; but a process with other threads
    (a Dask client's event loop, say) could be forked while one holds a lock: then the forkserver's clean,
    single-threaded process forks them instead. A worker ignores Ctrl-C (SIGINT); :meth:`close` ends it.
    """

    def __init__(self, jobs: int):
        import multiprocessing as mp
        import threading

        method = "fork" if threading.active_count() == 1 else "forkserver"
        self.jobs, self._context = jobs, mp.get_context(method)
        self._parent = os.getpid() if method == "fork" else None
        self._workers: dict = {}  # connection -> process, every live worker
        self._idle = [self._start() for _ in range(jobs)]

    def _start(self):
        ours, theirs = self._context.Pipe()
        process = self._context.Process(target=_serve, args=(theirs, self._parent), daemon=True,
                                        name="deformable pool worker")
        process.start()
        theirs.close()
        self._workers[ours] = process
        return ours

    def completed(self, fn: Callable, cases: list) -> Iterator[tuple[int, Any, Exception | None]]:
        """Yield ``(index, fn(cases[index]), None)`` or ``(index, None, error)`` as each case finishes.

        Leaving the loop early ends the cases running (their workers are terminated and replaced later).
        """
        from collections import deque
        from concurrent.futures.process import BrokenProcessPool
        from multiprocessing.connection import wait

        waiting, deaths = deque(range(len(cases))), [0] * len(cases)
        busy: dict = {}  # connection -> index of the case its worker runs
        try:
            while waiting or busy:
                while waiting and len(busy) < self.jobs:
                    connection = self._idle.pop() if self._idle else self._start()
                    i = waiting.popleft()
                    try:
                        connection.send((fn, cases[i]))
                    except Exception as err:  # noqa: BLE001 - a case that cannot be pickled
                        self._idle.append(connection)
                        yield i, None, err
                        continue
                    busy[connection] = i
                if not busy:  # no case could be sent: nothing to wait for
                    continue
                for connection in wait(list(busy)):
                    i = busy.pop(connection)
                    try:
                        result, error = connection.recv()
                    except (EOFError, OSError):  # the worker died running case i
                        process = self._workers.pop(connection)
                        process.join()
                        connection.close()
                        deaths[i] += 1
                        if deaths[i] > ALLOWED_FAILURES:
                            yield i, None, BrokenProcessPool(f"its worker process died {deaths[i]} times running it "
                                                             f"(last {_death(process.exitcode)})")
                        else:
                            log.warning("a worker process died running a case (%s); the case runs again on a new "
                                        "worker (attempt %d of %d)", _death(process.exitcode), deaths[i] + 1,
                                        ALLOWED_FAILURES + 1)
                            waiting.appendleft(i)
                        continue
                    except Exception as err:  # noqa: BLE001 - an outcome this process cannot unpickle
                        result, error = None, err
                    self._idle.append(connection)
                    yield i, result, error
        finally:
            for connection in busy:  # left early: the cases running now are not wanted
                if connection in self._workers:  # (not closed already)
                    self._stop(connection, now=True)

    def _stop(self, connection, now: bool) -> None:
        process = self._workers.pop(connection)
        if now:
            process.terminate()
        else:  # None, not only the closed end: a worker forked later holds a copy of this end
            try:
                connection.send(None)
            except OSError:  # it died meanwhile
                pass
        connection.close()
        process.join()
        if connection in self._idle:
            self._idle.remove(connection)

    def close(self, now: bool = False) -> None:
        """Stop every worker: at once (SIGTERM) when ``now``, else once it has finished its case (none runs here)."""
        for connection in list(self._workers):
            self._stop(connection, now)


class Runner:
    """Maps a case function over independent cases: serially, on a process pool or on Dask workers.

    Parameters
    ----------
    jobs : int
        Local worker processes; 1 runs in this process.
    progress : bool
        Report progress on stderr (:class:`Progress`) per map.
    scheduler : str, optional
        Run on Dask instead (module docstring): ``"local:N"``, a scheduler address or a scheduler
        file. Exclusive with ``jobs > 1``.

    Notes
    -----
    A runner with workers maps inside ``with runner:``, which starts the pool or connects to the
    scheduler (a LocalCluster is started there) and shuts them down on leaving. Bad arguments,
    Dask missing or a scheduler that cannot be reached raise ValueError with one line saying why.
    """

    def __init__(self, jobs: int = 1, progress: bool = False, scheduler: str | None = None,
                 progress_after: float = PROGRESS_AFTER):
        if isinstance(jobs, bool) or int(jobs) != jobs or jobs < 1:
            raise ValueError(f"jobs must be a positive integer, got {jobs!r}")
        self.jobs, self.progress, self.progress_after = int(jobs), progress, progress_after
        self.scheduler = None
        if scheduler is not None:
            if self.jobs > 1:
                raise ValueError("give either --jobs (a local process pool) or --scheduler (Dask), not both")
            self.scheduler = parse_scheduler(scheduler)
            _distributed()
        self._pool = self._client = self._cluster = self._environ = None

    # -- lifetime ---------------------------------------------------------------
    def __enter__(self):
        try:
            if self.scheduler is not None:
                self._connect(*self.scheduler)
            elif self.jobs > 1:
                self._pool = Pool(self.jobs)
        except BaseException:  # a Ctrl-C while the workers start: stop those started
            self.__exit__(*sys.exc_info())
            raise
        return self

    def __exit__(self, exc_type, *exc):
        if self._pool is not None:
            self._pool.close(now=exc_type is not None)  # interrupted or failed: end the cases running now
            self._pool = None
        if self._client is not None:
            self._client.close()
            self._client = None
        if self._cluster is not None:
            if exc_type is KeyboardInterrupt:  # the workers it was running are killed: Dask's nannies say so at
                logging.getLogger("distributed").setLevel(logging.ERROR)  # WARNING, which an interrupt does not need
            self._cluster.close()
            self._cluster = None
            _restore_environ(self._environ)  # a worker restarted since set them again

    def _connect(self, kind: str, where) -> None:
        distributed = _distributed()
        # Dask logs its life (scheduler up, workers joining and leaving) at INFO on its own handler; keep warnings
        logging.getLogger("distributed").setLevel(logging.WARNING)
        if kind == "local":
            import dask

            # Dask's workers get MALLOC_TRIM_THRESHOLD_=65536 (give freed memory back to the system at once),
            # which costs these allocation-heavy cases about 10 % (measured: FD 24 x 24, 2000 steps, 3.1 s
            # against 3.45 s); None unsets it, so glibc's own adaptive thresholds apply
            self._environ = dict(os.environ)
            with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}), \
                    _interrupts_blocked():
                self._cluster = distributed.LocalCluster(n_workers=where, threads_per_worker=1, processes=True,
                                                         dashboard_address=None, silence_logs=logging.ERROR)
            _restore_environ(self._environ)
            self._client = distributed.Client(self._cluster)
            return
        try:
            if kind == "address":
                self._client = distributed.Client(where, timeout=CONNECT_TIMEOUT)
            else:
                self._client = distributed.Client(scheduler_file=where, timeout=CONNECT_TIMEOUT)
        except (OSError, ValueError, KeyError) as err:
            first = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
            raise ValueError(f"cannot reach the Dask scheduler {where!r}: {first}") from None
        if not self._client.scheduler_info().get("workers"):
            log.warning("the Dask scheduler %s has no workers yet; the cases wait until workers join", where)

    @property
    def address(self) -> str | None:
        """The Dask scheduler's address while connected (a started LocalCluster's too), else None."""
        return None if self._client is None else self._client.scheduler.address

    @property
    def active(self) -> bool:
        """Whether the workers are there (inside ``with``), or no worker is needed."""
        return (self.jobs == 1 and self.scheduler is None) or self._pool is not None or self._client is not None

    def describe(self) -> str:
        """Where the cases run, in words: ``"serially"``, ``"on a process pool of 2"``, ``"on Dask ..."``."""
        if self.scheduler is None:
            return "serially" if self.jobs == 1 else f"on a process pool of {self.jobs}"
        kind, where = self.scheduler
        if kind == "local":
            return f"on a Dask LocalCluster of {where} workers"
        workers = len(self._client.scheduler_info().get("workers", {})) if self._client is not None else "?"
        return f"on the Dask scheduler {where} ({workers} workers)"

    # -- maps -------------------------------------------------------------------
    def completed(self, fn: Callable, cases: Iterable, desc: str = "") -> Iterator[tuple[int, Any, Exception | None]]:
        """Yield ``(index, fn(cases[index]), None)``, or ``(index, None, error)``, as each case finishes.

        Leaving the loop early cancels the cases not yet started and ends those running; to do it at once
        (an exception in the loop keeps the generator alive in its traceback), close the generator, e.g.
        ``with contextlib.closing(runner.completed(...)) as outcomes:``, as :meth:`map` does.
        """
        if not self.active:
            raise RuntimeError("a Runner with workers maps inside `with runner:`")
        cases = list(cases)
        progress = Progress(len(cases), desc or "cases", enabled=self.progress, after=self.progress_after)
        if self._client is not None:
            finished = self._dask(fn, cases)
        elif self._pool is not None:
            finished = self._pool.completed(fn, cases)
        else:
            finished = self._serial(fn, cases)
        done = 0
        try:
            for item in finished:
                yield item
                done += 1  # after the caller has taken the result (a sweep has stored it)
                progress.update(done, f"{done}/{counted(len(cases))} done")
        finally:
            finished.close()  # now, while the workers are there
            progress.close()

    def map(self, fn: Callable, cases: Iterable, desc: str = "") -> list[Any]:
        """``[fn(c) for c in cases]`` in order; the first error a case raises is raised here."""
        cases = list(cases)
        out: list[Any] = [None] * len(cases)
        with closing(self.completed(fn, cases, desc)) as outcomes:
            for i, result, error in outcomes:
                if error is not None:
                    raise error
                out[i] = result
        return out

    @staticmethod
    def _serial(fn, cases):
        for i, case in enumerate(cases):
            try:
                result = fn(case)
            except Exception as err:  # noqa: BLE001 - handed to the caller, which raises it or tabulates it
                yield i, None, err
            else:
                yield i, result, None

    def _dask(self, fn, cases):
        distributed = _distributed()
        futures = self._client.map(fn, cases, pure=False)
        index = {f.key: i for i, f in enumerate(futures)}
        # with_results: the results are gathered on the client's event loop, so this thread only waits on a
        # condition, and a Ctrl-C (KeyboardInterrupt) ends that wait and nothing of Dask's half-way
        done = distributed.as_completed(futures, loop=self._client.loop,  # not the default client's
                                        with_results=True, raise_errors=False)
        try:
            for future, result in done:
                if future.status == "error":  # the case's own error, or KilledWorker: its workers died too often
                    yield index[future.key], None, result[1]
                elif future.status == "cancelled":
                    yield index[future.key], None, result
                else:
                    yield index[future.key], result, None
        finally:
            if self._client is not None:  # (not closed already)
                self._client.cancel([f for f in futures if not f.done()])
