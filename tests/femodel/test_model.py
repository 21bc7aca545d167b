"""FEModel: the element, the protocol, K, M, loads, energy, constraints and bad input."""

import numpy as np
import pytest
from numpy.polynomial import polynomial as P

import deformable as dm
from femodel import ELEMENTS, FEModel
from femodel.hermite import LOCAL, basis

from .conftest import fe_model
from .surfaces import MongePatch, SkewSheet

EPS = np.finfo(float).eps


class Bicubic:
    """r = sum_pq c[p, q] a1^p a2^q with c (4, 4, 3): the element must reproduce it exactly."""

    def __init__(self, c):
        self.c = c

    def _eval(self, a1, a2, d1, d2):
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


# -- the element ------------------------------------------------------------
def test_shape_functions_are_dual_to_the_scaled_nodal_dofs():
    """h1^p h2^q d^(p+q) phi_l at corner (a, b) is 1 for l = (a, b, p, q) and 0 otherwise."""
    h = (0.3, 0.7)
    for a in (0, 1):
        for b in (0, 1):
            for p in (0, 1):
                for q in (0, 1):
                    v = basis(np.array([float(a)]), np.array([float(b)]), h, (p, q))[:, 0] * h[0] ** p * h[1] ** q
                    expected = np.array([float(loc == (a, b, p, q)) for loc in LOCAL])
                    assert np.max(np.abs(v - expected)) < 10 * EPS, (a, b, p, q, v)


def test_bicubic_surfaces_are_reproduced_exactly(rng):
    sheet = dm.Sheet(size=(1.0, 1.3), nodes=(6, 5))
    model = FEModel(dm.Scene(sheet, dm.Material(eta=1.0)))
    c = rng.normal(size=(4, 4, 3)) * 0.3
    c[1, 0] += [1.0, 0.0, 0.0]
    c[0, 1] += [0.0, 1.0, 0.0]
    surface = Bicubic(c)
    a = rng.uniform([0, 0], [1.0, 1.3], size=(200, 2))
    s = model.sample(model.discretize(surface), a)
    r1, r2 = surface.r1(a[:, 0], a[:, 1]), surface.r2(a[:, 0], a[:, 1])
    G = np.stack([np.stack([(r1 * r1).sum(-1), (r1 * r2).sum(-1)], -1),
                  np.stack([(r1 * r2).sum(-1), (r2 * r2).sum(-1)], -1)], -2)
    assert np.max(np.abs(s.r - surface.r(a[:, 0], a[:, 1]))) < 1e-13
    assert np.max(np.abs(s.G - G)) < 1e-12


def test_sample_at_nodes_is_grid():
    model = fe_model(nodes=(7, 5), size=(1.0, 1.3))
    X = model.discretize(MongePatch())
    a1, a2 = model.scene.sheet.coordinates()
    s = model.sample(X, np.stack([a1.ravel(), a2.ravel()], 1))
    assert np.max(np.abs(s.r - model.grid(X).reshape(-1, 3))) < 10 * EPS
    assert np.array_equal(model.grid(X), MongePatch().r(a1, a2))


# -- the protocol and the matrices ----------------------------------------------
def test_satisfies_the_backend_protocol():
    model = fe_model(nodes=(5, 4))
    assert isinstance(model, dm.Backend)
    assert model.ndof == 4 * 5 * 4 and not model.linear
    assert model.initial_state().shape == (model.ndof, 3)
    assert model.mesh.t.shape[1] == 4 * 3  # (M - 1)(N - 1) skfem elements on the sheet's nodes


def curved_model(**kw):
    sheet = dm.Sheet(size=(1.0, 1.3), nodes=(9, 7), rest=MongePatch(), initial=SkewSheet())
    eta = np.array([[20.0, 3.0], [3.0, 10.0]])
    xi = np.array([[0.5, 0.1], [0.1, 0.3]])
    return FEModel(dm.Scene(sheet, dm.Material(mu=0.4, gamma=0.1, eta=eta, xi=xi), **kw))


