r"""Output folders a run owns: no run replaces or mixes with another run's results.

A run writes into a folder that is new, empty, or already its own (a resumed run). :func:`inspect` says what a
folder holds; :class:`RunFolder` claims one:

- a folder holding another run's results is refused (:class:`~deformable.errors.OutputFolderError`) unless
  ``overwrite`` is given, and then the results are removed first; files that are not a run's results (anything
  :func:`is_result` does not recognise) are never removed, and a folder holding them is refused even with
  ``overwrite``;
- a lock file (:data:`LOCK`) keeps two runs out of one folder, also where HDF5's own file locking is switched off
  (``HDF5_USE_FILE_LOCKING=FALSE``, usual on network file systems): an OS lock on it (``flock``, or Windows' byte
  lock, by :mod:`filelock`), which the OS releases when its run dies, so a killed run's lock file blocks nobody
  (the next run takes it over, with a warning) and no test of whether a process lives is needed; the file holds
  the owner's pid and host, for the message that refuses a second run (:func:`held`);
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

from filelock import FileLock, Timeout

from ..errors import OutputFolderError, WriteError
from ..limits import existing

__all__ = ["LOCK", "RunFolder", "inspect", "is_result", "fresh", "write_text", "held"]

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


def _owner_line(fd: int) -> None:
    """Write 'PID HOST' into the lock file just locked (its descriptor): who holds it, for the refusal's message."""
    os.ftruncate(fd, 0)
    os.lseek(fd, 0, os.SEEK_SET)
    os.write(fd, f"{os.getpid()} {socket.gethostname()}\n".encode())


def _file_lock(lock: Path, owner: bool) -> FileLock:
    """The OS lock on ``lock`` (flock, or Windows' byte lock), tried once (timeout 0) and shared by the threads of
    the run; with ``owner``, its holder writes its pid and host into the file (filelock 4's ``on_acquired``; older
    versions leave the file empty)."""
    kwargs = dict(timeout=0, thread_local=False)
    if owner:
        try:
            return FileLock(lock, **kwargs, on_acquired=_owner_line)
        except TypeError:  # filelock < 4: no on_acquired
            pass
    return FileLock(lock, **kwargs)


def _read_owner(lock: Path) -> str:
    """'pid N on HOST' from the lock file, "an unknown run" when it says nothing readable."""
    try:
        pid, host = lock.read_text().split()[:2]
        return f"pid {int(pid)} on {host}"
    except (OSError, ValueError):
        return "an unknown run"


def _in_use(folder: Path, owner: str) -> OutputFolderError:
    return OutputFolderError(f"output folder {str(folder)!r} is in use by another run ({owner}; lock file {LOCK}); "
                             "choose another --out", field="out", value=str(folder))


def _cannot_lock(folder: Path, err: OSError) -> OutputFolderError:
    return OutputFolderError(f"cannot lock output folder {str(folder)!r}: {err.strerror or err}", field="out",
                             value=str(folder))


def held(folder) -> str | None:
    """'pid N on HOST' (or "an unknown run") when another run holds the lock of ``folder``, None when nobody does.

    Tries the OS lock and lets it go at once; creates no file (a folder without a lock file is free). A lock file
    that nobody holds is one a run left when it was killed: the OS released its lock with the process.
    """
    lock = Path(folder) / LOCK
    if not lock.is_file():
        return None
    owner = _read_owner(lock)  # read before trying: filelock < 4 truncates the file when it opens it
    probe = _file_lock(lock, owner=False)
    try:
        probe.acquire()
    except Timeout:
        return owner
    except OSError as err:
        raise _cannot_lock(Path(folder), err) from None
    probe.release()
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
        self._file_lock = None

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
        owner = held(path)
        if owner is not None:
            raise _in_use(path, owner)
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
        left = _read_owner(lock) if lock.is_file() else None  # (read before trying, as in held())
        file_lock = _file_lock(lock, owner=True)
        try:
            file_lock.acquire()
        except Timeout:
            raise _in_use(self.path, left or "an unknown run") from None
        except OSError as err:
            raise _cannot_lock(self.path, err) from None
        self._file_lock = file_lock
        if left is not None:
            log.warning("cleared the stale lock %s: its run (%s) ended without releasing it", lock, left)

    def release(self):
        """Remove the lock (a finished, diverged or failed run does); the OS releases it anyway when the run dies.

        The file goes first, while it is still locked: a run that opened it meanwhile then finds it unlinked and
        does not take it (filelock checks), rather than two runs holding two files of one name.
        """
        if self._file_lock is not None:
            (self.path / LOCK).unlink(missing_ok=True)
            self._file_lock.release()
            self._file_lock = None

    def __enter__(self):
        self.claim()
        return self

    def __exit__(self, *exc):
        self.release()
        return False
