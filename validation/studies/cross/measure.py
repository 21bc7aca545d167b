r"""What the cross study measures on a solution: r, G and B at fixed points, and two norms of a difference.

The points are the third points of the problem's coarsest grid: ``(i + 1/3) h`` and ``(i + 2/3) h`` in
each direction of every coarsest cell, the same points at every level. Refining by halves, they fall at
a third or two thirds of a cell of every finer grid too (2^k / 3 has the fractional part 1/3 or 2/3), so
each backend is measured at the same relative position in its cells at every level, and never at a node
(FE values and first derivatives are degrees of freedom there and superconverge). The position matters:
the second derivatives of a bicubic interpolant converge at O(h^3) at the two-point Gauss points and
O(h^2) elsewhere, so points that move relative to the cells (e.g. Gauss points of the coarsest cells)
bias the observed orders (measured: FE's B "converged" at 2.6 through them). FD is measured by the
bilinear interpolation of its node values that :meth:`~deformable.backends.Backend.sample` defines
(second order at any point).

- the L2 norm over the sheet, ``(sum_p w_p |f(a_p) - g(a_p)|^2)^(1/2)``, each point weighing a quarter of
  its cell (a second-order rule for the squared difference of smooth fields);
- the max over the interior: the largest ``|f - g|`` at the points at least 1/8 of the sheet's side from
  every edge (:data:`MARGIN`), where the layers and the singular corners of held edges do not reach (the
  clamped corner's singular exponent 1.74 held FE's G there at order 2.6 against 3 inside).

Tensors G and B are compared component by component (|.| the Frobenius norm over (i, j)); positions as
3-vectors.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Probe", "QUANTITIES", "MARGIN", "sample", "difference"]

#: the compared quantities, in report order
QUANTITIES = ("r", "G", "B")
#: the interior: points at least this fraction of each side from the edges
MARGIN = 1 / 8


@dataclass(frozen=True)
class Probe:
    """Fixed points (P, 2), their weights (P,) and the interior mask (P,) of a sheet (module docstring)."""

    points: np.ndarray
    weights: np.ndarray
    interior: np.ndarray

    @classmethod
    def on_cells(cls, size: tuple[float, float], cells: tuple[int, int]) -> "Probe":
        """The third points of each of the ``cells`` (c1, c2) of the rectangle ``size`` (L1, L2)."""
        axes, weights, inner = [], [], []
        for L, c in zip(size, cells):
            h = L / c
            a = ((np.arange(c)[:, None] + np.array([1.0, 2.0])[None] / 3) * h).ravel()
            axes.append(a)
            weights.append(np.full(2 * c, 0.5 * h))
            inner.append((a >= MARGIN * L) & (a <= (1 - MARGIN) * L))
        A1, A2 = np.meshgrid(*axes, indexing="ij")
        return cls(np.stack([A1.ravel(), A2.ravel()], axis=1), np.outer(*weights).ravel(),
                   np.outer(*inner).ravel())


def sample(model, X, probe: Probe) -> dict[str, np.ndarray]:
    """r (P, 3), G (P, 4), B (P, 4) of a solution at the probe's points."""
    s = model.sample(X, probe.points)
    return {"r": s.r, "G": s.G.reshape(-1, 4), "B": s.B.reshape(-1, 4)}


def difference(f: np.ndarray, g: np.ndarray, probe: Probe) -> tuple[float, float]:
    """(L2 over the sheet, max over the interior) of f - g, each (P, components)."""
    d = np.linalg.norm(np.asarray(f) - np.asarray(g), axis=-1)
    return float(np.sqrt(np.sum(probe.weights * d**2))), float(np.max(d[probe.interior]))
