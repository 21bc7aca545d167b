r"""Pictures of a run: PNG frames and a GIF, rendered offscreen with pyvista.

The frames are rendered from the XDMF time series that
:mod:`deformable.io.series` writes (positions = mesh points + the point field
``displacement``), so a run that was killed or diverged can still be drawn.
The camera is fixed for the whole series and frames the union of the sheet's
bounding boxes over all frames; the colour range of the chosen field is fixed
over the series too, so frames compare. A scene's obstacles
(:mod:`deformable.contact.obstacles`) are drawn in grey in every frame: a plane as a
square patch under the sheet's extent, spheres as they are, rounded boxes and
cylinders as their sharp cores (the solid less its rounding), so that a cloth
resting on a rounded rim is not drawn cut by a sharp one.

Headless machines: VTK falls back from an X window to EGL when no display is
there, and logs a warning first; choosing EGL up front
(``VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow``) avoids the warning. No
Xvfb is needed where EGL works (it does on the project's machines).
"""

from __future__ import annotations

import logging
import os
from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["render_series", "render_frame", "read_series", "obstacle_mesh", "offscreen_pyvista", "camera", "FIELDS", "TITLES"]

log = logging.getLogger(__name__)

#: point fields that can colour the sheet (written by deformable.io.series)
FIELDS = ("speed", "energy_density", "G11", "G12", "G22", "B11", "B12", "B22", "x", "y", "z")
#: the colour bar's title of each field, with its unit (G is dimensionless, B = n . r_ij is 1/m)
TITLES = {"speed": "speed (m/s)", "energy_density": "energy density (J/m^2)", "x": "x (m)", "y": "y (m)",
          "z": "z (m)", **{f"G{ij}": f"G{ij} (1)" for ij in ("11", "12", "22")},
          **{f"B{ij}": f"B{ij} (1/m)" for ij in ("11", "12", "22")}}
_AXIS = {"x": 0, "y": 1, "z": 2}


def offscreen_pyvista():
    if not os.environ.get("DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista

    pyvista.OFF_SCREEN = True
    return pyvista


def _faces(cells: np.ndarray) -> np.ndarray:
    """pyvista face array [4, i, j, k, l, ...] from (n, 4) quads."""
    cells = np.asarray(cells, dtype=np.int64)
    return np.hstack([np.full((cells.shape[0], 1), cells.shape[1]), cells]).ravel()


def camera(bounds: np.ndarray):
    """A camera position (position, focal point, view up) framing an axis-aligned box.

    ``bounds`` is (2, 3): min and max corners. The view looks from the front-right,
    slightly above, with z up.
    """
    lo, hi = bounds
    centre = 0.5 * (lo + hi)
    radius = 0.5 * float(np.linalg.norm(hi - lo)) or 1.0
    direction = np.array([0.8, -1.0, 0.6])
    direction /= np.linalg.norm(direction)
    distance = radius / np.tan(np.radians(30.0) / 2) * 1.05  # view angle 30 degrees
    return [tuple(centre + distance * direction), tuple(centre), (0.0, 0.0, 1.0)]


def obstacle_mesh(obstacle, bounds: np.ndarray):
    """A pyvista mesh of an obstacle; a plane is a square patch twice the extent of ``bounds`` (2, 3)."""
    pv = offscreen_pyvista()
    kind = obstacle.kind
    if kind == "sphere":
        return pv.Sphere(radius=obstacle.radius, center=obstacle.center, theta_resolution=64, phi_resolution=64)
    r = getattr(obstacle, "rounding", 0.0)  # a rounded solid is drawn as its sharp core, never outside it
    if kind == "cylinder":
        return pv.Cylinder(center=obstacle.center, direction=obstacle.axis, radius=obstacle.radius - r,
                           height=obstacle.height - 2 * r, resolution=96, capping=True)
    if kind == "box":
        lo, hi = np.asarray(obstacle.lower) + r, np.asarray(obstacle.upper) - r
        return pv.Box(bounds=(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]))
    if kind == "plane":
        n = np.asarray(obstacle.normal)
        centre = 0.5 * (bounds[0] + bounds[1])
        centre = centre - float((centre - np.asarray(obstacle.point)) @ n) * n  # projected onto the plane
        size = 2.0 * float(np.max(bounds[1] - bounds[0])) or 1.0
        return pv.Plane(center=centre, direction=n, i_size=size, j_size=size)
    raise ValueError(f"no picture for an obstacle of kind {kind!r}")