def test_stiffness_is_symmetric_on_a_fixed_pattern():
    model = curved_model()
    K = model.stiffness(model.initial_state())
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()
    K2 = model.stiffness(model.discretize(MongePatch()) * 1.1)
    assert K2.indptr is K.indptr and K2.indices is K.indices
    for A in (model.mass(), model.damping()):
        assert A.indptr is K.indptr and A.indices is K.indices
        assert abs(A - A.T).max() == 0


def test_zero_internal_force_at_the_rest_state():
    model = curved_model()
    X0 = model.discretize(MongePatch())
    assert np.max(np.abs(model.internal_force(X0))) <= 1e-12 * np.max(np.abs(X0))
    e = model.energy(X0)
    assert e.stretching == 0 and e.bending == 0
    # ... and not elsewhere
    assert np.max(np.abs(model.internal_force(model.initial_state()))) > 1e-3


def test_mass_and_kinetic_energy_integrate_the_density():
    """Constant 1 is the value dofs set to 1: 1^T M 1 = integral mu (bilinear mu is integrated exactly)."""
    sheet = dm.Sheet(size=(1.0, 1.3), nodes=(6, 5))
    mu = 1.0 + sheet.coordinates()[0]  # 1 + a1
    model = FEModel(dm.Scene(sheet, dm.Material(mu=mu, gamma=2.0)))
    one = np.zeros(model.ndof)
    one[0::4] = 1.0
    assert abs(one @ model.mass() @ one - (1.3 + 1.3 / 2)) < 1e-13
    assert abs(one @ model.damping() @ one - 2.0 * 1.3) < 1e-13
    V = np.zeros((model.ndof, 3))
    V[0::4] = [0.0, 3.0, 4.0]
    assert abs(model.kinetic_energy(V) - 0.5 * 25 * 1.95) < 1e-12


def test_loads_give_the_total_force_and_moment():
    """Sum over value dofs = total force; F . (a1 interpolated) = first moment (exact: a1 is bicubic)."""
    L1, L2 = 1.0, 1.3
    forces = [
        dm.Gravity(2.0),
        dm.BodyForce((1.0, 0.0, 0.0)),
        dm.EdgeLoad("right", (0.0, 3.0, 0.0)),
        dm.EdgeLoad("top", (0.0, 0.0, 5.0)),
        dm.PointLoad((0.37, 0.81), (0.0, 0.0, 7.0)),
    ]
    sheet = dm.Sheet(size=(L1, L2), nodes=(6, 5))
    model = FEModel(dm.Scene(sheet, dm.Material(mu=0.5), forces=forces))
    F = model.load(model.initial_state(), 0.0)
    total = F[0::4].sum(axis=0)
    expected = np.array([L1 * L2, 3.0 * L2, -0.5 * 2.0 * L1 * L2 + 5.0 * L1 + 7.0])
    assert np.max(np.abs(total - expected)) < 1e-12
    a1 = model.discretize(lambda x, y: np.stack(np.broadcast_arrays(x, 0 * x, 0 * x), -1))[:, 0]
    moment = a1 @ F
    expected = np.array([L1**2 / 2 * L2, 3.0 * L2 * L1, -0.5 * 2.0 * L1**2 / 2 * L2 + 5.0 * L1**2 / 2 + 7.0 * 0.37])
    assert np.max(np.abs(moment - expected)) < 1e-12


def test_time_dependent_load():
    model = fe_model(nodes=(4, 4), forces=[dm.BodyForce((0, 0, 1.0), time=dm.Sinusoidal(frequency=1.0))])
    X = model.initial_state()
    assert np.max(np.abs(model.load(X, 0.0))) < 1e-15
    assert abs(model.load(X, 0.25)[0::4, 2].sum() - 1.0) < 1e-12


