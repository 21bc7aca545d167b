r"""How the scenes' parameters translate: the same material under two force models, and the folds' length scale.

Under the paper's force (14) and under the gradient of the energy (13) the
same eta, xi are different materials (docs/design.md): about a rest state
the variational force is 4 times stiffer in stretching and 2 times in
bending (:attr:`deformable.physics.ForceModel.stiffness`).
:func:`equivalent_weights` maps weights between force models;
:func:`fold_wavelength` is the bending length that sets the width of a
hanging sheet's folds (Cerda and Mahadevan 2003).
"""

from __future__ import annotations

from ..physics.force_models import ForceModel

__all__ = ["equivalent_weights", "fold_wavelength"]


def equivalent_weights(eta: float, xi: float, source: str = "tpbf87", target: str = "variational"):
    """(eta, xi) under ``target`` with the linearised stiffness of (eta, xi) under ``source``.

    About a rest state, the paper's force (14) ``-d_i(eta (G - G0) d_j r) + ...``
    has the stretching stiffness eta and the bending stiffness xi; the gradient
    of the energy (13) has 4 eta (G = r . r is quadratic in r, and (G - G0)^2
    again) and 2 xi. So ``equivalent_weights(20, 1e-5)`` is (5, 5e-6): the
    variational weights of the same linear material. The frozen model counts
    like tpbf87 (its alpha, beta are the paper's). Any registered force model
    counts by its own :attr:`~deformable.physics.ForceModel.stiffness`.
    """
    (se, sx), (te, tx) = ForceModel.lookup(source).stiffness, ForceModel.lookup(target).stiffness
    return eta * se / te, xi * sx / tx


def fold_wavelength(xi: float, mu: float, g: float, height: float, scale: float = 1.0,
                    force_model: str = "variational") -> float:
    r"""The bending-length scale of the folds of a hanging sheet, ``(D H / (mu g))^(1/4)`` (m).

    A sheet hanging under its own weight and compressed across its width
    wrinkles where its bending stiffness D balances the stiffness of the
    tension that holds it straight: Cerda and Mahadevan (2003, "Geometry and
    physics of wrinkling", Phys. Rev. Lett. 90, 074302) give
    ``lambda ~ (D / K)^(1/4)`` with the tension's effective stiffness
    ``K = T / H^2``; a curtain's tension is its weight below, T ~ mu g H, so
    ``lambda ~ (D H / (mu g))^(1/4)``. The number of folds across a given
    width scales as ``xi^(-1/4)``; the prefactor is the curtain's own (the
    paper study measures it). D = 2 xi under the variational model, xi under
    the paper's force; mu and the forces are scaled together, so ``scale``
    divides D.
    """
    D = xi * ForceModel.lookup(force_model).stiffness[1]
    return (D * height / (scale * mu * g)) ** 0.25
