"""Contact: the barrier and friction potential, its derivatives, the safe step, and no penetration ever.

- b, b', b'' of the IPC barrier and the friction mollifier against differences;
- the contact potential's gradient and Hessian (FD and FE, barrier and lagged friction) against differences
  of its energy and gradient;
- the largest safe step keeps exactly (1 - margin) of the closest gap;
- a sheet hitting the floor at 5 m/s: every Newton iterate tried, and every step taken, stays outside;
- the scene and TOML plumbing, and the paper's exponential force, which lets a fast sheet through.
"""

from dataclasses import dataclass

import numpy as np
import pytest

import deformable as dm
from deformable import contact as ct
from deformable import scenes
from deformable.contact import obstacles as ob
from deformable.geometry.surfaces import Plane
from deformable.solve.potential import FlatEnergy, flat
from validation.harness.backends import make_model

CLOTH = dict(mu=0.2, gamma=0.0, eta=np.full((2, 2), 20.0), xi=np.full((2, 2), 1e-5))


def drop_scene(nodes, height, obstacles=(dm.HalfSpace(),), contact=None, force_model="variational", **material):
    """A 1 m sheet, flat and horizontal at ``height`` above the floor, under gravity."""
    sheet = dm.Sheet(size=(1.0, 1.0), nodes=nodes, initial=Plane(origin=(0.0, 0.0, height)))
    mat = dm.Material(**{**CLOTH, **material})
    return dm.Scene(sheet, mat, forces=[dm.Gravity()], force_model=force_model, obstacles=obstacles,
                    contact=contact or dm.Contact(distance=1e-3))


def test_barrier_and_mollifier_derivatives():
    dhat = 2e-3
    d = np.linspace(1e-5, 3e-3, 301)
    h = 1e-9
    b, b1, b2 = ct.barrier(d, dhat), ct.barrier_derivative(d, dhat), ct.barrier_second(d, dhat)
    assert np.max(np.abs(b1 - (ct.barrier(d + h, dhat) - ct.barrier(d - h, dhat)) / (2 * h))) <= 1e-6 * np.max(np.abs(b1))
    assert np.max(np.abs(b2 - (ct.barrier_derivative(d + h, dhat) - ct.barrier_derivative(d - h, dhat)) / (2 * h))
                  ) <= 1e-5 * np.max(np.abs(b2))
    assert np.all(b[d >= dhat] == 0) and np.all(b[d < dhat] > 0) and np.all(b1[d < dhat] < 0)
    assert np.all(b2[d < dhat] > 0)
    assert ct.barrier(np.array([0.0, -1e-3]), dhat).tolist() == [np.inf, np.inf]
    # C2 at dhat: b, b', b'' all vanish there
    edge = np.array([dhat * (1 - 1e-7)])
    assert abs(ct.barrier(edge, dhat)[0]) < 1e-18 and abs(ct.barrier_derivative(edge, dhat)[0]) < 1e-9
    assert abs(ct.barrier_second(edge, dhat)[0]) < 1e-5

    eps = 1e-4
    y = np.linspace(0.0, 3e-4, 301)
    f0, f1y, c2 = ct.mollifier(y, eps)
    f1 = f1y * y
    num = np.gradient(f0, y)
    assert np.max(np.abs(f1 - num)[1:-1]) <= 1e-3  # f1 = f0'
    assert np.allclose(f1[y >= eps], 1, rtol=0, atol=1e-15) and f1[0] == 0 and np.all(np.diff(f1) >= -1e-15)
    assert f0[0] == pytest.approx(eps / 3) and np.all(f1y > 0)
    # the Hessian coefficient (f1' - f1/y) / y^2, checked through f1' = f1/y + c2 y^2
    f1p = f1y + c2 * y**2
    assert np.max(np.abs(f1p - np.gradient(f1, y))[1:-1]) <= 0.01 * (2 / eps)  # f1'' jumps at eps


@dataclass(frozen=True)
class Case:
    backend: str
    nodes: int
    obstacle: ob.Obstacle


