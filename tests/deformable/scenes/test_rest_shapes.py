"""Named rest shapes in scene files (deformable/scenes/rest_shapes.py): G0 and B0 of a Monge patch, the paper's
compatibility test on them (`deformable check` with KEY=VALUE), and bad input in one line."""

import numpy as np
import pytest

from deformable import scenes
from deformable.errors import InputError
from deformable.geometry import tensors
from deformable.scenes.rest_shapes import from_table
from validation.commands import main

SIZE = (1.0, 0.8)


def _fd_tensors(f, a1, a2, h=1e-4):
    """G and B of r = (a1, a2, f) by central differences of f (independent of the patch's formulas)."""
    def r(x, y):
        return np.stack([x, y, f(x, y)], -1)
    r1 = (r(a1 + h, a2) - r(a1 - h, a2)) / (2 * h)
    r2 = (r(a1, a2 + h) - r(a1, a2 - h)) / (2 * h)
    r11 = (r(a1 + h, a2) - 2 * r(a1, a2) + r(a1 - h, a2)) / h**2
    r22 = (r(a1, a2 + h) - 2 * r(a1, a2) + r(a1, a2 - h)) / h**2
    r12 = (r(a1 + h, a2 + h) - r(a1 + h, a2 - h) - r(a1 - h, a2 + h) + r(a1 - h, a2 - h)) / (4 * h * h)
    dr = np.moveaxis(np.stack([r1, r2], -2), (-1, -2), (0, 1))
    ddr = np.moveaxis(np.stack([np.stack([r11, r12], -2), np.stack([r12, r22], -2)], -3), (-1, -3, -2), (0, 1, 2))
    G, B = tensors.metric(dr), tensors.curvature(ddr, tensors.normal(dr))
    return np.moveaxis(G, (0, 1), (-2, -1)), np.moveaxis(B, (0, 1), (-2, -1))


@pytest.mark.parametrize("table, f", [
    ({"kind": "sphere", "radius": 2.0}, lambda x, y: 2.0 - np.sqrt(4.0 - (x - 0.5) ** 2 - (y - 0.4) ** 2)),
    ({"kind": "cylinder", "radius": 0.9}, lambda x, y: 0.9 - np.sqrt(0.81 - (x - 0.5) ** 2) + 0 * y),
    ({"kind": "saddle", "curvature": 0.7}, lambda x, y: 0.35 * ((x - 0.5) ** 2 - (y - 0.4) ** 2)),
])
def test_the_patch_has_the_surfaces_metric_and_curvature(table, f):
    patch = from_table(table, SIZE)
    a1, a2 = np.meshgrid(np.linspace(0.05, 0.95, 7), np.linspace(0.05, 0.75, 6), indexing="ij")
    G, B = _fd_tensors(f, a1, a2)
    np.testing.assert_allclose(patch.metric(a1, a2), G, atol=1e-7)
    np.testing.assert_allclose(patch.curvature(a1, a2), B, atol=1e-5)


def test_a_height_field_interpolates_its_heights():
    x, y = np.meshgrid(np.linspace(0, 1.0, 9), np.linspace(0, 0.8, 7), indexing="ij")
    z = 0.05 * np.sin(np.pi * x) * np.cos(np.pi * y)
    patch = from_table({"kind": "height", "z": z.tolist()}, SIZE)
    G = patch.metric(x, y)
    # f_1 = 0.05 pi cos(pi x) cos(pi y): the bicubic spline's within a few per cent of it on 9 x 7 samples
    f1 = 0.05 * np.pi * np.cos(np.pi * x) * np.cos(np.pi * y)
    np.testing.assert_allclose(G[..., 0, 0], 1 + f1**2, atol=3e-3)


def test_a_sphere_shows_the_papers_ratio_and_cosine(capsys):
    assert main(["check", "hanging", 'rest_shape={kind="sphere", radius=2}', "--grid", "17x17"]) == 0
    out = capsys.readouterr().out
    # exit 0: the ratio and the cosine within 0.05 of one at every resolved point; printed, not the residual alone
    assert "rest state compatible" in out and out.count("ratio ") == 2 and out.count("cosine ") == 2


def test_a_rest_shape_round_trips_through_a_scene_file():
    cfg = scenes.config("hanging", rest_shape={"kind": "saddle", "curvature": 0.5})
    back = scenes.read_toml_text(scenes.to_toml(cfg), source="test")
    assert back.rest_shape == {"kind": "saddle", "curvature": 0.5}
    assert scenes.build(back).rest_curvature is not None


@pytest.mark.parametrize("fields, message", [
    (dict(rest_shape={"kind": "torus"}), "rest_shape.kind must be one of"),
    (dict(rest_shape={"kind": "sphere", "radius": 0.2}), "rest_shape.radius must exceed"),
    (dict(rest_shape={"kind": "sphere", "radius": "big"}), "rest_shape.radius must be a finite number"),
    (dict(rest_shape={"kind": "saddle", "curvature": 1.0, "radius": 2.0}), "unknown key 'radius'"),
    (dict(rest_shape={"kind": "height", "z": [[0, 1], [1, 0]]}), "at least 4 x 4"),
    (dict(rest_shape={"kind": "sphere", "radius": 2.0}, rest_curvature=(1.0, 0.0)), "cannot be given with"),
])
def test_bad_rest_shapes_name_the_field(fields, message):
    with pytest.raises(InputError, match=message):
        scenes.config("hanging", **fields)
