"""The backend contract (deformable.backends), checked on both backends.

Every test takes the ``backend`` fixture ("fd", "fe") and builds its models
through :func:`validation.harness.backends.make_model`: whatever the contract
promises, FDModel and FEModel keep alike. Facts that belong to one backend
only (FE derivative degrees of freedom, the FD ghost-row clamp, exact FD
eigenvalues) are in tests/fdmodel and tests/femodel.
"""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from hypothesis import given, settings
from hypothesis import strategies as st

import deformable as dm
from deformable.algebra.upper import FreeUpper
from validation.harness.backends import make_model
from validation.harness.surfaces import get

from ...conftest import FULL_ETA, FULL_XI, flat_model, flat_scene, gradient_error, hessian_error

#: attributes and methods the contract names (deformable.backends.Backend's docstring)
ATTRIBUTES = {"scene", "ndof", "linear", "spacing", "value_dofs", "points", "mu", "loads", "contact_samples"}
METHODS = {"initial_state", "discretize", "grid", "tensors", "sample", "stiffness", "mass", "damping", "load",
           "internal_force", "fixed_dofs", "prescribed", "stable_step", "energy", "kinetic_energy",
           "energy_gradient", "energy_hessian", "energy_elements", "integrate", "at_points", "density_matrix", "point_dofs", "edge_rule", "patches",
           "point_matrix"}
#: degrees of freedom per node
NODE_DOFS = {"fd": 1, "fe": 4}
#: small grids for the finite-difference checks of the energy's derivatives (cost ~ ndof^2)
SMALL = {"fd": (7, 6), "fe": (4, 3)}
#: round-off allowed below zero in the Gauss-Newton spectrum, relative to its largest entry
PSD_TOLERANCE = {"fd": 1e-10, "fe": 1e-12}


@pytest.fixture(params=["fd", "fe"])
def backend(request):
    return request.param


def curved_scene(nodes, force_model="tpbf87", initial=None, **scene):
    """A sheet whose rest shape is the generic Monge patch, full weight tensors on every component."""
    sheet = dm.Sheet(size=(1.0, 0.8), nodes=nodes, rest=get("monge"), initial=initial)
    material = dm.Material(mu=0.4, gamma=0.1, eta=FULL_ETA, xi=FULL_XI)
    return dm.Scene(sheet, material, force_model=force_model, **scene)


def perturbed(model, rng, scale=0.05):
    return model.initial_state() + scale * rng.normal(size=(model.ndof, 3))


def value_field(model, f):
    """An (ndof,) vector whose node values are f (derivative degrees of freedom zero)."""
    v = np.zeros(model.ndof)
    v[model.value_dofs] = np.ravel(f)
    return v


# -- the protocol and its shapes -----------------------------------------------------------
def test_the_protocol_names_what_the_contract_documents():
    names = set(dm.Backend.__annotations__) | {n for n, v in vars(dm.Backend).items()
                                                if callable(v) and not n.startswith("_")}
    assert names == ATTRIBUTES | METHODS
    assert dm.EnergyBackend is dm.Backend


def test_satisfies_the_protocol_with_the_documented_shapes(backend):
    M, N = 6, 5
    model = make_model(curved_scene((M, N)), backend)
    assert isinstance(model, dm.Backend)
    for name in ATTRIBUTES | METHODS:
        assert hasattr(model, name), name
    n = model.ndof
    assert n == NODE_DOFS[backend] * M * N and model.linear is False
    assert model.spacing == model.scene.sheet.h
    assert model.value_dofs.shape == (M * N,)
    X = model.initial_state()
    assert X.shape == (n, 3)
    a1, a2 = model.points
    assert a1.shape == a2.shape
    G, B = model.tensors(X)
    assert G.shape == B.shape == (2, 2, *a1.shape)
    s = model.sample(X, np.array([[0.3, 0.2], [1.0, 0.8]]))
    assert s.r.shape == (2, 3) and s.G.shape == s.B.shape == (2, 2, 2)
    for A in (model.stiffness(X), model.mass(), model.damping()):
        assert sp.isspmatrix_csr(A) and A.shape == (n, n)
    assert model.load(X, 0.0).shape == model.internal_force(X).shape == (n, 3)
    np.testing.assert_array_equal(model.internal_force(X), model.stiffness(X) @ X)
    fixed = model.fixed_dofs()
    assert len(fixed) == 3 and all(f.dtype.kind == "i" for f in fixed)
    assert model.prescribed(X, 1.0).shape == (n, 3)
    e = model.energy(X)
    assert isinstance(e, dm.Energy) and e.total == e.stretching + e.bending
    assert isinstance(model.kinetic_energy(X), float)
    var = make_model(curved_scene((M, N), "variational"), backend)
    assert var.linear is False
    assert var.energy_gradient(X).shape == (n, 3)
    np.testing.assert_array_equal(var.internal_force(X), var.energy_gradient(X))
    assert var.energy_hessian(X).shape == (3 * n, 3 * n)


