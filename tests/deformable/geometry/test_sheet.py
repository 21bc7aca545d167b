"""The parameter rectangle (deformable.geometry.sheet): its grid, named places, point location and surfaces."""

import math

import numpy as np
import pytest

import deformable as dm
from deformable.geometry.sheet import CELL_CORNERS, EDGES, bilinear, bilinear_weights
from deformable.geometry.surfaces import Plane, as_surface
from validation.harness.surfaces import get


@pytest.mark.parametrize(
    "kwargs, text",
    [
        (dict(nodes=(2, 5)), r"at least 3 nodes.*\(2, 5\)"),
        (dict(nodes=(5.5, 5)), r"two integers.*5\.5"),
        (dict(size=(1.0, -1.0)), r"Sheet\.size.*-1\.0"),
        (dict(size=(1.0, math.nan)), r"Sheet\.size.*nan"),
    ],
)
def test_sheet_rejects_bad_grids(kwargs, text):
    with pytest.raises(ValueError, match=text):
        dm.Sheet(**kwargs)


def test_edges_are_the_rows_of_the_node_grid():
    sheet = dm.Sheet(size=(2.0, 1.0), nodes=(5, 4))
    a1, a2 = sheet.coordinates()
    for name, line in (("left", a1 == 0), ("right", a1 == 2.0), ("bottom", a2 == 0), ("top", a2 == 1.0)):
        mask = np.zeros(sheet.nodes, bool)
        mask[sheet.edge(name).index] = True
        np.testing.assert_array_equal(mask, line)
        assert EDGES[name].along == (0 if name in ("bottom", "top") else 1)
    two = np.zeros(sheet.nodes, bool)
    two[sheet.edge("top").rows(2)] = True
    np.testing.assert_array_equal(two, a2 >= 1.0 - sheet.h[1] - 1e-12)
    with pytest.raises(ValueError, match=r"unknown edge 'middle'; expected one of"):
        sheet.edge("middle")


def test_locate_gives_the_cell_and_reference_coordinates(rng):
    sheet = dm.Sheet(size=(2.0, 1.3), nodes=(5, 4))
    h1, h2 = sheet.h
    a = rng.uniform([0, 0], [2.0, 1.3], size=(50, 2))
    i, j, s, t = sheet.locate(a)
    assert np.all((0 <= s) & (s <= 1) & (0 <= t) & (t <= 1))
    np.testing.assert_allclose((i + s) * h1, a[:, 0], rtol=0, atol=1e-14)
    np.testing.assert_allclose((j + t) * h2, a[:, 1], rtol=0, atol=1e-14)
    # the far edges belong to the last cell, at reference coordinate 1
    i, j, s, t = sheet.locate([2.0, 1.3])
    assert (i[0], j[0], s[0], t[0]) == (3, 2, 1.0, 1.0)


@pytest.mark.parametrize("point", [(2.0 + 1e-6, 0.5), (-1e-6, 0.5), (0.5, 1.31), (0.5, -0.1), (math.nan, 0.2)])
def test_locate_refuses_points_outside_the_rectangle(point):
    sheet = dm.Sheet(size=(2.0, 1.3), nodes=(5, 4))
    with pytest.raises(ValueError, match="PointLoad.at"):
        sheet.locate(np.array([[0.5, 0.5], point]), "PointLoad.at")


def test_bilinear_interpolation_is_exact_on_bilinear_fields(rng):
    sheet = dm.Sheet(size=(2.0, 1.3), nodes=(5, 4))
    f = lambda a1, a2: 0.3 + 1.2 * a1 - 0.7 * a2 + 0.9 * a1 * a2  # noqa: E731
    field = f(*sheet.coordinates())
    a = rng.uniform([0, 0], [2.0, 1.3], size=(40, 2))
    np.testing.assert_allclose(bilinear(field, *sheet.locate(a)), f(a[:, 0], a[:, 1]), rtol=0, atol=1e-13)
    s, t = rng.uniform(size=(2, 10))
    assert np.allclose(sum(bilinear_weights(s, t)), 1.0)
    assert len(CELL_CORNERS) == 4


def test_a_plain_callable_is_a_surface_with_numerical_derivatives():
    exact = get("monge")
    numeric = as_surface(exact.r)
    a1, a2 = np.meshgrid(np.linspace(0.1, 0.9, 5), np.linspace(0.1, 0.9, 5), indexing="ij")
    # first derivatives: truncation and round-off about 1e-10; the nested r12 loses more to round-off
    for name, tol in (("r", 0.0), ("r1", 1e-9), ("r2", 1e-9), ("r12", 1e-6)):
        assert np.max(np.abs(getattr(numeric, name)(a1, a2) - getattr(exact, name)(a1, a2))) <= tol, name
    with pytest.raises(ValueError, match="expected a surface"):
        as_surface(3.0)


def test_rest_is_the_plane_and_initial_the_rest_by_default():
    sheet = dm.Sheet(size=(1.0, 2.0), nodes=(3, 5))
    a1, a2 = sheet.coordinates()
    np.testing.assert_array_equal(sheet.rest.r(a1, a2), np.stack([a1, a2, 0 * a1], -1))
    assert sheet.initial is sheet.rest
    assert sheet.with_nodes((7, 9)).h == (1.0 / 6, 2.0 / 8)


def test_plane_is_exact():
    p = Plane(origin=(1.0, 2.0, 3.0), e1=(0.0, 1.0, 0.0), e2=(0.0, 0.0, 1.0))
    a1, a2 = np.array([0.0, 0.5]), np.array([1.0, 0.25])
    np.testing.assert_array_equal(p.r(a1, a2), [[1.0, 2.0, 4.0], [1.0, 2.5, 3.25]])
    assert p.r1(a1, a2).shape == (2, 3) and not p.r12(a1, a2).any()


def test_fibre_stretch_is_each_segments_strain_against_the_rest_shape():
    """A cylinder of radius 0.5 as the rest shape, stretched by 2 % along a1 and compressed by 1 % along a2: every
    segment's chord changes by exactly those factors (a chord of the arc scales with the radius)."""
    import numpy as np

    from deformable.geometry.sheet import Sheet

    def rest(a1, a2):
        return np.stack([0.5 * np.sin(a1 / 0.5), a2, 0.5 * (1 - np.cos(a1 / 0.5))], axis=-1)

    sheet = Sheet(size=(1.0, 0.6), nodes=(7, 5), rest=rest)
    a1, a2 = sheet.coordinates()
    r = rest(a1, a2)
    stretched = np.stack([1.02 * r[..., 0], 0.99 * r[..., 1], 1.02 * r[..., 2]], axis=-1)
    s1, s2 = sheet.fibre_stretch(stretched)
    assert s1.shape == (6, 5) and s2.shape == (7, 4)
    np.testing.assert_allclose(s1, 0.02, atol=1e-12)
    np.testing.assert_allclose(s2, -0.01, atol=1e-12)
