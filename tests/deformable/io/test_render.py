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


@pytest.mark.slow  # a slow fault or a whole pipeline, run by pytest -m slow
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


def test_a_frame_has_a_colour_bar_with_the_fields_title_and_the_time(series):
    """One renderer: render_frame draws the shaded surface, a colour bar titled with the field and its unit
    (TITLES) and the simulated time; frame_image lays panels out side by side, one bar for the picture."""
    import numpy as np

    from deformable.io.render import TITLES, Panel, frame_image, plotter, read_series, render_frame, time_label

    cells, frames = read_series(series)
    t, points, data = frames[-1]
    p = plotter((160, 120))
    try:
        render_frame(p, points, np.hstack([np.full((len(cells), 1), 4), cells]).ravel(), data["speed"], "speed",
                     (0.0, 1.0), "sheet", t=t)
        bars = [k.strip() for k in p.scalar_bars.keys()]  # noqa: SIM118 (ScalarBars is not a dict)
        assert bars == [TITLES["speed"]] == ["speed (m/s)"]
        assert p.actors["time"].input == time_label(t) == f"t = {t:.2f} s"
        assert p.actors["title"].input == "sheet"
        assert p.renderer.GetLights().GetNumberOfItems() == 5  # the light kit, not VTK's flat headlight
    finally:
        p.close()
    assert time_label(0.4) == "t = 0.40 s"
    grid = points.reshape(6, 6, 3)
    img = frame_image([[Panel(grid, grid[..., 2].ravel(), "FD", 0.0), Panel(grid, grid[..., 2].ravel(), "FE", t)]],
                      (120, 100), field="z")
    assert img.shape == (100, 240, 3) and img.dtype == np.uint8


def test_the_papers_media_frames_carry_their_time(tmp_path):
    """The README's animation (validation.studies.paper.pictures, drawn by the same renderer): frames differ in
    their time text even where the sheet does not move."""
    import io

    import numpy as np
    from PIL import Image

    from validation.studies.paper.pictures import animation, render, rest_axis

    a1, a2 = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 6), indexing="ij")
    pts = np.stack([a1, 0.0 * a1, a2], axis=-1)
    assert rest_axis(pts) == 1
    gif = Image.open(io.BytesIO(animation([("still", 0.0, pts), ("still", 0.5, pts)], size=(160, 120))))
    first = np.asarray(gif.convert("RGB"))
    gif.seek(1)
    assert np.any(np.asarray(gif.convert("RGB")) != first)
    assert Image.open(io.BytesIO(render([[("a", 0.0, pts), ("b", 1.0, pts)]], size=(120, 100)))).size == (240, 100)


def test_rendering_without_pyvista_is_one_line_naming_the_extra(monkeypatch):
    import sys

    from deformable.errors import InputError
    from deformable.io.render import offscreen_pyvista

    monkeypatch.setitem(sys.modules, "pyvista", None)  # as on the core install
    with pytest.raises(InputError) as err:
        offscreen_pyvista()
    assert "deformable-sheets[render]" in str(err.value) and "\n" not in str(err.value)