def test_the_element_hessians_sum_to_the_hessian_and_the_newton_block_holds_it(backend):
    """energy_elements: element upper triangles whose sum on their pattern is energy_hessian, bit for bit; the
    Newton matrix's free upper block (FreeUpper) assembled from them is that Hessian's free block plus c_M M + c_C C
    to round-off; the frozen model's constant matrix has no elements."""
    model = make_model(curved_scene((6, 5), "variational"), backend)
    X = model.initial_state() + 1e-2 * np.random.default_rng(3).standard_normal((model.ndof, 3))
    for kind in ("newton", "definite"):
        uppers, pattern = model.energy_elements(X, kind)
        H = model.energy_hessian(X, kind)
        np.testing.assert_array_equal(pattern.matrix(pattern.collect(uppers)).toarray(), H.toarray())
    n3 = 3 * model.ndof
    M = sp.kron(sp.identity(3), model.mass(), format="csr")
    fixed = np.arange(0, n3, 7)  # some held rows and columns, dropped from the block
    free = np.setdiff1d(np.arange(n3), fixed)
    block = FreeUpper(n3, fixed, M, M, 2.0, 0.5, pattern)
    A = block.assemble(model.energy_elements(X)[0]).tocsc().toarray()
    whole = (model.energy_hessian(X) + 2.5 * M).toarray()[np.ix_(free, free)]
    np.testing.assert_allclose(A, whole, rtol=0, atol=1e-12 * np.abs(whole).max())
    frozen = make_model(dm.Scene(dm.Sheet(nodes=(6, 5)), dm.Material(mu=1.0, alpha=1.0), force_model="frozen"),
                        backend)
    assert frozen.energy_elements(frozen.initial_state()) is None


def test_grid_is_the_value_rows_and_the_initial_shape_at_the_nodes(backend):
    s = get("monge")
    model = make_model(dm.Scene(dm.Sheet(size=(1.0, 1.3), nodes=(7, 5), initial=s), dm.Material()), backend)
    X = model.initial_state()
    np.testing.assert_array_equal(model.grid(X), X[model.value_dofs].reshape(7, 5, 3))
    a1, a2 = model.scene.sheet.coordinates()
    np.testing.assert_array_equal(model.grid(X), s.r(a1, a2))
    nodes = np.stack([a1.ravel(), a2.ravel()], 1)
    assert np.max(np.abs(model.sample(X, nodes).r - model.grid(X).reshape(-1, 3))) < 10 * np.finfo(float).eps


def test_tensors_are_the_sampled_tensors_at_the_backends_points(backend):
    s = get("monge")
    model = make_model(dm.Scene(dm.Sheet(size=(1.0, 1.3), nodes=(9, 7), rest=s), dm.Material(eta=1.0)), backend)
    X = model.initial_state()
    G, B = model.tensors(X)
    a1, a2 = model.points
    smp = model.sample(X, np.stack([a1.ravel(), a2.ravel()], 1))
    assert np.max(np.abs(np.moveaxis(smp.G, 0, -1).reshape(G.shape) - G)) < 1e-12
    assert np.max(np.abs(np.moveaxis(smp.B, 0, -1).reshape(B.shape) - B)) < 1e-12


def test_sample_points_outside_the_sheet_are_refused(backend):
    model = flat_model(backend, nodes=(4, 4))
    with pytest.raises(ValueError, match=r"sample points .*1\.5.* outside"):
        model.sample(model.initial_state(), np.array([[0.5, 0.5], [1.5, 0.2]]))