CASES = [Case("fd", 6, ob.Sphere(center=(0.5, 0.5, -0.3), radius=0.3)),
         Case("fe", 3, ob.Sphere(center=(0.5, 0.5, -1.0), radius=1.0)),
         Case("fe", 3, ob.Cylinder(center=(0.5, 0.5, -0.1), radius=0.35, height=0.2, rounding=0.05))]


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c.backend}-{c.obstacle.kind}")
def test_potential_gradient_and_hessian_match_differences(case, rng):
    """Barrier plus lagged friction on a sheet lying on the obstacle: exact derivatives, and a definite projection."""
    sc = drop_scene((case.nodes,) * 2, 0.0, obstacles=(case.obstacle,),
                    contact=dm.Contact(distance=0.08, friction=0.4, slip=0.5))
    model = make_model(sc, case.backend)
    pot = ct.ContactPotential(model)
    X = model.discretize(lambda a1, a2: np.stack([a1, a2, 0.005 + 0.1 * (a1 - 0.5) ** 2 + 0.02 * (a2 - 0.5) * a1], -1))
    x = flat(X)
    pot.lag(x, dt=0.01)
    assert sum(lg.points.size for lg in pot._lagged) >= 4  # friction active at some points
    x = x + 2e-3 * rng.normal(size=x.size) * (np.arange(x.size) % model.ndof < model.ndof)  # slide a bit
    assert np.isfinite(pot.energy(x))
    g, H = pot.gradient(x), pot.hessian(x).toarray()
    eps = 1e-7
    idx = rng.choice(x.size, 40, replace=False)
    for k in idx:
        e = np.zeros_like(x)
        e[k] = eps
        gk = (pot.energy(x + e) - pot.energy(x - e)) / (2 * eps)
        Hk = (pot.gradient(x + e) - pot.gradient(x - e)) / (2 * eps)
        assert gk == pytest.approx(g[k], abs=1e-6 * np.max(np.abs(g)))
        assert np.max(np.abs(Hk - H[:, k])) <= 1e-5 * np.max(np.abs(H))
    assert np.max(np.abs(H - H.T)) <= 1e-12 * np.max(np.abs(H))
    P = pot.hessian(x, "definite").toarray()
    assert np.min(np.linalg.eigvalsh(P)) >= -1e-10 * np.max(np.abs(P))
    # one fixed pattern for every state and kind: the very same index arrays
    assert pot.hessian(x).indices is pot.hessian(x + 1e-3, "definite").indices


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_max_step_keeps_a_fraction_of_the_gap(backend):
    model = make_model(drop_scene((5, 5), 0.01), backend)
    pot = ct.ContactPotential(model)
    x = flat(model.initial_state())
    down = np.zeros_like(x)
    down[2 * model.ndof + np.asarray(model.value_dofs)] = -1.0  # every node 1 m down, through the floor
    alpha = pot.max_step(x, down)
    assert alpha == pytest.approx(0.8 * 0.01, rel=1e-12)  # margin 0.8 of the 1 cm gap
    assert pot.max_step(x, -down) == 1.0  # moving away
    assert dm.clearance(model, model.initial_state()) == pytest.approx(0.01, abs=1e-15)


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_safe_start_holds_back_only_what_meets_the_obstacle(backend):
    """A step's start (ContactPotential.safe_start): the half of the sheet sent through the floor stops above it,
    the half sent sideways moves all the way (one common fraction would have held it at 0.8 % of its way)."""
    model = make_model(drop_scene((6, 6), 0.01), backend)
    pot = ct.ContactPotential(model)
    X = model.initial_state()
    x = flat(X)
    values = np.asarray(model.value_dofs)
    left = X[values, 0] < 0.3 * model.scene.sheet.size[0]
    right = X[values, 0] > 0.7 * model.scene.sheet.size[0]
    dx = np.zeros_like(x)
    dx[2 * model.ndof + values[left]] = -1.0  # 1 m down, through the floor
    dx[model.ndof + values[right]] = 0.5  # 0.5 m along y
    start = pot.safe_start(x, dx)
    moved = start.reshape(3, -1).T - X
    assert dm.clearance(model, start.reshape(3, -1).T) > 0
    assert np.all(moved[values[left], 2] < 0)  # the left part went down, as far as the floor lets it
    assert np.allclose(moved[values[right]], [0.0, 0.5, 0.0], rtol=0, atol=1e-15)  # the right part all the way
    assert pot.max_step(x, dx) == pytest.approx(0.008, rel=1e-12)


