"""What a force model is: the force e(r) of the equation of motion (11), as an object that answers for itself.

Every question the code asks of a force model is a class attribute or a method here; a new force model is one
subclass with a ``name``, registered by the project's registry (:mod:`deformable.registry`), and accepted wherever a
name is (``Scene(force_model=...)``, scene files, ``deformable run --force-model``). Two kinds:

- :class:`StrengthModel`: a force written as the strength matrix of eq. (20), ``e(r) = K(r) R`` with ``K = sum_ij
  D_i^T diag(alpha_ij) D_j + D_ij^T diag(beta_ij) D_ij``; the model supplies the coefficients alpha_ij and beta_ij
  at the backend's points (:meth:`StrengthModel.coefficients`). The paper's force (14)-(15) and the frozen model of
  section 3.2 are such.
- :class:`EnergyModel`: a force that is the exact gradient of an energy ``E = integral W(s, b) da1 da2`` whose
  density W depends on the surface only through the residuals of the metric and the curvature,

      s = (G11 - G0_11, G22 - G0_22, G12 - G0_12),   b = (B11 - B0_11, B22 - B0_22, B12 - B0_12),

  six numbers per point in the order of :data:`RESIDUALS`. The model supplies W, its gradient ``dW/d(s, b)`` (6, P)
  and its Hessian ``d2W/d(s, b)^2`` (6, 6, P); the backends own the geometry (the slots of
  :mod:`deformable.physics.integrand`) and the chain rule. Eq. (13) is one such model
  (:class:`~deformable.physics.force_models.variational.Variational`).

Which residuals a density couples (:attr:`EnergyModel.couples`) matters to finite differences only: FD places each
term of eq. (13) where its difference stencil is centred (second order), and evaluates residuals a density couples
at one point (:mod:`fdmodel.energy` says where).
"""

from __future__ import annotations

import functools
import math
from typing import ClassVar

import numpy as np

from ...errors import InputError
from ...registry import Registered
from ..material import TENSORS

__all__ = ["ForceModel", "StrengthModel", "EnergyModel", "RESIDUALS", "energy_density"]

#: the residuals of an energy density, in the order of its gradient and Hessian
RESIDUALS = ("s11", "s22", "s12", "b11", "b22", "b12")


def energy_density(eta, xi, G, G0, B, B0) -> tuple[np.ndarray, np.ndarray]:
    """The integrand of eq. (13): stretching and bending densities, each (*pts) (J per unit area).

    Parameters
    ----------
    eta, xi : arrays (2, 2, *pts)
        Weights (times any quadrature weight per component, as FD's row weights).
    G, G0, B, B0 : arrays (2, 2, *pts)
        Metric and curvature, and their rest values. ``B`` may be None when xi is zero everywhere (no normal is
        formed then); the bending density is 0.
    """
    stretching = np.sum(eta * (G - G0) ** 2, axis=(0, 1))
    if B is None:
        return stretching, np.zeros_like(stretching)
    return stretching, np.sum(xi * (B - B0) ** 2, axis=(0, 1))


class _class_or_instance:
    """A method bound to the instance it is read from, or to the class when read from the class."""

    def __init__(self, method):
        self.method = method
        functools.update_wrapper(self, method)

    def __get__(self, obj, cls):
        return functools.partial(self.method, cls if obj is None else obj)


