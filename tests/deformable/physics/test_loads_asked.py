"""Loads ask each force what it adds (deformable.physics.forces roles, deformable.physics.loads): a user's own
applied, conservative and velocity loads go through a Scene and into F of eq. (21) as the built-in ones do, and
the built-in ones keep their order of summation."""

import numpy as np
import pytest
import scipy.sparse as sp

import deformable as dm
from deformable.errors import InputError
from deformable.physics.forces import AppliedLoad, ConservativeLoad, Load, VelocityLoad
from deformable.solve.potential import flat

from ...conftest import flat_model, flat_scene


class Push(AppliedLoad):
    """A user's applied load: a uniform density f (N/m^2) over the sheet, integrated against the basis."""

    def __init__(self, f):
        self.f = np.asarray(f, float)

    def applied(self, loads, t):
        m = loads.model
        return m.integrate(np.broadcast_to(self.f, m.points[0].shape + (3,)))


class Tethers:
    """The potential of :class:`Tether` loads: k |X - X0|^2 / 2 over every degree of freedom."""

    rank, factored, linear = 3, False, True

    def __init__(self, model, tethers):
        self.k, self.X0, self.n = sum(t.k for t in tethers), model.initial_state(), model.ndof

    def energy(self, X, t, factor=1.0):
        return 0.5 * self.k * float(np.sum((X - self.X0) ** 2))

    def gradient(self, X, t, factor=1.0):
        return self.k * (X - self.X0)

    def hessian(self, X, t, factor=1.0):
        return sp.identity(3 * self.n, format="csr") * self.k


class Tether(ConservativeLoad):
    """A user's conservative load: every degree of freedom held to its start by a spring of stiffness k."""

    potential = Tethers

    def __init__(self, k):
        self.k = k


class Drag(VelocityLoad):
    """A user's velocity load: a linear drag -c v per unit current area."""

    def __init__(self, c):
        self.c = c

    def density(self, n, area, v, t):
        return -self.c * area[:, None] * v

    def damping(self, n, area, v, t):
        return self.c * area[:, None, None] * np.broadcast_to(np.eye(3), (area.size, 3, 3))


@pytest.fixture(params=["fd", "fe"])
def backend(request):
    return request.param


def test_a_users_applied_load_is_taken_and_applied_as_the_built_in_body_force(backend):
    f = (0.2, -0.5, 1.5)
    mine = flat_model(backend, nodes=(5, 6), forces=[Push(f)]).loads
    theirs = flat_model(backend, nodes=(5, 6), forces=[dm.BodyForce(f)]).loads
    np.testing.assert_array_equal(mine.applied(0.3), theirs.applied(0.3))
    assert not mine.potentials and mine.conservative and mine.linear


def test_a_users_conservative_load_enters_the_potential(backend, rng):
    m = flat_model(backend, nodes=(5, 5), forces=[dm.Gravity(), Tether(3.0), Tether(1.0)])
    loads = m.loads
    X = m.initial_state() + 0.01 * rng.normal(size=(m.ndof, 3))
    d = X - m.initial_state()
    assert loads.potentials and loads.linear and [type(p) for p in loads.parts] == [Tethers]
    assert loads.potential_energy(X, 0.0) == pytest.approx(2.0 * np.sum(d**2), rel=1e-14)
    np.testing.assert_allclose(loads.total(X, 0.0), loads.applied(0.0) - 4.0 * d, rtol=0, atol=1e-14)
    (H,) = loads.potential_hessians(X, 0.0)
    assert abs(H - 4.0 * sp.identity(3 * m.ndof)).max() == 0


def test_a_users_velocity_load_is_a_damping_taken_as_the_wind_is(backend, rng):
    m = flat_model(backend, nodes=(5, 5), forces=[Drag(0.7)])
    loads = m.loads
    X, V = m.initial_state(), rng.normal(size=(m.ndof, 3))
    assert not loads.conservative and not loads.linear and len(loads.winds) == 1
    F = flat(loads.wind_force(X, V, 0.0))
    np.testing.assert_allclose(F, -(loads.wind_damping(X, V, 0.0) @ flat(V)), rtol=0, atol=1e-12 * abs(F).max())


def test_point_loads_are_added_after_the_distributed_ones_in_the_scenes_order(backend):
    """F of eq. (21) sums the body and edge loads in the scene's order, then the point loads: bit for bit."""
    point, gravity, edge = dm.PointLoad((0.3, 0.6), (1.0, 2.0, -3.0)), dm.Gravity(), dm.EdgeLoad("top", (0, 0.5, 1))
    m = flat_model(backend, nodes=(5, 6), forces=[point, gravity, edge])
    expected = np.zeros((m.ndof, 3)) + m.integrate(gravity.density(*m.points, 0.2, m.mu))
    rule = m.edge_rule("top")
    expected += rule.at.T @ (rule.weights[:, None] * edge.traction(rule.a1, rule.a2, 0.2))
    dofs, w = m.point_dofs(point.at, "PointLoad.at")
    expected[dofs] += w[:, None] * point.force(0.2)[None]
    np.testing.assert_array_equal(m.loads.applied(0.2), expected)


def test_a_scene_refuses_what_is_not_a_load_in_one_line_naming_the_field():
    with pytest.raises(InputError) as caught:
        flat_scene(forces=[dm.Gravity(), 42])
    message = str(caught.value)
    assert message.startswith("Scene.forces: 42 is not a Gravity") and "\n" not in message
    assert caught.value.field == "Scene.forces" and caught.value.value == 42

    class Roleless(Load):
        """A Load of no role: nothing says what it adds."""

    with pytest.raises(InputError, match="Scene.forces: .*Roleless.* is not a .*AppliedLoad, ConservativeLoad or "
                                         "VelocityLoad"):
        flat_scene(forces=[Roleless()])


def test_a_point_load_checks_its_point_against_the_sheet():
    with pytest.raises(InputError, match="PointLoad.at"):
        flat_scene(forces=[dm.PointLoad((2.0, 0.5), (0.0, 0.0, 1.0))])
