r"""The paper's force (14)-(15), TPBF87's: ``e = sum_ij -d_i(alpha_ij d_j r) + d_ij(beta_ij d_ij r)``.

With the weights of eq. (15),

    alpha_ij = eta_ij (G_ij - G0_ij),   beta_ij = xi_ij (B_ij - B0_ij),

frozen at the current r, the force is ``K(r) R`` with the strength matrix of eq. (20), and the paper's semi-implicit
step (eq. 22-27) solves one linear system a step. It is *not* the gradient of the energy (13): about a flat sheet
with B0 = 0 it has no linear bending stiffness (the bending force enters at O(eps^2)), and in compression alpha < 0
makes K indefinite (docs/design.md, "Findings").

The step lags alpha, so it is stable only below a stretching bound (docs/design.md, "Time stepping"): with lambda_m
the largest eigenvalue of the membrane operator per unit alpha against the mass (FD ``4/h^2``, bicubic Hermite FE
about ``91/h^2``), ``dt < sqrt(2 mu / (eta G lambda_m))`` (:func:`stretching_step`; FD: ``h sqrt(mu / (2 eta G))``).

Tensor fields are components first, points last: (2, 2, *pts).
"""

from __future__ import annotations

import math

import numpy as np

from .base import StrengthModel

__all__ = ["TPBF87", "alpha", "beta", "stretching_step"]


def alpha(eta: np.ndarray, G: np.ndarray, G0: np.ndarray) -> np.ndarray:
    """alpha_ij = eta_ij (G_ij - G0_ij), eq. (15): (2, 2, *pts) (N/m)."""
    return eta * (G - G0)


def beta(xi: np.ndarray, B: np.ndarray, B0: np.ndarray) -> np.ndarray:
    """beta_ij = xi_ij (B_ij - B0_ij), eq. (15): (2, 2, *pts) (N)."""
    return xi * (B - B0)


def stretching_step(mu: float, eta: float, lambda_m: float, G: float = 1.0) -> float:
    """Stretching bound of the semi-implicit step, ``sqrt(2 mu / (eta G lambda_m))`` (s); inf when eta = 0.

    Parameters
    ----------
    mu : mass density (kg/m^2)
    eta : stretching weight (N/m)
    lambda_m : largest eigenvalue of the membrane operator per unit alpha against the mass (1/m^2)
    G : metric component along the stiffest direction (1 at rest)
    """
    if eta <= 0:
        return math.inf
    return math.sqrt(2.0 * mu / (eta * G * lambda_m))


class TPBF87(StrengthModel):
    """The paper's force (14)-(15) as written (module docstring)."""

    name = "tpbf87"
    rank = 0
    summary = "the paper's force (14)-(15): K(r) R with alpha, beta of eq. (15); not the gradient of eq. (13)"
    lags_alpha = True

    def coefficients(self, material_at, G, G0, B, B0):
        """alpha and beta of eq. (15) from eta, xi at the points (beta zero where B is None)."""
        a = alpha(material_at("eta"), G, G0)
        return a, np.zeros_like(a) if B is None else beta(material_at("xi"), B, B0)

    def stable_step(self, mu: np.ndarray, eta: np.ndarray, spacing, eigenvalue: float) -> float:
        """The stretching bound (s): the smallest mass density ``mu`` (any shape), the largest of eta_11, eta_22
        (``eta``: (2, 2, ...)), the smaller spacing h and lambda_m = ``eigenvalue`` / h^2 (the backend's stiffest
        membrane mode: FD 4, FE about 91)."""
        return stretching_step(float(np.min(mu)), float(max(np.max(eta[0, 0]), np.max(eta[1, 1]))),
                               eigenvalue / min(spacing) ** 2)
