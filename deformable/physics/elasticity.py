r"""The elastic law of the model, written once for both backends and the output writer.

- eq. (15), the weights of the paper's force (14):
  ``alpha_ij = eta_ij (G_ij - G0_ij)``, ``beta_ij = xi_ij (B_ij - B0_ij)``;
- eq. (13), the energy density (its integrand), split into stretching and bending:
  ``sum_ij eta_ij (G_ij - G0_ij)^2`` and ``sum_ij xi_ij (B_ij - B0_ij)^2`` (J/m^2);
- the frozen model of section 3.2 (alpha and beta given directly): a quadratic
  energy ``R^T K R / 2`` (:class:`QuadraticEnergy`);
- the stretching bound of the paper's semi-implicit step (eq. 22-27), which
  lags alpha (docs/design.md, "Time stepping"): with lambda_m the largest
  eigenvalue of the membrane operator per unit alpha against the mass (FD
  ``4/h^2``, bicubic Hermite FE about ``91/h^2``), the step is stable for
  ``dt < sqrt(2 mu / (eta G lambda_m))`` (:func:`stretching_step`; FD:
  ``h sqrt(mu / (2 eta G))``).

Tensor fields are components first, points last: (2, 2, *pts).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from ..errors import InputError
from .energy import Energy

__all__ = ["alpha", "beta", "energy_density", "stretching_step", "lagged_alpha_step", "QuadraticEnergy",
           "require_energy_gradient", "require_strength_matrix"]


def alpha(eta: np.ndarray, G: np.ndarray, G0: np.ndarray) -> np.ndarray:
    """alpha_ij = eta_ij (G_ij - G0_ij), eq. (15): (2, 2, *pts) (N/m)."""
    return eta * (G - G0)


def beta(xi: np.ndarray, B: np.ndarray, B0: np.ndarray) -> np.ndarray:
    """beta_ij = xi_ij (B_ij - B0_ij), eq. (15): (2, 2, *pts) (N)."""
    return xi * (B - B0)


def energy_density(eta, xi, G, G0, B, B0) -> tuple[np.ndarray, np.ndarray]:
    """The integrand of eq. (13): stretching and bending densities, each (*pts) (J per unit area).

    Parameters
    ----------
    eta, xi : arrays (2, 2, *pts)
        Weights (times any quadrature weight per component, as FD's row weights).
    G, G0, B, B0 : arrays (2, 2, *pts)
        Metric and curvature, and their rest values. ``B`` may be None when xi
        is zero everywhere (no normal is formed then); the bending density is 0.
    """
    stretching = np.sum(eta * (G - G0) ** 2, axis=(0, 1))
    if B is None:
        return stretching, np.zeros_like(stretching)
    return stretching, np.sum(xi * (B - B0) ** 2, axis=(0, 1))


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


def lagged_alpha_step(scene, mu: np.ndarray, eta: np.ndarray | None, spacing, eigenvalue: float) -> float:
    """A backend's stable step of the semi-implicit scheme (s): the stretching bound for tpbf87, else inf.

    Only the tpbf87 model lags alpha (eq. 25). The bound takes the smallest
    mass density ``mu`` (any shape), the largest of eta_11, eta_22 (``eta``:
    (2, 2, ...)), the smaller spacing h and lambda_m = ``eigenvalue`` / h^2
    (the backend's stiffest membrane mode: FD 4, FE about 91).
    """
    if scene.force_model != "tpbf87":
        return math.inf
    return stretching_step(float(np.min(mu)), float(max(np.max(eta[0, 0]), np.max(eta[1, 1]))),
                           eigenvalue / min(spacing) ** 2)


def require_energy_gradient(scene) -> None:
    """ValueError unless the scene's force model is the gradient of an energy (not tpbf87's eq. (14))."""
    if scene.force_model == "tpbf87":
        raise InputError("force_model 'tpbf87' has no energy gradient: its force (14) is not the gradient of "
                         "eq. (13); use force_model 'variational'")


def require_strength_matrix(scene) -> None:
    """ValueError unless the scene's force model has the strength matrix K(r) of eq. (20)."""
    if scene.force_model == "variational":
        raise InputError("the variational force model has no strength matrix K(r) of eq. (20); use "
                         "energy_gradient / energy_hessian (TimeStepper scheme 'implicit-euler' or 'newmark')")


class QuadraticEnergy:
    """The frozen model's energy ``R^T K R / 2`` with K = K_alpha + K_beta constant (section 3.2).

    Parameters
    ----------
    K : sparse (ndof, ndof)
        The strength matrix (integrated rows), symmetric.
    K_alpha, K_beta : sparse (ndof, ndof)
        Its membrane and bending parts, for the split of :meth:`energy`.
    """

    def __init__(self, K: sp.csr_matrix, K_alpha: sp.csr_matrix, K_beta: sp.csr_matrix):
        self.K, self.K_alpha, self.K_beta = K, K_alpha, K_beta

    def energy(self, X: np.ndarray) -> Energy:
        return Energy(0.5 * float(np.sum(X * (self.K_alpha @ X))), 0.5 * float(np.sum(X * (self.K_beta @ X))))

    def gradient(self, X: np.ndarray) -> np.ndarray:
        return self.K @ X

    def hessian(self, X: np.ndarray, kind: str = "newton") -> sp.csr_matrix:
        """The coordinate-blocked Hessian diag(K, K, K) (exact, whatever ``kind``)."""
        return sp.kron(sp.identity(3), self.K, format="csr")
