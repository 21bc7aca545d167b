"""Koiter's shell energy (issue 28, point 1): its quadratic form, its exact derivatives, its reduction to eq. (13)
at nu = 0 on both backends, and a plate's bending stiffness D = E h^3 / (12 (1 - nu^2)) against Navier's series."""

import numpy as np
import pytest
import scipy.sparse.linalg as spla

import deformable as dm
from deformable.errors import InputError
from deformable.physics.force_models import Koiter
from deformable.physics.force_models.koiter import form, weights
from validation.harness.backends import make_model
from validation.harness.plates import navier_centre

RNG = np.random.default_rng(7)


def _metrics(P):
    """P random symmetric positive definite rest metrics, (2, 2, P)."""
    L = RNG.normal(size=(P, 2, 2)) + 2 * np.eye(2)
    return np.moveaxis(L @ np.swapaxes(L, 1, 2), 0, -1)


def test_the_form_is_the_plane_stress_tensor_contracted_twice():
    """t^T K t against the four-index tensor nu A^ab A^cd + (1 - nu) (A^ac A^bd + A^ad A^bc) / 2 contracted with
    t_ab t_cd, point by point; K = diag(1, 1, 2) at G0 = I, nu = 0."""
    P, nu = 6, 0.3
    G0 = _metrics(P)
    K, J = form(G0, nu)
    t = RNG.normal(size=(3, P))
    for p in range(P):
        A = np.linalg.inv(G0[:, :, p])
        C = nu * np.einsum("ab,cd->abcd", A, A) + (1 - nu) / 2 * (np.einsum("ac,bd->abcd", A, A)
                                                                   + np.einsum("ad,bc->abcd", A, A))
        T = np.array([[t[0, p], t[2, p]], [t[2, p], t[1, p]]])
        assert t[:, p] @ K[:, :, p] @ t[:, p] == pytest.approx(np.einsum("abcd,ab,cd", C, T, T), rel=1e-12)
        assert J[p] == pytest.approx(np.sqrt(np.linalg.det(G0[:, :, p])), rel=1e-12)
    K0, _ = form(np.eye(2)[:, :, None], 0.0)
    np.testing.assert_allclose(K0[:, :, 0], np.diag([1.0, 1.0, 2.0]), atol=1e-15)


def test_the_gradient_and_hessian_are_those_of_the_density():
    model, P = Koiter(E=3e5, nu=0.3, h=2e-3), 5
    params = {"G0": _metrics(P)}
    r, eps = RNG.normal(scale=0.1, size=(6, P)), 1e-2  # W is quadratic: central differences are exact
    g, H = model.gradient(r[:3], r[3:], params), model.hessian(r[:3], r[3:], params)
    for k in range(6):
        dr = np.zeros((6, P))
        dr[k] = eps
        plus, minus = r + dr, r - dr
        numeric = (model.density(plus[:3], plus[3:], params) - model.density(minus[:3], minus[3:], params)) / (2 * eps)
        np.testing.assert_allclose(g[k], numeric, rtol=1e-10, atol=1e-12 * np.max(np.abs(g)))
        dg = (model.gradient(plus[:3], plus[3:], params) - model.gradient(minus[:3], minus[3:], params)) / (2 * eps)
        np.testing.assert_allclose(H[:, k], dg, rtol=1e-10, atol=1e-12 * np.max(np.abs(H)))


