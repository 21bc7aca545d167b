r"""The energy-consistent model: the exact gradient of the energy (13), the built-in energy density.

    W(s, b) = sum_ij eta_ij (G_ij - G0_ij)^2 + xi_ij (B_ij - B0_ij)^2
            = eta_11 s11^2 + eta_22 s22^2 + (eta_12 + eta_21) s12^2 + xi_11 b11^2 + xi_22 b22^2 + (xi_12 + xi_21) b12^2

in the residuals of :mod:`.base`. It couples no residuals (each term stands alone), so finite differences keep each
term at the point where its stencil is centred (:mod:`fdmodel.energy`). The backends evaluate it with the compiled
kernels of :mod:`deformable.physics.kernels` (the class's ``compiled`` flag); the methods below are the same density
in numpy, for the output's energy density and for checking the generic path against the compiled one.

Linearised about a flat rest state with G0 = g0 I, B0 = 0, the transverse force is ``-4 eta (1 - g0) (w_11 + w_22) +
2 xi (w_1111 + w_2222)``: four times the paper's force (14) in stretching, twice in bending
(:attr:`Variational.stiffness`, docs/design.md). With full weight tensors (eta_12 = eta, xi_12 = xi) it is the St
Venant-Kirchhoff plate with E h = 8 eta and D = 2 xi (Poisson ratio 0); with eta_12 = 0 or xi_12 = 0, shear or twist
costs nothing (:meth:`Variational.free_modes`).
"""

from __future__ import annotations

import numpy as np

from .base import EnergyModel, energy_density

__all__ = ["Variational", "weights"]


def weights(params: dict) -> np.ndarray:
    """The six residual weights of eq. (13), (6, P): eta_11, eta_22, eta_12 + eta_21, xi_11, xi_22, xi_12 + xi_21."""
    e, x = params["eta"], params["xi"]
    return np.stack([e[0, 0], e[1, 1], e[0, 1] + e[1, 0], x[0, 0], x[1, 1], x[0, 1] + x[1, 0]])


class Variational(EnergyModel):
    """Eq. (13) and its exact gradient (module docstring)."""

    name = "variational"
    rank = 2
    summary = "the exact gradient of the energy (13), stepped implicitly by Newton's method"
    stiffness = (4.0, 2.0)
    couples = ()
    compiled = True

    def density(self, s, b, params):
        r = np.concatenate([s, b])
        return np.sum(weights(params) * r * r, axis=0)

    def gradient(self, s, b, params):
        return 2.0 * weights(params) * np.concatenate([s, b])

    def hessian(self, s, b, params):
        c = weights(params)
        H = np.zeros((6, 6, c.shape[1]))
        H[np.arange(6), np.arange(6)] = 2.0 * c
        return H

    def bends(self, params) -> bool:
        return bool(np.any(params["xi"] != 0))

    def density_field(self, material_at, G, G0, B, B0):
        """Eq. (13)'s integrand in the tensors' own form (:func:`.base.energy_density`)."""
        return energy_density(material_at("eta"), material_at("xi"), G, G0, B, B0)

    def free_modes(self, material) -> list[str]:
        """The deformations the weights leave free: "shear" (eta_12 = 0), "twist" (xi_12 = 0, with bending)."""
        free = []
        for name, mode in (("eta", "shear"), ("xi", "twist")):
            w = np.asarray(getattr(material, name), float)
            w = w * np.eye(2) if w.ndim == 0 else w  # a scalar is eta_11 = eta_22, eta_12 = 0
            if np.any(w[0, 0] != 0) and not np.any(w[0, 1]):
                free.append(f"{mode} ({name}_12 = 0)")
        return free
