r"""Shell benchmark problems shared by the tests and the ``shells`` study (issue 28).

The rolled cantilever (Simo and Fox 1989, CMAME 72, 267-304, section 6.1; Sze, Liu and Lo 2004, FEAD 40,
1551-1569, test 3.1): a strip of length L, clamped at a1 = 0, rolled by an end moment about its width
(:class:`deformable.EdgeMoment`) into a circle of radius EI / M; at M = 2 pi EI / L the free end comes back
to the clamp. With Koiter's energy at nu = 0 (no anticlastic coupling) the strip bends cylindrically, its
bending stiffness per unit width D = E h^3 / 12. Koiter's bending measure is B = n . r_11, the curvature times
the stretch of the axis, so the moment also stretches the axis by about kappa^2 D / (E h) (3e-6 here, h / R
= 0.006): the circle is the exact solution up to that.
"""

from __future__ import annotations

import numpy as np

import deformable as dm

__all__ = ["ROLL", "rolled_cantilever", "tip_gap"]

#: the rolled strip: length, width (m), Young's modulus (Pa), thickness (m); D = E h^3 / 12 = 1 N m
ROLL = dict(L=1.0, b=0.1, E=1.2e10, h=1e-3)


def rolled_cantilever(nodes: int, fraction: float = 1.0, width_nodes: int = 3) -> dm.Scene:
    """The strip on ``nodes`` x ``width_nodes`` nodes under ``fraction`` of the moment that closes the circle,
    m = fraction 2 pi D / L per unit width (N m/m)."""
    L, b, E, h = ROLL["L"], ROLL["b"], ROLL["E"], ROLL["h"]
    D = E * h**3 / 12
    unused = np.ones((2, 2))  # Koiter reads E, nu and h, not eta and xi
    return dm.Scene(dm.Sheet(size=(L, b), nodes=(nodes, width_nodes)), dm.Material(mu=1.0, eta=unused, xi=unused),
                    force_model=dm.Koiter(E=E, nu=0.0, h=h), constraints=[dm.Clamp("left")],
                    forces=[dm.EdgeMoment("right", m=fraction * 2 * np.pi * D / L)], name="rolled cantilever")


def tip_gap(model, X) -> float:
    """The distance of the free end's midpoint from the clamped end's, over L."""
    R = model.grid(X)
    return float(np.linalg.norm(R[-1].mean(axis=0) - R[0].mean(axis=0)) / ROLL["L"])
