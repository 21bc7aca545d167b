r"""Checkpoints of a run: the state, the constraint reference and the resolved scene config in a .npz.

:func:`save_checkpoint` / :func:`load_checkpoint` store the state (X, V, t,
step), the constraint reference X0 and the resolved scene config;
:class:`CheckpointWriter` writes one every ``every`` steps. Resuming from a
checkpoint continues a run bit for bit.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..dynamics.trackers import Tracker

__all__ = ["CheckpointWriter", "save_checkpoint", "load_checkpoint", "CHECKPOINT_KEYS"]

CHECKPOINT_KEYS = ("X", "V", "t", "step", "X0", "scene", "config", "backend", "dt", "nodes")


def save_checkpoint(path, state, X0, *, scene: str, config: str, backend: str, dt: float, nodes) -> Path:
    """Write a checkpoint .npz atomically (a partly written file never has the final name).

    Parameters
    ----------
    path : target file (.npz)
    state : deformable.State (X, V and, when known, A (ndof, 3), t in s, step)
    X0 : (ndof, 3) the constraint reference of the run (its initial positions)
    scene : scene name; config : the resolved scene config as TOML text
    backend : "fd" or "fe"; dt : time step (s); nodes : (M, N)
    """
    path = Path(path)
    tmp = path.with_name(path.stem + ".tmp.npz")
    extra = {} if state.A is None else {"A": state.A}  # the implicit schemes' acceleration, when there is one
    np.savez(tmp, X=state.X, V=state.V, t=np.float64(state.t), step=np.int64(state.step), X0=X0,
             scene=np.str_(scene), config=np.str_(config), backend=np.str_(backend), dt=np.float64(dt),
             nodes=np.asarray(nodes, dtype=np.int64), **extra)
    os.replace(tmp, path)
    return path


def load_checkpoint(path) -> dict:
    """Read a checkpoint written by :func:`save_checkpoint`; ValueError if it is not one."""
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as data:
            missing = [k for k in CHECKPOINT_KEYS if k not in data.files]
            if missing:
                raise ValueError(f"{str(path)!r} is not a checkpoint: missing {', '.join(missing)}")
            out = {k: data[k] for k in CHECKPOINT_KEYS}
            out["A"] = data["A"] if "A" in data.files else None
    except (OSError, EOFError) as err:
        raise ValueError(f"cannot read checkpoint {str(path)!r}: {err}") from None
    except ValueError as err:
        if "is not a checkpoint" in str(err):
            raise
        raise ValueError(f"cannot read checkpoint {str(path)!r}: {err}") from None
    for k in ("scene", "config", "backend"):
        out[k] = str(out[k])
    out["t"], out["dt"], out["step"] = float(out["t"]), float(out["dt"]), int(out["step"])
    out["nodes"] = tuple(int(n) for n in out["nodes"])
    return out


class CheckpointWriter(Tracker):
    """Write ``<folder>/<stem>-<step>.npz`` every ``every`` steps (see :func:`save_checkpoint`).

    ``X0`` is the run's constraint reference (its initial positions, (ndof, 3));
    ``meta`` the keyword arguments of :func:`save_checkpoint` after it.
    """

    def __init__(self, folder, stem: str, every: int, X0, **meta):
        self.folder, self.stem, self.every, self.meta = Path(folder), stem, int(every), meta
        self.X0 = np.asarray(X0)
        if self.every < 1:
            raise ValueError(f"checkpoint-every must be a positive integer, got {every!r}")
        self.written: list[Path] = []

    def path(self, step: int) -> Path:
        return self.folder / f"{self.stem}-{step:07d}.npz"

    def handle(self, state):
        if state.step % self.every == 0:
            self.written.append(save_checkpoint(self.path(state.step), state, self.X0, **self.meta))