class ForceModel(Registered, family="force model"):
    """The force e(r) of eq. (11), with what the solvers and backends need to know of it.

    Subclass :class:`StrengthModel` or :class:`EnergyModel` (not this class) and give the class attributes below
    that differ from their defaults.

    Class attributes
    ----------------
    name : str
        The registry name (``Scene(force_model=name)``).
    summary : str
        One line for listings.
    has_energy : bool
        Its force is the gradient of an energy: Newton's implicit schemes and static equilibrium apply.
    has_strength_matrix : bool
        It has the strength matrix K(r) of eq. (20): the paper's semi-implicit scheme applies.
    linear : bool
        K does not depend on r (its Newton matrix is factorised once per dt).
    scheme : str
        The time-stepping scheme taken by default (:mod:`deformable.dynamics`).
    weights : (str, str)
        The Material fields that carry its stretching and bending weights (``("eta", "xi")``; the frozen model's
        ``("alpha", "beta")``).
    stiffness : (float, float)
        Its linearised stretching and bending stiffness per unit weight about a rest state, relative to the paper's
        force (14): eq. (13)'s gradient is (4, 2) (:func:`deformable.scenes.equivalent_weights`).
    lags_alpha : bool
        The semi-implicit step lags its stretching coefficient, so that the step is stable only below the stretching
        bound of the backend's ``stable_step()`` (docs/design.md, "Time stepping").
    """

    summary: ClassVar[str] = ""
    has_energy: ClassVar[bool] = False
    has_strength_matrix: ClassVar[bool] = False
    linear: ClassVar[bool] = False
    scheme: ClassVar[str] = "semi-implicit"
    weights: ClassVar[tuple[str, str]] = ("eta", "xi")
    stiffness: ClassVar[tuple[float, float]] = (1.0, 1.0)
    lags_alpha: ClassVar[bool] = False

    @classmethod
    def of(cls, value) -> ForceModel:
        """A force model from a registered name, a ForceModel class or instance; InputError otherwise."""
        if isinstance(value, ForceModel):
            return value
        if isinstance(value, type) and issubclass(value, ForceModel) and value.name:
            return value()
        return cls.from_name(value)

    @property
    def implicit(self) -> bool:
        """Its default scheme solves the Newton matrix of an energy (3 ndof, coordinates coupled)."""
        return self.scheme != "semi-implicit"

    def __str__(self) -> str:
        return self.name

    def __eq__(self, other) -> bool:
        """Equal to a model of the same class and parameters; a model without parameters also equals its registered
        name."""
        if isinstance(other, str):
            return not vars(self) and other == self.name
        return type(self) is type(other) and vars(self) == vars(other)

    def __hash__(self) -> int:
        return hash(self.name) if not vars(self) else hash((type(self), tuple(sorted(vars(self).items()))))

    def __repr__(self) -> str:
        fields = ", ".join(f"{k}={v!r}" for k, v in vars(self).items())
        return f"{type(self).__name__}({fields})"

    # -- what a scene asks -----------------------------------------------------------
    def check(self, material) -> None:
        """InputError when ``material`` lacks what this model needs (naming the field); nothing by default."""
        for name in getattr(self, "fields", ()):
            if name not in TENSORS:
                raise InputError(f"force model {self.name!r} reads the Material field {name!r}; the tensor fields "
                                 f"are {', '.join(TENSORS)}", field=f"{type(self).__name__}.fields",
                                 value=name)

    def free_modes(self, material) -> list[str]:
        """Deformations that cost no energy with ``material`` (Scene warns ``IllPosedScene``); none by default."""
        return []

    def stretching_weight(self, material):
        """The Material tensor field that weighs stretching (the stable-step estimates read it)."""
        return getattr(material, self.weights[0])

    def stable_step(self, mu: np.ndarray, eta: np.ndarray, spacing, eigenvalue: float) -> float:
        """The largest stable step of the semi-implicit scheme (s) for a backend whose stiffest membrane mode is
        ``eigenvalue / h^2`` (FD 4, FE about 91): inf unless the model lags its stretching coefficient
        (:class:`~deformable.physics.force_models.tpbf87.TPBF87` overrides it)."""
        return math.inf

    def require_energy(self) -> None:
        """InputError unless the force is the gradient of an energy (the implicit schemes, equilibrium)."""
        if not self.has_energy:
            raise InputError(f"force_model {self.name!r} has no energy gradient: its force is not the gradient "
                             "of an energy (eq. (14) is not the gradient of eq. (13)); use force_model "
                             "'variational'", field="force_model", value=self.name)

    def require_strength_matrix(self) -> None:
        """InputError unless the model has the strength matrix K(r) of eq. (20) (the semi-implicit scheme)."""
        if not self.has_strength_matrix:
            raise InputError(f"the {self.name} force model has no strength matrix K(r) of eq. (20); use "
                             "energy_gradient / energy_hessian (TimeStepper scheme 'implicit-euler' or 'newmark')",
                             field="force_model", value=self.name)

    # -- what the output asks ----------------------------------------------------------
    def density_field(self, material_at, G, G0, B, B0) -> tuple[np.ndarray, np.ndarray]:
        """Stretching and bending energy densities (J/m^2) at points, each (P,): eq. (13)'s integrand.

        ``material_at(name)`` gives a Material tensor field at the points, (2, 2, P); G, G0, B, B0 are (2, 2, P). A
        model whose energy is not eq. (13)'s overrides this (:class:`EnergyModel` does).
        """
        return energy_density(material_at("eta"), material_at("xi"), G, G0, B, B0)


class StrengthModel(ForceModel):
    """A force model written as the strength matrix of eq. (20): ``e = K(r) R`` (module docstring).

    A subclass gives :meth:`coefficients`, the alpha_ij and beta_ij of K at the backend's points.
    """

    has_strength_matrix: ClassVar[bool] = True

    def coefficients(self, material_at, G, G0, B, B0) -> tuple[np.ndarray, np.ndarray]:
        """alpha_ij (N/m) and beta_ij (N) at points, each (2, 2, *pts).

        ``material_at(name)`` gives a Material tensor field at the points, (2, 2, *pts); G, B (the current metric
        and curvature, eq. 18-19 on FD) and their rest values G0, B0 are (2, 2, *pts). B is None when the model's
        bending weights are zero everywhere.
        """
        raise NotImplementedError


