"""Obstacles: exact signed distances, their gradient and Hessian against differences, and the safe step."""

from dataclasses import dataclass

import numpy as np
import pytest

import deformable as dm
from deformable.contact import obstacles as ob


@dataclass(frozen=True)
class Shape:
    name: str
    obstacle: ob.Obstacle


SHAPES = [
    Shape("tilted plane", ob.HalfSpace(point=(0.1, -0.2, 0.3), normal=(0.3, -0.4, 1.0))),
    Shape("sphere", ob.Sphere(center=(0.1, 0.2, -0.3), radius=0.4)),
    Shape("sharp box", ob.Box(lower=(-0.3, -0.2, -0.1), upper=(0.4, 0.3, 0.2))),
    Shape("rounded box", ob.Box(lower=(-0.3, -0.2, -0.1), upper=(0.4, 0.3, 0.2), rounding=0.05)),
    Shape("sharp cylinder", ob.Cylinder(center=(0.1, 0.0, -0.1), radius=0.3, height=0.2)),
    Shape("rounded tilted cylinder", ob.Cylinder(center=(0.0, 0.1, 0.0), radius=0.3, height=0.4,
                                                 axis=(0.2, 0.5, 1.0), rounding=0.08)),
]


def outside_points(obstacle, rng, count=60, gap=0.02):
    """Random points at least ``gap`` outside the obstacle, within about a metre of the origin."""
    x = rng.uniform(-1.0, 1.0, size=(20 * count, 3))
    return x[obstacle.distance(x) > gap][:count]


@pytest.mark.parametrize("shape", SHAPES, ids=lambda s: s.name)
def test_gradient_and_hessian_match_central_differences(shape, rng):
    o = shape.obstacle
    x = outside_points(o, rng)
    d, g, H = o.derivatives(x)
    eps = 1e-6
    E = np.eye(3)
    g_num = np.stack([(o.distance(x + eps * E[k]) - o.distance(x - eps * E[k])) / (2 * eps) for k in range(3)], 1)
    H_num = np.stack([(o.derivatives(x + eps * E[k])[1] - o.derivatives(x - eps * E[k])[1]) / (2 * eps)
                      for k in range(3)], 2)
    assert x.shape[0] >= 40
    assert np.max(np.abs(g - g_num)) <= 1e-8, shape.name
    assert np.max(np.abs(np.linalg.norm(g, axis=1) - 1)) <= 1e-12  # an exact distance: |grad d| = 1
    assert np.max(np.abs(H - H_num)) <= 1e-6 * max(1.0, np.max(np.abs(H))), shape.name
    assert np.max(np.abs(np.einsum("pij,pj->pi", H, g))) <= 1e-12  # hess d n = 0
    assert np.min(np.linalg.eigvalsh(H)) >= -1e-12  # convex obstacle: positive semi-definite


def test_distances_in_closed_form():
    box = ob.Box(lower=(0, 0, 0), upper=(2, 2, 2), rounding=0.5)
    cases = [((1, 1, 3), 1.0), ((3, 1, 1), 1.0), ((3, 3, 1), np.sqrt(2) * 1.5 - 0.5), ((3, 3, 3), np.sqrt(3) * 1.5 - 0.5),
             ((1, 1, 1), -1.0)]
    for x, d in cases:
        assert box.distance(np.array([x], float))[0] == pytest.approx(d, abs=1e-14), x
    table = ob.Cylinder(center=(0, 0, -0.01), radius=0.09, height=0.02)
    assert table.distance(np.array([[0.05, 0.0, 0.01]]))[0] == pytest.approx(0.01, abs=1e-15)  # over the top
    assert table.distance(np.array([[0.0, 0.1, -0.01]]))[0] == pytest.approx(0.01, abs=1e-15)  # beside the side
    assert table.distance(np.array([[0.12, 0.0, 0.04]]))[0] == pytest.approx(0.05, abs=1e-15)  # off the rim (3-4-5)
    ball = ob.Sphere(center=(1, 2, 3), radius=0.5)
    assert ball.distance(np.array([[1, 2, 5]]))[0] == pytest.approx(1.5, abs=1e-15)
    floor = ob.HalfSpace(point=(0, 0, 1), normal=(0, 0, 2))
    assert floor.normal == (0.0, 0.0, 1.0)
    assert floor.distance(np.array([[5, 5, 0.25]]))[0] == pytest.approx(-0.75, abs=1e-15)


