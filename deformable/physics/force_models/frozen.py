r"""The frozen model of section 3.2: alpha_ij and beta_ij given directly, the controlled-continuity spline.

The paper's alternative to eq. (15) (after Terzopoulos): set the weights of the force (14) as material parameters
instead of computing them from eta, xi and the current tensors. K of eq. (20) is then constant, the force is linear,
``e = K R``, and the gradient of the quadratic energy ``R^T K R / 2`` (:class:`QuadraticEnergy`), so both the
semi-implicit scheme and the implicit ones apply. The paper warns that positive alpha, beta "always induce a
residual initial elastic energy": the rest shape is not a rest state of this model.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ...errors import InputError
from ..energy import Energy
from .base import StrengthModel

__all__ = ["Frozen", "QuadraticEnergy"]


class QuadraticEnergy:
    """The frozen model's energy ``R^T K R / 2`` with K = K_alpha + K_beta constant (section 3.2).

    Parameters
    ----------
    K : sparse (ndof, ndof)
        The strength matrix (integrated rows), symmetric.
    K_alpha, K_beta : sparse (ndof, ndof)
        Its membrane and bending parts, for the split of :meth:`energy`.
    linear : array (ndof, 3), optional
        An affine term f of the bending energy, ``R^T K R / 2 + f . R + constant`` (FD's clamp: the ghost rows'
        slope, :meth:`fdmodel.FDModel._clamp_force`); None: none.
    constant : float
        The bending energy's constant (J).
    """

    def __init__(self, K: sp.csr_matrix, K_alpha: sp.csr_matrix, K_beta: sp.csr_matrix, linear=None,
                 constant: float = 0.0):
        self.K, self.K_alpha, self.K_beta = K, K_alpha, K_beta
        self.linear, self.constant = linear, float(constant)

    def energy(self, X: np.ndarray) -> Energy:
        bending = 0.5 * float(np.sum(X * (self.K_beta @ X)))
        if self.linear is not None:
            bending += float(np.sum(self.linear * X)) + self.constant
        return Energy(0.5 * float(np.sum(X * (self.K_alpha @ X))), bending)

    def gradient(self, X: np.ndarray) -> np.ndarray:
        return self.K @ X if self.linear is None else self.K @ X + self.linear

    def hessian(self, X: np.ndarray, kind: str = "newton") -> sp.csr_matrix:
        """The coordinate-blocked Hessian diag(K, K, K) (exact, whatever ``kind``)."""
        return sp.kron(sp.identity(3), self.K, format="csr")

    def elements(self, X: np.ndarray, kind: str = "newton"):
        """None: a constant matrix has no element Hessians (:meth:`deformable.Backend.energy_elements`)."""
        return None


class Frozen(StrengthModel):
    """alpha and beta given by the Material (module docstring)."""

    name = "frozen"
    rank = 1
    summary = "alpha, beta given directly (section 3.2): linear, the controlled-continuity spline"
    has_energy = True
    linear = True
    weights = ("alpha", "beta")

    def check(self, material) -> None:
        if material.alpha is None and material.beta is None:
            raise InputError("Scene.force_model 'frozen' needs Material.alpha and/or Material.beta",
                             field="Material.alpha", value=None)

    def coefficients(self, material_at, G, G0, B, B0):
        """The Material's own alpha and beta at the points (whatever the state)."""
        return material_at("alpha"), material_at("beta")
