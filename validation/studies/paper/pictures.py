r"""Pictures of the paper study: stability maps and line panels (matplotlib), side-by-side renders and animations
(drawn by the one renderer, :mod:`deformable.io.render`), and the contact scenes' frames among their obstacles
(:func:`contact_images`: the camera on the sheet, a floor drawn only around it)."""

from __future__ import annotations

import io
import math

import numpy as np

from .cases import VISIBLE

__all__ = ["DIRECTION", "FLOOR_MARGIN", "animation", "contact_images", "fit_camera", "floor_patch", "line_figure",
           "map_figure", "panels_figure", "render", "rest_axis"]

_MARK = {"bounded": ("o", "tab:green"), "runaway": ("^", "tab:orange"), "diverged": ("x", "tab:red")}


def _png_from_matplotlib(fig) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80)
    return buf.getvalue()


def _legend_outside(ax) -> None:
    """The legend to the right of the axes, clear of the data."""
    ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, frameon=False)


def map_figure(panels: list[dict], xlabel: str, ylabel: str, title: str, zero_floor: float | None = None) -> bytes:
    """A grid of stability maps: markers per class, predicted limits as lines (log-log axes)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = 2
    cols = math.ceil(len(panels) / rows)
    fig, axes = plt.subplots(rows, cols, figsize=(6.0 * cols, 3.9 * rows), squeeze=False)
    for ax, p in zip(axes.ravel(), panels):
        for cls, (m, c) in _MARK.items():
            pts = [(x, y) for x, y, k in p["points"] if k == cls]
            if pts:
                x, y = zip(*pts)
                y = [zero_floor if (zero_floor and v == 0) else v for v in y]
                ax.scatter(x, y, marker=m, color=c, s=36, label=cls, zorder=3)
        for line in p["lines"]:
            ax.plot(line["x"], line["y"], line.get("style", "-"), color=line.get("color", "0.2"), lw=1.3,
                    label=line["label"])
        ax.set_xscale("log")
        ax.set_yscale("log")
        if zero_floor:
            ax.axhline(zero_floor * 2.2, color="0.8", lw=0.6)
            ax.text(ax.get_xlim()[0], zero_floor, " 0", va="center", fontsize=7, color="0.3")
        ax.set_title(p["title"], fontsize=9)
        ax.set_xlabel(xlabel, fontsize=8)
        ax.set_ylabel(ylabel, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, alpha=0.3)
        _legend_outside(ax)
    for ax in axes.ravel()[len(panels):]:
        ax.axis("off")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    png = _png_from_matplotlib(fig)
    plt.close(fig)
    return png


def line_figure(panels: list[dict], xlabel: str, ylabel: str, title: str) -> bytes:
    """Small log-x panels of a scalar against xi (xi = 0 drawn at the left edge)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(panels), figsize=(5.8 * len(panels), 3.6), squeeze=False)
    for ax, p in zip(axes[0], panels):
        for line in p["lines"]:
            ax.plot(line["x"], line["y"], line.get("style", "o-"), label=line["label"], ms=4)
        ax.axhline(VISIBLE, color="0.4", ls=":", lw=1, label=f"visible ({VISIBLE:g} of the motion)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(p["title"], fontsize=9)
        ax.set_xlabel(xlabel, fontsize=8)
        ax.set_ylabel(ylabel, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, alpha=0.3)
        _legend_outside(ax)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    png = _png_from_matplotlib(fig)
    plt.close(fig)
    return png


def panels_figure(panels: list[dict], title: str, width: float = 4.6, height: float = 3.7) -> bytes:
    """Panels side by side, each a dict: title, xlabel, ylabel, lines [dict(x, y, label, style=..., color=...)],
    optional xlog, ylog (log axes), integer (integer ticks on a linear y axis: a count) and hline (y, label).
    Points that are NaN are skipped; the legend is outside the axes, to the right."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(panels), figsize=((width + 1.4) * len(panels), height), squeeze=False)
    for ax, p in zip(axes[0], panels):
        for line in p["lines"]:
            x, y = np.asarray(line["x"], float), np.asarray(line["y"], float)
            ok = np.isfinite(x) & np.isfinite(y)
            if ok.any():
                ax.plot(x[ok], y[ok], line.get("style", "o-"), label=line["label"], ms=4, lw=1.2,
                        color=line.get("color"))
        if "hline" in p:
            ax.axhline(p["hline"][0], color="0.4", ls=":", lw=1, label=p["hline"][1])
        if p.get("xlog"):
            ax.set_xscale("log")
        if p.get("ylog"):
            ax.set_yscale("log")
        elif p.get("integer"):
            from matplotlib.ticker import MaxNLocator

            ax.yaxis.set_major_locator(MaxNLocator(integer=True))
        ax.set_title(p["title"], fontsize=9)
        ax.set_xlabel(p["xlabel"], fontsize=8)
        ax.set_ylabel(p["ylabel"], fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, alpha=0.3)
        _legend_outside(ax)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    png = _png_from_matplotlib(fig)
    plt.close(fig)
    return png


#: the scenes' view: from the front, a little to the right and above (z up)
DIRECTION = (0.5, -1.0, 0.3)


def rest_axis(points: np.ndarray) -> int:
    """The axis (0, 1, 2: x, y, z) along which the points (..., 3) spread least: the rest plane's normal, for the
    sheet at its start (the curtain's and flag's y, the hanging cloth's z)."""
    return int(np.argmin(np.ptp(np.reshape(points, (-1, 3)), axis=0)))


def _panels(frames, axis: int | None) -> tuple[list[list], int]:
    """Rows of (label, t, points (M, N, 3)) as rows of render.Panel coloured by the coordinate ``axis`` (default:
    :func:`rest_axis` of the earliest frame's points)."""
    from deformable.io.render import Panel

    if axis is None:
        axis = rest_axis(min((f for row in frames for f in row), key=lambda f: f[1])[2])
    return [[Panel(pts, np.asarray(pts)[..., axis].ravel(), label, t) for label, t, pts in row] for row in frames], axis


def _picture(rows, size, lines, direction, axis, font_size) -> list[np.ndarray]:
    """One screenshot per row of ``rows`` (each a list of rows of panels), one camera and one colour range for all."""
    from deformable.io.render import TITLES, camera, colour_range, frame_image

    flat = [p for pic in rows for row in pic for p in row]
    pts = np.concatenate([np.reshape(p.points, (-1, 3)) for p in flat] + [np.reshape(lines, (-1, 3))])
    view = camera(np.array([pts.min(axis=0), pts.max(axis=0)]), direction, margin=1.2)
    clim = colour_range([p.values for p in flat], percentile=98.0, symmetric=True)
    field = "xyz"[axis]
    return [frame_image(pic, size, field=field, bar_title=TITLES[field], clim=clim, view=view, cmap="coolwarm",
                        rods=lines, font_size=font_size, digits=2) for pic in rows]


def render(frames: list[list[tuple[str, float, np.ndarray]]], size=(300, 260), lines=(), direction=DIRECTION,
           axis: int | None = None) -> bytes:
    """Render rows of (label, t (s; None: no time written), points (M, N, 3)) side by side
    (deformable.io.render.frame_image); a PNG (palette) as bytes.

    Colour: the coordinate out of the rest plane (``axis``, default :func:`rest_axis` of the earliest frame), one
    colour range for the whole picture (the 2nd to 98th percentile, symmetric about 0 when it has both signs),
    the colour bar in the last panel; one camera for every panel, looking from ``direction``; ``lines``:
    segments ((x, y, z), (x, y, z)) drawn as rods in every panel (the curtain's rail, the flag's pole).
    """
    from deformable.io.render import png_bytes

    rows, axis = _panels(frames, axis)
    return png_bytes(_picture([rows], size, lines, direction, axis, 8)[0])


def animation(frames: list[tuple[str, float, np.ndarray]], size=(360, 320), lines=(), direction=DIRECTION,
              fps: float = 12.0, axis: int | None = None) -> bytes:
    """A GIF of (label, t (s), points (M, N, 3)) frames: one camera and one colour range for all (as
    :func:`render`), each with its colour bar and time; one palette for the whole animation
    (deformable.io.render.gif_bytes)."""
    from deformable.io.render import gif_bytes

    if not frames:
        raise ValueError("an animation needs at least one frame")
    rows, axis = _panels([frames], axis)
    return gif_bytes(_picture([[[p]] for p in rows[0]], size, lines, direction, axis, 10), fps=fps)


#: a floor (a plane obstacle) is drawn this fraction of the sheet's footprint beyond it on every side
FLOOR_MARGIN = 0.15


def floor_patch(plane, points: np.ndarray, margin: float = FLOOR_MARGIN):
    """A pyvista rectangle of a plane obstacle (``point``, ``normal``) just around the sheet: the ``points``
    (..., 3) projected onto the plane, their rectangle in the plane widened by ``margin`` of its larger side
    on every side (at least 1 cm), so that the floor frames the sheet instead of filling the picture."""
    from deformable.io.render import offscreen_pyvista

    pv = offscreen_pyvista()
    n = np.asarray(plane.normal, float)
    n = n / np.linalg.norm(n)
    e1 = np.cross(n, (1.0, 0.0, 0.0) if abs(n[0]) < 0.9 else (0.0, 1.0, 0.0))
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    o = np.asarray(plane.point, float)
    rel = np.reshape(points, (-1, 3)) - o
    u, v = rel @ e1, rel @ e2
    pad = max(margin * max(np.ptp(u), np.ptp(v)), 0.01)
    (u0, u1), (v0, v1) = (u.min() - pad, u.max() + pad), (v.min() - pad, v.max() + pad)
    corners = np.array([o + a * e1 + b * e2 for a, b in ((u0, v0), (u1, v0), (u1, v1), (u0, v1))])
    return pv.PolyData(corners, np.array([4, 0, 1, 2, 3]))


def fit_camera(points: np.ndarray, direction=DIRECTION, size=(360, 320), margin: float = 1.08, bar: float = 0.84):
    """A camera position (position, focal point, view up; z up) looking from ``direction`` at the axis-aligned
    bounding box of ``points`` (..., 3), as near as it can be with the whole box in view: the box's corners
    projected across the view, its half width and height against the view angle
    (:data:`deformable.io.render.VIEW_ANGLE`, vertical) and the picture's aspect, ``bar`` of its width left of
    the colour bar; ``margin`` > 1 leaves room around it. Tighter than :func:`deformable.io.render.camera`,
    which frames the box's bounding sphere: a tall box, a ribbon standing before it falls, wastes less of the
    picture."""
    from deformable.io.render import VIEW_ANGLE

    pts = np.reshape(points, (-1, 3))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre = 0.5 * (lo + hi)
    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    right = np.cross((0.0, 0.0, 1.0), d)
    right = right / np.linalg.norm(right) if np.linalg.norm(right) > 1e-9 else np.array([1.0, 0.0, 0.0])
    up = np.cross(d, right)
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]) - centre
    half_w, half_h, depth = (float(np.abs(corners @ e).max()) for e in (right, up, d))
    tan = math.tan(math.radians(VIEW_ANGLE) / 2)
    aspect = bar * size[0] / size[1]
    distance = depth + max(half_h / tan, half_w / (tan * aspect), 1e-3) * margin
    return [tuple(centre + distance * d), tuple(centre), (0.0, 0.0, 1.0)]