def render_frame(plotter, points, faces, values, field, clim, title, obstacles=()):
    """Draw one frame into ``plotter`` (cleared first).

    The colour bar stands at the right edge, upright, its title (the field and its unit, :data:`TITLES`)
    above it and three labels of three significant digits beside it, so that no label meets the title
    or another label. ``obstacles``: pyvista meshes drawn in grey.
    """
    pv = offscreen_pyvista()
    plotter.clear()
    for mesh in obstacles:
        plotter.add_mesh(mesh, color="lightgrey", smooth_shading=True, opacity=1.0)
    mesh = pv.PolyData(points, faces)
    mesh[field] = values
    plotter.add_mesh(mesh, scalars=field, clim=clim, cmap="viridis", smooth_shading=True, show_edges=False,
                     scalar_bar_args=dict(title=TITLES.get(field, field) + "\n", vertical=True, position_x=0.84,
                                          position_y=0.12, width=0.06, height=0.62, n_labels=3, fmt="%.3g",
                                          title_font_size=13, label_font_size=12, color="black"))
    plotter.add_text(title, position="upper_left", font_size=10, color="black")


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
    field : point field to colour by (one of :data:`FIELDS`; ``x``, ``y``, ``z`` are positions)
    size : window size in pixels (width, height)
    gif : also assemble the frames into a GIF (Pillow)
    title : text drawn in the corner, followed by the frame's time
    max_frames : render at most this many frames, evenly spread (all by default)
    progress : show a progress bar on stderr (tqdm; silent when stderr is not a terminal)
    obstacles : sequence of deformable.contact.obstacles.Obstacle, drawn in every frame (a scene's ``obstacles``)

    Returns
    -------
    list of Path
        The PNG files written (and the GIF last, if made).
    """
    if field not in FIELDS:
        raise InputError(f"unknown field {field!r}; choose one of {', '.join(FIELDS)}")
    pv = offscreen_pyvista()
    cells, frames = read_series(xdmf)
    if not frames:
        log.warning("no frames in %s: nothing to render", xdmf)
        return []
    if max_frames is not None and len(frames) > max_frames:
        pick = np.unique(np.linspace(0, len(frames) - 1, max_frames).round().astype(int))
        frames = [frames[i] for i in pick]
    faces = _faces(cells)
    values = [f[1][:, _AXIS[field]] if field in _AXIS else f[2][field] for f in frames]
    allv = np.concatenate([np.ravel(v) for v in values])
    allv = allv[np.isfinite(allv)]
    clim = (float(allv.min()), float(allv.max())) if allv.size else (0.0, 1.0)
    if clim[1] <= clim[0]:
        clim = (clim[0] - 0.5, clim[0] + 0.5)
    pts = np.concatenate([f[1] for f in frames])
    bounds = np.array([pts.min(axis=0), pts.max(axis=0)])
    meshes = [obstacle_mesh(o, bounds) for o in obstacles]
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    plotter = pv.Plotter(off_screen=True, window_size=list(size))
    plotter.set_background("white")
    written = []
    bar = None
    if progress:
        import sys

        from tqdm import tqdm

        bar = tqdm(total=len(frames), desc="rendering", unit="frame", disable=not sys.stderr.isatty(), leave=False)
    try:
        for k, ((t, points, _), v) in enumerate(zip(frames, values)):
            render_frame(plotter, points, faces, np.ravel(v), field, clim, f"{title}  t = {t:.3f} s".strip(), meshes)
            plotter.camera_position = camera(bounds)
            png = out_dir / f"frame-{k:05d}.png"
            plotter.screenshot(str(png))
            written.append(png)
            if bar is not None:
                bar.update()
    finally:
        plotter.close()
        if bar is not None:
            bar.close()
    if gif and written:
        from PIL import Image

        images = [Image.open(p).convert("P", palette=Image.ADAPTIVE, colors=128) for p in written]
        gif_path = out_dir / f"{Path(xdmf).stem}.gif"
        images[0].save(gif_path, save_all=True, append_images=images[1:], duration=int(1000 / fps), loop=0)
        written.append(gif_path)
    log.info("rendered %d frames of %s to %s", len(frames), xdmf, out_dir)
    return written
