"""Closed-form plate solutions the studies, tests and examples compare with.

:func:`navier_centre`: the centre deflection of the simply supported rectangular Kirchhoff plate,
``D (w_1111 + 2 w_1122 + w_2222) = q``, by Navier's double sine series (Timoshenko and Woinowsky-Krieger
1959, *Theory of Plates and Shells*, section 30), summed here.
"""

from __future__ import annotations

import numpy as np

__all__ = ["navier_centre"]


def navier_centre(D: float, q: float, a: float = 1.0, b: float = 1.0, terms: int = 2001) -> float:
    """Centre deflection (m) of the simply supported a x b plate of bending stiffness D (N m) under the uniform
    load q (N/m^2): ``16 q / (pi^6 D) sum_{m, n odd} sin(m pi / 2) sin(n pi / 2) / (m n (m^2/a^2 + n^2/b^2)^2)``
    over m, n below ``terms``."""
    j = np.arange(1, terms, 2, dtype=float)
    sj = np.where((j // 2) % 2 == 0, 1.0, -1.0)  # sin(j pi / 2) for odd j
    M, N = np.meshgrid(j, j, indexing="ij")
    return float(16 * q / (np.pi**6 * D) * np.sum(np.outer(sj, sj) / (M * N * (M**2 / a**2 + N**2 / b**2) ** 2)))
