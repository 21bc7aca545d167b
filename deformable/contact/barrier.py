"""The barrier of Incremental Potential Contact and IPC's friction mollifier, as functions of a distance.

    b(d) = -(d - dhat)^2 ln(d / dhat)   for 0 < d < dhat,   0 for d >= dhat

(Li et al. 2020, "Incremental Potential Contact", ACM TOG 39(4), eq. (6)), its first and second derivatives, and the
friction mollifier f0 of IPC's section 5 with the two coefficients of its gradient and Hessian. All are pointwise:
arrays of distances (m) in, arrays out. The potential built from them is :mod:`deformable.contact.potential`.
"""

from __future__ import annotations

import numpy as np

__all__ = ["barrier", "barrier_derivative", "barrier_second", "mollifier"]


# -- the barrier and the friction mollifier -----------------------------------------------
def barrier(d: np.ndarray, dhat: float) -> np.ndarray:
    """b(d) = -(d - dhat)^2 ln(d / dhat) for d < dhat, 0 beyond, +inf for d <= 0 (m^2)."""
    d = np.asarray(d, float)
    out = np.zeros_like(d)
    on = d < dhat
    with np.errstate(divide="ignore", invalid="ignore"):
        out[on] = np.where(d[on] > 0, -(d[on] - dhat) ** 2 * np.log(d[on] / dhat), np.inf)
    return out


def barrier_derivative(d: np.ndarray, dhat: float) -> np.ndarray:
    """b'(d) = (dhat - d) (2 ln(d / dhat) - dhat / d + 1) for 0 < d < dhat, 0 beyond (m)."""
    d = np.asarray(d, float)
    out = np.zeros_like(d)
    on = d < dhat
    x = d[on]
    out[on] = (dhat - x) * (2 * np.log(x / dhat) - dhat / x + 1)
    return out


def barrier_second(d: np.ndarray, dhat: float) -> np.ndarray:
    """b''(d) = (dhat / d + 2) dhat / d - 2 ln(d / dhat) - 3 for 0 < d < dhat, 0 beyond (dimensionless)."""
    d = np.asarray(d, float)
    out = np.zeros_like(d)
    on = d < dhat
    r = dhat / d[on]
    out[on] = (r + 2) * r + 2 * np.log(r) - 3
    return out


def mollifier(y: np.ndarray, eps: float):
    """IPC's friction mollifier at tangential displacements y >= 0 (m), eps = eps_v dt (m).

    Returns f0(y) (m), f1(y) / y (1/m) and (f1'(y) - f1(y) / y) / y^2 (1/m^3), each (P,):
    the potential, and the two coefficients of its gradient ``f1/y u`` and Hessian
    ``(f1/y) I + c2 u u^T`` in the tangential displacement u, |u| = y.
    """
    y = np.asarray(y, float)
    slow = y < eps
    f0 = np.where(slow, y * y * (1 - y / (3 * eps)) / eps + eps / 3, y)
    with np.errstate(divide="ignore"):
        f1y = np.where(slow, (2 - y / eps) / eps, 1 / np.where(slow, 1.0, y))
        c2 = np.where(slow, -1 / (eps * eps * np.where(y > 0, y, 1.0)), -1 / np.where(slow, 1.0, y) ** 3)
    c2 = np.where(y > 0, c2, 0.0)
    return f0, f1y, c2


