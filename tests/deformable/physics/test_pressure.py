"""Follower pressure (deformable.Pressure, deformable.physics.pressure): the potential -p V, its gradient the
follower load p r_1 x r_2 where every edge is held, its exact Hessian, and the refusal where an edge is free."""

import numpy as np
import pytest

import deformable as dm
from validation.harness.backends import make_model

EDGES = ["left", "right", "bottom", "top"]


def bulged(a1, a2):
    s = np.sin(np.pi * a1) * np.sin(np.pi * a2)
    return np.stack([a1 + 0.05 * s, a2, 0.2 * s], -1)


def model(backend, nodes, p=2.0, constraints=None, initial=bulged, forces=None):
    unused = np.ones((2, 2))
    sheet = dm.Sheet(size=(1.0, 1.0), nodes=(nodes, nodes), initial=initial)
    scene = dm.Scene(sheet, dm.Material(mu=1.0, eta=unused, xi=unused), force_model=dm.Koiter(E=1e4, nu=0.3, h=0.01),
                     forces=forces if forces is not None else [dm.Pressure(p)],
                     constraints=constraints or [dm.Pin(EDGES)])
    return make_model(scene, backend)


def defect(m, p=2.0):
    """max |grad(-p V) - (-p int phi (r_1 x r_2))| over the free value rows, relative to the latter."""
    pp = m.loads._pressure
    X = m.initial_state()
    _, r1, r2 = pp._fields(X)
    direct = np.zeros((m.ndof, 3))
    np.add.at(direct, pp.cols, -p * np.einsum("gqc,gq,gqd->gcd", pp.T[0], pp.w, np.cross(r1, r2)))
    rows = np.setdiff1d(m.value_dofs, m.fixed_dofs()[0])
    return np.max(np.abs((pp.gradient(X, 0.0) - direct)[rows])) / np.max(np.abs(direct[rows]))


def test_on_fe_the_potential_gives_the_follower_load_to_round_off():
    assert max(defect(model("fe", n)) for n in (5, 9)) < 1e-11


def test_on_fd_the_potential_gives_the_follower_load_at_second_order():
    """Measured 6.3e-3, 1.7e-3, 4.3e-4 on 9, 17, 33 nodes; the bound is twice the finest."""
    e = np.array([defect(model("fd", n)) for n in (9, 17, 33)])
    orders = np.log2(e[:-1] / e[1:])
    assert np.all((orders > 1.7) & (orders < 2.3)) and e[-1] < 9e-4, (e, orders)


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_the_gradient_and_hessian_are_exact(backend, rng):
    m = model(backend, 5)
    pp = m.loads._pressure
    X = m.initial_state() + 0.02 * rng.normal(size=(m.ndof, 3))
    g, H = pp.gradient(X, 0.0).T.ravel(), pp.hessian(X, 0.0)
    x, eps = X.T.ravel(), 1e-6
    for k in rng.choice(x.size, 10, replace=False):
        e = np.zeros_like(x)
        e[k] = eps
        up, down = (x + e).reshape(3, -1).T, (x - e).reshape(3, -1).T
        assert abs((pp.energy(up, 0.0) - pp.energy(down, 0.0)) / (2 * eps) - g[k]) <= 1e-7 * abs(g).max()
        col = (pp.gradient(up, 0.0).T.ravel() - pp.gradient(down, 0.0).T.ravel()) / (2 * eps)
        np.testing.assert_allclose(H[:, k].toarray().ravel(), col, rtol=0, atol=1e-6 * abs(col).max())
    assert abs(H - H.T).max() <= 1e-12 * abs(H).max()


def test_a_small_pressure_is_the_dead_load_of_the_flat_plate():
    """On the flat pinned plate a pressure p and the dead load (0, 0, p) agree to first order in the slope:
    centre deflections within 1e-3 at a deflection of about 0.04 h."""
    def flat(a1, a2):
        return np.stack([a1, a2, 0 * a1], -1)

    w = []
    for forces in ([dm.Pressure(1e-4)], [dm.BodyForce((0.0, 0.0, 1e-4))]):
        m = model("fe", 9, initial=flat, forces=forces)
        X, _ = dm.equilibrium(m, m.initial_state(), tol=1e-12, check_stability=False)
        w.append(m.grid(X)[4, 4, 2])
    assert w[0] > 0 and abs(w[0] / w[1] - 1) < 1e-3, w


def test_a_pressure_on_a_sheet_with_a_free_edge_is_refused():
    with pytest.raises(dm.InputError, match=r"Pressure: .*edges are all held.*free: top"):
        model("fe", 5, constraints=[dm.Pin(["left", "right", "bottom"])])
    with pytest.raises(dm.InputError, match=r"Pressure\.p must be a number"):
        dm.Pressure("high")
