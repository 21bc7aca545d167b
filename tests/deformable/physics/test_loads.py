"""External forces (deformable.physics.loads) over the backends' integration hooks, on both backends.

The hooks are checked against each other and against the backends' own
matrices; springs and wind against central differences and against the
closed forms of a falling sheet (terminal speed) and a sheet on a spring
(force balance).
"""

import numpy as np
import pytest

import deformable as dm
from deformable.geometry.surfaces import Plane
from deformable.solve.potential import flat
from validation.harness.surfaces import get

from ...conftest import central_differences, flat_scene

#: FD with control-area weights integrates a constant exactly over the sheet
OPTIONS = {"fd": {"weighting": "control-area"}, "fe": {}}


@pytest.fixture(params=["fd", "fe"])
def backend(request):
    return request.param


def model_of(scene, backend):
    from validation.harness.backends import make_model

    return make_model(scene, backend, **OPTIONS[backend])


def curved(model):
    return model.discretize(get("monge"))


# -- the hooks ---------------------------------------------------------------------------
def test_density_matrix_of_mu_is_the_mass_and_integrate_agrees_with_it(backend):
    rng = np.random.default_rng(1)
    model = model_of(flat_scene((6, 5), size=(1.0, 0.8), material=dm.Material(mu=0.3)), backend)
    assert abs(model.density_matrix(model.mu) - model.mass()).max() < 1e-15
    c = rng.uniform(0.5, 2.0, model.points[0].shape)
    ones = np.zeros(model.ndof)
    ones[model.value_dofs] = 1.0  # the constant function 1
    e = np.array([0.2, -1.0, 3.0])
    F = model.integrate(c[..., None] * e)
    np.testing.assert_allclose(F, np.outer(model.density_matrix(c) @ ones, e), rtol=0, atol=1e-14)
    # a constant density integrates to density x area (FD: with control-area weights)
    assert np.allclose(model.integrate(np.broadcast_to(e, (*c.shape, 3)))[model.value_dofs].sum(axis=0), 0.8 * e)


def test_at_points_is_exact_for_a_linear_map(backend):
    A = np.array([[1.0, 0.2], [0.1, 1.5], [0.3, -0.4]])
    model = model_of(flat_scene((6, 5), size=(1.0, 0.8)), backend)
    X = model.discretize(Plane(origin=(1.0, 1.0, 1.0), e1=A[:, 0], e2=A[:, 1]))
    a1, a2 = (a.ravel() for a in model.points)
    np.testing.assert_allclose(model.at_points(X), np.stack([a1, a2], -1) @ A.T + 1.0, rtol=0, atol=1e-13)
    np.testing.assert_allclose(model.at_points(X, (1, 0)), np.broadcast_to(A[:, 0], (a1.size, 3)), atol=1e-12)
    np.testing.assert_allclose(model.at_points(X, (0, 1)), np.broadcast_to(A[:, 1], (a1.size, 3)), atol=1e-12)


def test_point_dofs_interpolate_like_sample(backend):
    model = model_of(flat_scene((6, 5), size=(1.0, 0.8)), backend)
    X = curved(model)
    for a in ([0.31, 0.47], [1.0, 0.8], [0.0, 0.0]):
        dofs, w = model.point_dofs(a)
        np.testing.assert_allclose(w @ X[dofs], model.sample(X, np.array([a])).r[0], rtol=0, atol=1e-13)


# -- springs -----------------------------------------------------------------------------
@pytest.mark.parametrize("rest_length", [0.0, 0.1])
def test_spring_gradient_and_hessian_are_the_derivatives_of_its_energy(backend, rest_length):
    spring = dm.Spring(at=(0.37, 0.52), anchor=lambda t: (0.2, 0.1 * t, 0.6), stiffness=3.0, rest_length=rest_length)
    model = model_of(flat_scene((4, 4), forces=[spring]), backend)
    loads, t = model.loads, 0.5
    X = curved(model)
    g = flat(loads.spring_gradient(X, t))
    np.testing.assert_allclose(g, central_differences(lambda Y: loads.spring_energy(Y, t), X).ravel(), atol=1e-8)
    H = loads.spring_hessian(X, t).toarray()  # stretched (|d| > L0): the exact Hessian is definite, kept whole
    numeric = central_differences(lambda Y: flat(loads.spring_gradient(Y, t)), X)
    np.testing.assert_allclose(H, numeric, atol=1e-7)
    assert np.allclose(model.load(X, t), -loads.spring_gradient(X, t))