# -- the rest state, K, M and C ------------------------------------------------------------
@pytest.mark.parametrize("force_model", ["tpbf87", "variational"])
def test_zero_internal_force_and_energy_at_the_rest_state_only(backend, force_model):
    model = make_model(curved_scene((9, 7), force_model, initial=get("skew")), backend)
    X0 = model.discretize(model.scene.sheet.rest)
    assert np.max(np.abs(model.internal_force(X0))) <= 1e-12 * np.max(np.abs(X0))
    e = model.energy(X0)
    assert e.stretching == 0 and e.bending == 0
    # ... and not elsewhere
    assert np.max(np.abs(model.internal_force(model.initial_state()))) > 1e-3


@pytest.mark.parametrize("force_model", ["tpbf87", "frozen"])
def test_stiffness_is_symmetric_on_a_fixed_pattern(backend, force_model, rng):
    if force_model == "frozen":
        material = dm.Material(mu=0.4, alpha=np.array([[2.0, 0.7], [0.7, 1.0]]), beta=0.3)
        model = make_model(dm.Scene(dm.Sheet(nodes=(8, 11)), material, force_model="frozen"), backend)
    else:
        model = make_model(curved_scene((8, 7), constraints=[dm.Pin("top")]), backend)
    X = perturbed(model, rng)
    K = model.stiffness(X)
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()
    K2 = model.stiffness(perturbed(model, rng))
    assert K2.indptr is K.indptr and K2.indices is K.indices
    assert np.array_equal(K2.data, K.data) == model.linear  # refilled, unless the model is linear
    for A in (model.mass(), model.damping()):
        assert abs(A - A.T).max() == 0


#: (backend, options, pointwise): the FD paper rows are pointwise, the control-area ones the trapezoidal rule
WEIGHTINGS = [("fd", {}, True), ("fd", {"weighting": "control-area"}, False), ("fe", {}, False)]
WEIGHTING_IDS = ["fd-pointwise", "fd-control-area", "fe"]


@pytest.mark.parametrize("backend, options, pointwise", WEIGHTINGS, ids=WEIGHTING_IDS)
def test_mass_damping_and_kinetic_energy_integrate_the_density(backend, options, pointwise):
    """With mu = 1 + a1 (bilinear: integrated exactly by the trapezoidal and the Gauss rule)
    1^T M 1 = integral mu = L2 (L1 + L1^2 / 2). FD's pointwise rows each stand for a whole cell h1 h2,
    M N of them: the total is h1 h2 sum mu = (L1 + h1)(L2 + h2)(1 + L1 / 2), more than the sheet's."""
    L1, L2, gamma = 1.0, 1.3, 2.0
    sheet = dm.Sheet(size=(L1, L2), nodes=(6, 5))
    h1, h2 = sheet.h
    mu = 1.0 + sheet.coordinates()[0]
    model = make_model(dm.Scene(sheet, dm.Material(mu=mu, gamma=gamma)), backend, **options)
    one = value_field(model, 1.0)
    area, mass = L1 * L2, L2 * (L1 + L1**2 / 2)
    if pointwise:
        area, mass = (L1 + h1) * (L2 + h2), (L1 + h1) * (L2 + h2) * (1 + L1 / 2)
    assert abs(one @ model.mass() @ one - mass) < 1e-13
    assert abs(one @ model.damping() @ one - gamma * area) < 1e-13
    V = np.zeros((model.ndof, 3))
    V[model.value_dofs] = [0.0, 3.0, 4.0]
    assert abs(model.kinetic_energy(V) - 0.5 * 25 * mass) < 1e-12


