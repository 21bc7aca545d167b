r"""Material parameters of eq. (11), (13) and (15).

``mu`` (mass density) and ``gamma`` (damping density) of the equation of motion (11); the elasticity weights
``eta_ij`` (stretching) and ``xi_ij`` (bending) of the energy (13); and, for the "frozen" force model of section 3.2
(the controlled-continuity spline), the weights ``alpha_ij`` and ``beta_ij`` given directly instead of through eq.
(15).

Every weight may be

- a scalar ``s``: the tensor diag(s, s), so ``w_12 = w_21 = 0`` (the paper's choice, section 3.2, "eta_12 = eta_21 =
  xi_12 = xi_21 = 0");
- a symmetric 2 x 2 array: the same tensor at every point;
- an (M, N) array: a scalar field on the node grid (diagonal tensor);
- a (2, 2, M, N) array: a symmetric tensor field on the node grid;
- a callable ``f(a1, a2)`` of the parameter coordinates (arrays of one shape S, in m), returning an array of shape S
  (a scalar field: diagonal tensor) or S + (2, 2) (components last, as ``Scene.rest_metric``'s callable). A backend
  evaluates it where its terms live (:meth:`Material.tensor_at`): FD at the centre of each difference term
  (:func:`fdmodel.operators.centred_tensor`), FE at the Gauss points. Node arrays are carried to the same points
  (FD: the mean of the nodes around a centre; FE: bilinear interpolation), so that a weight varying over the sheet
  (a curved parameterisation, a graded fabric) keeps FD second order. A callable is checked (finite, sign, symmetry)
  where it is evaluated; it also keeps its meaning on every grid, where a node array fits one.

``mu`` and ``gamma`` are a scalar, an (M, N) field or a callable of shape S (lumped at the nodes on FD, at the Gauss
points on FE). Units are those of the scene (SI in the shipped scenes): mu in kg/m^2, gamma in kg/(m^2 s), eta in
N/m (per unit of G, which is dimensionless), xi in N m (per unit of B, 1/m).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
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


def _evaluate(name: str, f, a1, a2) -> np.ndarray:
    """A callable weight at points (a1, a2) of shape S: its values, components first: (2, 2, *S) for a tensor, S for
    a scalar field."""
    a1, a2 = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
    try:
        value = f(a1, a2)
    except Exception as err:  # noqa: BLE001 (the user's function: say which field it is)
        raise InputError(f"Material.{name}: the callable failed at the sheet's points: {type(err).__name__}: {err}",
                         field=f"Material.{name}", value=f) from None
    value = _as_array(name, value)
    S = a1.shape
    if value.shape == S + (2, 2) and value.ndim > 0:
        return np.moveaxis(value, (-2, -1), (0, 1))
    if value.ndim == 0 or value.shape == S:
        return np.broadcast_to(value, S)
    raise InputError(f"Material.{name}: the callable returned shape {value.shape}, expected {S} or {S + (2, 2)}",
                     field=f"Material.{name}", value=f)


@dataclass(frozen=True, kw_only=True)
class Material:
    """Material of an elastic sheet; see the module docstring for shapes and units.

    Examples
    --------
    >>> Material(mu=1.0, gamma=0.1, eta=100.0, xi=0.0)       # doctest: +ELLIPSIS
    Material(mu=1.0, gamma=0.1, eta=100.0, xi=0.0, ...)
    """

    mu: float | np.ndarray | Callable = 1.0
    gamma: float | np.ndarray | Callable = 0.0
    eta: float | np.ndarray | Callable = 0.0
    xi: float | np.ndarray | Callable = 0.0
    alpha: float | np.ndarray | Callable | None = None
    beta: float | np.ndarray | Callable | None = None

    def __post_init__(self):
        for name in _FIELDS + TENSORS:
            value = getattr(self, name)
            if value is None and name in ("alpha", "beta"):
                continue
            if callable(value):
                continue  # checked where a backend evaluates it (tensor_at, field_at)
            arr = _as_array(name, value)
            if arr.ndim == 0:
                object.__setattr__(self, name, float(arr))
            else:
                arr.setflags(write=False)
                object.__setattr__(self, name, arr)
        self._validate({name: getattr(self, name) for name in _FIELDS + TENSORS if not callable(getattr(self, name))})

    def _validate(self, values: dict) -> None:
        """InputError naming the field unless each value (a name's array, node or point values) is admissible."""
        if "mu" in values and np.any(np.asarray(values["mu"]) <= 0):
            raise InputError(f"Material.mu must be positive, got {np.min(values['mu'])!r}", field="Material.mu",
                             value=self.mu)
        if "gamma" in values and np.any(np.asarray(values["gamma"]) < 0):
            raise InputError(f"Material.gamma must be non-negative, got {np.min(values['gamma'])!r}",
                             field="Material.gamma", value=self.gamma)
        for name in ("eta", "xi"):
            w = np.asarray(values.get(name, 0.0))
            if np.any(w < 0):
                raise InputError(f"Material.{name} must be non-negative (a weight of the energy (13)), got "
                                 f"{np.min(w)!r}", field=f"Material.{name}", value=getattr(self, name))
        for name in TENSORS:
            w = values.get(name)
            if w is None:
                continue
            w = np.asarray(w)
            if w.ndim >= 2 and w.shape[:2] == (2, 2) and not np.allclose(w[0, 1], w[1, 0], rtol=0, atol=0):
                raise InputError(f"Material.{name} must be symmetric: {name}_12 != {name}_21", field=f"Material.{name}",
                                 value=getattr(self, name))

    def varies(self) -> bool:
        """Whether any field is a callable of (a1, a2)."""
        return any(callable(getattr(self, name)) for name in _FIELDS + TENSORS)

    def field(self, name: str, nodes: tuple[int, int]) -> np.ndarray:
        """``mu`` or ``gamma`` as an (M, N) field on a node grid of shape ``nodes`` (not for a callable: see
        :meth:`field_at` and :meth:`nodal`)."""
        value = getattr(self, name)
        if callable(value):
            raise InputError(f"Material.{name} is a callable: evaluate it at points (Material.field_at, "
                             "Material.nodal)", field=f"Material.{name}", value=value)
        value = np.asarray(value)
        if value.ndim == 0:
            return np.full(nodes, float(value))
        if value.shape == tuple(nodes):
            return value
        raise InputError(f"Material.{name} has shape {value.shape}, expected a scalar or {tuple(nodes)}")

    def tensor(self, name: str, nodes: tuple[int, int]) -> np.ndarray:
        """Weight tensor ``name`` (eta, xi, alpha, beta) as a (2, 2, M, N) field (not for a callable: see
        :meth:`tensor_at` and :meth:`nodal`)."""
        value = getattr(self, name)
        M, N = nodes
        if value is None:
            return np.zeros((2, 2, M, N))
        if callable(value):
            raise InputError(f"Material.{name} is a callable: evaluate it at points (Material.tensor_at, "
                             "Material.nodal)", field=f"Material.{name}", value=value)
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

    def field_at(self, name: str, nodes: tuple[int, int], points, interpolate) -> np.ndarray:
        """``mu`` or ``gamma`` at points ``(a1, a2)`` of shape S: a callable evaluated there (checked), a node field
        carried there by ``interpolate`` ((..., M, N) -> (..., *S), the backend's own rule)."""
        value = getattr(self, name)
        if not callable(value):
            return interpolate(self.field(name, nodes))
        out = np.array(_evaluate(name, value, *points))
        if out.shape != np.broadcast(*points).shape:
            raise InputError(f"Material.{name}: the callable returned a tensor, expected a scalar field",
                             field=f"Material.{name}", value=value)
        self._validate({name: out})
        return out

    def tensor_at(self, name: str, nodes: tuple[int, int], points, interpolate) -> np.ndarray:
        """Weight tensor ``name`` at points ``(a1, a2)`` of shape S, (2, 2, *S): a callable evaluated there (checked
        for sign, finiteness and symmetry), node values carried there by ``interpolate``."""
        value = getattr(self, name)
        if not callable(value):
            return interpolate(self.tensor(name, nodes))
        v = _evaluate(name, value, *points)
        if v.ndim == np.broadcast(*points).ndim + 2:
            out = np.array(v)
        else:
            out = np.zeros((2, 2, *v.shape))
            out[0, 0] = out[1, 1] = v
        self._validate({name: out})
        return out

    def nodal(self, sheet) -> Material:
        """This material with every callable replaced by its values at ``sheet``'s nodes (checked): what a consumer
        of node fields (the stable-step estimate, the series, the trackers) reads."""
        if not self.varies():
            return self
        points = sheet.coordinates()
        changes = {}
        for name in _FIELDS + TENSORS:
            value = getattr(self, name)
            if callable(value):
                at = self.field_at if name in _FIELDS else self.tensor_at
                changes[name] = at(name, sheet.nodes, points, None)
        return dataclasses.replace(self, **changes)

    def check(self, nodes: tuple[int, int]) -> None:
        """Raise ValueError if any per-node array does not fit a node grid of shape ``nodes`` (callables are checked
        where they are evaluated)."""
        for name in _FIELDS:
            if not callable(getattr(self, name)):
                self.field(name, nodes)
        for name in TENSORS:
            if not callable(getattr(self, name)):
                self.tensor(name, nodes)

    def replace(self, **changes) -> Material:
        """A copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)