def relax_case(backend, dhat=1e-3):
    """A sheet 0.5 dhat above the floor (one row of nodes 10 cm up), a direction that carries its nodes 0.1 to 3
    dhat down (to the barrier, or through the floor) and 0.1 mm along x, a uniform stiffness, one node held."""
    model = make_model(drop_scene((5, 5), 0.5 * dhat), backend)
    X = model.initial_state()
    values = np.asarray(model.value_dofs)
    X[values[:5], 2] = 0.1
    x, n = flat(X), model.ndof
    dx = np.zeros_like(x)
    dx[2 * n + values] = -dhat * np.random.default_rng(3).uniform(0.1, 3.0, values.size)
    dx[values] += 1e-4
    stiffness = np.full_like(x, 50.0)
    held = values[-1]
    stiffness[held::n] = dx[held::n] = 0.0
    return model, x, dx, stiffness, held


def test_relax_solves_each_contact_normal_against_the_barrier():
    """ContactPotential.relax (FD): a node the direction carries into (or through) the barrier gets the normal
    displacement s that solves its 1-D model, k (s - s_N) - w (b'(d) + b''(d) s_N) + w b'(d + s) = 0 (checked by
    bisection); its tangential displacement, the nodes far from the floor and the held one keep Newton's."""
    dhat = 1e-3
    model, x, dx, stiffness, held = relax_case("fd", dhat)
    pot = ct.ContactPotential(model)
    out = pot.relax(x, dx, stiffness)
    n = model.ndof
    moved = 0
    for j in range(n):
        d0, sN, s = x[2 * n + j], dx[2 * n + j], out[2 * n + j]
        assert out[j] == dx[j] and out[n + j] == dx[n + j]  # tangential: Newton's
        if j == held or d0 + min(sN, 0.0) >= dhat:
            assert s == sN
            continue
        w = pot.weight[j]
        b1, b2 = (fn(np.array([d0]), dhat)[0] for fn in (ct.barrier_derivative, ct.barrier_second))

        def f(t):
            return stiffness[j] * (t - sN) - w * (b1 + b2 * sN) + w * ct.barrier_derivative(np.array([d0 + t]), dhat)[0]

        lo, hi = -d0 * (1 - 1e-12), 1.0
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if f(mid) < 0 else (lo, mid)
        assert s == pytest.approx(0.5 * (lo + hi), rel=1e-6, abs=1e-12 * dhat)
        assert d0 + s > 0
        moved += s != sN
    assert moved >= 10  # the check ran over the carried nodes


def test_solved_normals_change_the_path_not_the_result(monkeypatch):
    """A sheet dropped onto the ball, to a tight Newton tolerance, with the solved contact normals and with
    Newton's own clipped directions: the same final state, to the tolerance; the solved ones were taken."""
    ball = dm.Sphere(center=(0.5, 0.5, -0.3), radius=0.3)
    model = make_model(drop_scene((8, 8), 2e-3, obstacles=(ball,)), "fd")
    X0 = model.initial_state()
    solved = []
    relax = ct.ContactPotential.relax

    def counted(self, x, dx, stiffness):
        out = relax(self, x, dx, stiffness)
        solved.append(out is not dx)
        return out

    def run():
        return dm.TimeStepper(model, dt=5e-3, newton=dict(rtol=1e-10)).run(X0, t_end=0.1).state.X

    monkeypatch.setattr(ct.ContactPotential, "relax", counted)
    with_solved = run()
    monkeypatch.setattr(ct.ContactPotential, "relax", lambda self, x, dx, stiffness: dx)
    newton_only = run()
    motion = np.max(np.abs(newton_only - X0))
    assert motion > 0.01 and sum(solved) >= 10
    assert np.max(np.abs(with_solved - newton_only)) <= 1e-8 * motion


@pytest.mark.parametrize("nodes", [5, 10, 34])
def test_fd_contact_points_are_their_nodes_alone(nodes):
    """W maps each FD contact point to its node with weight 1 and nothing else, also on grids whose
    interpolation leaves neighbours weights at round-off (a 1 m sheet on 10 x 10 nodes: 44 of them, 4e-16),
    so that relax sees every point."""
    model = make_model(drop_scene((nodes, nodes), 0.01), "fd")
    W = ct.contact_points(model).W
    assert np.array_equal(np.diff(W.indptr), np.ones(nodes * nodes, int))
    assert np.allclose(W.data, 1.0, rtol=0, atol=1e-12) and np.all(ct.contact_points(model).owner >= 0)


def test_relax_leaves_fe_directions_to_newton():
    """FE's contact points between the nodes share the nodes' degrees of freedom: relax returns the direction."""
    model, x, dx, stiffness, _ = relax_case("fe")
    assert ct.ContactPotential(model).relax(x, dx, stiffness) is dx