@pytest.mark.parametrize("backend, options, pointwise", WEIGHTINGS, ids=WEIGHTING_IDS)
def test_loads_give_the_total_force_and_first_moment(backend, options, pointwise):
    """Sum over the value rows = the total force; F . a1 (a1 interpolated exactly) = its first moment.

    Exact for FE and the FD control-area weighting; FD's pointwise body rows carry (L1 + h1)(L2 + h2) of
    area instead of L1 L2. Edge and point loads are exact on every backend."""
    L1, L2 = 1.0, 1.3
    sheet = dm.Sheet(size=(L1, L2), nodes=(6, 5))
    h1, h2 = sheet.h
    body = [dm.Gravity(2.0), dm.BodyForce((1.0, 0.0, 0.0))]
    rest = [dm.EdgeLoad("right", (0.0, 3.0, 0.0)), dm.EdgeLoad("top", (0.0, 0.0, 5.0)),
            dm.PointLoad((0.37, 0.81), (0.0, 0.0, 7.0))]
    model = make_model(dm.Scene(sheet, dm.Material(mu=0.5), forces=body + rest), backend, **options)
    F = model.load(model.initial_state(), 0.0)
    factor = (L1 + h1) * (L2 + h2) / (L1 * L2) if pointwise else 1.0
    body_total = np.array([L1 * L2, 0.0, -0.5 * 2.0 * L1 * L2])
    body_moment = np.array([1.0, 0.0, -1.0]) * L1**2 / 2 * L2
    total = factor * body_total + np.array([0.0, 3.0 * L2, 5.0 * L1 + 7.0])
    moment = factor * body_moment + np.array([0.0, 3.0 * L2 * L1, 5.0 * L1**2 / 2 + 7.0 * 0.37])
    assert np.max(np.abs(F[model.value_dofs].sum(axis=0) - total)) < 1e-12
    a1 = model.discretize(lambda x, y: np.stack(np.broadcast_arrays(x, 0 * x, 0 * x), -1))[:, 0]
    assert np.max(np.abs(a1 @ F - moment)) < 1e-12


def test_time_dependent_load(backend):
    model = flat_model(backend, nodes=(4, 4), weighting="control-area" if backend == "fd" else None,
                       forces=[dm.BodyForce((0, 0, 1.0), time=dm.Sinusoidal(frequency=1.0))])
    X = model.initial_state()
    assert np.max(np.abs(model.load(X, 0.0))) < 1e-15
    assert abs(model.load(X, 0.25)[model.value_dofs, 2].sum() - 1.0) < 1e-12


@pytest.mark.parametrize("force", [dm.PointLoad((0.2, 2.0), (0, 0, 1.0)), dm.Spring((0.2, 2.0))])
def test_a_point_outside_the_sheet_names_its_field(force):
    with pytest.raises(ValueError, match=rf"{type(force).__name__}\.at .*2\..* outside"):
        flat_scene((4, 4), forces=[force])


# -- constraints ------------------------------------------------------------------------------
def node_rows(model, where):
    """The value rows of the nodes a selection names."""
    return set(model.value_dofs[dm.select(where, model.scene.sheet).ravel()].tolist())


def test_pin_slide_and_clamp_hold_the_value_rows_they_name(backend):
    model = flat_model(backend, nodes=(5, 4), constraints=[dm.Pin("bottom-right"), dm.Slide("top", "x")])
    fx, fy, fz = (set(f.tolist()) for f in model.fixed_dofs())
    values = set(model.value_dofs.tolist())
    corner, top = node_rows(model, "bottom-right"), node_rows(model, "top")
    assert fx & values == corner and fy & values == fz & values == corner | top
    clamped = flat_model(backend, nodes=(5, 4), constraints=[dm.Clamp("left")])
    for f in clamped.fixed_dofs():
        assert set(f.tolist()) & values >= node_rows(clamped, "left")
        assert not set(f.tolist()) & node_rows(clamped, "right")


def test_bad_selections_are_named(backend):
    scene = flat_scene(nodes=(5, 5), constraints=[dm.Pin(lambda a1, a2: a1 > 2.0)])
    with pytest.raises(ValueError, match="selects no node"):
        make_model(scene, backend)
    with pytest.raises(ValueError, match=r"unknown edge or corner 'middle'"):
        make_model(flat_scene(nodes=(5, 5), constraints=[dm.Pin("middle")]), backend)


def test_slide_lets_nodes_move_along_their_axis_only(backend):
    model = flat_model(backend, nodes=(9, 9), material=dm.Material(mu=1.0, gamma=0.5, eta=20.0),
                       constraints=[dm.Slide("top", axis="x"), dm.Pin("top-left")],
                       forces=[dm.Gravity(direction=(0, -1, 0)), dm.EdgeLoad("top", f=(3.0, 0, 0))])
    X0 = model.initial_state()
    assert 2e-3 < model.stable_step()
    state = dm.TimeStepper(model, dt=2e-3).run(X0, steps=100).state
    top, top0 = model.grid(state.X)[:, -1], model.grid(X0)[:, -1]
    assert np.array_equal(top[:, 1:], top0[:, 1:])  # y and z held on the rail
    assert np.max(np.abs(top[1:, 0] - top0[1:, 0])) > 1e-4  # x moved
    assert np.array_equal(top[0], top0[0])  # the pinned corner holds


