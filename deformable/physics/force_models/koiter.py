r"""Koiter's shell energy: an isotropic shell of Young's modulus E, Poisson's ratio nu and thickness h.

With the strains measured in the rest metric G0 (Koiter 1966, Proc. KNAW B 69; Ciarlet 2005, *An Introduction to
Differential Geometry with Applications to Elasticity*, chapter 4),

    eps = (G - G0) / 2 = s / 2,          kappa = B - B0 = b,
    W = sqrt(det G0) [ C_m / 2  H(eps, eps) + C_b / 2  H(kappa, kappa) ],
    H(t, t) = nu tr(A t)^2 + (1 - nu) tr(A t A t),      A = G0^-1 (raises indices),
    C_m = E h / (1 - nu^2),   C_b = E h^3 / (12 (1 - nu^2)),

per unit parameter area (the area element sqrt(det G0) da1 da2). H is the plane-stress elasticity tensor ``nu A^ab
A^cd + (1 - nu) (A^ac A^bd + A^ad A^bc) / 2`` contracted twice; in the residuals of :mod:`.base` it is a quadratic
form ``t^T K t`` of t = (t11, t22, t12) with a 3 x 3 matrix K of each point's A (:func:`form`), so the gradient and
the Hessian below are exact.

At nu = 0 on a flat rest state (G0 = I) K = diag(1, 1, 2) and W is eq. (13) with the weights ``eta_ij = E h / 8``
and ``xi_ij = E h^3 / 24`` for every i, j (:func:`weights`); on an orthogonal parameterisation (G0_12 = 0) it is eq.
(13) with weights that vary as the metric does (an annulus in polar coordinates: eta_11 = E h r / 8, eta_22 = E h /
(8 r^3), eta_12 = E h / (8 r)). Then no residual is coupled to another and finite differences place each term where
eq. (13)'s stands (second order); for nu > 0 the membrane terms are coupled (evaluated at FD's cell centres) and so
are the bending terms (at its nodes), :mod:`fdmodel.energy`. A flat plate's bending stiffness is ``D = C_b = E h^3 /
(12 (1 - nu^2))``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...checks import is_real
from ...errors import InputError
from .base import RESIDUALS, EnergyModel

__all__ = ["Koiter", "ShellEnergy", "form", "weights"]

#: the unit component tensors of (t11, t22, t12) (a symmetric t = sum_c t_c U_c)
_UNITS = np.array([[[1.0, 0.0], [0.0, 0.0]], [[0.0, 0.0], [0.0, 1.0]], [[0.0, 1.0], [1.0, 0.0]]])


def form(G0: np.ndarray, nu: float) -> tuple[np.ndarray, np.ndarray]:
    """The matrix K (3, 3, P) of ``H(t, t) = t^T K t`` (module docstring) and sqrt(det G0) (P,) at rest metrics G0
    (2, 2, P); both 0 where G0 is degenerate (points a backend carries with zero weight)."""
    det = G0[0, 0] * G0[1, 1] - G0[0, 1] * G0[1, 0]
    inv = np.divide(1.0, det, out=np.zeros_like(det), where=det > 0)  # 0 at points without a rest metric (FD's
    A = np.stack([np.stack([G0[1, 1], -G0[0, 1]]), np.stack([-G0[1, 0], G0[0, 0]])]) * inv  # unweighted ones)
    AU = np.einsum("ijp,cjk->cikp", A, _UNITS)  # A U_c, (3, 2, 2, P)
    trace = np.einsum("ciip->cp", AU)  # tr(A U_c)
    K = nu * trace[:, None] * trace[None, :] + (1 - nu) * np.einsum("cijp,djip->cdp", AU, AU)
    return K, np.sqrt(np.maximum(det, 0.0))


def weights(E: float, nu: float, h: float) -> tuple[float, float]:
    """The eta and xi of eq. (13) that Koiter's energy equals at nu = 0 on a flat rest state (every component): (E h
    / 8, E h^3 / 24); nu must be 0."""
    if nu != 0:
        raise InputError(f"eq. (13) has no Poisson coupling: Koiter's energy reduces to it at nu = 0 only, got "
                         f"nu = {nu!r}", field="nu", value=nu)
    return E * h / 8, E * h**3 / 24


class ShellEnergy(EnergyModel):
    """A shell energy quadratic in the strains at each point, ``W = cs s^T K s + cb b^T K b`` with a 3 x 3 form K
    (3, 3, P) of the residuals (t11, t22, t12) and per-point factors cs, cb (P,) from :meth:`_form`: Koiter's
    isotropic shell and the orthotropic one (:mod:`.orthotropic`) share the density and its exact derivatives."""

    fields = ()
    rest = True

    def _form(self, params):  # -> (K (3, 3, P), cs (P,), cb (P,))
        raise NotImplementedError

    def density(self, s, b, params):
        K, cs, cb = self._form(params)
        return cs * np.einsum("cp,cdp,dp->p", s, K, s) + cb * np.einsum("cp,cdp,dp->p", b, K, b)

    def gradient(self, s, b, params):
        K, cs, cb = self._form(params)
        return np.concatenate([2 * cs * np.einsum("cdp,dp->cp", K, s), 2 * cb * np.einsum("cdp,dp->cp", K, b)])

    def hessian(self, s, b, params):
        K, cs, cb = self._form(params)
        H = np.zeros((6, 6, K.shape[-1]))
        H[:3, :3], H[3:, 3:] = 2 * cs * K, 2 * cb * K
        return H


def positive_parameter(model, name: str) -> None:
    """Check a shell's parameter ``name`` as a positive finite real number (numpy's scalars too) and store it as a
    float; InputError naming ``<Class>.<name>`` otherwise."""
    v, owner = getattr(model, name), type(model).__name__
    if not is_real(v) or not np.isfinite(v) or v <= 0:
        raise InputError(f"{owner} {name} must be a positive number, got {v!r}", field=f"{owner}.{name}", value=v)
    object.__setattr__(model, name, float(v))


def finite_stiffnesses(model, modulus: str = "E") -> None:
    """InputError when a shell's membrane or bending stiffness (E h / (1 - nu^2), E h^3 / 12 / (1 - nu^2) and the
    like) is not a finite positive number in double precision (E = 1e300 with h = 1e10)."""
    with np.errstate(over="ignore", invalid="ignore"):
        values = np.asarray(model.stiffnesses, dtype=float)
    if not (np.all(np.isfinite(values)) and np.all(values > 0)):
        owner = type(model).__name__
        raise InputError(f"{owner}: its stiffnesses {tuple(float(v) for v in values)} (N/m, N m) are not finite "
                         "positive numbers in double precision; choose E and h of a physical sheet",
                         field=f"{owner}.{modulus}", value=getattr(model, modulus))


@dataclass(frozen=True, eq=False)
class Koiter(ShellEnergy):
    """Koiter's isotropic shell (module docstring): ``Scene(force_model=Koiter(E=..., nu=..., h=...))``.

    Parameters
    ----------
    E : float
        Young's modulus (Pa), positive.
    nu : float
        Poisson's ratio, in [0, 1/2).
    h : float
        The thickness (m), positive.

    The Material's eta and xi are not read (its mu and gamma are).
    """

    name = "koiter"
    summary = "Koiter's isotropic shell: Young's modulus E, Poisson's ratio nu, thickness h (strains in G0)"
    E: float = 1.0e6
    nu: float = 0.3
    h: float = 1.0e-3

    def __post_init__(self):
        for name in ("E", "h"):
            positive_parameter(self, name)
        nu = self.nu
        if not is_real(nu) or not 0 <= nu < 0.5:
            raise InputError(f"Koiter nu must lie in [0, 1/2), got {nu!r}", field="Koiter.nu", value=nu)
        object.__setattr__(self, "nu", float(nu))
        finite_stiffnesses(self)

    @property
    def couples(self):
        """At nu = 0 no residual is coupled (on an orthogonal rest parameterisation, checked in :meth:`prepare`);
        else the metric's three and the curvature's three."""
        return () if self.nu == 0 else (RESIDUALS[:3], RESIDUALS[3:])

    @property
    def stiffnesses(self) -> tuple[float, float]:
        """(C_m, C_b): the membrane stiffness E h / (1 - nu^2) (N/m) and the bending stiffness D (N m)."""
        c = self.E / (1 - self.nu**2)
        return c * self.h, c * self.h**3 / 12

    def prepare(self, params):
        """The rest metric's form K (3, 3, P) and area element (1, 1, P), once (checked at nu = 0: an orthogonal
        parameterisation)."""
        G0 = params["G0"]
        if self.nu == 0 and np.any(np.abs(G0[0, 1]) > 1e-10 * np.maximum(np.abs(G0[0, 0]), np.abs(G0[1, 1]))):
            raise InputError(f"Koiter at nu = 0 evaluates each residual on its own (as eq. (13)), which needs an "
                             f"orthogonal rest parameterisation; here |G0_12| reaches {np.max(np.abs(G0[0, 1])):.3g}",
                             field="Koiter.nu", value=self.nu)
        K, J = form(G0, self.nu)
        return {**params, "K": K, "J": J[None, None]}

    def _form(self, params):
        if "K" not in params:  # called without the backends' prepare (e.g. on residuals of one's own)
            params = self.prepare(params)
        cm, cb = self.stiffnesses
        J = params["J"][0, 0]
        return params["K"], J * cm / 8, J * cb / 2  # W = cs s^T K s + cb b^T K b
