r"""The panel of section 3.2, Figs 1-2: a square sheet with its whole border held, blown out by a pressure.

Section 3.2 ("Micro Control") argues that the metric G and the curvature B of a sheet cannot change
independently: "a plane surface with its border held fixed (Fig. 1) ... it would be impossible to stretch the
surface (i.e. increase its area) without producing curvature effects (Fig. 2). There must be coherence between
stretching and bending. This coherence is stated by the equations (10)." Figure 1 is "A panel resistant to
stretching", Figure 2 the "Same panel of Fig. 1 with decreased stretching resistance".

``panel`` (Fig. 1)
    A 1 m square sheet, rest and start flat in the horizontal x-y plane, its four edges pinned (``Pin`` on
    every edge: positions held, the edge free to turn, a simply supported border), under a uniform follower
    pressure ``pressure`` along its normal r_1 x r_2 (+z at the start): :class:`~deformable.physics.forces.Pressure`,
    the potential -p V of the enclosed volume, exact because every edge is held. Stiff in stretching,
    eta = 2e4 N/m (E h = 8 eta = 1.6e5 N/m, paper-like): it stays nearly flat.
``panel-soft`` (Fig. 2)
    The same panel with eta = 20 N/m (E h = 160 N/m, the cloth scenes' fabric), 1000 times softer in stretching:
    it stretches and, its border held, can only do so by bulging out of its plane.

Why a pressure: the paper does not say what loads its panel; a load across the plane that stays normal to the
sheet is the one a membrane carries by its tension times its curvature alone (Laplace's law, below), and the
project has it. A dead load across the plane (a ``BodyForce`` along z) would differ from it to first order in
the slope (tests/deformable/physics/test_pressure.py), which reaches 0.5 at the soft panel's border. The scene
is weightless by default (``g = 0``) so that the pressure is the only load; ``g = 9.81`` adds the weight
mu g = 2 N/m^2 along -z, against the pressure.

What it shows, measured (tests/deformable/scenes/test_panel.py). The border bounds a fixed plane square, so a
flat sheet cannot change its area: any increase of the area int sqrt(det G) da over 1 m^2 comes with a curved
surface. At equilibrium the membrane's normal balance is Laplace's law, in the variational model's terms
(energy (13), W = sum_ij eta_ij (G_ij - delta_ij)^2, bending terms of order xi w / L^4 left out)

    sum_ij 4 eta_ij (G_ij - delta_ij) B_ij + p sqrt(det G) = 0,

the stretching (G - I) times the curvature B carries the pressure: the stiff panel carries it with a large
tension and a small curvature, the soft one with a small tension and a large curvature. The membrane's centre
deflection scales as a (p a / (E h))^(1/3), a = L / 2 (Foppl-Hencky membrane theory: the tension E h w^2 / a^2
times the curvature w / a^2 carries p), the area increase as its square: 1000 times the stretching resistance
is 10 times less deflection and 100 times less area increase.

Measured, the equilibria (``deformable.equilibrium`` from :func:`start`) on 17 x 17 nodes (FD; FE 16 x 16
elements), G and B at the nodes (:func:`validation.panel.node_tensors`, :func:`validation.panel.measure`), FD / FE:

==============================  ===================  ===================
                                panel (Fig. 1)       panel-soft (Fig. 2)
==============================  ===================  ===================
centre deflection (m)           0.0124 / 0.0124      0.1258 / 0.1259
  membrane estimate (m)         0.0126               0.1263
area increase                   0.052 % / 0.052 %    5.36 % / 5.35 %
fibre stretch at the centre     3.9e-4 / 3.9e-4      0.041 / 0.041
mean curvature H, centre (1/m)  -0.079 / -0.079      -0.756 / -0.751
det B / det G, centre (1/m^2)   0.0063 / 0.0062      0.571 / 0.564
Laplace residual, inner half    0.003 / 0.008        0.004 / 0.008
==============================  ===================  ===================

The paper's compatibility test (eq. (10), :func:`deformable.geometry.check_compatibility`, tolerance 0.05) on
these states, which are surfaces by construction, measures its own differencing error; it reads nearly the same
on both panels (their shapes nearly scale into each other), mismatch_relative at h = 1/16 and at 2h (every other
node), FD / FE:

- default margin (2 rows): h 0.44 / 0.54 (stiff), 0.37 / 0.35 (soft), 2h 0.26 / 0.26 and 0.26 / 0.27, all
  INCOMPATIBLE: the rows next to the border, where the pinned membrane's fields are steep (its corners), do
  not converge (FD 33 x 33: 0.41 and 0.13);
- the inner half (margin a quarter of the side): h 0.070 / 0.087 (stiff), 0.070 / 0.093 (soft), 2h 0.26 /
  0.26, a fall by 3.7 (FD) and 2.9 (FE), second order on FD; on FD 33 x 33 0.018, *compatible*, Gauss
  residual (gauss_relative) 0.009.

So the test cannot tell the stiff panel from the soft one (both are surfaces); what ties their stretching to their
curvature is the equilibrium, Laplace's law above.

Dynamics (``deformable run panel``): the pressure is applied at t = 0 to the flat sheet; the damping gamma = 1
kg/(m^2 s) settles it: the soft panel's centre is within 4e-5 of its equilibrium after 1 s (FD 17 x 17, dt =
10 ms), the stiff one's within 1e-9; t_end = 2 s. ``deformable run panel --grid 16x16``: 3 s wall time.
The picture docs/scenes/panel.png: :func:`main` (FD 33 x 33).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..geometry.sheet import Sheet
from ..physics.forces import Gravity, Pressure
from ..scene.constraints import Pin
from ..scene.scene import Scene
from .config import SceneConfig
from .shapes import HORIZONTAL

__all__ = ["PanelConfig", "SoftPanelConfig", "BORDER", "membrane_deflection", "start"]

#: the panel's border: all four edges (section 3.2, "a plane surface with its border held fixed")
BORDER = ("left", "right", "bottom", "top")


@dataclass(frozen=True, kw_only=True)
class PanelConfig(SceneConfig):
    """The panel resistant to stretching (section 3.2, Fig. 1): a 1 m square sheet, flat in the x-y plane, its
    whole border pinned, under a follower pressure along its normal (module docstring).

    mu = 0.2 kg/m^2, gamma = 1 kg/(m^2 s), eta = 2e4 N/m (E h = 1.6e5 N/m), xi = 1e-4 N m (D = 2e-4 N m), full
    tensors, weightless (g = 0), pressure 10 Pa, on 17 x 17 nodes.

    Parameters
    ----------
    pressure : float
        The follower pressure p on the sheet, along r_1 x r_2 (+z at the start) (Pa = N/m^2); ``scale`` multiplies
        it (section 3.1). 10 Pa: the soft panel bulges by an eighth of its side.
    """

    name = "panel"
    rank = 9
    summary = "square panel, border held, blown out by a pressure: stiff in stretching, stays flat (Fig. 1)"
    nodes: tuple = (17, 17)
    gamma: float = 1.0
    eta: float = 2e4
    xi: float = 1e-4
    g: float = 0.0
    t_end: float = 2.0
    dt: float = 1e-2

    pressure: float = 10.0

    def build(self) -> Scene:
        """The Scene of this config."""
        sheet = Sheet(size=self.size, nodes=self.nodes, rest=HORIZONTAL)
        forces = [Pressure(self.scale * self.pressure)]
        if self.g:
            forces.append(Gravity(self.g))
        return Scene(sheet, self.material(), forces=forces, constraints=[Pin(list(BORDER))], **self.scene_kwargs())


@dataclass(frozen=True, kw_only=True)
class SoftPanelConfig(PanelConfig):
    """Fig. 2: the panel of Fig. 1 with decreased stretching resistance, eta = 20 N/m (E h = 160 N/m), 1000 times
    softer: it stretches, and bulges (module docstring)."""

    name = "panel-soft"
    rank = 10
    summary = "the panel with 1000 times less stretching resistance: stretches and bulges (Fig. 2)"
    eta: float = 20.0


def membrane_deflection(cfg: PanelConfig) -> float:
    """An estimate of the centre deflection of the square membrane under the pressure (m), Newton's start
    (:func:`start`): Foppl-Hencky's scale a (p a / E h)^(1/3), a the half side L1 / 2, E h = 8 eta_11 (the
    variational model's tensile stiffness, full tensors), times 0.8, a prefactor fitted to this scene's equilibria
    (measured 0.79 on FD and FE 17 x 17 nodes), not a literature value. Bending is left out: the plate alone would
    deflect 0.00406 p L^4 / D = 200 m with D = 2 xi (simply supported: Navier's double sine series, summed), so
    at these loads the membrane carries it."""
    a, Eh = 0.5 * cfg.size[0], 8.0 * cfg.eta
    p = cfg.scale * cfg.pressure
    return math.copysign(0.8 * a * (abs(p) * a / Eh) ** (1.0 / 3.0), p) if Eh > 0 else math.inf


def start(cfg: PanelConfig, model) -> np.ndarray:
    """A start for :func:`deformable.equilibrium`: the flat panel raised by w0 sin(pi a1 / L1) sin(pi a2 / L2),
    w0 = :func:`membrane_deflection`, the border where it is (X (ndof, 3), the model's discretisation).

    From the flat start the first Newton step meets no membrane stiffness across the plane (a flat sheet has
    none, only bending) and goes far (1e7 m on 17 x 17 nodes at eta = 2e4 N/m); the stiff panel's solve then
    stopped at 58 times the load a node (the tolerance follows the round-off floor of the Newton matrix at its
    iterates, :mod:`deformable.solve.newton`). From this start it converges to the load's 1e-10.
    """
    L1, L2 = cfg.size
    w0 = membrane_deflection(cfg)

    def bulge(a1, a2):
        return np.stack([a1, a2, w0 * np.sin(np.pi * a1 / L1) * np.sin(np.pi * a2 / L2)], axis=-1)

    return model.discretize(bulge)