class EnergyModel(ForceModel):
    """A force model that is the exact gradient of an energy density W(s, b) (module docstring).

    A subclass gives :meth:`density`, :meth:`gradient` and :meth:`hessian`, with residuals s (3, P) and b (3, P) in
    the order of :data:`RESIDUALS` and material fields at the points. Attributes below; the backends do the rest.

    Class attributes
    ----------------
    fields : tuple of str
        The Material tensor fields it reads, each given at the points as (2, 2, P) in ``params``.
    couples : tuple of tuples of residual names
        The groups of residuals the density couples: W is the sum of one function of each group's residuals (a
        residual in no group stands alone). Default: all six in one group. Eq. (13) couples none (six groups of
        one), a membrane energy of the metric alone couples (s11, s22, s12).
    compiled : bool
        The backends take the compiled fast path of eq. (13) (:class:`deformable.physics.integrand.Integrand`)
        instead of calling the methods; only :class:`.variational.Variational` itself sets it (a subclass that
        changes the density is called, not compiled).
    rest : bool
        The density reads the rest metric: ``params["G0"]`` (2, 2, P), at the points where the residuals are (a
        shell energy measures strains in it, :class:`~deformable.physics.force_models.koiter.Koiter`); FD gives its
        nodes' points the node-centred rest metric (:mod:`fdmodel.model`).

    The density must vanish in the rest state (W(0, 0) = 0): the rest shape carries no energy.
    """

    has_energy: ClassVar[bool] = True
    scheme: ClassVar[str] = "implicit-euler"
    fields: ClassVar[tuple[str, ...]] = ("eta", "xi")
    couples: ClassVar[tuple[tuple[str, ...], ...]] = (RESIDUALS,)
    compiled: ClassVar[bool] = False
    rest: ClassVar[bool] = False

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if "compiled" not in cls.__dict__:
            cls.compiled = False
        for group in cls.couples if isinstance(cls.couples, tuple) else ():  # (a property: checked in groups)
            bad = [r for r in group if r not in RESIDUALS]
            if bad:
                raise TypeError(f"{cls.__qualname__}.couples names {bad!r}; residuals are {RESIDUALS}")

    @_class_or_instance
    def groups(self) -> tuple[tuple[int, ...], ...]:
        """:attr:`couples` as index tuples into :data:`RESIDUALS`, every residual in exactly one group; of the
        class, or of an instance (whose couples may depend on its parameters, as Koiter's on nu)."""
        out, seen = [], set()
        for group in self.couples:
            idx = tuple(RESIDUALS.index(r) for r in group if RESIDUALS.index(r) not in seen)
            seen.update(idx)
            if idx:
                out.append(idx)
        out += [(k,) for k in range(len(RESIDUALS)) if k not in seen]
        return tuple(out)

    def density(self, s: np.ndarray, b: np.ndarray, params: dict) -> np.ndarray:
        """W (P,) (J per unit parameter area) at residuals s, b (3, P); ``params``: name -> (2, 2, P)."""
        raise NotImplementedError

    def gradient(self, s: np.ndarray, b: np.ndarray, params: dict) -> np.ndarray:
        """dW/d(s, b), (6, P), in the order of :data:`RESIDUALS`."""
        raise NotImplementedError

    def hessian(self, s: np.ndarray, b: np.ndarray, params: dict) -> np.ndarray:
        """d2W/d(s, b)^2, (6, 6, P), symmetric in its first two indices."""
        raise NotImplementedError

    def prepare(self, params: dict) -> dict:
        """``params`` with what the density derives from them once, at points that do not change (the backends call
        it when they build their integrands, and the output's density field); sliced along the points like the
        fields, each added entry (a, b, P). None by default: a shell energy's metric tensors
        (:class:`~deformable.physics.force_models.koiter.Koiter`)."""
        return params

    def bends(self, params: dict) -> bool:
        """Whether W depends on b at these parameters; False lets a backend skip the normal (a sheet with degenerate
        tangents can still be stretched). True by default; eq. (13): some xi is not zero."""
        return True

    def density_field(self, material_at, G, G0, B, B0):
        """Stretching and bending densities from :meth:`density`: W(s, 0) and W(s, b) - W(s, 0) (J/m^2)."""
        params = {f: material_at(f) for f in self.fields}
        if self.rest:
            params["G0"] = G0
        params = self.prepare(params)
        s = np.stack([G[0, 0] - G0[0, 0], G[1, 1] - G0[1, 1], G[0, 1] - G0[0, 1]])
        b = np.stack([B[0, 0] - B0[0, 0], B[1, 1] - B0[1, 1], B[0, 1] - B0[0, 1]])
        stretching = self.density(s, np.zeros_like(b), params)
        return stretching, self.density(s, b, params) - stretching
