"""How the sheet meets the scene's obstacles and itself: :class:`Contact`, the settings of the barrier and friction
(:mod:`deformable.contact.potential`, :mod:`deformable.contact.repulsion`, :mod:`deformable.contact.selfpotential`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

from ..checks import known_keys
from ..physics.forces import Gravity
from .barrier import barrier_derivative

__all__ = ["Contact", "METHODS", "weight_per_area"]


METHODS = ("barrier", "exponential")


#: the barrier stiffness's default: the sheet's weight rests at this fraction of dhat
REST_FRACTION = 0.1


#: the closing speed (m/s) of two folds that the default self-contact stiffness stops at a tenth of its reach
SELF_SPEED = 2.0


#: the exponential force's default strength c, in units of the sheet's weight per area
REPULSION_STRENGTH = 100.0


#: standard gravity (m/s^2): sizes the default stiffness of a scene without Gravity
STANDARD_GRAVITY = 9.81


# -- settings -----------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class Contact:
    """How the sheet meets the scene's obstacles (module docstring).

    Parameters
    ----------
    distance : float
        The activation distance dhat of the barrier (m); for the exponential force, its length eps.
    friction : float
        Coulomb's coefficient mu_f against the obstacles (0: frictionless).
    stiffness : float or None
        The barrier's kappa (N/m^3); None: the sheet's own weight rests at dhat / 10.
    slip : float
        eps_v (m/s): below this tangential speed friction (against the obstacles and between folds) is smoothed (a
        creep instead of a stick).
    samples : int or None
        Contact points per cell side; None: the backend's own (FD 1, the nodes; FE 2).
    method : "barrier" or "exponential"
        The barrier with friction (implicit schemes), or the paper's exponential force (semi-implicit scheme; no
        guarantee).
    pressure : float or None
        c of the exponential force (N/m^2); None: 100 times the sheet's weight per area.
    margin : float
        The fraction, in (0, 1), of the largest safe step a Newton step may take.
    self_distance : float or None
        The activation distance of the self-contact barrier (m), beyond ``thickness`` (implicit schemes, a force
        model with an energy); None or 0: no self-contact.
    thickness : float
        The sheet's thickness (m): no two primitives of the contact mesh that may touch come closer (0: they only
        never cross).
    self_stiffness : float or None
        The self-contact barrier's kappa (N/m^5); None: two folds closing at ``self_speed`` stop at a gap of
        thickness + self_distance / 10.
    self_speed : float
        The closing speed (m/s) the default self-contact stiffness is sized for (and the mesh obstacles' largest,
        their start when one moves).
    self_friction : float
        Coulomb's coefficient between folds of the sheet (0: frictionless), smoothed below ``slip``.
    """

    distance: float = 1e-3
    friction: float = 0.0
    stiffness: float | None = None
    slip: float = 1e-3
    samples: int | None = None
    method: str = "barrier"
    pressure: float | None = None
    margin: float = 0.8
    self_distance: float | None = None
    thickness: float = 0.0
    self_stiffness: float | None = None
    self_speed: float = SELF_SPEED
    self_friction: float = 0.0

    def __post_init__(self):
        if self.self_distance == 0 and not isinstance(self.self_distance, bool):  # 0: off (a TOML file has no None)
            object.__setattr__(self, "self_distance", None)
        for name in ("distance", "friction", "stiffness", "slip", "pressure", "margin", "self_distance",
                     "thickness", "self_stiffness", "self_speed", "self_friction"):
            v = getattr(self, name)
            if v is None and name in ("stiffness", "pressure", "self_distance", "self_stiffness"):
                continue
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ValueError(f"Contact.{name} must be a finite number, got {v!r}")
            zero = name in ("friction", "thickness", "self_friction")
            if v < 0 or (v == 0 and not zero):
                raise ValueError(f"Contact.{name} must be {'non-negative' if zero else 'positive'}, got {v!r}")
            object.__setattr__(self, name, float(v))
        if not self.margin < 1:
            raise ValueError(f"Contact.margin must lie in (0, 1), got {self.margin!r}")
        if self.samples is not None and (isinstance(self.samples, bool) or not isinstance(self.samples, int)
                                         or self.samples < 1):
            raise ValueError(f"Contact.samples must be a positive integer or None, got {self.samples!r}")
        if self.method not in METHODS:
            raise ValueError(f"Contact.method must be one of {METHODS}, got {self.method!r}")

    @classmethod
    def from_table(cls, table, source: str = "contact", base: Contact | None = None) -> Contact:
        """Contact from a TOML table, over ``base`` (default ``Contact()``); an unknown key is a ValueError."""
        if isinstance(table, Contact):
            return table
        if not isinstance(table, dict):
            raise ValueError(f"{source} must be a table of {', '.join(f.name for f in fields(cls))}, got {table!r}")
        known_keys(table, [f.name for f in fields(cls)], f"in {source}")
        return replace(base, **table) if base is not None else cls(**table)

    def table(self) -> dict:
        """The settings as a TOML table (None values left out)."""
        return {f.name: getattr(self, f.name) for f in fields(self) if getattr(self, f.name) is not None}

    def barrier_stiffness(self, weight: float) -> float:
        """kappa (N/m^3): the given one, or the one under which a weight per area (N/m^2) rests at dhat / 10."""
        if self.stiffness is not None:
            return self.stiffness
        return weight / -barrier_derivative(np.array([REST_FRACTION * self.distance]), self.distance)[0]

    def repulsion_pressure(self, weight: float) -> float:
        """c (N/m^2) of the exponential force: the given one, or 100 times the weight per area."""
        return self.pressure if self.pressure is not None else REPULSION_STRENGTH * weight


def weight_per_area(scene) -> float:
    """The heaviest weight per area of the sheet, max(mu) |g| (N/m^2), standard gravity when there is none."""
    g = sum(abs(f.g) for f in scene.forces if isinstance(f, Gravity)) or STANDARD_GRAVITY
    return float(np.max(scene.nodal_material().mu)) * g
