r"""Shell benchmark problems shared by the tests and the ``shells`` study (issue 28).

The rolled cantilever (Simo and Fox 1989, CMAME 72, 267-304, section 6.1; Sze, Liu and Lo 2004, FEAD 40,
1551-1569, test 3.1): a strip of length L, clamped at a1 = 0, rolled by an end moment about its width
(:class:`deformable.EdgeMoment`) into a circle of radius EI / M; at M = 2 pi EI / L the free end comes back
to the clamp. With Koiter's energy at nu = 0 (no anticlastic coupling) the strip bends cylindrically, its
bending stiffness per unit width D = E h^3 / 12. Koiter's bending measure is B = n . r_11, the curvature times
the stretch of the axis, so the moment also stretches the axis by about kappa^2 D / (E h) (3e-6 here, h / R
= 0.006): the circle is the exact solution up to that.

The buckled column: the same strip clamped at a1 = 0 under an axial compressive edge load at its free end,
twice Euler's load P_cr = pi^2 EI / (4 L^2) at load factor 1. Its post-buckling path is the elastica
(Timoshenko and Gere 1961, *Theory of Elastic Stability*, section 2.7): with k = sin(theta_tip / 2) and K the
complete elliptic integral of the first kind, P / P_cr = 4 K(k)^2 / pi^2 and the tip's lateral deflection
delta / L = 2 k / K(k) (:func:`elastica_load`).

The shallow arch: the strip with the rest shape z = H sin(pi a1 / L), pinned (hinged) at both ends, under a
line load across its middle; it snaps through a limit point (the test of the arc-length path).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipk

import deformable as dm

__all__ = ["ROLL", "column", "elastica_load", "rolled_cantilever", "shallow_arch", "tip_gap"]

#: the rolled strip: length, width (m), Young's modulus (Pa), thickness (m); D = E h^3 / 12 = 1 N m
ROLL = dict(L=1.0, b=0.1, E=1.2e10, h=1e-3)


def rolled_cantilever(nodes: int, fraction: float = 1.0, width_nodes: int = 3) -> dm.Scene:
    """The strip on ``nodes`` x ``width_nodes`` nodes under ``fraction`` of the moment that closes the circle,
    m = fraction 2 pi D / L per unit width (N m/m)."""
    D = ROLL["E"] * ROLL["h"] ** 3 / 12
    return _strip(nodes, width_nodes, constraints=[dm.Clamp("left")],
                  forces=[dm.EdgeMoment("right", m=fraction * 2 * np.pi * D / ROLL["L"])])


def tip_gap(model, X) -> float:
    """The distance of the free end's midpoint from the clamped end's, over L."""
    R = model.grid(X)
    return float(np.linalg.norm(R[-1].mean(axis=0) - R[0].mean(axis=0)) / ROLL["L"])


def _strip(nodes, width_nodes=3, rest=None, constraints=(), forces=()) -> dm.Scene:
    L, b, E, h = ROLL["L"], ROLL["b"], ROLL["E"], ROLL["h"]
    unused = np.ones((2, 2))  # Koiter reads E, nu and h, not eta and xi
    return dm.Scene(dm.Sheet(size=(L, b), nodes=(nodes, width_nodes), rest=rest),
                    dm.Material(mu=1.0, eta=unused, xi=unused), force_model=dm.Koiter(E=E, nu=0.0, h=h),
                    constraints=list(constraints), forces=list(forces))


def euler_load() -> float:
    """P_cr = pi^2 EI / (4 L^2) of the clamped-free strip (N), EI = E h^3 b / 12."""
    L, b, E, h = ROLL["L"], ROLL["b"], ROLL["E"], ROLL["h"]
    return float(np.pi**2 * E * h**3 * b / 12 / (4 * L**2))


def column(nodes: int) -> dm.Scene:
    """The clamped strip under 2 P_cr of axial compression at its free end at load factor 1 (module docstring)."""
    b = ROLL["b"]
    return _strip(nodes, constraints=[dm.Clamp("left")], forces=[dm.EdgeLoad("right", f=(-2 * euler_load() / b, 0, 0))])


#: the elastica's largest tip deflection over L (reached at m = k^2 = 0.7013): a deflection has one load below it
_PEAK_M = 0.7013


def elastica_load(deflection: float) -> float:
    """P / P_cr on the elastica at the tip's lateral deflection delta / L (module docstring), for 0 < delta / L
    below the peak 0.806."""
    m = brentq(lambda m: 2 * np.sqrt(m) / ellipk(m) - deflection, 1e-14, _PEAK_M)
    return float(4 * ellipk(m) ** 2 / np.pi**2)


def shallow_arch(nodes: int, rise: float = 1.5e-3) -> dm.Scene:
    """The hinged shallow arch z = rise sin(pi a1 / L) under a line load of peak 1 N/m across its middle
    (a Gaussian of width L / 20) at load factor 1 (module docstring)."""
    L = ROLL["L"]

    def load(a1, a2, t):
        return np.stack([0 * a1, 0 * a1, -np.exp(-(((a1 - L / 2) / (0.05 * L)) ** 2))], axis=-1)

    return _strip(nodes, rest=lambda a1, a2: np.stack([a1, a2, rise * np.sin(np.pi * a1 / L)], -1),
                  constraints=[dm.Pin(["left", "right"])], forces=[dm.EdgeLoad("top", f=load)])
