"""What a resumed run checks against its checkpoint, and what it leaves behind (:class:`Simulation.resume`)."""

from __future__ import annotations

import logging
from dataclasses import fields
from pathlib import Path

from .. import scenes
from ..errors import InputError
from ..io import CheckpointWriter, load_checkpoint

__all__ = ["differences", "fits", "abandon", "owns"]

log = logging.getLogger(__name__)


def differences(a: scenes.SceneConfig, b: scenes.SceneConfig, skip=("t_end",)) -> list[str]:
    """The fields (but ``skip``) in which two configs differ, as 'name = a vs b'."""
    if a.scene != b.scene:
        return [f"scene = {a.scene!r} vs {b.scene!r}"]
    return [f"{f.name} = {getattr(a, f.name)!r} vs {getattr(b, f.name)!r}" for f in fields(a)
            if f.name not in skip and getattr(a, f.name) != getattr(b, f.name)]


def fits(path, checkpoint: dict, config, backend: str, stepper) -> None:
    """InputError naming the first field in which the run asked for (``config`` on ``backend``, stepped by
    ``stepper``) differs from the checkpoint's, or the checkpoint's states do not fit the model."""
    base = scenes.read_toml_text(checkpoint["config"], source=path)
    diff = differences(config, base)
    if checkpoint["backend"] != backend:
        diff.insert(0, f"backend = {backend!r} vs {checkpoint['backend']!r}")
    scheme = scenes.run_table(checkpoint["config"], path).get("scheme")
    if scheme is not None and scheme != stepper.scheme:
        diff.append(f"scheme = {stepper.scheme!r} vs {scheme!r}")
    if checkpoint["dt"] != config.dt:
        diff.append(f"dt = {config.dt!r} vs {checkpoint['dt']!r}")
    if diff:
        more = f" (and {len(diff) - 1} more)" if len(diff) > 1 else ""
        raise InputError(f"resume file {str(path)!r} does not fit the run asked for: {diff[0]} (asked for vs the "
                         f"checkpoint's){more}", field=diff[0].split(" =")[0], value=path)
    X = checkpoint["X"]
    if X.shape != (stepper.model.ndof, 3):
        raise InputError(f"resume file {str(path)!r} holds states of shape {X.shape}, the scene has "
                         f"({stepper.model.ndof}, 3)", field="resume", value=path)


def owns(folder, config, backend: str) -> bool:
    """Whether ``folder`` holds a run of ``config`` on ``backend`` (its resolved config the same, but t_end)."""
    path = Path(folder) / f"{config.scene}.toml"
    try:
        mine = scenes.read_toml(path)
        theirs = scenes.run_table(path.read_text(), str(path)).get("backend", backend)
    except (InputError, OSError):
        return False
    return not differences(mine, config) and theirs == backend


def abandon(folder: Path, scene: str, step: int) -> None:
    """Remove the checkpoints in ``folder`` later than ``step``: the run resumed from ``step`` replaces them.

    Their series is cut back to ``step``; resumed from, they would leave a hole in it (a diverged run's last
    good state likewise).
    """
    later = [p for k, p in CheckpointWriter.found(folder, f"{scene}-checkpoint").items() if k > step]
    diverged = folder / f"{scene}-diverged.npz"
    if diverged.is_file():
        try:
            if load_checkpoint(diverged)["step"] > step:
                later.append(diverged)
        except InputError:
            pass  # not a checkpoint this run can read: left alone
    for path in later:
        path.unlink(missing_ok=True)
    if later:
        log.warning("removed %d checkpoints later than step %d (%s), of the run this one replaces from there",
                    len(later), step, ", ".join(p.name for p in later[:3]) + (" ..." if len(later) > 3 else ""))