def test_first_contact_is_the_exact_root_for_plane_and_sphere(rng):
    floor = ob.HalfSpace(point=(0, 0, 0), normal=(0.0, 0.6, 0.8))
    x = rng.uniform(-1, 1, (200, 3))
    x = x[floor.distance(x) > 0.05]
    dx = rng.normal(size=x.shape)
    level = 0.2 * floor.distance(x)
    t = floor.first_contact(x, dx, level, t_max=np.inf)
    n = np.array(floor.normal)
    exact = np.where(dx @ n < 0, (floor.distance(x) - level) / -(dx @ n), np.inf)
    assert np.all(np.isinf(t) == np.isinf(exact))
    fin = np.isfinite(exact)
    assert fin.sum() >= 10
    assert np.max(np.abs(t[fin] - exact[fin]) / exact[fin]) <= 1e-13

    ball = ob.Sphere(center=(0, 0, 0), radius=0.5)
    x = np.array([[0.0, 0.0, 1.0], [0.3, 0.0, 1.0], [0.9, 0.0, 1.0], [0.0, 0.0, 1.0]])
    dx = np.array([[0.0, 0.0, -2.0], [0.0, 0.0, -2.0], [0.0, 0.0, -2.0], [0.0, 0.0, 1.0]])
    t = ball.first_contact(x, dx, 0.0, t_max=np.inf)
    # |x + t dx| = 0.5: z = sqrt(0.25 - x^2) reached at t = (1 - z) / 2; x = 0.9 misses; moving away never meets
    assert t[0] == pytest.approx(0.25, rel=1e-14)
    assert t[1] == pytest.approx((1 - 0.4) / 2, rel=1e-14)
    assert np.isinf(t[2]) and np.isinf(t[3])


@pytest.mark.parametrize("shape", SHAPES, ids=lambda s: s.name)
def test_first_contact_lands_on_the_level_from_above(shape, rng):
    o = shape.obstacle
    x = outside_points(o, rng, gap=0.05)
    dx = -2.0 * x + 0.3 * rng.normal(size=x.shape)  # mostly towards the obstacle
    level = 0.2 * o.distance(x)
    t = o.first_contact(x, dx, level, t_max=np.inf)
    hit = np.isfinite(t)
    assert hit.sum() >= 20
    reached = o.distance(x[hit] + t[hit, None] * dx[hit])
    assert np.max(np.abs(reached - level[hit])) <= 1e-11
    for s in np.linspace(0.0, 1.0, 11)[:-1]:  # above the level all along the way
        assert np.all(o.distance(x[hit] + s * t[hit, None] * dx[hit]) >= level[hit] - 1e-12)
    # beyond t_max a root is not refined: the point counts as never reaching
    assert np.all(np.isinf(o.first_contact(x[hit], dx[hit], level[hit], t_max=0.5 * np.min(t[hit]))))


def test_tables_round_trip_and_bad_input_is_named():
    for s in SHAPES:
        assert ob.from_table(s.obstacle.table()) == s.obstacle
    with pytest.raises(ValueError, match="unknown key 'radus'"):
        ob.from_table({"kind": "sphere", "radus": 1.0})
    with pytest.raises(ValueError, match="kind"):
        ob.from_table({"kind": "torus"})
    with pytest.raises(ValueError, match="Sphere.radius"):
        ob.Sphere(radius=0.0)
    with pytest.raises(ValueError, match="HalfSpace.normal"):
        ob.HalfSpace(normal=(0, 0, 0))
    with pytest.raises(ValueError, match="Box.rounding"):
        ob.Box(lower=(0, 0, 0), upper=(1, 1, 0.1), rounding=0.06)
    with pytest.raises(ValueError, match="Box.lower"):
        ob.Box(lower=(0, 0, 1), upper=(1, 1, 0))
    with pytest.raises(ValueError, match="Cylinder.rounding"):
        ob.Cylinder(radius=0.1, height=1.0, rounding=0.2)
    with pytest.warns(DeprecationWarning, match="obstacles.Plane is deprecated; use deformable.HalfSpace"):
        assert ob.Plane is dm.HalfSpace  # the former name of the half-space: one Plane now, the rest-shape surface
    assert ob.Obstacle.names() == ("plane", "sphere", "box", "cylinder", "mesh")
