"""Rendered frames (deformable.io.render): PNG frames and a GIF of a series, offscreen."""

import pytest

import deformable as dm
from deformable.io import XDMFWriter
from deformable.io.render import FIELDS, render_series
from validation.harness.backends import make_model


@pytest.fixture(scope="module")
def series(tmp_path_factory):
    folder = tmp_path_factory.mktemp("series")
    model = make_model(dm.Scene(dm.Sheet(nodes=(6, 6)), dm.Material(mu=0.1, eta=50.0), forces=[dm.Gravity()],
                                constraints=[dm.Pin("top")]), "fd")
    dm.TimeStepper(model, 1e-3).run(model.initial_state(), steps=6,
                                    trackers=[XDMFWriter(folder / "sheet.xdmf", every=2)])
    return folder / "sheet.xdmf"


def test_every_frame_becomes_a_png_and_the_gif_comes_last(series, tmp_path):
    written = render_series(series, tmp_path / "frames", field="energy_density", size=(160, 120), title="sheet")
    pngs, gif = written[:-1], written[-1]
    assert [p.name for p in pngs] == [f"frame-{k:05d}.png" for k in range(4)]
    assert all(p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for p in pngs)
    assert gif.name == "sheet.gif" and gif.stat().st_size > 0
    fewer = render_series(series, tmp_path / "few", field="z", size=(160, 120), gif=False, max_frames=2)
    assert len(fewer) == 2


def test_an_unknown_field_is_refused_before_any_work(series, tmp_path):
    with pytest.raises(ValueError, match="unknown field 'colour'"):
        render_series(series, tmp_path / "none", field="colour")
    assert not (tmp_path / "none").exists()
    assert {"speed", "energy_density", "x", "y", "z"} <= set(FIELDS)


def test_obstacles_are_drawn_in_every_frame(series, tmp_path):
    """Each kind of obstacle has a mesh inside its own bounds; a frame with them differs from one without."""
    import numpy as np
    from PIL import Image

    from deformable.io.render import obstacle_mesh, read_series

    sheet_bounds = np.array([[0.0, 0.0, -1.0], [1.0, 1.0, 0.0]])
    shapes = [dm.HalfSpace(point=(0, 0, -1.2)), dm.Sphere(center=(0.5, 0.5, -1.5), radius=0.3),
              dm.Box(lower=(0.2, 0.2, -2.0), upper=(0.8, 0.8, -1.6)),
              dm.Cylinder(center=(0.5, 0.5, -1.4), radius=0.2, height=0.1),
              dm.Cylinder(center=(0.5, 0.5, -1.4), radius=0.2, height=0.1, rounding=0.01)]
    for o in shapes:
        mesh = obstacle_mesh(o, sheet_bounds)
        assert mesh.n_points > 0
        d = o.distance(np.asarray(mesh.points))
        r = getattr(o, "rounding", 0.0)  # a rounded solid is drawn as its core: inside by the rounding at most
        assert np.max(d) <= 1e-6 and np.min(d) >= -r - 0.02, o  # never outside (float32 points); facets
    plain = render_series(series, tmp_path / "plain", field="z", size=(160, 120), gif=False, max_frames=1)
    points = read_series(series)[1][0][1]
    ball = dm.Sphere(center=tuple(points.mean(axis=0)), radius=0.2)  # in the middle of the picture
    drawn = render_series(series, tmp_path / "drawn", field="z", size=(160, 120), gif=False, max_frames=1,
                          obstacles=[ball])
    assert np.any(np.asarray(Image.open(plain[0])) != np.asarray(Image.open(drawn[0])))
