r"""An orthotropic shell: a fabric's warp and weft (Koiter's energy with an orthotropic plane-stress law).

The material axes run along the parameter lines: warp along a1, weft along a2, on a rest parameterisation whose
lines meet at right angles (G0_12 = 0, checked). The strains and curvature changes of Koiter's shell
(:mod:`.koiter`), eps = s / 2 and kappa = b, in the orthonormal frame of the rest tangents, in Voigt form

    e = S t,   S = diag(1 / G0_11, 1 / G0_22, 2 / sqrt(G0_11 G0_22)),   t = (t11, t22, t12),

enter the plane-stress orthotropic law (Lekhnitskii 1968, *Anisotropic Plates*; Jones 1999, *Mechanics of Composite
Materials*, section 2.6)

    Q = [[Q11, Q12, 0], [Q12, Q22, 0], [0, 0, G12]],  Q11 = E1 / (1 - nu12 nu21),  Q22 = E2 / (1 - nu12 nu21),
    Q12 = nu12 E2 / (1 - nu12 nu21),                  nu21 = nu12 E2 / E1,

    W = sqrt(det G0) [ h / 2  (S s / 2)^T Q (S s / 2) + h^3 / 24  (S b)^T Q (S b) ]

per unit parameter area, i.e. :class:`.koiter.ShellEnergy`'s ``cs s^T K s + cb b^T K b`` with K = S^T Q S, cs =
sqrt(det G0) h / 8 and cb = sqrt(det G0) h^3 / 24. With E1 = E2 = E, nu12 = nu and G12 = E / (2 (1 + nu)) it is
Koiter's isotropic energy (tested to round-off). Q is positive definite when E1, E2, G12 > 0 and nu12^2 E2 / E1 < 1
(checked). The bending law is the membrane's scaled by h^2 / 12 (a homogeneous sheet); a woven fabric's bending
rigidity, measured on its own (the Peirce test), may differ: give ``h`` as the thickness that matches it, or a
separate bending law as another member of this family.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...checks import is_real
from ...errors import InputError
from .base import RESIDUALS
from .koiter import ShellEnergy, finite_stiffnesses, positive_parameter

__all__ = ["Orthotropic"]


@dataclass(frozen=True, eq=False)
class Orthotropic(ShellEnergy):
    """An orthotropic shell (module docstring): ``Scene(force_model=Orthotropic(E1=..., E2=..., G12=..., nu12=...,
    h=...))``.

    Parameters
    ----------
    E1, E2 : float
        Young's moduli along a1 (warp) and a2 (weft) (Pa), positive.
    G12 : float
        The in-plane shear modulus (Pa), positive.
    nu12 : float
        Poisson's ratio (contraction along a2 under stretch along a1), with nu12^2 E2 / E1 < 1.
    h : float
        The thickness (m), positive.

    The Material's eta and xi are not read (its mu and gamma are).
    """

    name = "orthotropic"
    summary = "an orthotropic shell (warp E1 along a1, weft E2 along a2, shear G12, nu12, thickness h)"
    E1: float = 1.0e6
    E2: float = 1.0e6
    G12: float = 5.0e5
    nu12: float = 0.0
    h: float = 1.0e-3

    def __post_init__(self):
        for name in ("E1", "E2", "G12", "h"):
            positive_parameter(self, name)
        nu = self.nu12
        if not is_real(nu) or not np.isfinite(nu) or nu < 0 \
                or nu**2 * self.E2 / self.E1 >= 1:
            raise InputError(f"Orthotropic nu12 must be non-negative with nu12^2 E2 / E1 < 1 (a positive definite "
                             f"law), got {nu!r}", field="Orthotropic.nu12", value=nu)
        object.__setattr__(self, "nu12", float(nu))
        finite_stiffnesses(self, "E1")

    @property
    def couples(self):
        """nu12 couples the two stretches and the two bendings (the shear stands alone, G0_12 = 0); grouped as
        Koiter's (the metric's three, the curvature's three), so that FD places the terms alike and the isotropic
        law gives Koiter's discrete energy on both backends."""
        return () if self.nu12 == 0 else (RESIDUALS[:3], RESIDUALS[3:])

    @property
    def law(self) -> np.ndarray:
        """Q (3, 3) (Pa), Voigt (e11, e22, 2 e12)."""
        nu21 = self.nu12 * self.E2 / self.E1
        d = 1 - self.nu12 * nu21
        return np.array([[self.E1 / d, self.nu12 * self.E2 / d, 0.0], [self.nu12 * self.E2 / d, self.E2 / d, 0.0],
                         [0.0, 0.0, self.G12]])

    @property
    def stiffnesses(self) -> tuple[float, float]:
        """(E1 h / (1 - nu12 nu21), E1 h^3 / (12 (1 - nu12 nu21))): the warp's membrane and bending stiffness."""
        q = self.law[0, 0]
        return q * self.h, q * self.h**3 / 12

    def prepare(self, params):
        """K = S^T Q S (3, 3, P) and the area element (1, 1, P) of the rest metric, once (module docstring)."""
        G0 = params["G0"]
        g1, g2 = G0[0, 0], G0[1, 1]
        if np.any(np.abs(G0[0, 1]) > 1e-10 * np.maximum(np.abs(g1), np.abs(g2))):
            raise InputError(f"Orthotropic: the material axes follow the parameter lines, which must meet at right "
                             f"angles at rest; here |G0_12| reaches {np.max(np.abs(G0[0, 1])):.3g}",
                             field="Scene.force_model", value=self.name)
        ok = (g1 > 0) & (g2 > 0)  # FD carries points of zero weight without a rest metric
        S = np.zeros((3, g1.size))
        S[0, ok], S[1, ok], S[2, ok] = 1 / g1[ok], 1 / g2[ok], 2 / np.sqrt(g1[ok] * g2[ok])
        K = S[:, None] * self.law[:, :, None] * S[None, :]
        J = np.sqrt(np.maximum(g1 * g2 - G0[0, 1] ** 2, 0.0))
        return {**params, "K": K, "J": J[None, None]}

    def _form(self, params):
        if "K" not in params:
            params = self.prepare(params)
        J = params["J"][0, 0]
        return params["K"], J * self.h / 8, J * self.h**3 / 24
