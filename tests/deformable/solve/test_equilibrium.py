r"""Static equilibrium (deformable.equilibrium) on both backends.

The clamped strip with rest curvature B0_11 = kappa and a flat rest metric (the cylinder: a compatible
pair) curls into the arc of radius 1/kappa; its tip goes to (sin(theta)/kappa, W/2, (1 - cos(theta))/kappa),
theta = kappa L. Full weight tensors (eta_12 = eta, xi_12 = xi) make shear and twist cost energy, so the
equilibrium is unique.

Theory of the tip error. FD: the clamp is a ghost row outside the edge (the central difference across the
edge is the clamp's tangent; fdmodel.clamp), the classical second-order closure: O(h^2). FE: the exact arc has
zero energy, so the discrete minimiser is, to leading order, the projection of the arc onto the bicubic space
in the linearised energy norm a(e, e) = integral 4 eta (t . e_1)^2 + xi (n . e_11)^2: membrane strain in H1,
bending in H2, error O(h^2) in that norm. The tip value J(e) = a(e, z - z_h) by duality, z the solution for a
point force at the tip: O(h^2) O(h^2) = O(h^4). (FEModel's clamp holds the slope, not the in-plane stretch at
the edge; holding r_1 whole, as it once did, left a membrane-strain layer of width h there and O(h^3).)
"""

import numpy as np
import pytest
import scipy.sparse.linalg as spla

import deformable as dm
from deformable.errors import ConvergenceError
from validation.harness.backends import make_model
from validation.harness.orders import fit_order

from ...conftest import ALL_EDGES, flat_model, free_dofs

L, W = 1.0, 0.2


def strip(backend, along, kappa, across, eta=100.0, xi=1.0):
    """A strip clamped at a1 = 0 curling to B0 = diag(kappa, 0); FD with its default (control-area) weighting."""
    scene = dm.Scene(dm.Sheet(size=(L, W), nodes=(along, across)),
                     dm.Material(eta=np.full((2, 2), eta), xi=np.full((2, 2), xi)), force_model="variational",
                     rest_curvature=np.diag([kappa, 0.0]), constraints=[dm.Clamp("left")])
    return make_model(scene, backend)


def arc_tip(kappa):
    theta = kappa * L
    return np.array([np.sin(theta) / kappa, W / 2, (1 - np.cos(theta)) / kappa])


#: backend -> (nodes along the strip, nodes across, eta, theory order, window, finest-error constant)
STRIPS = {"fd": ((11, 21, 41), 5, 100.0, 2, (1.7, 2.3), 1.0),
          "fe": ((9, 17, 33), 3, 1.0, 4, (3.7, 4.3), 0.05)}


@pytest.mark.parametrize("kappa", [2.0, -2.0])
@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_clamped_strip_curls_into_the_arc_of_its_rest_curvature(backend, kappa):
    levels, across, eta, order, (lo, hi), constant = STRIPS[backend]
    hs, errors = [], []
    for n in levels:
        model = strip(backend, n, kappa, across, eta=eta)
        X, history = dm.equilibrium(model, model.initial_state())
        assert history[-1] < 1e-7  # N, at the round-off floor of the finest FD strip
        hs.append(model.spacing[0])
        errors.append(np.linalg.norm(model.grid(X)[-1, across // 2] - arc_tip(kappa)))
    p = fit_order(hs, errors)
    assert lo <= p <= hi, f"{backend}: tip error order {p:.2f}, theory {order}; errors {errors}"
    assert errors[-1] < constant * hs[-1] ** order, f"{backend}: tip error {errors[-1]:.2e} at h = {hs[-1]}"


@pytest.mark.parametrize("kappa", [2.0, -2.0])
def test_soft_strip_on_a_fine_mesh_still_curls(kappa):
    """eta = xi = 1 on 64 FE elements: without the Newton step cap the path jumped into twisted states that
    depended on round-off; with it the arc is reached for both signs."""
    model = strip("fe", 65, kappa, 3, eta=1.0)
    X, history = dm.equilibrium(model, model.initial_state())
    assert history[-1] < 1e-8 and np.linalg.norm(model.grid(X)[-1, 1] - arc_tip(kappa)) < 1e-6


def test_the_frozen_model_equilibrium_is_the_linear_solve():
    """The frozen energy is R^T K R / 2: its equilibrium is K R = F on the free degrees of freedom."""
    model = flat_model("fe", nodes=(6, 5), force_model="frozen", material=dm.Material(alpha=0.5, beta=0.02),
                       constraints=[dm.Pin(ALL_EDGES)], forces=[dm.BodyForce((0.0, 0.0, 1e-2))])
    X, _ = dm.equilibrium(model, model.initial_state(), tol=1e-12)
    X0 = model.initial_state()
    free = free_dofs(model)
    K = model.stiffness(X0).tocsc()[free][:, free]
    F = model.load(X0, 0.0)[free, 2] - (model.stiffness(X0) @ X0)[free, 2]
    expected = X0[free, 2] + spla.spsolve(K, F)
    assert np.max(np.abs(X[free, 2] - expected)) < 1e-10 * np.max(np.abs(expected))


def test_equilibrium_says_when_it_does_not_converge():
    model = strip("fd", 11, 3.0, 5)
    with pytest.raises(ConvergenceError, match="did not converge in 2 Newton iterations"):
        dm.equilibrium(model, model.initial_state(), max_iter=2)
    with pytest.raises(ValueError, match="no energy gradient"):
        dm.equilibrium(make_model(dm.Scene(model.scene.sheet, model.scene.material), "fd"), model.initial_state())
    with pytest.raises(ValueError, match="load_steps must be a positive integer"):
        dm.equilibrium(model, model.initial_state(), load_steps=0)


@pytest.mark.parametrize("backend, along, across", [("fd", 41, 5), ("fd", 81, 9), ("fe", 17, 3), ("fe", 33, 3)])
def test_the_cantilever_reaches_its_large_deflection_from_flat_in_at_most_20_newton_iterations(backend, along, across):
    """Sze, Liu and Lo's cantilever (L = 10, b = 1, E h = 1.2e5, D = 100, nu = 0: eta = E h / 8, xi = D / 2,
    the variational model's St Venant-Kirchhoff constants) under a dead tip shear P L^2 / EI = 4, from flat,
    one load step: the definite Newton matrix and the watchdog search reach the tolerance within 20
    iterations, at the elastica's tip (-u/L, w/L) = (0.3289, 0.6700) to the discretisation error."""
    Lc, b, eta, xi, load = 10.0, 1.0, 1.2e5 / 8, 100.0 / 2, 4.0
    P = load * 2 * xi * b / Lc**2
    scene = dm.Scene(dm.Sheet(size=(Lc, b), nodes=(along, across)),
                     dm.Material(eta=np.full((2, 2), eta), xi=np.full((2, 2), xi)), force_model="variational",
                     forces=[dm.EdgeLoad("right", f=(0.0, 0.0, -P / b))], constraints=[dm.Clamp("left")])
    model = make_model(scene, backend)
    X, history = dm.equilibrium(model, model.initial_state())
    assert len(history) - 1 <= 20, f"{len(history) - 1} Newton iterations"
    tip = model.grid(X)[-1, across // 2]
    u, w = (Lc - tip[0]) / Lc, -tip[2] / Lc
    h = model.spacing[0] / Lc
    assert abs(u - 0.32894) < 2 * h**2 and abs(w - 0.66996) < 2 * h**2  # FD's ghost-row clamp: O(h^2); FE closer
