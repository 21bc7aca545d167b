r"""Material parameters of eq. (11), (13) and (15).

``mu`` (mass density) and ``gamma`` (damping density) of the equation of
motion (11); the elasticity weights ``eta_ij`` (stretching) and ``xi_ij``
(bending) of the energy (13); and, for the "frozen" force model of section 3.2
(the controlled-continuity spline), the weights ``alpha_ij`` and ``beta_ij``
given directly instead of through eq. (15).

Every weight may be

- a scalar ``s``: the tensor diag(s, s), so ``w_12 = w_21 = 0`` (the paper's
  choice, section 3.2, "eta_12 = eta_21 = xi_12 = xi_21 = 0");
- a symmetric 2 x 2 array: the same tensor at every point;
- an (M, N) array: a scalar field on the node grid (diagonal tensor);
- a (2, 2, M, N) array: a symmetric tensor field on the node grid.

``mu`` and ``gamma`` are a scalar or an (M, N) field. Units are those of the
scene (SI in the shipped scenes): mu in kg/m^2, gamma in kg/(m^2 s), eta in
N/m (per unit of G, which is dimensionless), xi in N m (per unit of B, 1/m).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..checks import finite_array
from ..errors import InputError

__all__ = ["Material", "TENSORS"]

#: the weight tensors of eq. (13) and (15) (a force model reads them at the backend's points)
TENSORS = ("eta", "xi", "alpha", "beta")
_FIELDS = ("mu", "gamma")


def _as_array(name: str, value) -> np.ndarray:
    return finite_array(f"Material.{name}", value)


@dataclass(frozen=True, kw_only=True)
class Material:
    """Material of an elastic sheet; see the module docstring for shapes and units.

    Examples
    --------
    >>> Material(mu=1.0, gamma=0.1, eta=100.0, xi=0.0)       # doctest: +ELLIPSIS
    Material(mu=1.0, gamma=0.1, eta=100.0, xi=0.0, ...)
    """

    mu: float | np.ndarray = 1.0
    gamma: float | np.ndarray = 0.0
    eta: float | np.ndarray = 0.0
    xi: float | np.ndarray = 0.0
    alpha: float | np.ndarray | None = None
    beta: float | np.ndarray | None = None

    def __post_init__(self):
        for name in _FIELDS + TENSORS:
            value = getattr(self, name)
            if value is None and name in ("alpha", "beta"):
                continue
            arr = _as_array(name, value)
            if arr.ndim == 0:
                object.__setattr__(self, name, float(arr))
            else:
                arr.setflags(write=False)
                object.__setattr__(self, name, arr)
        mu = np.asarray(self.mu)
        if np.any(mu <= 0):
            raise InputError(f"Material.mu must be positive, got {np.min(mu)!r}", field="Material.mu", value=self.mu)
        gamma = np.asarray(self.gamma)
        if np.any(gamma < 0):
            raise InputError(f"Material.gamma must be non-negative, got {np.min(gamma)!r}", field="Material.gamma",
                             value=self.gamma)
        for name in ("eta", "xi"):
            w = np.asarray(getattr(self, name))
            if np.any(w < 0):
                raise InputError(f"Material.{name} must be non-negative (a weight of the energy (13)), got "
                                 f"{np.min(w)!r}", field=f"Material.{name}", value=getattr(self, name))
        for name in TENSORS:
            w = getattr(self, name)
            if w is None:
                continue
            w = np.asarray(w)
            if w.ndim in (2, 4) and w.shape[:2] == (2, 2) and not np.allclose(w[0, 1], w[1, 0], rtol=0, atol=0):
                raise InputError(f"Material.{name} must be symmetric: {name}_12 != {name}_21", field=f"Material.{name}",
                                 value=getattr(self, name))

    def field(self, name: str, nodes: tuple[int, int]) -> np.ndarray:
        """``mu`` or ``gamma`` as an (M, N) field on a node grid of shape ``nodes``."""
        value = np.asarray(getattr(self, name))
        if value.ndim == 0:
            return np.full(nodes, float(value))
        if value.shape == tuple(nodes):
            return value
        raise InputError(f"Material.{name} has shape {value.shape}, expected a scalar or {tuple(nodes)}")

    def tensor(self, name: str, nodes: tuple[int, int]) -> np.ndarray:
        """Weight tensor ``name`` (eta, xi, alpha, beta) as a (2, 2, M, N) field."""
        value = getattr(self, name)
        M, N = nodes
        if value is None:
            return np.zeros((2, 2, M, N))
        value = np.asarray(value)
        out = np.zeros((2, 2, M, N))
        if value.ndim == 0 or value.shape == (M, N):
            out[0, 0] = out[1, 1] = value
        elif value.shape == (2, 2):
            out[...] = value[:, :, None, None]
        elif value.shape == (2, 2, M, N):
            out[...] = value
        else:
            raise InputError(
                f"Material.{name} has shape {value.shape}, expected a scalar, (2, 2), "
                f"({M}, {N}) or (2, 2, {M}, {N})"
            )
        return out

    def check(self, nodes: tuple[int, int]) -> None:
        """Raise ValueError if any per-node array does not fit a node grid of shape ``nodes``."""
        for name in _FIELDS:
            self.field(name, nodes)
        for name in TENSORS:
            self.tensor(name, nodes)

    def replace(self, **changes) -> Material:
        """A copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)
