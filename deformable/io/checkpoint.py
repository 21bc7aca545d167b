r"""Checkpoints of a run: the state, the constraint reference and the resolved scene config in a .npz.

:func:`save_checkpoint` / :func:`load_checkpoint` store the state (X, V, A, t, step), the constraint reference X0,
the resolved scene config and the controller's memory (:meth:`deformable.TimeStepper.memory`: the adapted step, the
accepted steps since it changed, Newton's round-off floor), as JSON text; :class:`CheckpointWriter` writes one every
``every`` steps. Resuming from a checkpoint (the state, and :meth:`~deformable.TimeStepper.restore` of the memory)
continues a run bit for bit, also a run whose step adapted. A checkpoint of an earlier version has no memory: it
resumes with the requested step.
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import numpy as np

from ..checks import count
from ..dynamics.trackers import Tracker
from ..errors import CheckpointError, WriteError

__all__ = ["CheckpointWriter", "save_checkpoint", "load_checkpoint", "CHECKPOINT_KEYS"]

CHECKPOINT_KEYS = ("X", "V", "t", "step", "X0", "scene", "config", "backend", "dt", "nodes")


def save_checkpoint(path, state, X0, *, scene: str, config: str, backend: str, dt: float, nodes,
                    memory: dict | None = None) -> Path:
    """Write a checkpoint .npz atomically (a partly written file never has the final name).

    Parameters
    ----------
    path : target file (.npz); its folder is created if needed
    state : deformable.State (X, V and, when known, A (ndof, 3), t in s, step)
    X0 : (ndof, 3) the constraint reference of the run (its initial positions)
    scene : scene name; config : the resolved scene config as TOML text
    backend : the backend's registered name; dt : time step (s); nodes : (M, N)
    memory : the controller's memory (:meth:`deformable.TimeStepper.memory`), optional

    Raises WriteError naming the file when it cannot be written (the partial file is removed).
    """
    path = Path(path)
    tmp = path.with_name(path.stem + ".tmp.npz")
    extra = {} if state.A is None else {"A": state.A}  # the implicit schemes' acceleration, when there is one
    if memory is not None:
        extra["memory"] = np.str_(json.dumps(memory))
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez(tmp, X=state.X, V=state.V, t=np.float64(state.t), step=np.int64(state.step), X0=X0,
                 scene=np.str_(scene), config=np.str_(config), backend=np.str_(backend), dt=np.float64(dt),
                 nodes=np.asarray(nodes, dtype=np.int64), **extra)
        os.replace(tmp, path)
    except OSError as err:
        tmp.unlink(missing_ok=True)
        raise WriteError(f"cannot write checkpoint {str(path)!r}: {err.strerror or err}") from None
    return path


def _numbers(value) -> bool:
    """Whether ``value`` is a number, or a list or table of such (a controller's memory read from JSON)."""
    if isinstance(value, dict):
        return all(isinstance(k, str) and _numbers(v) for k, v in value.items())
    if isinstance(value, list):
        return all(_numbers(v) for v in value)
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _damaged(path, why: str) -> CheckpointError:
    return CheckpointError(f"checkpoint {str(path)!r} is damaged or not a checkpoint: {why}", field="resume",
                           value=str(path))


def load_checkpoint(path, t0: float | None = None, adaptive: bool | None = None) -> dict:
    """Read and validate a checkpoint written by :func:`save_checkpoint` (module docstring).

    Parameters
    ----------
    path : the .npz file
    t0 : float, optional
        The time the checkpoint's run started at; given, t and step must fit each other.
    adaptive : bool, optional
        Whether the run's scheme adapts dt (the implicit ones); None: either.

    Returns
    -------
    dict
        The keys :data:`CHECKPOINT_KEYS`, ``A`` and ``memory`` (a dict; each None when not stored).

    Raises
    ------
    CheckpointError
        A ValueError naming the file and what is wrong.
    """
    path = Path(path)
    if not path.is_file():
        raise CheckpointError(f"cannot read checkpoint {str(path)!r}: no such file", field="resume", value=str(path))
    try:
        with np.load(path, allow_pickle=False) as data:
            missing = [k for k in CHECKPOINT_KEYS if k not in data.files]
            if missing:
                raise CheckpointError(f"cannot read checkpoint {str(path)!r}: {str(path)!r} is not a checkpoint: "
                                      f"missing {', '.join(missing)}", field="resume", value=str(path))
            out = {k: data[k] for k in CHECKPOINT_KEYS}
            out["A"] = data["A"] if "A" in data.files else None
            out["memory"] = data["memory"] if "memory" in data.files else None
    except CheckpointError:
        raise
    except Exception as err:  # zipfile.BadZipFile, zlib.error, EOFError, OSError, ValueError, MemoryError ...
        raise CheckpointError(f"cannot read checkpoint {str(path)!r}: {type(err).__name__}: {err}",
                              field="resume", value=str(path)) from None
    for k in ("scene", "config", "backend"):
        if out[k].dtype.kind != "U" or out[k].shape != ():
            raise _damaged(path, f"{k} is not a string")
        out[k] = str(out[k])
    for k in ("t", "dt", "step"):
        if out[k].shape != () or out[k].dtype.kind not in ("i" if k == "step" else "f"):
            raise _damaged(path, f"{k} is not a {'whole' if k == 'step' else 'real'} number")
    out["t"], out["dt"], out["step"] = float(out["t"]), float(out["dt"]), int(out["step"])
    if out["nodes"].shape != (2,) or out["nodes"].dtype.kind != "i" or out["nodes"].min() < 3:
        raise _damaged(path, f"nodes = {out['nodes']!r} is not a grid")
    out["nodes"] = tuple(int(n) for n in out["nodes"])
    if out["memory"] is not None:
        try:
            out["memory"] = json.loads(str(out["memory"]))
        except ValueError:
            out["memory"] = None
        if not isinstance(out["memory"], dict) or not _numbers(out["memory"]):
            raise _damaged(path, "its controller memory is not a table of numbers")
    shape = out["X"].shape
    if len(shape) != 2 or shape[1] != 3 or shape[0] < 9:
        raise _damaged(path, f"X has shape {shape}, not (ndof, 3)")
    for k in ("X", "V", "X0", "A"):
        a = out[k]
        if a is None:
            continue
        if a.dtype.kind != "f" or a.shape != shape:
            raise _damaged(path, f"{k} is a {a.dtype} array of shape {a.shape}, not a float array of shape {shape}")
        if not np.all(np.isfinite(a)):
            raise _damaged(path, f"{k} holds {np.count_nonzero(~np.isfinite(a))} NaN or infinite values")
    t, dt, step = out["t"], out["dt"], out["step"]
    if not (np.isfinite(t) and np.isfinite(dt) and dt > 0 and step >= 0):
        raise _damaged(path, f"t = {t!r}, dt = {dt!r}, step = {step!r}")
    if t0 is not None:
        elapsed, tol = t - t0, 1e-9 * max(1.0, step) * dt
        low = 0.0 if step == 0 else ((step - 1) * dt if adaptive is False else step * dt / 2**10)
        if not (low - tol <= elapsed <= step * dt + tol) or (step == 0 and abs(elapsed) > tol):
            raise _damaged(path, f"step {step} and t = {t!r} s do not fit a run from t = {t0!r} s at dt = {dt!r} s")
    return out


class CheckpointWriter(Tracker):
    """Write ``<folder>/<stem>-<step>.npz`` every ``every`` steps (see :func:`save_checkpoint`).

    ``X0`` is the run's constraint reference (its initial positions, (ndof, 3)); ``meta`` the keyword arguments of
    :func:`save_checkpoint` after it; the controller's memory is the stepper's at the step written.
    """

    def __init__(self, folder, stem: str, every: int, X0, **meta):
        self.folder, self.stem, self.every, self.meta = Path(folder), stem, count("checkpoint-every", every), meta
        self.X0 = np.asarray(X0)
        self.written: list[Path] = []

    def path(self, step: int) -> Path:
        return self.folder / f"{self.stem}-{step:07d}.npz"

    @staticmethod
    def found(folder, stem: str) -> dict[int, Path]:
        """The checkpoints a writer of ``stem`` left in ``folder``, by step (those :meth:`path` names)."""
        pattern = re.compile(rf"{re.escape(stem)}-(\d+)\.npz")
        return {int(m.group(1)): p for p in sorted(Path(folder).glob(f"{stem}-*.npz"))
                if (m := pattern.fullmatch(p.name))}

    def handle(self, state):
        if state.step % self.every == 0:
            stepper = getattr(self, "stepper", None)  # set by initialize in a run; a bare handle() has none
            memory = stepper.memory() if hasattr(stepper, "memory") else None
            self.written.append(save_checkpoint(self.path(state.step), state, self.X0, memory=memory, **self.meta))
