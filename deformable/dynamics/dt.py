r"""The time step a stepper takes (module docstring of :mod:`deformable.dynamics.stepper`, "Step size").

``dt="auto"`` takes the semi-implicit scheme's stable step from the backend (half of
:meth:`~deformable.backends.Backend.stable_step`, rounded down to two significant digits); the implicit schemes,
stable at any dt, take :data:`IMPLICIT_AUTO` times the explicit stretching bound on the same grid
(:func:`deformable.physics.force_models.stretching_step`). A given dt is a positive finite number of seconds, at
least :data:`DT_MIN`.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..physics.force_models import stretching_step

__all__ = ["DT_MIN", "IMPLICIT_AUTO", "resolve_dt", "round_down"]

#: the implicit schemes' "auto" dt, in units of the explicit stretching bound
IMPLICIT_AUTO = 10.0
#: the smallest time step (s) a stepper accepts
DT_MIN = 1e-12


def round_down(x: float, digits: int = 2) -> float:
    """x rounded down to ``digits`` significant digits (a step never above the bound it comes from)."""
    if not np.isfinite(x) or x <= 0:
        return x
    scale = 10.0 ** (np.floor(np.log10(x)) - digits + 1)
    return float(np.floor(x / scale * (1 + 1e-12)) * scale)


def resolve_dt(model, implicit: bool, dt) -> float:
    """The step (s) of a stepper on ``model`` (a backend) whose scheme is ``implicit`` or not, for ``dt`` (s, or
    "auto"; module docstring). InputError naming dt for a bad value."""
    if isinstance(dt, str) and dt == "auto":
        if not implicit:
            bound = model.stable_step()
            if not np.isfinite(bound):
                raise InputError(f"dt 'auto': the {model.scene.force_model} model's semi-implicit step has no "
                                 "stretching bound; give dt")
            return round_down(0.5 * bound)
        mat, h = model.scene.nodal_material(), min(model.scene.sheet.h)
        weight = np.asarray(model.scene.force_model.stretching_weight(mat))
        bound = stretching_step(float(np.min(mat.mu)), float(np.max(weight)) if weight.size else 0.0, 4 / h**2)
        if not np.isfinite(bound):
            raise InputError("dt 'auto' needs a stretching weight to set the step; give dt")
        return round_down(IMPLICIT_AUTO * bound)
    try:
        dt = float(dt)
    except (TypeError, ValueError):
        raise InputError(f"dt must be a positive number or 'auto', got {dt!r}") from None
    if not np.isfinite(dt) or dt <= 0:
        raise InputError(f"dt must be positive and finite, got {dt!r}")
    if dt < DT_MIN:
        raise InputError(f"dt must be at least {DT_MIN:g} s (below it M/dt^2 swamps every stiffness in double "
                         f"precision), got {dt!r}", field="dt", value=dt)
    return dt
