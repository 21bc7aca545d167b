r"""The case runner: a case function mapped over independent cases, serially or on a process pool."""

from __future__ import annotations

from typing import Any, Callable, Iterable

__all__ = ["Runner"]


class Runner:
    """Maps a case function over independent cases, serially or on a process pool, with a tqdm bar.

    Parameters
    ----------
    jobs : int
        Worker processes; 1 runs in this process.
    progress : bool
        Show a tqdm progress bar (on stderr) per map.
    """

    def __init__(self, jobs: int = 1, progress: bool = False):
        if isinstance(jobs, bool) or int(jobs) != jobs or jobs < 1:
            raise ValueError(f"jobs must be a positive integer, got {jobs!r}")
        self.jobs, self.progress = int(jobs), progress
        self._pool = None

    def __enter__(self):
        if self.jobs > 1:
            import multiprocessing as mp
            from concurrent.futures import ProcessPoolExecutor

            self._pool = ProcessPoolExecutor(self.jobs, mp_context=mp.get_context("fork"))
        return self

    def __exit__(self, *exc):
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None

    def map(self, fn: Callable, cases: Iterable, desc: str = "") -> list[Any]:
        """``[fn(c) for c in cases]`` in order; on the pool when there is one."""
        from tqdm.auto import tqdm

        cases = list(cases)
        bar = tqdm(total=len(cases), desc=desc, unit="case", leave=False, disable=not self.progress)
        try:
            if self._pool is None or len(cases) < 2:
                out = []
                for c in cases:
                    out.append(fn(c))
                    bar.update()
                return out
            futures = [self._pool.submit(fn, c) for c in cases]
            out = []
            for f in futures:
                out.append(f.result())
                bar.update()
            return out
        finally:
            bar.close()
