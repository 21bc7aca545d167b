"""The orthotropic shell (deformable.Orthotropic): Koiter's energy with a fabric's plane-stress law; isotropic
parameters give Koiter's shell to round-off on both backends, and warp and weft stretch by their own moduli."""

import numpy as np
import pytest

import deformable as dm
from validation.harness.backends import make_model

E, NU, H = 2e5, 0.3, 2e-3


def cylinder(a1, a2):  # an orthogonal curved rest parameterisation: radius 0.7, a1 around, a2 along the axis
    return np.stack([0.7 * np.sin(a1 / 0.7), a2, 0.7 * (1 - np.cos(a1 / 0.7))], axis=-1)


def model(force_model, backend, nodes=(6, 5)):
    unused = np.ones((2, 2))
    sheet = dm.Sheet(size=(1.0, 0.8), nodes=nodes, rest=cylinder)
    return make_model(dm.Scene(sheet, dm.Material(mu=1.0, eta=unused, xi=unused), constraints=[dm.Clamp("left")],
                               force_model=force_model), backend)


@pytest.mark.parametrize("backend", ["fd", "fe"])
@pytest.mark.parametrize("nu", [0.0, NU])
def test_isotropic_parameters_are_koiters_shell(backend, nu, rng):
    koiter = model(dm.Koiter(E=E, nu=nu, h=H), backend)
    ortho = model(dm.Orthotropic(E1=E, E2=E, G12=E / (2 * (1 + nu)), nu12=nu, h=H), backend)
    X = koiter.initial_state() + 0.03 * rng.normal(size=(koiter.ndof, 3))
    ek, eo = koiter.energy(X), ortho.energy(X)
    assert eo.stretching == pytest.approx(ek.stretching, rel=1e-12)
    assert eo.bending == pytest.approx(ek.bending, rel=1e-12)
    gk, go = koiter.energy_gradient(X), ortho.energy_gradient(X)
    assert np.max(np.abs(go - gk)) <= 1e-12 * np.max(np.abs(gk))
    Hk, Ho = koiter.energy_hessian(X), ortho.energy_hessian(X)
    assert abs(Ho - Hk).max() <= 1e-11 * abs(Hk).max()


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_warp_and_weft_stretch_by_their_own_moduli(backend):
    """A square pulled by a small traction T (N/m) along a1, then along a2, with nu12 = 0: the strain is T / (E h)
    of the direction's modulus (within the geometric nonlinearity, T / (E h) / 2 = 2.5e-5 relative)."""
    E1, E2, T = 4e5, 1e5, 1e-3
    fm = dm.Orthotropic(E1=E1, E2=E2, G12=5e4, nu12=0.0, h=H)
    unused = np.ones((2, 2))
    strains = []
    for pulled, held, axis in (("right", "left", "x"), ("top", "bottom", "y")):
        k = "xyz".index(axis)
        f = np.zeros(3)
        f[k] = T
        scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(5, 5)), dm.Material(mu=1.0, eta=unused, xi=unused),
                         force_model=fm, forces=[dm.EdgeLoad(pulled, f=tuple(f))],
                         constraints=[dm.Pin(held, axes=(axis, "z")), dm.Pin("bottom-left")])
        m = make_model(scene, backend)
        X, _ = dm.equilibrium(m, m.initial_state(), tol=1e-12, check_stability=False)
        strains.append(float(np.mean(m.grid(X)[..., k].max() - 1.0)))
    np.testing.assert_allclose(strains, [T / (E1 * H), T / (E2 * H)], rtol=1e-3)


@pytest.mark.parametrize("kwargs, message", [
    ({"E1": -1.0}, r"Orthotropic E1 must be a positive number"),
    ({"G12": 0.0}, r"Orthotropic G12 must be a positive number"),
    ({"E1": 1e5, "E2": 4e5, "nu12": 0.6}, r"nu12\^2 E2 / E1 < 1"),
])
def test_bad_parameters_are_named(kwargs, message):
    with pytest.raises(dm.InputError, match=message):
        dm.Orthotropic(**kwargs)


def test_the_material_axes_need_a_rest_parameterisation_at_right_angles():
    sheared = dm.Sheet(size=(1.0, 1.0), nodes=(5, 5), rest=lambda a1, a2: np.stack([a1 + 0.3 * a2, a2, 0 * a1], -1))
    with pytest.raises(dm.InputError, match=r"must meet at right angles at rest"):
        make_model(dm.Scene(sheared, dm.Material(eta=np.ones((2, 2)), xi=np.ones((2, 2))),
                            force_model=dm.Orthotropic()), "fe")
