r"""A manufactured membrane problem with weights that vary over the sheet (issue 28, point 2).

The method of manufactured solutions (Roache 2002, "Code verification by the method of manufactured
solutions", J. Fluids Eng. 124, 4-10): choose the solution, compute the load that makes it exact, and
measure how fast a discretisation recovers it. Here the unit square, flat at rest (G0 = I), all four
edges pinned at the chosen shape

    r*(a) = (1.25 a1 + A sin(pi a1) sin^2(pi a2),  1.25 a2 + A/2 sin(2 pi a1) sin(pi a2),
             W sin(pi a1) sin(pi a2)),          A = 0.05, W = 0.15,

stretched everywhere (|r*_i|^2 > 1: a membrane in tension, so the problem is well posed without bending),
and the full weight tensor eta_ij(a) of eq. (13) varying smoothly in both directions, shear included
(:func:`eta`). Eq. (13)'s membrane energy sum_ij eta_ij (G_ij - G0_ij)^2 has the first variation
int sum_ij 4 eta_ij s_ij r_i . dr_j (s = G - G0, eta and s symmetric), so the body load that makes r*
the equilibrium is

    f = -sum_j d_j P_j,    P_j = sum_i 4 eta_ij s_ij r*_i        (N/m^2; scene units)

with the flux P from the analytic derivatives of r* and its divergence by a fourth-order central
difference of step 1e-3 (error about 1e-12 of f, far below any grid's error). The measured error is the
largest node distance to r*. FE (bicubic Hermite) recovers r* at order about 4, which checks the load.
"""

from __future__ import annotations

import numpy as np

import deformable as dm

__all__ = ["A", "W", "eta", "load", "node_error", "scene", "shape"]

A, W = 0.05, 0.15
_STRETCH = 1.25
_STEP = 1e-3


def shape(a1, a2) -> np.ndarray:
    """r*(a1, a2), (..., 3) in m."""
    p = np.pi
    return np.stack([_STRETCH * a1 + A * np.sin(p * a1) * np.sin(p * a2) ** 2,
                     _STRETCH * a2 + A / 2 * np.sin(2 * p * a1) * np.sin(p * a2),
                     W * np.sin(p * a1) * np.sin(p * a2)], axis=-1)


def _tangents(a1, a2) -> tuple[np.ndarray, np.ndarray]:
    """r*_1, r*_2, each (..., 3), analytic."""
    p = np.pi
    s1, c1, s2, c2 = np.sin(p * a1), np.cos(p * a1), np.sin(p * a2), np.cos(p * a2)
    r1 = np.stack([_STRETCH + A * p * c1 * s2**2, A * p * np.cos(2 * p * a1) * s2, W * p * c1 * s2], axis=-1)
    r2 = np.stack([2 * A * p * s1 * s2 * c2, _STRETCH + A / 2 * p * np.sin(2 * p * a1) * c2, W * p * s1 * c2],
                  axis=-1)
    return r1, r2


def eta(a1, a2) -> np.ndarray:
    """The stretching weights eta_ij(a), (..., 2, 2) in N/m: positive definite, varying in both directions."""
    e11 = 1.0 + 0.5 * np.sin(1.3 * a1 + 0.7 * a2) + 0.3 * a1 * a2
    e22 = 1.2 + 0.4 * np.cos(0.9 * a1 - 1.1 * a2)
    e12 = 0.6 + 0.2 * np.sin(2.0 * a1) * np.cos(a2)
    return np.stack([np.stack([e11, e12], -1), np.stack([e12, e22], -1)], -2)


def _flux(a1, a2) -> list[np.ndarray]:
    """P_j = sum_i 4 eta_ij s_ij r*_i for j = 1, 2, each (..., 3)."""
    r = _tangents(a1, a2)
    e = eta(a1, a2)
    return [sum(4 * e[..., i, j, None] * (np.sum(r[i] * r[j], -1) - float(i == j))[..., None] * r[i]
                for i in range(2)) for j in range(2)]


def load(a1, a2, t: float = 0.0) -> np.ndarray:
    """The body load f = -div P that makes r* the equilibrium, (..., 3) in N/m^2 (``BodyForce``'s signature)."""
    d = _STEP

    def diff(j):  # d_j P_j, fourth-order central difference
        e = np.array([d, 0.0]) if j == 0 else np.array([0.0, d])
        P = [_flux(a1 + k * e[0], a2 + k * e[1])[j] for k in (-2, -1, 1, 2)]
        return (P[0] - 8 * P[1] + 8 * P[2] - P[3]) / (12 * d)

    return -(diff(0) + diff(1))


def scene(nodes: int, weights: str = "callable") -> dm.Scene:
    """The problem on an n x n node grid; ``weights`` "callable" (evaluated where each backend's terms
    stand) or "nodes" (an array of the node values, carried there by the backend)."""
    sheet = dm.Sheet(size=(1.0, 1.0), nodes=(nodes, nodes), initial=shape)
    if weights == "callable":
        w = eta
    elif weights == "nodes":
        w = np.moveaxis(eta(*sheet.coordinates()), (-2, -1), (0, 1))
    else:
        raise ValueError(f"weights must be 'callable' or 'nodes', got {weights!r}")
    return dm.Scene(sheet, dm.Material(mu=1.0, eta=w, xi=0.0), forces=[dm.BodyForce(load)],
                    constraints=[dm.Pin(["left", "right", "bottom", "top"])], force_model="variational",
                    name="manufactured membrane")


def node_error(model, X) -> float:
    """The largest distance of a node from r* (m)."""
    a1, a2 = model.scene.sheet.coordinates()
    return float(np.max(np.linalg.norm(model.grid(X) - shape(a1, a2), axis=-1)))
