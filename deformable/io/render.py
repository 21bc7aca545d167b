"""Pictures of a sheet: one renderer for ``deformable run --render``, the README's animations and the reports.

A *frame* is the sheet drawn offscreen with pyvista: its surface smooth-shaded under a light kit and coloured by a
point field, a colour bar with the field's name and unit (:data:`TITLES`), the simulated time (``t = 0.40 s``) and a
label in the corners, and a scene's obstacles and rods in grey. :func:`render_frame` draws one frame into a plotter;
:func:`frame_image` draws rows of panels (FD above FE, or the start, middle and end of a run) side by side in a fresh
plotter, one camera and one colour range for all, and returns the screenshot; :func:`png_bytes` and :func:`gif_bytes`
encode them (a GIF with one palette for all its frames, so that the colours do not flicker).

:func:`render_series` draws the XDMF time series that :mod:`deformable.io.series` writes (positions = mesh points +
the point field ``displacement``), so a run that was killed or diverged can still be drawn: PNG frames and a GIF, the
camera and the field's colour range fixed over the series. Each obstacle draws itself
(:meth:`~deformable.contact.obstacles.Obstacle.picture`, through :func:`obstacle_mesh`).

Every picture gets a fresh plotter (:func:`plotter`): ``Plotter.clear()`` removes the light kit too. Headless
machines: VTK falls back from an X window to EGL when no display is there, after a warning; choosing EGL up front
(``VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow``) avoids the warning.
"""

from __future__ import annotations

import io
import logging
import math
import os
from pathlib import Path
from dataclasses import dataclass

import numpy as np

from ..checks import extra
from ..errors import InputError
from ..progress import Progress, counted

__all__ = ["FIELDS", "TITLES", "Panel", "camera", "colour_range", "frame_image", "gif_bytes", "grid_faces",
           "obstacle_mesh", "offscreen_pyvista", "plotter", "png_bytes", "read_series", "render_frame", "render_series",
           "time_digits", "time_label"]

log = logging.getLogger(__name__)

#: point fields that can colour the sheet (written by deformable.io.series)
FIELDS = ("speed", "energy_density", "G11", "G12", "G22", "B11", "B12", "B22", "x", "y", "z")
#: the colour bar's title of each field, with its unit (G is dimensionless, B = n . r_ij is 1/m)
TITLES = {"speed": "speed (m/s)", "energy_density": "energy density (J/m^2)", "x": "x (m)", "y": "y (m)",
          "z": "z (m)", **{f"G{ij}": f"G{ij} (1)" for ij in ("11", "12", "22")},
          **{f"B{ij}": f"B{ij} (1/m)" for ij in ("11", "12", "22")}}
_AXIS = {"x": 0, "y": 1, "z": 2}
#: the sheet's material under the light kit: diffuse, some ambient (the shadowed side stays readable), a soft highlight
SURFACE = {"smooth_shading": True, "ambient": 0.2, "diffuse": 0.8, "specular": 0.25, "specular_power": 20.0}
#: the default view direction of :func:`camera` (from the front-right, slightly above; z up)
VIEW = (0.8, -1.0, 0.6)
#: pyvista's view angle (degrees)
VIEW_ANGLE = 30.0


@dataclass(frozen=True)
class Panel:
    """One surface of a picture: ``points`` (P, 3) or (M, N, 3) (a node grid), ``values`` (P,) for the colour,
    ``label`` (upper left) and ``t`` (s, the time drawn upper right; None: none)."""

    points: np.ndarray
    values: np.ndarray
    label: str = ""
    t: float | None = None