def test_pin_motion_translates_the_pinned_value_rows_only(backend):
    shift = np.array([0.1, -0.2, 0.3])
    model = flat_model(backend, nodes=(5, 4), constraints=[dm.Pin("top", motion=lambda t: t * shift)])
    X0 = model.discretize(get("monge"))
    X = model.prescribed(X0, 2.0)
    moved = sorted(node_rows(model, "top"))
    assert np.allclose(X[moved] - X0[moved], 2.0 * shift, rtol=0, atol=1e-15)
    others = np.setdiff1d(np.arange(model.ndof), moved)
    assert np.array_equal(X[others], X0[others])


def test_pin_motion_prescribes_positions_during_a_run(backend):
    model = flat_model(backend, nodes=(7, 7), material=dm.Material(mu=1.0, gamma=1.0, eta=10.0),
                       constraints=[dm.Pin("left", motion=lambda t: (0.0, 0.0, 0.5 * t))])
    dt = min(0.01, 0.5 * model.stable_step())
    states = list(dm.TimeStepper(model, dt=dt).iterate(model.initial_state(), 10))
    left = model.grid(states[-1].X)[0]
    assert np.allclose(left[:, 2], 0.5 * states[-1].t, rtol=0, atol=1e-15)


# -- the stretching bound ---------------------------------------------------------------------
def hanging(backend, nodes):
    """A sheet pinned along its top edge, falling across its plane (mu 0.1, eta 50)."""
    return flat_model(backend, nodes=(nodes, nodes), material=dm.Material(mu=0.1, gamma=0.0, eta=50.0),
                      forces=[dm.Gravity(direction=(0, -1, 0))], constraints=[dm.Pin("top")])


def test_stable_step_is_the_bound_of_the_largest_membrane_eigenvalue(backend):
    """sqrt(2 mu / (eta lambda_m)) with lambda_m the largest eigenvalue of the membrane operator per unit
    alpha against the mass, computed here from the backend's own matrices."""
    nodes = {"fd": 25, "fe": 9}[backend]
    model = hanging(backend, nodes)
    unit = flat_model(backend, nodes=(nodes, nodes), force_model="frozen",
                      material=dm.Material(mu=1.0, alpha=np.diag([1.0, 0.0])))
    lam = spla.eigsh(unit.stiffness(unit.initial_state()).tocsc(), k=1, M=unit.mass().tocsc(), which="LM",
                     return_eigenvectors=False)[0]
    bound = np.sqrt(2 * 0.1 / (50.0 * lam))
    assert 0 < model.stable_step() < np.inf
    assert abs(model.stable_step() / bound - 1) < 0.01, (model.stable_step(), bound)


def test_the_stable_step_separates_stable_runs_from_diverging_ones(backend):
    """Measured: a run at 0.9 of the bound finishes; at 1.1 and 1.5 of it, it diverges (gravity stretches the
    fibres, G > 1, which lowers the bound below its value at rest)."""
    model = hanging(backend, {"fd": 9, "fe": 5}[backend])
    runs = {f: dm.TimeStepper(model, f * model.stable_step()).run(model.initial_state(), t_end=0.5)
            for f in (0.9, 1.1, 1.5)}
    assert runs[0.9].status == "finished", runs[0.9].message
    assert runs[1.1].status == runs[1.5].status == "diverged"


@pytest.mark.parametrize("force_model", ["frozen", "variational"])
def test_models_without_a_lagged_alpha_have_no_stretching_bound(backend, force_model):
    material = dm.Material(mu=1.0, eta=10.0, alpha=1.0 if force_model == "frozen" else None)
    assert flat_model(backend, nodes=(4, 4), force_model=force_model, material=material).stable_step() == np.inf


# -- the energy and its derivatives -----------------------------------------------------------
def test_energy_gradient_matches_finite_differences_of_the_energy(backend, rng):
    model = make_model(curved_scene(SMALL[backend], "variational"), backend)
    err = gradient_error(model, perturbed(model, rng))
    assert err < 1e-6, f"relative gradient error {err:.2e}"


