r"""The paper study's measurements of a run: stability class, trajectory difference, linearised limits."""

from __future__ import annotations

import math

import numpy as np

from deformable.physics.force_models import stretching_step

from .cases import RUNAWAY_G

__all__ = ["classify", "trajectory_difference", "predictions"]

def classify(r: dict) -> str:
    """"diverged", "runaway" (max G_ii > RUNAWAY_G) or "bounded"."""
    if r["status"] == "diverged":
        return "diverged"
    return "runaway" if r["Gmax"] > RUNAWAY_G else "bounded"


def trajectory_difference(a: dict, b: dict) -> float:
    """max over snapshots and nodes of |r_a - r_b|, over the largest displacement of run b (dimensionless)."""
    sa, sb = a["snaps"], b["snaps"]
    k = min(len(sa), len(sb))
    motion = float(np.max(np.linalg.norm(sb[:k] - sb[0], axis=-1)))
    return float(np.max(np.linalg.norm(sa[:k] - sb[:k], axis=-1)) / motion)


def predictions(spec: dict, mu: float, eta: float, dt: float, G: float, Bneg=(0.0, 0.0)) -> dict:
    """The linearisation's stability limits (module docstring, item 3).

    Parameters
    ----------
    spec : the :func:`spectrum` of the grid
    mu, eta, dt, G : mass density, stretching weight, time step, largest metric component
    Bneg : (B_1, B_2), the largest negative curvatures max(-B_11), max(-B_22) (1/m)

    Returns
    -------
    dict with dt_c = sqrt(2 mu / (eta G lambda_m)), eta_c = 2 mu / (G lambda_m dt^2) and
    xi_c = mu / (dt^2 max_i B_i lambda_bi) (inf when no curvature is negative).
    """
    lm, lb = spec["lambda_m"], spec["lambda_b"]
    worst = max(Bneg[0] * lb[0], Bneg[1] * lb[1])
    dt_c = stretching_step(mu, eta, lm, G)
    return dict(dt_c=dt_c, eta_c=eta * (dt_c / dt) ** 2,
                xi_c=mu / (worst * dt**2) if worst > 0 else math.inf)