def test_a_sheet_on_a_spring_carries_its_weight_in_the_spring(backend):
    """Equilibrium of a free sheet hung from a linear spring at its centre: k |d| = total weight."""
    k, mu, g = 40.0, 0.2, 9.81
    spring = dm.Spring(at=(0.5, 0.5), anchor=(0.5, 0.5, 0.0), stiffness=k)
    scene = flat_scene((7, 7), material=dm.Material(mu=mu, eta=50.0, xi=0.05), force_model="variational",
                       forces=[dm.Gravity(g), spring])
    model = model_of(scene, backend)
    X, _ = dm.equilibrium(model, model.initial_state(), tol=1e-12)
    dofs, w = model.point_dofs((0.5, 0.5))
    d = w @ X[dofs] - np.array([0.5, 0.5, 0.0])
    np.testing.assert_allclose(d, [0.0, 0.0, -mu * g * 1.0 / k], rtol=0, atol=1e-9)


# -- wind --------------------------------------------------------------------------------
def test_wind_on_a_sheet_at_rest_is_c_w_squared_per_area(backend):
    wind = dm.Wind(velocity=(0.0, 0.0, 3.0), coefficient=0.6)
    model = model_of(flat_scene((5, 6), size=(1.0, 0.8), forces=[wind]), backend)
    F = model.load(model.initial_state(), 0.0)
    np.testing.assert_allclose(F[model.value_dofs].sum(axis=0), [0.0, 0.0, 0.6 * 9.0 * 0.8], rtol=1e-12, atol=1e-12)
    # a wind in the sheet's plane does not push it
    side = model_of(flat_scene((5, 6), forces=[dm.Wind(velocity=(3.0, 1.0, 0.0))]), backend)
    assert np.max(np.abs(side.load(side.initial_state(), 0.0))) == 0.0


def test_wind_damping_is_minus_the_velocity_jacobian(backend):
    rng = np.random.default_rng(3)
    wind = dm.Wind(velocity=lambda t: (0.5, -0.3, 2.0 + t), coefficient=0.7)
    model = model_of(flat_scene((4, 4), forces=[wind]), backend)
    X = curved(model)
    V = 0.3 * rng.normal(size=X.shape)
    D = model.loads.wind_damping(X, V, 0.2).toarray()
    numeric = central_differences(lambda W: flat(model.loads.wind_force(X, W, 0.2)), V)
    np.testing.assert_allclose(D, -numeric, atol=1e-7)
    assert np.min(np.linalg.eigvalsh(D)) > -1e-12 * np.max(np.abs(D))


@pytest.mark.parametrize("scheme", ["implicit-euler", "newmark", "semi-implicit"])
def test_a_falling_sheet_reaches_the_terminal_speed_of_its_drag(backend, scheme):
    """Still air: mu g = c v^2 at the terminal speed v = sqrt(mu g / c), for every scheme."""
    mu, g, c = 0.1, 9.81, 0.6
    force_model, dt = ("tpbf87", 2e-3) if scheme == "semi-implicit" else ("variational", 1e-2)
    scene = flat_scene((5, 5), material=dm.Material(mu=mu, eta=20.0, xi=0.01), force_model=force_model,
                       forces=[dm.Gravity(g), dm.Wind(coefficient=c)])
    model = model_of(scene, backend)
    newton = None if scheme == "semi-implicit" else dict(precision="double")  # round-off: double precision's
    result = dm.TimeStepper(model, dt, scheme=scheme, newton=newton).run(model.initial_state(), t_end=1.5)
    assert result.status == "finished"
    v = result.state.V[model.value_dofs]
    np.testing.assert_allclose(v[:, 2], -np.sqrt(mu * g / c), rtol=1e-4)
    assert np.max(np.abs(v[:, :2])) < 1e-8  # no sideways drift beyond round-off


@pytest.mark.parametrize("make, message", [
    (lambda: dm.Spring((0.1, 0.1), stiffness=-1.0), r"Spring.stiffness .* -1\.0"),
    (lambda: dm.Spring((0.1, 0.1), rest_length=float("nan")), r"Spring.rest_length .* nan"),
    (lambda: dm.Spring((0.1, 0.1), anchor=(0.0, 1.0)), r"Spring.anchor"),
    (lambda: dm.Spring((0.1,), anchor=(0.0, 1.0, 0.0)), r"Spring.at"),
    (lambda: dm.Wind(velocity=(0.0, 0.0, "fast")), r"Wind.velocity"),
    (lambda: dm.Wind(coefficient=-0.6), r"Wind.coefficient .* -0\.6"),
])
def test_bad_springs_and_winds_name_the_field(make, message):
    with pytest.raises(ValueError, match=message):
        make()


def test_a_compressed_springs_hessian_keeps_its_positive_part():
    """|d| < L0: the transverse stiffness k (1 - L0/|d|) is negative; the Hessian keeps the axial k only."""
    s = dm.Spring((0.0, 0.0), anchor=(0.0, 0.0, 0.0), stiffness=2.0, rest_length=1.0)
    H = s.hessian(np.array([0.0, 0.0, 0.5]), 0.0)
    np.testing.assert_allclose(H, np.diag([0.0, 0.0, 2.0]), atol=1e-14)
    np.testing.assert_allclose(s.force(np.array([0.0, 0.0, 0.5]), 0.0), [0.0, 0.0, 1.0])  # pushes out to L0
