r"""Output folders a run owns: no run replaces or mixes with another run's results.

A run writes into a folder that is new, empty, or already its own (a resumed run). :func:`inspect` says what a
folder holds; :class:`RunFolder` claims one:

- a folder holding another run's results is refused (:class:`~deformable.errors.OutputFolderError`) unless
  ``overwrite`` is given, and then the results are removed first; files that are not a run's results (anything
  :func:`is_result` does not recognise) are never removed, and a folder holding them is refused even with
  ``overwrite``;
- a lock file (:data:`LOCK`, created with ``O_EXCL``, holding the owner's pid and host) keeps two runs out of one
  folder, also where HDF5's own file locking is switched off (``HDF5_USE_FILE_LOCKING=FALSE``, usual on network file
  systems); a stale lock (same host, and its process gone, started after the lock was written, or not a Python
  process: :func:`stale`) is cleared with a warning and taken over;
- text files (the resolved config) are written atomically (a temporary file, then a rename), so the config beside
  the results always describes them.

:func:`fresh` picks a folder name that is free (``runs/curtain``, ``runs/curtain-2``, ...), for a default output
folder that every run of a scene would otherwise share.
"""

from __future__ import annotations

import logging
import os
import re
import shutil
import socket
from pathlib import Path

from ..errors import OutputFolderError, WriteError
from ..limits import existing

__all__ = ["LOCK", "RunFolder", "inspect", "is_result", "fresh", "write_text", "stale"]

log = logging.getLogger(__name__)

#: the lock file of a folder in use
LOCK = ".deformable.lock"
#: the first line of a resolved config (deformable.scenes.to_toml)
CONFIG_HEADER = "# resolved scene config"


def _run_file():
    """A pattern of the names of the files ``deformable run`` writes for any scene of deformable.scenes.SCENES."""
    from ..scenes.registry import SCENES

    names = "|".join(re.escape(n) for n in sorted(SCENES, key=len, reverse=True))
    return re.compile(rf"(?:{names})(?:-from-\d+)?(?:\.xdmf|\.h5|\.xdmf\.tmp|-checkpoint-\d+(?:\.tmp)?\.npz"
                      rf"|-diverged(?:\.tmp)?\.npz)")


def is_result(path: Path) -> bool:
    """Whether ``path`` is a file (or the frames folder) that ``deformable run`` writes.

    Its series ``<scene>.xdmf`` / ``.h5`` (and the ``<scene>-from-<step>`` series of older versions), checkpoints
    ``<scene>-checkpoint-<step>.npz`` and ``<scene>-diverged.npz``, a resolved config (a ``.toml`` file whose first
    line is :data:`CONFIG_HEADER`), the lock, and a ``frames`` folder of PNG and GIF files only. Anything else (a
    user's own ``data.h5``, a scene file) is not, and is never removed.
    """
    name = path.name
    if path.is_dir():
        return name == "frames" and all(p.is_file() and (p.suffix in (".png", ".gif")) for p in path.iterdir())
    if name == LOCK or _run_file().fullmatch(name):
        return True
    if path.suffix == ".toml":
        try:
            with open(path, encoding="utf-8") as f:
                return f.readline().startswith(CONFIG_HEADER)
        except (OSError, UnicodeDecodeError):
            return False
    return False


def inspect(folder) -> tuple[list[Path], list[Path]]:
    """(a run's results, other files) in ``folder``; both empty when it does not exist."""
    folder = Path(folder)
    if not folder.is_dir():
        return [], []
    results, others = [], []
    for p in sorted(folder.iterdir()):
        (results if is_result(p) else others).append(p)
    return results, others


def _names(paths, most: int = 3) -> str:
    names = [p.name for p in paths[:most]]
    return ", ".join(names) + (f" and {len(paths) - most} more" if len(paths) > most else "")


def _started(pid: int) -> float | None:
    """When process ``pid`` started (s since the epoch, from Linux's /proc); None where that cannot be read."""
    try:
        fields_ = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
        boot = next(float(line.split()[1]) for line in Path("/proc/stat").read_text().splitlines()
                    if line.startswith("btime "))
        return boot + int(fields_[19]) / os.sysconf("SC_CLK_TCK")  # field 22 of proc(5): starttime in ticks
    except (OSError, ValueError, IndexError, StopIteration):
        return None


def _runs_python(pid: int) -> bool | None:
    """Whether process ``pid`` runs Python (a run of this package does); None where that cannot be read."""
    try:
        argv = Path(f"/proc/{pid}/cmdline").read_bytes().split(b"\0")
    except OSError:
        return None
    return any(b"python" in Path(os.fsdecode(a)).name.encode() or b"deformable" in a for a in argv[:2])


def _holder(folder: Path) -> tuple[str | None, str | None]:
    """The lock in ``folder``: ('pid N on HOST', None) when it is live, (None, why) when it is stale
    (:func:`stale`), (None, None) when there is none."""
    lock = folder / LOCK
    try:
        pid, host = lock.read_text().split()[:2]
        pid = int(pid)
    except (OSError, ValueError):
        return (None if not lock.exists() else "an unknown run"), None
    why = stale(lock, pid) if host == socket.gethostname() else None
    return (None, why) if why is not None else (f"pid {pid} on {host}", None)


def _owner(folder: Path) -> str | None:
    """'pid N on HOST' of a live lock in ``folder``; None when there is none or it is stale (:func:`stale`)."""
    return _holder(folder)[0]


