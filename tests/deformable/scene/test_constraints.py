"""Constraints (deformable.scene.constraints): node selections and the one mapping of constraints to dofs."""

import numpy as np
import pytest

import deformable as dm
from deformable.scene.constraints import HeldDofs, hold

SHEET = dm.Sheet(size=(1.0, 1.0), nodes=(5, 4))


def test_every_kind_of_selection_names_the_same_nodes():
    top = np.zeros(SHEET.nodes, bool)
    top[:, -1] = True
    by_index = np.array([[m, 3] for m in range(5)])
    for where in ("top", ["top"], by_index, lambda a1, a2: a2 > 0.99):
        np.testing.assert_array_equal(dm.select(where, SHEET), top)
    both = dm.select(["left", "bottom-right"], SHEET)
    assert both.sum() == 4 + 1 and both[-1, 0] and both[0].all()


@pytest.mark.parametrize("where, message", [
    (lambda a1, a2: a1 > 2.0, "selects no node"),
    ("middle", r"unknown edge or corner 'middle'"),
    (np.array([[5, 0]]), "lie outside the 5 x 4 grid"),
    (np.array([0.5, 0.5]), "cannot select nodes"),
])
def test_bad_selections_are_named(where, message):
    with pytest.raises(ValueError, match=message):
        dm.select(where, SHEET)


def test_slide_axis_and_clamp_edges_are_checked():
    assert dm.Slide("top", "z").axis == 2 and dm.Slide("top", 1).axis == 1
    assert dm.Slide("top", ("y", "x")).axes == (0, 1)
    for bad in ("w", ("x", "x"), ("x", "y", "z"), (), True):
        with pytest.raises(ValueError, match="Slide.axis"):
            dm.Slide("top", bad)
    with pytest.raises(ValueError, match="Clamp.where must name edges"):
        dm.Clamp("top-left")
    assert dm.Clamp(["left", "top"]).edges == ["left", "top"]


def test_hold_maps_pins_slides_and_clamps_through_the_backends_callbacks():
    """A backend with two dofs per node (value 2k, slope 2k + 1): edges also hold their slope, clamps both."""
    scene = dm.Scene(SHEET, dm.Material(), constraints=[
        dm.Pin("bottom-left", motion=lambda t: (t, 0.0, 0.0)), dm.Slide("top", "y"), dm.Clamp("right")])
    node = lambda mask: 2 * np.flatnonzero(mask)  # noqa: E731
    edge = lambda name: 2 * np.flatnonzero(dm.select(name, SHEET)) + 1  # noqa: E731
    clamp = lambda name: np.concatenate([edge(name) - 1, edge(name)])  # noqa: E731
    held = hold(scene, 2 * 20, node, edge, clamp)
    assert isinstance(held, HeldDofs)
    corner, top, right = {0}, set(edge("top") - 1) | set(edge("top")), set(clamp("right"))
    fx, fy, fz = (set(f.tolist()) for f in held.fixed)
    assert fx == fz == corner | top | right and fy == corner | right
    plane = dm.Scene(SHEET, dm.Material(), constraints=[dm.Slide("top", ("x", "y"))])
    fx, fy, fz = (set(f.tolist()) for f in hold(plane, 2 * 20, node, edge, clamp).fixed)
    assert fx == fy == set() and fz == top  # a plane slide holds only the third coordinate
    X0 = np.zeros((40, 3))
    X = held.prescribed(X0, 2.0)
    assert X[0].tolist() == [2.0, 0.0, 0.0] and not X[1:].any()


def test_a_pin_may_hold_some_coordinates_only():
    assert dm.Pin("top").axes is None and dm.Pin("top").held == (0, 1, 2)
    assert dm.Pin("top", axes=("z", "x")).held == (0, 2) and dm.Pin("top", axes="y").held == (1,)
    for bad in ("w", ("x", "x"), (), True):
        with pytest.raises(ValueError, match="Pin.axes"):
            dm.Pin("top", axes=bad)
    node = lambda mask: np.flatnonzero(mask)  # noqa: E731
    none = lambda name: np.array([], int)  # noqa: E731
    scene = dm.Scene(SHEET, dm.Material(), constraints=[dm.Pin("top-right", motion=lambda t: (t, 5.0, 0.0),
                                                               axes=("x", "z"))])
    held = hold(scene, 20, node, none, none)
    corner = set(np.flatnonzero(dm.select("top-right", SHEET)).tolist())
    fx, fy, fz = (set(f.tolist()) for f in held.fixed)
    assert fx == fz == corner and fy == set()  # y stays free: its prescribed value is never used
