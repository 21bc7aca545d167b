"""A fabric in SI units (deformable.Fabric): the weights of eq. (13) from what a textile lab measures.

The derivation (deformable/physics/fabric.py) is held to an independent model: on a flat orthonormal sheet the
variational energy with a fabric's weights is the orthotropic Koiter shell with E_i = T_i / h, G12 = S / h,
nu12 = 0, for the fabric whose D_i, D_12 are that shell's (E_i h^3 / 12, G12 h^3 / 6), at any state."""

import numpy as np
import pytest

import deformable as dm
from deformable.errors import InputError
from deformable.physics.fabric import G, Fabric
from validation.harness.backends import make_model

H = 4e-4  # the shell's thickness (m)
T1, T2, S = 800.0, 300.0, 60.0  # tensile (warp, weft) and shear stiffness (N/m)


def _energy(material, force_model, backend, X=None, rng=None):
    scene = dm.Scene(dm.Sheet(size=(0.3, 0.2), nodes=(6, 5)), material, force_model=force_model,
                     constraints=[dm.Clamp("left")])
    m = make_model(scene, backend)
    return m, m.energy(X if X is not None else m.initial_state() + 0.01 * rng.normal(size=(m.ndof, 3)))


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_the_weights_are_the_orthotropic_shell_at_nu_0(backend, rng):
    fabric = Fabric(density=0.12, bending=(T1 * H**2 / 12, T2 * H**2 / 12), tensile=(T1, T2), shear=S,
                    twist=S * H**2 / 6)
    shell = dm.Orthotropic(E1=T1 / H, E2=T2 / H, G12=S / H, nu12=0.0, h=H)
    m, _ = _energy(fabric.material(), "variational", backend, rng=rng)
    X = m.initial_state() + 0.01 * rng.normal(size=(m.ndof, 3))
    ours = m.energy(X)
    _, theirs = _energy(dm.Material(mu=0.12, eta=np.ones((2, 2)), xi=np.ones((2, 2))), shell, backend, X=X)
    assert ours.stretching == pytest.approx(theirs.stretching, rel=1e-10)
    assert ours.bending == pytest.approx(theirs.bending, rel=1e-10)


def test_other_force_models_get_the_same_linear_stiffness():
    fabric = Fabric(density=0.1, bending=2e-5, tensile=500.0)
    (ev, xv), (et, xt) = fabric.weights("variational"), fabric.weights("tpbf87")
    np.testing.assert_allclose(et, 4 * ev)  # the paper's force (14) is 4 times softer in stretching,
    np.testing.assert_allclose(xt, 2 * xv)  # 2 times in bending (deformable.scenes.equivalent_weights)
    assert ev[0, 1] == pytest.approx(500.0 / 2 / 4) and xv[0, 1] == pytest.approx(xv[0, 0])  # nu = 0 defaults


def test_the_bending_length_is_peirces():
    fabric = Fabric.from_bending_length(0.1, (0.03, 0.02), tensile=400.0)
    assert fabric.bending[0] == pytest.approx(0.1 * G * 0.03**3)
    assert fabric.bending_length == pytest.approx((0.03, 0.02))
    material = fabric.material(gamma=0.2, scale=20.0)
    assert material.mu == pytest.approx(2.0) and material.gamma == pytest.approx(4.0)


@pytest.mark.parametrize("kwargs, field", [
    (dict(density=0.0, bending=1e-5, tensile=100.0), "Fabric.density"),
    (dict(density=0.1, bending=(1e-5, -1.0), tensile=100.0), "Fabric.bending"),
    (dict(density=0.1, bending=1e-5, tensile="stiff"), "Fabric.tensile"),
    (dict(density=0.1, bending=1e-5, tensile=100.0, shear=float("nan")), "Fabric.shear"),
])
def test_bad_input_names_the_field(kwargs, field):
    with pytest.raises(InputError, match=field):
        Fabric(**kwargs)
