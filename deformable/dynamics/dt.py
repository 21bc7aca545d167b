r"""The time step a stepper takes (module docstring of :mod:`deformable.dynamics.stepper`, "Step size").

The one rule of the stable step: half the backend's stretching bound
(:meth:`~deformable.backends.Backend.stable_step`, eq. (25) lags alpha), rounded down to two significant digits
(:func:`within_stable`). ``dt="auto"`` takes it for the semi-implicit scheme; the implicit schemes, stable at any
dt, take :data:`IMPLICIT_AUTO` times the time the membrane wave takes to cross a grid spacing, h / (c sqrt 2) with
c = sqrt(eta / mu) (:func:`deformable.physics.force_models.stretching_step` at (2 / h)^2): the same on every
backend, since what an implicit step must resolve is the continuum's wave, not a backend's stiffest discrete mode
(which sets the semi-implicit bound, :attr:`deformable.backends.Discretisation.membrane_eigenvalue`). A scene's own dt (written for FD) is taken as is where
it is within the backend's bound, else the bound's half (:func:`within_stable`, the run's step in
:class:`deformable.session.Simulation`). A given dt is a positive finite number of seconds, at least
:data:`DT_MIN`.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..physics.force_models import stretching_step

__all__ = ["DT_MIN", "IMPLICIT_AUTO", "resolve_dt", "round_down", "within_stable"]

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


def within_stable(model, dt: float = np.inf) -> float:
    """``dt`` (s) where it is at most half ``model``'s stretching bound, else that half rounded down (two
    significant digits): the step a run takes for a scene's dt. The frozen and variational models have no bound
    (inf): dt stays."""
    half = 0.5 * model.stable_step()
    return round_down(half) if dt > half else dt


def resolve_dt(model, implicit: bool, dt) -> float:
    """The step (s) of a stepper on ``model`` (a backend) whose scheme is ``implicit`` or not, for ``dt`` (s, or
    "auto"; module docstring). InputError naming dt for a bad value."""
    if isinstance(dt, str) and dt == "auto":
        if not implicit:
            step = within_stable(model)
            if not np.isfinite(step):
                raise InputError(f"dt 'auto': the {model.scene.force_model} model's semi-implicit step has no "
                                 "stretching bound; give dt")
            return step
        mat, h = model.scene.nodal_material(), min(model.scene.sheet.h)
        weight = np.asarray(model.scene.force_model.stretching_weight(mat))
        # the membrane wave (speed c = sqrt(eta / mu)) crossing a grid spacing: h / (c sqrt 2), the explicit bound
        # at the continuum's (2 / h)^2 = 4 / h^2; a property of the grid and the material, the same on every backend (a
        # backend's stiffest discrete mode sets the semi-implicit bound, not what an implicit step resolves)
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
