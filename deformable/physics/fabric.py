r"""A fabric as a textile lab measures it, in SI units, and the weights of eq. (13) that make it.

A lab reports, along the warp (a1 here) and the weft (a2):

- the areal density w (kg/m^2; ASTM D3776);
- the bending rigidity D per unit width (N m), usually from the cantilever bending length c (ASTM D1388, Peirce
  1930, J. Textile Inst. 21, T377): D = w g c^3 (:meth:`Fabric.from_bending_length`);
- the tensile stiffness T (N/m): force per unit width over strain, the initial slope;
- the in-plane shear stiffness S (N/m): force per unit width over the shear angle (KES-F's G).

The weights (sections 3.2 and 4). About a flat rest state on an orthonormal parameterisation (G0 = I), the
variational model's energy (13) is, to second order in the displacement, that of a linear sheet at Poisson's ratio 0
(Koiter's energy at nu = 0, docs/design.md): with G_11 - 1 = 2 e_11, G_12 = gamma the shear angle, B_ij = kappa_ij
the curvature changes, and eq. (13) counting eta_12 and eta_21 both,

    eta_11 (G_11 - 1)^2 = (T_1 / 2) e_11^2     ->  eta_11 = T_1 / 8   (Koiter: E h / 8)
    2 eta_12 G_12^2     = (S / 2) gamma^2      ->  eta_12 = S / 4     (Koiter at nu = 0: S = E h / 2)
    xi_11 B_11^2        = (D_1 / 2) kappa_11^2 ->  xi_11 = D_1 / 2    (Koiter: E h^3 / 24)
    2 xi_12 B_12^2      = D_12 kappa_12^2      ->  xi_12 = D_12 / 2

with D_12, the twisting rigidity a lab seldom measures, sqrt(D_1 D_2) unless given (the isotropic sheet at nu = 0
has D_12 = D). Any other force model takes the weights with the same linear stiffness: multiplied by the variational
model's :attr:`~deformable.physics.ForceModel.stiffness` over its own (the paper's force (14): eta_11 = T_1 / 2,
xi_11 = D_1; :func:`deformable.scenes.equivalent_weights`). The nonlinear response differs between the models; this
fixes their stiffness about the flat sheet.

Named fabrics measured by others (:mod:`deformable.physics.fabric_presets`: the ten of Wang, O'Brien and Ramamoorthi
2011 as ARCSim ships them, and ARCSim's paper estimate): ``Fabric.preset("denim")``, their names
``Fabric.presets()``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..checks import is_real, real
from ..errors import InputError
from . import fabric_presets
from .force_models import ForceModel
from .material import Material

__all__ = ["Fabric", "G"]

#: standard gravity (m/s^2), that of the bending-length test
G = 9.80665


def _pair(name: str, value) -> tuple[float, float]:
    """(warp, weft) from a number (both) or a pair; InputError unless finite and positive."""
    pair = (value, value) if np.ndim(value) == 0 else tuple(value)
    try:
        pair = tuple(float(v) for v in pair)
    except (TypeError, ValueError):
        pair = ()
    if len(pair) != 2 or not all(math.isfinite(v) and v > 0 for v in pair):
        raise InputError(f"Fabric.{name} must be a positive number or a (warp, weft) pair of them, got {value!r}",
                         field=f"Fabric.{name}", value=value)
    return pair


@dataclass(frozen=True)
class Fabric:
    """A fabric's measured properties in SI units (module docstring).

    Parameters
    ----------
    density : float
        Areal density w (kg/m^2).
    bending : float or (warp, weft)
        Bending rigidity per unit width D (N m).
    tensile : float or (warp, weft)
        Tensile stiffness T (N/m).
    shear : float, optional
        In-plane shear stiffness S (N/m); default the isotropic sheet's at Poisson's ratio 0, the mean T / 2.
    twist : float, optional
        Twisting rigidity D_12 (N m); default sqrt(D_warp D_weft).
    name, source : str
        What it is and where each value was read.
    """

    density: float
    bending: object
    tensile: object
    shear: float | None = None
    twist: float | None = None
    name: str = ""
    source: str = ""

    def __post_init__(self):
        if not (is_real(self.density) and math.isfinite(self.density) and self.density > 0):
            raise InputError(f"Fabric.density must be a positive areal density in kg/m^2, got {self.density!r}",
                             field="Fabric.density", value=self.density)
        object.__setattr__(self, "density", float(self.density))
        object.__setattr__(self, "bending", _pair("bending", self.bending))
        object.__setattr__(self, "tensile", _pair("tensile", self.tensile))
        for name in ("shear", "twist"):
            v = getattr(self, name)
            if v is not None and not (is_real(v) and math.isfinite(v) and v > 0):
                raise InputError(f"Fabric.{name} must be positive (or None for the default), got {v!r}",
                                 field=f"Fabric.{name}", value=v)
            if v is not None:
                object.__setattr__(self, name, float(v))

    @classmethod
    def from_bending_length(cls, density: float, length, tensile, **kw) -> Fabric:
        """A fabric from its cantilever bending length c (m, a number or (warp, weft); ASTM D1388): D = w g c^3
        (Peirce 1930)."""
        c = _pair("bending length", length)
        return cls(density, tuple(density * G * x**3 for x in c), tensile, **kw)

    @classmethod
    def preset(cls, name: str) -> Fabric:
        """The named fabric ``name`` (one of :meth:`presets`), derived from its source's values
        (:mod:`~deformable.physics.fabric_presets`: warp = the source's u, T = 2 c, S = c33 / 2, D_warp the bending
        about a hinge across the warp); InputError naming the known presets for any other name."""
        return cls(**fabric_presets.arguments(name))

    @classmethod
    def presets(cls) -> tuple[str, ...]:
        """The names of the named fabrics, sorted."""
        return fabric_presets.names()

    @property
    def bending_length(self) -> tuple[float, float]:
        """Peirce's c = (D / (w g))^(1/3) along the warp and the weft (m)."""
        return tuple((d / (self.density * G)) ** (1 / 3) for d in self.bending)

    def weights(self, force_model="variational") -> tuple[np.ndarray, np.ndarray]:
        """eta_ij (N/m) and xi_ij (N m), two symmetric 2 x 2 arrays, under ``force_model`` (module docstring)."""
        (T1, T2), (D1, D2) = self.tensile, self.bending
        S = self.shear if self.shear is not None else (T1 + T2) / 4
        D12 = self.twist if self.twist is not None else math.sqrt(D1 * D2)
        eta = np.array([[T1 / 8, S / 4], [S / 4, T2 / 8]])
        xi = np.array([[D1 / 2, D12 / 2], [D12 / 2, D2 / 2]])
        (ve, vx), (te, tx) = ForceModel.lookup("variational").stiffness, ForceModel.of(force_model).stiffness
        return eta * ve / te, xi * vx / tx

    def material(self, force_model="variational", gamma: float = 0.0, scale: float = 1.0) -> Material:
        """The :class:`Material` of this fabric under ``force_model``; ``gamma`` the damping density (kg/(m^2 s));
        ``scale`` the section 3.1 factor: mu and gamma times ``scale`` and the weights too, so that the scaled sheet
        (its loads scaled with it) moves as the fabric does."""
        gamma = real("Fabric.material gamma", gamma, non_negative=True)
        scale = real("Fabric.material scale", scale, positive=True)
        eta, xi = self.weights(force_model)
        return Material(mu=scale * self.density, gamma=scale * gamma, eta=scale * eta, xi=scale * xi)
