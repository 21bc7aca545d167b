r"""Observed orders of convergence (docs/design.md, "Validation").

``p = log(e_h / e_{h/2}) / log 2`` between two levels, and the least-squares
slope of log e against log h over several (the order a convergence test
asserts); Richardson extrapolation and Roache's grid convergence index from
three grids (:func:`gci`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["fit_order", "pairwise_orders", "gci", "FS"]

#: Roache's safety factor of the grid convergence index for three grids
FS = 1.25


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


def gci(f1: float, f2: float, f3: float, r: float = 2.0, p_theory: float | None = None) -> dict:
    """Richardson extrapolation and Roache's grid convergence index from three grids, f1 the finest.

    Roache (1994), "Perspective: a method for uniform reporting of grid refinement studies":
    eps21 = f2 - f1, eps32 = f3 - f2, p = ln|eps32 / eps21| / ln r, phi_ext = f1 + (f1 - f2) / (r^p - 1),
    GCI_12 = Fs |eps21 / f1| / (r^p - 1), GCI_23 = Fs |eps32 / f2| / (r^p - 1), and the asymptotic-range
    ratio GCI_23 / (r^p GCI_12), near 1 in the asymptotic range. With p observed on the same three grids that
    ratio is f1 / f2 identically; with the theoretical order ``p_theory`` it is (f1 / f2) r^(p - p_theory),
    the informative check ("asymptotic_theory").

    Returns a dict: p, oscillatory (eps21 eps32 < 0) and, where defined, extrapolated, gci_12, gci_23,
    asymptotic, gci_12_theory, asymptotic_theory.
    """
    e21, e32 = f2 - f1, f3 - f2
    with np.errstate(divide="ignore", invalid="ignore"):
        p = float(np.log(abs(e32 / e21)) / np.log(r)) if e21 != 0 and e32 != 0 else np.nan
    out = {"p": p, "oscillatory": bool(e21 * e32 < 0)}
    if np.isfinite(p) and p > 0:
        out["extrapolated"] = f1 + (f1 - f2) / (r**p - 1)
        out["gci_12"] = FS * abs(e21 / f1) / (r**p - 1)
        out["gci_23"] = FS * abs(e32 / f2) / (r**p - 1)
        out["asymptotic"] = out["gci_23"] / (r**p * out["gci_12"])
    if p_theory is not None and e21 != 0:
        g12 = FS * abs(e21 / f1) / (r**p_theory - 1)
        g23 = FS * abs(e32 / f2) / (r**p_theory - 1)
        out["gci_12_theory"] = g12
        out["asymptotic_theory"] = g23 / (r**p_theory * g12)
    return out
