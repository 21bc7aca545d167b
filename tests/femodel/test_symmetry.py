"""The symmetry plane (deformable.Symmetry) on FE: a quarter model has the whole sheet's discrete solution."""

import numpy as np
import pytest

import deformable as dm
from validation.harness.backends import make_model

E, NU, H, A = 1e6, 0.3, 0.01, 1.0


def plate(nodes, size, constraints, q):
    unused = np.ones((2, 2))  # Koiter reads E, nu and h
    scene = dm.Scene(dm.Sheet(size=size, nodes=nodes), dm.Material(mu=1.0, eta=unused, xi=unused),
                     force_model=dm.Koiter(E=E, nu=NU, h=H), forces=[dm.BodyForce((0.0, 0.0, q))],
                     constraints=constraints)
    model = make_model(scene, "fe")
    X, _ = dm.equilibrium(model, model.initial_state(), tol=1e-12, load_steps=2, check_stability=False)
    return model, X


def test_a_quarter_plate_with_two_symmetry_edges_is_the_whole_plate():
    """Koiter at nu = 0.3, simply supported (edges pinned), a load that makes the deflection about 1.5 h
    (membrane action: nonlinear, so the in-plane symmetry conditions are exercised too): the quarter on 4 x 4
    elements against the whole on 8 x 8, the same elements. Their discrete solutions coincide (the whole
    plate's is symmetric and meets the quarter's held degrees of freedom), so the centres agree to the
    solver's tolerance, and every node of the quarter sits where the whole plate's does."""
    q = 40.0
    whole, Xw = plate((9, 9), (A, A), [dm.Pin(["left", "right", "bottom", "top"])], q)
    quarter, Xq = plate((5, 5), (A / 2, A / 2), [dm.Pin(["left", "bottom"]), dm.Symmetry("right", "x"),
                                                   dm.Symmetry("top", "y")], q)
    Rw, Rq = whole.grid(Xw), quarter.grid(Xq)
    centre = Rw[4, 4, 2]
    assert centre > 1.0 * H  # nonlinear range
    np.testing.assert_allclose(Rq, Rw[:5, :5], rtol=0, atol=1e-9 * centre)


def test_the_symmetry_plane_holds_its_coordinate_and_the_perpendicular_tangent():
    model, X = plate((5, 5), (A / 2, A / 2), [dm.Pin(["left", "bottom"]), dm.Symmetry("right", "x")], 40.0)
    R = model.grid(X)
    assert np.all(R[-1, :, 0] == A / 2)  # on the plane x = A / 2
    r1 = X[4 * np.arange(25).reshape(5, 5)[-1] + 1]  # h1 r_1 at the edge's nodes
    assert np.all(r1[:, 1:] == 0.0) and np.all(r1[:, 0] > 0)  # along x only: the surface meets it at right angles


def test_symmetry_is_refused_where_it_cannot_hold():
    sheet = dm.Sheet(size=(1.0, 1.0), nodes=(5, 5))
    with pytest.raises(dm.InputError, match=r"Symmetry is a constraint of the FE backend only"):
        make_model(dm.Scene(sheet, dm.Material(eta=1.0), constraints=[dm.Symmetry("right", "x")]), "fd")
    with pytest.raises(dm.InputError, match=r"Symmetry\.normal must be one of"):
        dm.Symmetry("right", "w")
    with pytest.raises(dm.InputError, match=r"Symmetry\.where must name edges"):
        dm.Symmetry("middle", "x")
    tilted = dm.Sheet(size=(1.0, 1.0), nodes=(5, 5), initial=lambda a1, a2: np.stack([a1, a2, 0.3 * a1], -1))
    with pytest.raises(dm.InputError, match=r"must lie on the plane along the edge and meet it perpendicularly"):
        make_model(dm.Scene(tilted, dm.Material(eta=1.0), constraints=[dm.Symmetry("right", "x")]), "fe")
