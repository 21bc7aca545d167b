r"""Observed orders of convergence (docs/design.md, "Validation").

``p = log(e_h / e_{h/2}) / log 2`` between two levels, and the least-squares
slope of log e against log h over several (the order a convergence test
asserts).
"""

from __future__ import annotations

import numpy as np

__all__ = ["fit_order", "pairwise_orders"]


def fit_order(h, e) -> float:
    """Least-squares slope of log e against log h over all levels (at least two)."""
    h, e = np.asarray(h, float), np.asarray(e, float)
    if h.size < 2 or h.shape != e.shape:
        raise ValueError(f"need matching arrays of at least two levels, got {h.shape} and {e.shape}")
    if np.any(e <= 0) or np.any(h <= 0):
        raise ValueError("orders need positive spacings and errors")
    return float(np.polyfit(np.log(h), np.log(e), 1)[0])


def pairwise_orders(h, e) -> np.ndarray:
    """Order between consecutive levels, shape (levels - 1,)."""
    h, e = np.asarray(h, float), np.asarray(e, float)
    return np.log(e[:-1] / e[1:]) / np.log(h[:-1] / h[1:])