def contact_images(frames: list[tuple[str, float, np.ndarray]], obstacles=(), size=(360, 320), direction=DIRECTION,
                   cell: float = 0.0, margin: float = 1.15, colour_from: float | None = None) -> list[np.ndarray]:
    """One picture (H, W, 3) uint8 of each of ``frames``, (label, t (s), points (M, N, 3)), of a sheet among its
    ``obstacles`` (deformable.contact.obstacles), drawn by :func:`deformable.io.render.frame_image`.

    The sheet is coloured by its height z (viridis, one range for all the frames: the 2nd to 98th percentile of
    the frames at or after ``colour_from`` (s; default: all), so that a sheet's start high above where it
    comes to rest, the coil's ribbon upright, saturates and the rest's layers get the whole range);
    one camera for all, looking from ``direction`` at the sheet's bounding box over the frames
    (:func:`fit_camera`, ``margin`` around it), so the sheet, not the floor, fills the picture; the obstacles
    in grey: a plane (the floor) as a rectangle just around the sheet's footprint over the frames
    (:func:`floor_patch`), a ball smaller by the sag of a cell's diagonal ``cell`` (m), rounded solids as
    their sharp cores
    (:func:`deformable.io.render.obstacle_mesh`), a moving obstacle where it is at each frame. A still is this
    with one frame: framed and coloured on that frame alone."""
    from deformable.io.render import TITLES, Panel, colour_range, frame_image, obstacle_mesh, time_digits

    if not frames:
        raise ValueError("a picture needs at least one frame")
    pts = np.concatenate([np.reshape(p, (-1, 3)) for _, _, p in frames])
    bounds = np.array([pts.min(axis=0), pts.max(axis=0)])
    view = fit_camera(pts, direction, size, margin)
    late = [p for _, t, p in frames if colour_from is None or t >= colour_from] or [frames[-1][2]]
    clim = colour_range([np.asarray(p)[..., 2] for p in late], percentile=98.0)

    def meshes(t):
        return [floor_patch(o, pts) if o.kind == "plane" else obstacle_mesh(o, bounds, t, cell) for o in obstacles]

    fixed = None if any(o.moving for o in obstacles) else meshes(0.0)
    digits = time_digits([t for _, t, _ in frames])
    return [frame_image([[Panel(p, np.asarray(p)[..., 2].ravel(), label, t)]], size, field="z", bar_title=TITLES["z"],
                        clim=clim, view=view, obstacles=fixed if fixed is not None else meshes(t), digits=digits)
            for label, t, p in frames]