def stale(lock: Path, pid: int) -> str | None:
    """Why the lock file ``lock`` of process ``pid`` (on this host) is stale, or None when its run may be alive.

    Stale: the process is gone; or it started after the lock was written (the pid was reused, after a reboot say);
    or it is not a Python process (a run of this package is). A process that cannot be inspected (no /proc) counts
    as alive.
    """
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return f"its run (pid {pid}) is gone"
    except PermissionError:
        pass
    except (OverflowError, ValueError):
        return f"pid {pid} is not a process number"
    started = _started(pid)
    try:
        written = lock.stat().st_mtime
    except OSError:
        return None
    if started is not None and started > written + 1.0:  # /proc's start time is in clock ticks
        return f"pid {pid} is a newer process than the lock"
    if _runs_python(pid) is False:
        return f"pid {pid} is not a run of this package"
    return None


def fresh(folder) -> Path:
    """``folder`` if it holds nothing, else the first of ``folder-2``, ``folder-3``, ... that holds nothing."""
    folder = Path(folder)
    k, candidate = 1, folder
    while candidate.exists() and (not candidate.is_dir() or any(candidate.iterdir())):
        k += 1
        candidate = folder.with_name(f"{folder.name}-{k}")
    return candidate


def write_text(path, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (a temporary file, then a rename); WriteError naming the file."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.tmp")
    try:
        tmp.write_text(text, encoding="utf-8")
        os.replace(tmp, path)
    except OSError as err:
        tmp.unlink(missing_ok=True)
        raise WriteError(f"cannot write {str(path)!r}: {err.strerror or err}") from None
    return path


class RunFolder:
    """A folder one run owns: checked with :meth:`check`, then claimed (locked, cleared) with :meth:`claim`.

    Parameters
    ----------
    path : str or Path
        The folder (created by :meth:`claim` if needed).
    overwrite : bool
        Replace another run's results in it (they are removed at :meth:`claim`).
    own : callable (Path) -> bool, optional
        Whether the results already in the folder are this run's own (a resumed run): then they are kept, neither
        refused nor removed.
    """

    def __init__(self, path, overwrite: bool = False, own=None):
        self.path, self.overwrite, self.own = Path(path), bool(overwrite), own
        self._locked = False

    def check(self) -> bool:
        """OutputFolderError unless the folder can be this run's; True when it holds the run's own results.

        Reads only; nothing is written.
        """
        path = self.path
        parent = existing(path)
        if not parent.is_dir() or not os.access(parent, os.W_OK | os.X_OK):
            why = "is a file" if parent == path else f"{str(parent)!r} is not a writable folder"
            raise OutputFolderError(f"cannot write to output folder {str(path)!r}: {why}", field="out",
                                    value=str(path))
        owner = _owner(path)
        if owner is not None:
            raise OutputFolderError(f"output folder {str(path)!r} is in use by another run ({owner}; lock file "
                                    f"{LOCK}); choose another --out", field="out", value=str(path))
        results, others = inspect(path)
        results = [p for p in results if p.name != LOCK]
        if not results and not others:
            return False
        if self.own is not None and results and self.own(path):
            return True
        if others:
            raise OutputFolderError(f"output folder {str(path)!r} holds files that are not a run's results "
                                    f"({_names(others)}); choose a new or empty folder", field="out",
                                    value=str(path))
        if not self.overwrite:
            raise OutputFolderError(f"output folder {str(path)!r} holds another run's results ({_names(results)}); "
                                    "choose another --out, or give --overwrite to replace them", field="out",
                                    value=str(path))
        return False

    def claim(self) -> Path:
        """Check again, create the folder, take its lock, and remove another run's results (``overwrite``)."""
        own = self.check()
        try:
            self.path.mkdir(parents=True, exist_ok=True)
        except OSError as err:
            raise OutputFolderError(f"cannot write to output folder {str(self.path)!r}: {err.strerror or err}",
                                    field="out", value=str(self.path)) from None
        self._lock()
        if not own:
            for p in [p for p in inspect(self.path)[0] if p.name != LOCK]:
                try:
                    shutil.rmtree(p) if p.is_dir() else p.unlink()
                except OSError as err:
                    self.release()
                    raise OutputFolderError(f"cannot remove {str(p)!r} from the output folder: "
                                            f"{err.strerror or err}", field="out", value=str(self.path)) from None
        return self.path

    def _lock(self):
        lock = self.path / LOCK
        for _ in range(2):
            try:
                fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                owner, why = _holder(self.path)
                if owner is not None:
                    raise OutputFolderError(f"output folder {str(self.path)!r} is in use by another run ({owner}; "
                                            f"lock file {LOCK}); choose another --out", field="out",
                                            value=str(self.path)) from None
                lock.unlink(missing_ok=True)
                if why is not None:  # (None: the lock went away meanwhile)
                    log.warning("cleared the stale lock %s: %s", lock, why)
                continue
            except OSError as err:
                raise OutputFolderError(f"cannot write to output folder {str(self.path)!r}: {err.strerror or err}",
                                        field="out", value=str(self.path)) from None
            with os.fdopen(fd, "w") as f:
                f.write(f"{os.getpid()} {socket.gethostname()}\n")
            self._locked = True
            return
        raise OutputFolderError(f"cannot lock output folder {str(self.path)!r}", field="out", value=str(self.path))

    def release(self):
        """Remove the lock (a finished, diverged or failed run does)."""
        if self._locked:
            (self.path / LOCK).unlink(missing_ok=True)
            self._locked = False

    def __enter__(self):
        self.claim()
        return self

    def __exit__(self, *exc):
        self.release()
        return False