@pytest.mark.parametrize("backend, nodes", [("fd", (8, 8)), ("fe", (4, 4))])
def test_a_fast_drop_never_penetrates_not_even_in_a_trial_point(backend, nodes):
    """A sheet hitting the floor at 5 m/s: every potential evaluation of the line search sees a positive clearance."""
    model = make_model(drop_scene(nodes, 0.01), backend)
    stepper = dm.TimeStepper(model, 5e-3)
    pot = stepper._scheme.flat.contact
    tried = []
    energy = pot.energy

    def watched(x):
        tried.append(dm.clearance(model, x.reshape(3, -1).T))
        return energy(x)

    pot.energy = watched
    X0 = model.initial_state()
    V0 = np.zeros_like(X0)
    V0[model.value_dofs, 2] = -5.0
    taken = []
    result = stepper.run(X0, V0=V0, t_end=0.06, trackers=[dm.Callback(lambda s: taken.append(dm.clearance(model, s.X)))])
    assert result.status == "finished", result.message
    assert len(tried) >= 12 and min(tried) > 0, f"smallest clearance of a trial point {min(tried):.3g} m"
    assert min(taken) > 0
    assert taken[-1] < 1e-3  # it did land: within the barrier's reach


def test_scene_and_files_take_obstacles_and_contact(tmp_path):
    sc = drop_scene((4, 4), 0.1)
    assert sc.contact == dm.Contact(distance=1e-3)
    assert dm.Scene(sc.sheet, sc.material, obstacles=dm.Sphere()).contact == dm.Contact()
    with pytest.raises(ValueError, match="not an obstacle"):
        dm.Scene(sc.sheet, sc.material, obstacles=[(0, 0, 1)])
    with pytest.raises(ValueError, match="Contact.friction"):
        dm.Contact(friction=-0.1)
    with pytest.raises(ValueError, match="Contact.method"):
        dm.Contact(method="penalty")
    text = '''scene = "hanging"
nodes = [5, 5]

[contact]
friction = 0.4

[[obstacles]]
kind = "sphere"
center = [0.5, 0.5, -0.6]
radius = 0.5

[[obstacles]]
kind = "plane"
'''
    path = tmp_path / "ball.toml"
    path.write_text(text)
    cfg = scenes.read_toml(path)
    scene = scenes.build(cfg)
    assert [o.kind for o in scene.obstacles] == ["sphere", "plane"] and scene.contact.friction == 0.4
    assert scenes.read_toml_text(scenes.to_toml(cfg)) == cfg
    with pytest.raises(ValueError, match="unknown key 'radius'.*plane"):
        scenes.read_toml_text(text.replace('kind = "plane"', 'kind = "plane"\nradius = 1'))
    with pytest.raises(ValueError, match="unknown key 'mu'"):
        scenes.read_toml_text(text.replace("friction = 0.4", "mu = 0.4"))
    # a [contact] table overrides the scene's own settings, field by field
    assert scenes.config("sphere", contact={"slip": 0.05}).contact.friction == scenes.config("sphere").contact.friction


def test_contact_points_map_the_surface(rng):
    for backend, samples in (("fd", 1), ("fe", 2)):
        model = make_model(drop_scene((5, 4), 0.1), backend)
        pts = ct.contact_points(model)
        # each point stands for the area its mass does: FD's pointwise node areas h1 h2 (the paper's lumping),
        # the trapezoidal rule on FE's sub-grid (summing to the sheet's area)
        lumped = model.integrate(np.ones(model.points[0].shape + (3,)))[np.asarray(model.value_dofs), 0]
        area = lumped if backend == "fd" else np.full(1, 1.0)
        assert pts.samples == samples and pts.area.sum() == pytest.approx(area.sum(), rel=1e-14)
        if backend == "fd":
            assert np.array_equal(pts.area, lumped)
        X = model.discretize(lambda a1, a2: np.stack([a1 + 0.1 * a2**2, a2, np.sin(a1) * a2], -1))
        assert np.max(np.abs(pts.positions(X) - model.sample(X, pts.a).r)) <= 1e-14
        assert ct.contact_points(model) is pts  # built once per model
    # FD with points between its nodes: on the bilinear cells, with trapezoidal areas
    model = make_model(drop_scene((5, 4), 0.1, contact=dm.Contact(samples=2)), "fd")
    pts = ct.contact_points(model)
    assert pts.P == 9 * 7 and pts.area.sum() == pytest.approx(1.0, rel=1e-14)
    X = model.discretize(lambda a1, a2: np.stack([a1 + 0.1 * a2**2, a2, np.sin(a1) * a2], -1))
    assert np.max(np.abs(pts.positions(X) - model.sample(X, pts.a).r)) <= 1e-14