def test_tpbf87_energy_of_a_stretched_sheet_is_exact():
    """r = (s a1, a2, 0), rest flat: G11 = s^2, so eq. (13) gives eta (s^2 - 1)^2 L1 L2."""
    s, eta = 1.2, 3.0
    sheet = dm.Sheet(size=(1.0, 1.3), nodes=(5, 6), initial=lambda a1, a2: np.stack(
        np.broadcast_arrays(s * a1, a2, 0 * a1), -1))
    model = FEModel(dm.Scene(sheet, dm.Material(eta=eta, xi=1.0)))
    e = model.energy(model.initial_state())
    assert abs(e.stretching - eta * (s**2 - 1) ** 2 * 1.3) < 1e-12 and e.bending == 0


def test_tpbf87_bending_energy_of_a_cylinder_converges():
    """A flat sheet rolled to radius R: B11 = 1/R, energy xi L1 L2 / R^2 (+ O(h^2) from B)."""
    R, xi = 0.8, 2.0
    cyl = lambda a1, a2: np.stack(np.broadcast_arrays(  # noqa: E731
        R * np.sin(a1 / R), a2, R * (1 - np.cos(a1 / R))), -1)
    errs = []
    for n in (8, 16):
        sheet = dm.Sheet(size=(1.0, 1.3), nodes=(n + 1, n + 1), initial=cyl)
        model = FEModel(dm.Scene(sheet, dm.Material(eta=1.0, xi=xi)))
        e = model.energy(model.initial_state())
        errs.append(abs(e.bending / (xi * 1.3 / R**2) - 1))
        assert e.stretching < 1e-8
    assert errs[1] < 2e-4 and errs[1] < errs[0] / 3, errs


def test_frozen_energy_is_half_RKR_split():
    """Frozen alpha = a I, beta = b I on r = (a1, a2, a1^2 a2) over the unit square:
    stretching a/2 (2 + 29/45), bending b/2 (4/3)."""
    a, b = 3.0, 0.7
    c = np.zeros((4, 4, 3))
    c[1, 0, 0] = c[0, 1, 1] = c[2, 1, 2] = 1.0
    sheet = dm.Sheet(size=(1.0, 1.0), nodes=(5, 5), initial=Bicubic(c))
    model = FEModel(dm.Scene(sheet, dm.Material(alpha=a, beta=b), force_model="frozen"))
    assert model.linear
    e = model.energy(model.initial_state())
    assert abs(e.stretching - a / 2 * (2 + 29 / 45)) < 1e-12 and abs(e.bending - b / 2 * 4 / 3) < 1e-12


def test_frozen_energy_gradient_and_hessian(rng):
    model = FEModel(dm.Scene(dm.Sheet(nodes=(4, 5)), dm.Material(alpha=2.0, beta=0.3), force_model="frozen"))
    X = model.discretize(MongePatch()) + 0.01 * rng.normal(size=(model.ndof, 3))
    g = model.energy_gradient(X)
    d = rng.normal(size=X.shape)
    e = lambda t: model.energy(X + t * d).total  # noqa: E731  (quadratic: central difference exact)
    assert abs((e(1e-3) - e(-1e-3)) / 2e-3 - np.sum(g * d)) < 1e-9 * np.sum(np.abs(g * d))
    H = model.energy_hessian(X)
    assert np.allclose(H @ X.T.ravel(), g.T.ravel(), rtol=0, atol=1e-12 * np.max(np.abs(g)))
    with pytest.raises(ValueError, match="tpbf87"):
        fe_model(nodes=(4, 4)).energy_gradient(np.zeros((64, 3)))


# -- constraints --------------------------------------------------------------
def dofs(model, mask, k):
    """Set of the k-th degrees of freedom (0 value, 1 h1 r_1, 2 h2 r_2, 3 h1 h2 r_12) of masked nodes."""
    return set((4 * np.flatnonzero(mask) + k).tolist())