def test_exact_hessian_matches_finite_differences_of_the_gradient(backend, rng):
    model = make_model(curved_scene(SMALL[backend], "variational"), backend)
    H, err = hessian_error(model, perturbed(model, rng))
    assert err < 1e-6, f"relative Hessian error {err:.2e}"
    assert abs(H - H.T).max() < 1e-12 * abs(H).max()


def test_gauss_newton_hessian_is_psd_and_exact_where_residuals_vanish(backend, rng):
    model = make_model(curved_scene(SMALL[backend], "variational"), backend)
    GN = model.energy_hessian(perturbed(model, rng), "gauss-newton").toarray()
    assert np.min(np.linalg.eigvalsh(GN)) > -PSD_TOLERANCE[backend] * np.max(np.abs(GN))
    rest = model.initial_state()  # all residuals zero: the exact Hessian is Gauss-Newton, the gradient zero
    H = model.energy_hessian(rest, "newton")
    assert abs(H - model.energy_hessian(rest, "gauss-newton")).max() < 1e-12 * abs(H).max()
    assert np.max(np.abs(model.energy_gradient(rest))) < 1e-12 * abs(H).max()


def test_frozen_energy_is_half_RKR_with_its_gradient_and_hessian(backend, rng):
    model = make_model(dm.Scene(dm.Sheet(nodes=(4, 5)), dm.Material(alpha=2.0, beta=0.3), force_model="frozen"),
                       backend)
    assert model.linear
    X = model.discretize(get("monge")) + 0.01 * rng.normal(size=(model.ndof, 3))
    K = model.stiffness(X)
    assert abs(model.energy(X).total - 0.5 * np.sum(X * (K @ X))) < 1e-12 * model.energy(X).total
    g = model.energy_gradient(X)
    d = rng.normal(size=X.shape)
    e = lambda t: model.energy(X + t * d).total  # noqa: E731  (quadratic: central difference exact)
    assert abs((e(1e-3) - e(-1e-3)) / 2e-3 - np.sum(g * d)) < 1e-9 * np.sum(np.abs(g * d))
    H = model.energy_hessian(X)
    assert np.allclose(H @ X.T.ravel(), g.T.ravel(), rtol=0, atol=1e-12 * np.max(np.abs(g)))


def test_each_force_model_refuses_what_it_does_not_have(backend):
    tpbf87 = flat_model(backend, nodes=(4, 4))
    with pytest.raises(ValueError, match="tpbf87.*no energy gradient"):
        tpbf87.energy_gradient(tpbf87.initial_state())
    with pytest.raises(ValueError, match="tpbf87.*no energy gradient"):
        tpbf87.energy_hessian(tpbf87.initial_state())
    variational = flat_model(backend, nodes=(4, 4), force_model="variational")
    with pytest.raises(ValueError, match="no strength matrix"):
        variational.stiffness(variational.initial_state())
    with pytest.raises(ValueError, match="hessian kind"):
        variational.energy_hessian(variational.initial_state(), "bfgs")


# -- invariance ----------------------------------------------------------------------------------
def rotation(q):
    q = np.asarray(q, float)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


RIGID = {b: make_model(dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(11, 11), rest=get("monge")),
                                dm.Material(eta=1.0, xi=1.0)), b) for b in ("fd", "fe")}
unit = st.floats(-1, 1, allow_nan=False)


@pytest.mark.parametrize("name", ["fd", "fe"])
@settings(max_examples=40, deadline=None)
@given(q=st.tuples(unit, unit, unit, unit).filter(lambda q: np.linalg.norm(q) > 0.1),
       shift=st.tuples(*[st.floats(-100, 100, allow_nan=False)] * 3))
def test_G_and_B_are_invariant_under_rigid_motions(name, q, shift):
    """Rotate every degree of freedom, translate the positions (FE derivative dofs are not translated)."""
    model = RIGID[name]
    X0 = model.initial_state()
    G, B = model.tensors(X0)
    X = X0 @ rotation(q).T
    X[model.value_dofs] += np.asarray(shift)
    G2, B2 = model.tensors(X)
    # round-off: positions up to 1e2 differenced over h = 0.1
    tol = 1e-13 * (1 + np.max(np.abs(shift))) / min(model.spacing) ** 2
    assert np.max(np.abs(G2 - G)) < tol and np.max(np.abs(B2 - B)) < tol
