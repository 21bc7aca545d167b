"""Arc-length continuation (deformable.solve.continuation): through a limit point, the stability of each point,
and branch switching at a simple bifurcation onto the elastica (validation.harness.shells)."""

import numpy as np
import pytest

import deformable as dm
from deformable.solve.continuation import equilibrium_path
from deformable.solve.potential import FlatEnergy, flat
from validation.harness import shells
from validation.harness.backends import make_model


def residuals(model, path):
    """The free residual max-norm of each point, from a fresh potential, relative to the load's."""
    fl = FlatEnergy(model)
    F = fl.load(0.0)
    return [np.max(np.abs((fl.gradient(flat(p.X)) - p.load * F)[fl.free])) / np.max(np.abs(F[fl.free]))
            for p in path]


@pytest.fixture(scope="module")
def arch():
    model = make_model(shells.shallow_arch(17), "fe")
    return model, equilibrium_path(model, model.initial_state(), length=5e-4, steps=12)


def test_the_path_passes_the_arch_limit_point_and_counts_its_instability(arch):
    """Load control cannot pass the limit point; the path does: the load rises to a maximum and falls while
    the middle keeps going down. Stable (no negative eigenvalue) up to the limit point, unstable after it."""
    model, path = arch
    limits = path.limit_points()
    assert limits, path.loads
    top = limits[0]
    z = path.displacement(model, (0.5, 0.05))
    assert np.all(np.diff(z[:top + 3]) < 0)  # the middle goes down through the snap
    assert np.all(path.negative[:top] == 0) and np.all(path.negative[top + 1:top + 3] >= 1), path.negative
    assert path.loads[top] == path.loads[:top + 3].max()
    # converged to the round-off floor of the internal forces (10 eps max|diag K| |x|, K's membrane part E h =
    # 1.2e7 N/m against a load of 1 N/m): measured at most 1.4e-6 of the load
    assert max(residuals(model, path)) < 1e-5


def test_a_stable_point_of_the_path_is_the_load_controlled_equilibrium(arch):
    _, path = arch
    p = path[2]
    scene = shells.shallow_arch(17)
    scaled = dm.Scene(scene.sheet, scene.material, force_model=scene.force_model, constraints=scene.constraints,
                      forces=[dm.EdgeLoad("top", f=lambda a1, a2, t, f=scene.forces[0].f: p.load * f(a1, a2, t))])
    fixed = make_model(scaled, "fe")
    X, _ = dm.equilibrium(fixed, fixed.initial_state(), tol=1e-12)
    assert np.max(np.abs(X - p.X)) < 1e-7 * np.max(np.abs(p.X))


@pytest.mark.parametrize("backend, nodes, bound", [("fe", 17, 2e-3), ("fd", 33, 7e-3)])
def test_branch_switching_at_euler_load_follows_the_elastica(backend, nodes, bound):
    """The straight column loses stability at P_cr (one negative eigenvalue past it, none before); switching
    along the critical mode follows the elastica: P / P_cr against the tip's deflection within ``bound``
    (twice the measured 8.4e-4 on FE 17 nodes, 3.5e-3 on FD 33; FE 9, 17, 33: 5.2e-3, 8.4e-4, 2.8e-5; FD 17,
    33, 65: 1.9e-2, 3.5e-3, 6.5e-4), every point of the secondary branch stable."""
    model = make_model(shells.column(nodes), backend)
    straight = equilibrium_path(model, model.initial_state(), length=0.05, psi=1.0, steps=5)
    ratio = 2 * straight.loads
    assert np.all(straight.negative[ratio < 0.99] == 0) and np.all(straight.negative[ratio > 1.01] == 1)
    assert np.any(ratio > 1.01)
    path = equilibrium_path(model, model.initial_state(), length=0.05, psi=1.0, steps=30, switch=True, max_load=0.7)
    secondary = [p for p in path if p.branch == 1]
    assert len(secondary) > 10
    errors = [abs(2 * p.load - shells.elastica_load(abs(model.grid(p.X)[-1, 1, 2]))) for p in secondary]
    assert max(errors) < bound, errors
    assert all(p.stability.negative == 0 for p in secondary)
    assert max(abs(model.grid(p.X)[-1, 1, 2]) for p in secondary) > 0.5  # well into the post-buckled range


def test_bad_arguments_are_named():
    model = make_model(shells.column(5), "fe")
    with pytest.raises(dm.InputError, match=r"equilibrium_path length must be positive"):
        equilibrium_path(model, model.initial_state(), length=0.0)
    with pytest.raises(dm.InputError, match=r"equilibrium_path steps must be a positive integer"):
        equilibrium_path(model, model.initial_state(), length=0.1, steps=0)