def test_pinned_edges_fix_values_and_tangential_derivatives():
    model = fe_model(nodes=(5, 4), constraints=[dm.Pin(["left", "bottom"])])
    M, N = 5, 4
    left, bottom = np.zeros((M, N), bool), np.zeros((M, N), bool)
    left[0, :], bottom[:, 0] = True, True
    expected = dofs(model, left | bottom, 0) | dofs(model, left, 2) | dofs(model, bottom, 1)
    for f in model.fixed_dofs():
        assert set(f.tolist()) == expected  # r_12 stays free, also at the corner


def test_pins_by_predicate_or_corner_fix_values_only():
    model = fe_model(nodes=(5, 4), constraints=[dm.Pin(lambda a1, a2: a2 > 0.99), dm.Pin("bottom-left")])
    mask = np.zeros((5, 4), bool)
    mask[:, -1] = mask[0, 0] = True
    for f in model.fixed_dofs():
        assert set(f.tolist()) == dofs(model, mask, 0)


def test_slide_and_clamp():
    model = fe_model(nodes=(5, 4), constraints=[dm.Slide("top", "x"), dm.Clamp("left")])
    top, left = np.zeros((5, 4), bool), np.zeros((5, 4), bool)
    top[:, -1], left[0, :] = True, True
    clamp = set().union(*(dofs(model, left, k) for k in range(4)))
    fx, fy, fz = (set(f.tolist()) for f in model.fixed_dofs())
    assert fx == clamp
    assert fy == fz == clamp | dofs(model, top, 0) | dofs(model, top, 1)


def test_pin_motion_translates_value_dofs_only():
    shift = np.array([0.1, -0.2, 0.3])
    model = fe_model(nodes=(5, 4), constraints=[dm.Pin("top", motion=lambda t: t * shift)])
    X0 = model.discretize(MongePatch())
    X = model.prescribed(X0, 2.0)
    top = np.zeros((5, 4), bool)
    top[:, -1] = True
    moved = sorted(dofs(model, top, 0))
    assert np.allclose(X[moved] - X0[moved], 2.0 * shift, rtol=0, atol=1e-15)
    rest = np.setdiff1d(np.arange(model.ndof), moved)
    assert np.array_equal(X[rest], X0[rest])


# -- bad input ----------------------------------------------------------------
def test_unknown_element_names_the_valid_ones():
    scene = dm.Scene(dm.Sheet(nodes=(4, 4)), dm.Material())
    with pytest.raises(ValueError, match="element.*hermite.*'bfs'"):
        FEModel(scene, element="bfs")
    assert ELEMENTS == ("hermite",)


def test_variational_has_no_strength_matrix():
    scene = dm.Scene(dm.Sheet(nodes=(4, 4)), dm.Material(eta=1.0), force_model="variational")
    model = FEModel(scene)
    with pytest.raises(ValueError, match="no strength matrix"):
        model.stiffness(model.initial_state())


def test_bad_input_names_field_and_value():
    model = fe_model(nodes=(4, 4))
    with pytest.raises(ValueError, match=r"X has shape \(16, 3\), expected \(64, 3\)"):
        model.stiffness(np.zeros((16, 3)))
    with pytest.raises(ValueError, match=r"V has shape"):
        model.kinetic_energy(np.zeros(64))
    with pytest.raises(ValueError, match=r"sample points .*1\.5.* outside"):
        model.sample(model.initial_state(), np.array([[0.5, 0.5], [1.5, 0.2]]))
    bad = fe_model(nodes=(4, 4), forces=[dm.PointLoad((0.2, 2.0), (0, 0, 1.0))])
    with pytest.raises(ValueError, match=r"PointLoad.at .*2\..* outside"):
        bad.load(bad.initial_state(), 0.0)
    with pytest.raises(ValueError, match=r"Scene.rest_metric callable returned shape"):
        fe_model(nodes=(4, 4), rest_metric=lambda a1, a2: np.ones(a1.shape + (3,)))
    with pytest.raises(ValueError, match=r"Material.mu"):
        fe_model(nodes=(4, 4), material=dm.Material(mu=np.ones((3, 4))))