def test_the_schemes_refuse_the_other_method():
    with pytest.raises(ValueError, match="semi-implicit"):
        FlatEnergy(make_model(drop_scene((4, 4), 0.1, contact=dm.Contact(method="exponential")), "fd"))
    tpbf87 = drop_scene((4, 4), 0.1, force_model="tpbf87", eta=20.0, xi=0.0)
    with pytest.raises(ValueError, match="exponential"):
        dm.TimeStepper(make_model(tpbf87, "fd"), 1e-3)


def test_the_papers_exponential_force_does_not_stop_a_fast_sheet():
    """TPBF87's field c exp(-d/eps) n, evaluated at the step's start, lets a 5 m/s sheet through (as documented)."""
    contact = dm.Contact(method="exponential", distance=1e-3)
    slow = drop_scene((5, 5), 0.01, contact=contact, force_model="tpbf87", eta=20.0, xi=0.0)
    model = make_model(slow, "fd")
    rep = ct.Repulsion(model)
    X = model.initial_state()
    F = rep.force(X)
    area = ct.contact_points(model).area
    assert np.allclose(F[:, 2], rep.c * area * np.exp(-0.01 / 1e-3), rtol=1e-13, atol=0)
    assert rep.c == pytest.approx(100 * 0.2 * 9.81)
    stepper = dm.TimeStepper(model, 1e-3)
    V0 = np.zeros_like(X)
    V0[:, 2] = -5.0
    lowest = []
    stepper.run(X, V0=V0, steps=10, trackers=[dm.Callback(lambda s: lowest.append(dm.clearance(model, s.X)))])
    assert min(lowest) < 0  # through the floor


@pytest.mark.parametrize("backend, nodes", [("fd", (9, 9)), ("fe", (5, 5))])
def test_static_equilibrium_rests_on_the_ball_outside_it(backend, nodes):
    """A sheet pinned at its corners sags onto a ball: Newton's clipped steps keep it outside, in contact."""
    ball = dm.Sphere(center=(0.5, 0.5, -0.2), radius=0.2)
    sc = drop_scene(nodes, 0.02, obstacles=(ball,), xi=np.full((2, 2), 1e-3))
    sc = dm.Scene(sc.sheet, sc.material, forces=sc.forces, force_model="variational", obstacles=sc.obstacles,
                  contact=sc.contact, constraints=[dm.Pin(["top-left", "top-right", "bottom-left", "bottom-right"])])
    model = make_model(sc, backend)
    X, history = dm.equilibrium(model, model.initial_state())
    gap = dm.clearance(model, X)
    assert 0 < gap < sc.contact.distance, f"clearance {gap:.3g} m"  # resting on the ball, within the barrier
    # equilibrium raises unless the residual reached its tolerance or Newton's round-off floor, which the
    # barrier's stiffness lifts (FD 9 x 9: 3.7e-6 of the first residual); the fall is Newton's, not the start's
    assert history[-1] <= 1e-5 * history[0]


def test_the_papers_exponential_force_repels_a_gentle_landing():
    """From 2 cm (0.63 m/s at the floor) the field c exp(-d/eps) n turns the sheet back before it reaches the floor.
    Evaluated at each step's start, the force lags: weaker on the way in than on the way out, so the bounce gains
    energy and the sheet rises above its starting height."""
    cfg = scenes.config("floor", nodes=(8, 8), force_model="tpbf87", height=0.02, contact={"method": "exponential"})
    from fdmodel import FDModel

    model = FDModel(scenes.build(cfg))
    gaps = []
    result = dm.TimeStepper(model, 0.5 * model.stable_step()).run(
        model.initial_state(), t_end=0.3, trackers=[dm.Callback(lambda s: gaps.append(dm.clearance(model, s.X)))])
    assert result.status == "finished" and len(gaps) >= 50
    assert 0 < min(gaps) < cfg.contact.distance  # it came within the field's length, and no closer than the floor
    assert max(gaps[len(gaps) // 3:]) > cfg.height  # turned back, and higher than it fell from
