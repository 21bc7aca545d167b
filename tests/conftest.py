"""What several test modules share: a flat-sheet scene factory, the random generator, numerical derivatives.

Everything else comes from the package itself: analytic surfaces from
:mod:`validation.harness.surfaces`, the order fit from
:func:`validation.harness.orders.fit_order`, models from
:func:`validation.harness.backends.make_model`.
"""

import meshio
import numpy as np
import pytest

import deformable as dm
from deformable.geometry.surfaces import Plane
from validation.harness.backends import make_model

#: the four edges of the parameter rectangle: pinned together, a simply supported sheet
ALL_EDGES = ["left", "right", "bottom", "top"]
#: full (non-diagonal) weight tensors of eq. (13), so every component of the energy is exercised
FULL_ETA = np.array([[5.0, 1.0], [1.0, 3.0]])
FULL_XI = np.array([[0.5, 0.2], [0.2, 0.1]])


def flat_scene(nodes=(9, 9), size=(1.0, 1.0), **scene) -> dm.Scene:
    """A scene on a flat sheet; keyword arguments go to Scene (default material mu 1, gamma 0, eta 10, xi 0)."""
    material = scene.pop("material", dm.Material(mu=1.0, gamma=0.0, eta=10.0, xi=0.0))
    sheet = scene.pop("sheet", dm.Sheet(size=size, nodes=nodes))
    return dm.Scene(sheet, material, **scene)


def flat_model(backend="fd", nodes=(9, 9), size=(1.0, 1.0), weighting=None, **scene):
    """The model of :func:`flat_scene` on ``backend``; ``weighting`` is FD's option."""
    options = {} if weighting is None else {"weighting": weighting}
    return make_model(flat_scene(nodes, size, **scene), backend, **options)


def vertical_hanging(nodes) -> dm.Scene:
    """A 1 x 1 sheet hanging in the x-z plane from its top edge under gravity (tpbf87; mu 0.1, eta 50)."""
    sheet = dm.Sheet(size=(1.0, 1.0), nodes=(nodes, nodes), rest=Plane(e1=(1.0, 0.0, 0.0), e2=(0.0, 0.0, 1.0)))
    material = dm.Material(mu=0.1, gamma=0.05, eta=50.0, xi=0.0)
    return dm.Scene(sheet, material, forces=[dm.Gravity(9.81)], constraints=[dm.Pin("top")], name="hanging")


def central_differences(f, X, eps=1e-6) -> np.ndarray:
    """Central differences of f over every entry of X (ndof, 3), stacked as columns, coordinate-blocked.

    Column ``a * ndof + k`` is the derivative in X[k, a] (the layout of the energy Hessians).
    """
    cols = []
    for a in range(X.shape[1]):
        for k in range(X.shape[0]):
            Xp, Xm = X.copy(), X.copy()
            Xp[k, a] += eps
            Xm[k, a] -= eps
            cols.append(np.ravel((f(Xp) - f(Xm)) / (2 * eps)))
    return np.array(cols).T


def gradient_error(model, X) -> float:
    """max |energy_gradient - central differences of the energy|, relative to the gradient's largest entry."""
    g = model.energy_gradient(X).T.ravel()
    numeric = central_differences(lambda Y: model.energy(Y).total, X).ravel()
    return float(np.max(np.abs(g - numeric)) / np.max(np.abs(g)))


def hessian_error(model, X):
    """The exact Hessian at X, and its largest difference from central differences of the gradient (relative)."""
    H = model.energy_hessian(X, "newton")
    numeric = central_differences(lambda Y: model.energy_gradient(Y).T.ravel(), X)
    return H, float(np.max(np.abs(H.toarray() - numeric)) / np.max(np.abs(numeric)))


def sine_eigenvalue(k, nodes, L) -> float:
    """Eigenvalue of -D11 (natural rule, pinned ends) for the sine mode k: 4/h^2 sin^2(k pi h / 2L)."""
    h = L / (nodes - 1)
    return 4 / h**2 * np.sin(k * np.pi * h / (2 * L)) ** 2


def free_dofs(model, component=2) -> np.ndarray:
    """The degrees of freedom of one coordinate that no constraint holds."""
    return np.setdiff1d(np.arange(model.ndof), model.fixed_dofs()[component])


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


class Polynomial:
    """r = sum_pq c[p, q] a1^p a2^q with c (P, Q, 3): a surface with exact derivatives, for element exactness."""

    def __init__(self, c):
        self.c = np.asarray(c, float)

    def _eval(self, a1, a2, d1, d2):
        from numpy.polynomial import polynomial as P

        c = P.polyder(P.polyder(self.c, d1, axis=0), d2, axis=1) if (d1 or d2) else self.c
        return np.stack([P.polyval2d(a1, a2, c[..., k]) for k in range(3)], axis=-1)

    def r(self, a1, a2):
        return self._eval(a1, a2, 0, 0)

    def r1(self, a1, a2):
        return self._eval(a1, a2, 1, 0)

    def r2(self, a1, a2):
        return self._eval(a1, a2, 0, 1)

    def r12(self, a1, a2):
        return self._eval(a1, a2, 1, 1)


def checks_pass(res):
    """A study's result, after asserting that every one of its checks passed (the failures listed)."""
    failed = [f"{c.name}: expected {c.expectation}, observed {c.observed}" for c in res.checks if not c.passed]
    assert not failed, "\n".join(failed)
    assert res.checks, f"study {res.study} made no check"
    return res


def series_frames(xdmf):
    """(t, points, point data) of every frame of a series."""
    with meshio.xdmf.TimeSeriesReader(str(xdmf)) as reader:
        points, _ = reader.read_points_cells()
        return [(t, points, data) for t, data, _ in (reader.read_data(k) for k in range(reader.num_steps))]


def assert_same_series(a, b):
    """Two XDMF series have the same frames, times, positions and point data, bit for bit."""
    fa, fb = series_frames(a), series_frames(b)
    assert len(fa) == len(fb) > 1
    for (ta, pa, da), (tb, pb, db) in zip(fa, fb):
        assert ta == tb and set(da) == set(db)
        np.testing.assert_array_equal(pa, pb)
        for name in da:
            np.testing.assert_array_equal(da[name], db[name], err_msg=f"{name} at t = {ta}")