def offscreen_pyvista():
    """pyvista set to draw off screen (EGL where there is no display); without pyvista, an InputError saying in one
    line how to install it (the ``render`` extra, :func:`deformable.checks.extra`)."""
    if not os.environ.get("DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    pyvista = extra("pyvista", "render", "rendering (deformable.io.render)")
    pyvista.OFF_SCREEN = True
    return pyvista


def _faces(cells: np.ndarray) -> np.ndarray:
    """pyvista face array [4, i, j, k, l, ...] from (n, 4) quads."""
    cells = np.asarray(cells, dtype=np.int64)
    return np.hstack([np.full((cells.shape[0], 1), cells.shape[1]), cells]).ravel()


def grid_faces(nodes: tuple[int, int]) -> np.ndarray:
    """pyvista face array of the quads of an M x N node grid, node (m, n) at m N + n (the series' cells)."""
    M, N = nodes
    idx = np.arange(M * N).reshape(M, N)
    return _faces(np.column_stack([idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(),
                                   idx[:-1, 1:].ravel()]))


def camera(bounds: np.ndarray, direction=VIEW, margin: float = 1.05):
    """A camera position (position, focal point, view up) framing an axis-aligned box.

    ``bounds`` is (2, 3): min and max corners. The view looks from ``direction`` (by default from the front-right,
    slightly above), with z up; ``margin`` > 1 leaves room around the box.
    """
    lo, hi = np.asarray(bounds, float)
    centre = 0.5 * (lo + hi)
    radius = 0.5 * float(np.linalg.norm(hi - lo)) or 1.0
    direction = np.asarray(direction, float)
    direction = direction / np.linalg.norm(direction)
    distance = radius / np.tan(np.radians(VIEW_ANGLE) / 2) * margin
    return [tuple(centre + distance * direction), tuple(centre), (0.0, 0.0, 1.0)]


def colour_range(values, percentile: float = 100.0, symmetric: bool = False) -> tuple[float, float]:
    """(low, high) of the finite ``values``: their ``percentile`` range (100: min and max; 98 leaves a few outlying
    points out, so they do not wash the rest out); ``symmetric``: about 0, when the values have both signs. Never
    empty: a constant field gets a range of 1 about its value."""
    v = np.concatenate([np.ravel(x) for x in values]) if isinstance(values, (list, tuple)) else np.ravel(values)
    v = v[np.isfinite(v)]
    if not v.size:
        return 0.0, 1.0
    lo, hi = (float(v.min()), float(v.max())) if percentile >= 100 else \
        (float(np.percentile(v, 100 - percentile)), float(np.percentile(v, percentile)))
    if symmetric and lo < 0 < hi:
        lo, hi = -max(-lo, hi), max(-lo, hi)
    if hi <= lo:
        lo, hi = lo - 0.5, lo + 0.5
    return lo, hi


def time_label(t: float, digits: int = 2) -> str:
    """``t = 0.40 s``: the simulated time with ``digits`` decimals."""
    return f"t = {t:.{digits}f} s"


def time_digits(times) -> int:
    """Decimals that tell frames at these times apart (2 at least, 6 at most)."""
    steps = np.diff(np.unique(np.round(np.asarray(times, float), 9)))
    steps = steps[steps > 0]
    if not steps.size:
        return 2
    return int(min(6, max(2, math.ceil(-math.log10(float(steps.min())) - 1e-9))))


def plotter(size=(640, 480), shape=(1, 1)):
    """A fresh offscreen plotter of ``shape`` (rows, columns) panels of ``size`` (width, height) pixels each: white
    background, a light kit in every panel."""
    pv = offscreen_pyvista()
    rows, cols = shape
    p = pv.Plotter(off_screen=True, shape=(rows, cols), window_size=[size[0] * cols, size[1] * rows], border=False,
                   lighting="light kit")
    p.set_background("white")
    return p


def _bar(field: str, title: str | None) -> str:
    return title or TITLES.get(field, field)


def render_frame(plotter, points, faces, values, field, clim, title="", obstacles=(), *, t=None, digits: int = 2,
                 cmap="viridis", bar_title: str | None = None, scalar_bar: bool = True, rods=(), view=None,
                 shift: bool | None = None, font_size: int = 10, clear: bool = True):
    """Draw one frame into ``plotter``'s active panel (the plotter cleared first and its light kit put back, unless
    ``clear`` is False: a panel of a layout).

    The surface (``points`` (P, 3), pyvista ``faces``) is smooth-shaded and coloured by ``values`` (P,) over
    ``clim`` with ``cmap``. The colour bar (``scalar_bar``) stands at the right edge, upright, its title (the field
    and its unit, :data:`TITLES`, or ``bar_title``) above it and three labels of three significant digits beside it,
    so that no label meets the title or another label. ``title`` is written upper left, the time ``t`` (s,
    :func:`time_label` with ``digits`` decimals) upper right. ``obstacles``: pyvista meshes drawn in grey; ``rods``:
    segments ((x, y, z), (x, y, z)) drawn as dark grey rods (a curtain's rail, a flag's pole); ``view``: a camera
    position (:func:`camera`); ``shift`` (default: with a colour bar) moves the picture left, clear of the bar.
    """
    pv = offscreen_pyvista()
    if clear:
        plotter.clear()
        plotter.renderer.remove_all_lights()
        plotter.enable_lightkit(only_active=True)
    points = np.asarray(points, float).reshape(-1, 3)
    for mesh in obstacles:
        plotter.add_mesh(mesh, color="lightgrey", **SURFACE)
    if len(rods):
        extent = float(np.linalg.norm(np.ptp(np.concatenate([points, np.reshape(rods, (-1, 3))]), axis=0))) or 1.0
        for a, b in rods:
            plotter.add_mesh(pv.Tube(pointa=a, pointb=b, radius=0.005 * extent, n_sides=24), color="#505050",
                             **SURFACE)
    mesh = pv.PolyData(points, faces)
    name = _bar(field, bar_title)
    mesh.point_data[name] = np.ravel(values)
    actor = plotter.add_mesh(mesh, scalars=name, clim=clim, cmap=cmap, show_edges=False, show_scalar_bar=False,
                             **SURFACE)
    if scalar_bar:
        plotter.add_scalar_bar(name + "\n", mapper=actor.mapper, vertical=True, position_x=0.84, position_y=0.12,
                               width=0.06, height=0.62, n_labels=3, fmt="%.3g", title_font_size=font_size + 3,
                               label_font_size=font_size + 2, color="black")
    for text, x, side, name in ((title, 0.02, "left", "title"), (None if t is None else time_label(t, digits), 0.98,
                                                                     "right", "time")):
        if text:
            actor = plotter.add_text(text, position=(x, 0.97), viewport=True, font_size=font_size, color="black",
                                     name=name)
            actor.prop.justification_horizontal, actor.prop.justification_vertical = side, "top"
    if view is not None:
        plotter.camera_position = view
        if scalar_bar if shift is None else shift:
            plotter.camera.SetWindowCenter(0.12, 0.0)  # the picture left of the colour bar
    return actor


def frame_image(panels, size=(360, 320), *, faces=None, field: str = "", clim=None, view=None, cmap="viridis",
                bar_title: str | None = None, obstacles=(), rods=(), digits: int | None = None,
                font_size: int = 10, bar: str = "last") -> np.ndarray:
    """Rows of :class:`Panel` drawn side by side in a fresh plotter (:func:`plotter`); the screenshot (H, W, 3)
    uint8.

    One colour range (``clim``, default :func:`colour_range` of all the panels' values), one camera (``view``,
    default :func:`camera` framing every panel and rod) for all panels; ``faces``: the pyvista faces of the points
    (default: the quads of each panel's (M, N, 3) node grid, :func:`grid_faces`). ``bar``: which panels carry the
    colour bar, ``"last"`` (the last of the picture), ``"all"`` or ``"none"``; ``digits``: the time's decimals
    (default :func:`time_digits` of the panels' times).
    """
    rows = [list(r) for r in panels]
    flat = [p for r in rows for p in r]
    if not flat:
        raise ValueError("a picture needs at least one panel")
    clim = colour_range([p.values for p in flat]) if clim is None else clim
    if view is None:
        pts = [np.reshape(p.points, (-1, 3)) for p in flat] + [np.reshape(rods, (-1, 3))]
        pts = np.concatenate(pts)
        view = camera(np.array([pts.min(axis=0), pts.max(axis=0)]))
    if digits is None:
        digits = time_digits([p.t for p in flat if p.t is not None])
    shape = (len(rows), max(len(r) for r in rows))
    p = plotter(size, shape)
    try:
        for i, row in enumerate(rows):
            for j, panel in enumerate(row):
                p.subplot(i, j)
                f = faces if faces is not None else grid_faces(np.shape(panel.points)[:2])
                last = (i, j) == (len(rows) - 1, len(row) - 1)
                render_frame(p, panel.points, f, panel.values, field, clim, panel.label, obstacles, t=panel.t,
                             digits=digits, cmap=cmap, bar_title=bar_title, rods=rods, view=view,
                             scalar_bar=bar == "all" or (bar == "last" and last), shift=bar != "none",
                             font_size=font_size, clear=False)
        return p.screenshot(None, return_img=True)
    finally:
        p.close()


def png_bytes(image: np.ndarray, colors: int = 128) -> bytes:
    """A picture (H, W, 3) uint8 as a palette PNG of ``colors`` colours."""
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(image).convert("P", palette=Image.ADAPTIVE, colors=colors).save(buf, format="png", optimize=True)
    return buf.getvalue()


def gif_bytes(images, fps: float = 12.0, colors: int = 96) -> bytes:
    """A looping GIF of pictures, each (H, W, 3) uint8 or the path of an image file: one palette of ``colors`` for
    all (from a mosaic of every sixth picture), no dithering, so that frames do not flicker and the file stays
    small. Files are read as needed, not all held at once in full colour."""
    from PIL import Image

    def rgb(im):
        return (Image.open(im) if isinstance(im, (str, Path)) else Image.fromarray(np.asarray(im))).convert("RGB")

    images = list(images)
    if not images:
        raise ValueError("an animation needs at least one frame")
    picked = [rgb(im) for im in images[::6]]
    w, h = picked[0].size
    mosaic = Image.new("RGB", (w * len(picked), h))
    for k, im in enumerate(picked):
        mosaic.paste(im, (k * w, 0))
    palette = mosaic.convert("P", palette=Image.ADAPTIVE, colors=colors)
    gif = [rgb(im).quantize(palette=palette, dither=Image.Dither.NONE) for im in images]
    buf = io.BytesIO()
    gif[0].save(buf, format="gif", save_all=True, append_images=gif[1:], duration=int(1000 / fps), loop=0,
                optimize=True)
    return buf.getvalue()


def obstacle_mesh(obstacle, bounds: np.ndarray, t: float = 0.0, cell: float = 0.0):
    """A pyvista mesh of an obstacle, which draws itself (:meth:`deformable.contact.Obstacle.picture`): a plane a
    square patch twice the extent of ``bounds`` (2, 3); a mesh obstacle its own triangles where they are at time t
    (s); a sphere smaller by the sag h^2 / (8 R) of a sheet cell's diagonal h = ``cell`` (m) (module docstring)."""
    return obstacle.picture(offscreen_pyvista(), bounds, t, cell)


def read_series(xdmf):
    """Frames of an XDMF series: cells (n, 4), then a list of (t, points (P, 3), point_data)."""
    import meshio

    frames = []
    with meshio.xdmf.TimeSeriesReader(str(xdmf)) as reader:
        points, cells = reader.read_points_cells()
        for k in range(reader.num_steps):
            t, data, _ = reader.read_data(k)
            frames.append((t, points + data["displacement"], data))
    return cells[0].data, frames


def render_series(xdmf, out_dir, field: str = "speed", *, size=(640, 480), gif: bool = True, title: str = "",
                  fps: float = 12.0, max_frames: int | None = None, progress: bool = False,
                  obstacles=()) -> list[Path]:
    """Render every frame of an XDMF series to PNG (and a GIF of them).

    Parameters
    ----------
    xdmf : path of the series written by :class:`deformable.io.XDMFWriter`
    out_dir : folder for ``frame-00000.png`` ... and ``<stem>.gif``
    field : point field to colour by (one of :data:`FIELDS`; ``x``, ``y``, ``z`` are positions); the
        colour bar says its name and unit (:data:`TITLES`)
    size : window size in pixels (width, height)
    gif : also assemble the frames into a GIF (Pillow; one palette, :func:`gif_bytes`)
    title : text drawn in the upper left corner; the frame's time is drawn in the upper right
    max_frames : render at most this many frames, evenly spread (all by default)
    progress : say how far the rendering is on stderr: a bar on a terminal, elsewhere a timestamped line each tenth
        of the frames with an estimate of the time left (:class:`deformable.progress.Progress`), and a line when the
        GIF is assembled
    obstacles : sequence of deformable.contact.obstacles.Obstacle, drawn in every frame (a scene's ``obstacles``)

    Returns
    -------
    list of Path
        The PNG files written (and the GIF last, if made).
    """
    if field not in FIELDS:
        raise InputError(f"unknown field {field!r}; choose one of {', '.join(FIELDS)}")
    from PIL import Image

    cells, frames = read_series(xdmf)
    if not frames:
        log.warning("no frames in %s: nothing to render", xdmf)
        return []
    if max_frames is not None and len(frames) > max_frames:
        pick = np.unique(np.linspace(0, len(frames) - 1, max_frames).round().astype(int))
        frames = [frames[i] for i in pick]
    faces = _faces(cells)
    values = [f[1][:, _AXIS[field]] if field in _AXIS else f[2][field] for f in frames]
    clim = colour_range(values)
    pts = np.concatenate([f[1] for f in frames])
    bounds = np.array([pts.min(axis=0), pts.max(axis=0)])
    first = frames[0][1][np.asarray(cells, np.int64)]  # (n, 4, 3): the cells' corners in the first frame
    cell = float(np.max(np.linalg.norm(first[:, :, None] - first[:, None, :], axis=3), initial=0.0))  # diagonals
    meshes = [obstacle_mesh(o, bounds, cell=cell) for o in obstacles]
    moving = any(o.moving for o in obstacles)  # an obstacle on its path: drawn where it is at each frame
    view = camera(bounds)
    digits = time_digits([f[0] for f in frames])
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    written = []
    # the first frame opens the renderer (VTK, an EGL or X context): the estimate is measured from the second on
    bar = Progress(len(frames), f"rendering {Path(xdmf).name}", enabled=progress, warmup=True)
    try:
        for k, ((t, points, _), v) in enumerate(zip(frames, values)):
            if moving:
                meshes = [obstacle_mesh(o, bounds, t, cell) for o in obstacles]
            image = frame_image([[Panel(points, np.ravel(v), title, t)]], size, faces=faces, field=field, clim=clim,
                                view=view, obstacles=meshes, digits=digits)
            png = out_dir / f"frame-{k:05d}.png"
            Image.fromarray(image).save(png)
            written.append(png)
            bar.update(k + 1, f"{k + 1} of {counted(len(frames), 'frame')}")
    finally:
        bar.close()
    if gif and written:
        gif_path = out_dir / f"{Path(xdmf).stem}.gif"
        bar.note(f"assembling {gif_path.name} from the {counted(len(written), 'frame')}")
        gif_path.write_bytes(gif_bytes(written, fps=fps, colors=128))
        written.append(gif_path)
    log.info("rendered %d frames of %s to %s", len(frames), xdmf, out_dir)
    return written
