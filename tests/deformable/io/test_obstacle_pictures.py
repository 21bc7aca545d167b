"""Obstacles draw themselves (deformable.contact.obstacles.Obstacle.picture): render.obstacle_mesh asks the
obstacle, and each shape's picture is the mesh the renderer drew by its kind before (the same radii, sharp cores,
plane patch and sag rule), point for point."""

import numpy as np
import pytest

import deformable as dm
from deformable.contact.obstacles import Obstacle
from deformable.errors import InputError
from deformable.io.render import obstacle_mesh, offscreen_pyvista

pv = pytest.importorskip("pyvista")

BOUNDS = np.array([[0.0, -0.2, -0.1], [1.0, 1.3, 0.5]])
OBSTACLES = [
    dm.Sphere((0.5, 0.5, -0.3), 0.25),
    dm.Cylinder((0.1, 0.2, 0.3), 0.4, 0.2, (0.0, 1.0, 1.0), 0.05),
    dm.Box((-0.1, 0.0, 0.0), (0.3, 0.5, 0.2), 0.02),
    dm.HalfSpace((0.0, 0.0, -0.2), (0.1, 0.0, 1.0)),
    dm.MeshObstacle(vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]], faces=[[0, 1, 2], [0, 1, 3], [1, 2, 3]],
                    velocity=(0.1, 0, 0), angular_velocity=(0, 0, 1.0)),
]


def by_kind(obstacle, bounds, t=0.0, cell=0.0):
    """The renderer's switch on the obstacle's kind before the obstacles drew themselves (the reference)."""
    pv = offscreen_pyvista()
    if not obstacle.analytic:
        F = np.asarray(obstacle.triangles)
        return pv.PolyData(np.asarray(obstacle.points(t)), np.column_stack([np.full(len(F), 3), F]).ravel())
    name = type(obstacle).__name__
    if name == "Sphere":
        R = obstacle.radius
        return pv.Sphere(radius=R - min(cell * cell / (8 * R), 0.5 * R), center=obstacle.center, theta_resolution=64,
                         phi_resolution=64)
    r = getattr(obstacle, "rounding", 0.0)
    if name == "Cylinder":
        return pv.Cylinder(center=obstacle.center, direction=obstacle.axis, radius=obstacle.radius - r,
                           height=obstacle.height - 2 * r, resolution=96, capping=True)
    if name == "Box":
        lo, hi = np.asarray(obstacle.lower) + r, np.asarray(obstacle.upper) - r
        return pv.Box(bounds=(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]))
    n = np.asarray(obstacle.normal)
    centre = 0.5 * (bounds[0] + bounds[1])
    centre = centre - float((centre - np.asarray(obstacle.point)) @ n) * n
    size = 2.0 * float(np.max(bounds[1] - bounds[0])) or 1.0
    return pv.Plane(center=centre, direction=n, i_size=size, j_size=size)


@pytest.mark.parametrize("obstacle", OBSTACLES, ids=lambda o: o.kind)
@pytest.mark.parametrize("t, cell", [(0.0, 0.0), (0.4, 0.1)])
def test_each_obstacle_draws_the_picture_the_renderer_drew_by_its_kind(obstacle, t, cell):
    mine, before = obstacle_mesh(obstacle, BOUNDS, t, cell), by_kind(obstacle, BOUNDS, t, cell)
    assert type(mine) is type(before) and mine.n_points > 0
    np.testing.assert_array_equal(np.asarray(mine.points), np.asarray(before.points))
    np.testing.assert_array_equal(np.asarray(mine.faces), np.asarray(before.faces))


def test_the_sphere_shrinks_by_the_sag_of_a_cell_and_the_plane_spans_twice_the_bounds():
    sphere = OBSTACLES[0].picture(pv, BOUNDS, cell=0.1)
    radius = np.linalg.norm(np.asarray(sphere.points) - OBSTACLES[0].center, axis=1)
    assert radius.max() == pytest.approx(0.25 - 0.01 / (8 * 0.25), rel=1e-6)
    plane = OBSTACLES[3].picture(pv, BOUNDS)
    assert np.ptp(np.asarray(plane.points) @ np.array([0.0, 1.0, 0.0])) == pytest.approx(3.0, rel=1e-6)


def test_a_shape_without_a_picture_says_so_naming_its_class():
    class Blob(Obstacle):  # no name: not registered
        def derivatives(self, x, hessian=True):
            raise NotImplementedError

    with pytest.raises(InputError, match="Blob needs a picture method"):
        obstacle_mesh(Blob(), BOUNDS)