def _sheet_scene(force_model, material, nodes=7):
    sheet = dm.Sheet(size=(1.0, 0.8), nodes=(nodes, nodes))
    return dm.Scene(sheet, material, forces=[dm.Gravity()], constraints=[dm.Pin("top")], force_model=force_model)


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_koiter_at_nu_0_is_eq_13_with_the_mapped_weights_to_round_off(backend):
    E, h = 2e5, 1e-2
    eta, xi = weights(E, 0.0, h)
    full = np.ones((2, 2))
    koiter = make_model(_sheet_scene(Koiter(E=E, nu=0.0, h=h), dm.Material(mu=0.2, eta=full, xi=full)), backend)
    eq13 = make_model(_sheet_scene("variational", dm.Material(mu=0.2, eta=eta * full, xi=xi * full)), backend)
    X = koiter.initial_state()
    X = 1.03 * X + 0.02 * RNG.normal(size=X.shape)  # stretched, sheared and bent
    a, b = koiter.energy(X), eq13.energy(X)
    assert a.stretching == pytest.approx(b.stretching, rel=1e-12) and a.bending == pytest.approx(b.bending, rel=1e-12)
    ga, gb = koiter.energy_gradient(X), eq13.energy_gradient(X)
    np.testing.assert_allclose(ga, gb, rtol=0, atol=1e-12 * np.max(np.abs(gb)))
    Ha, Hb = koiter.energy_hessian(X), eq13.energy_hessian(X)
    assert abs(Ha - Hb).max() <= 1e-12 * abs(Hb).max()


def test_a_plate_bends_with_d_e_h3_over_12_1_minus_nu2():
    """FE, 16 x 16 elements, simply supported, uniform load, linearised about the flat plate: the centre
    deflection within 1e-3 of Navier's for D = E h^3 / (12 (1 - nu^2)) at nu = 0.3 (and not at nu = 0's D)."""
    E, nu, h, q = 1e6, 0.3, 1e-2, 1.0
    model_ = Koiter(E=E, nu=nu, h=h)
    sheet = dm.Sheet(size=(1.0, 1.0), nodes=(17, 17))
    scene = dm.Scene(sheet, dm.Material(mu=1.0, eta=np.ones((2, 2)), xi=np.ones((2, 2))), force_model=model_,
                     forces=[dm.BodyForce(f=(0.0, 0.0, q))], constraints=[dm.Pin(["left", "right", "bottom", "top"])])
    model = make_model(scene, "fe")
    X = model.initial_state()
    n = model.ndof
    free = np.setdiff1d(np.arange(n), model.fixed_dofs()[2])
    H = model.energy_hessian(X).tocsr()[2 * n:, 2 * n:][free][:, free]
    w = np.zeros(n)
    w[free] = spla.spsolve(H.tocsc(), model.load(X, 0.0)[free, 2])
    centre = float(model.sample(X + np.outer(w, [0.0, 0.0, 1.0]), np.array([[0.5, 0.5]])).r[0, 2])
    D = model_.stiffnesses[1]
    assert D == pytest.approx(E * h**3 / (12 * (1 - nu**2)))
    assert centre == pytest.approx(navier_centre(D, q), rel=1e-3)
    assert abs(centre / navier_centre(E * h**3 / 12, q) - 1) > 0.05  # the 1 - nu^2 is there


@pytest.mark.parametrize("kw, field", [(dict(E=0.0), "Koiter.E"), (dict(h=-1.0), "Koiter.h"),
                                       (dict(nu=0.5), "Koiter.nu"), (dict(nu=True), "Koiter.nu")])
def test_bad_koiter_parameters_are_refused_naming_the_field(kw, field):
    with pytest.raises(InputError, match=field.split(".")[1]):
        Koiter(**kw)


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_a_koiter_sheet_falls_and_bends_under_the_implicit_step(backend):
    """The registered model runs where eq. (13) runs: a sheet pinned along its top edge, under gravity, 20 steps
    of implicit Euler (its default scheme); it falls, its energy stays finite, and Newton converged every step."""
    scene = _sheet_scene(Koiter(E=1e5, nu=0.3, h=1e-3), dm.Material(mu=0.2, eta=np.ones((2, 2)), xi=np.ones((2, 2))))
    model = make_model(scene, backend)
    stepper = dm.TimeStepper(model, 5e-3)
    result = stepper.run(model.initial_state(), steps=20)
    assert result.status == "finished" and all(r.converged for r in stepper.newton_reports)
    assert np.min(result.state.X[:, 2]) < -1e-3 and np.isfinite(model.energy(result.state.X).total)
