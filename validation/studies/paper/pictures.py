r"""Pictures of the paper study: stability maps and line panels (matplotlib), side-by-side renders (pyvista)."""

from __future__ import annotations

import io
import math

import numpy as np

from .cases import VISIBLE

__all__ = ["map_figure", "line_figure", "panels_figure", "render", "animation"]

_MARK = {"bounded": ("o", "tab:green"), "runaway": ("^", "tab:orange"), "diverged": ("x", "tab:red")}


def _png_from_matplotlib(fig) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80)
    return buf.getvalue()


def map_figure(panels: list[dict], xlabel: str, ylabel: str, title: str, zero_floor: float | None = None) -> bytes:
    """A grid of stability maps: markers per class, predicted limits as lines (log-log axes)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = 2
    cols = math.ceil(len(panels) / rows)
    fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 3.9 * rows), squeeze=False)
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
        ax.legend(fontsize=6, loc="best", framealpha=0.8)
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

    fig, axes = plt.subplots(1, len(panels), figsize=(4.4 * len(panels), 3.6), squeeze=False)
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
        ax.legend(fontsize=6)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    png = _png_from_matplotlib(fig)
    plt.close(fig)
    return png


def panels_figure(panels: list[dict], title: str, width: float = 4.6, height: float = 3.7) -> bytes:
    """Panels side by side, each a dict: title, xlabel, ylabel, lines [dict(x, y, label, style=..., color=...)],
    optional xlog, ylog (log axes) and hline (y, label). Points that are NaN are skipped."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(panels), figsize=(width * len(panels), height), squeeze=False)
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
        ax.set_title(p["title"], fontsize=9)
        ax.set_xlabel(p["xlabel"], fontsize=8)
        ax.set_ylabel(p["ylabel"], fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6, loc="best", framealpha=0.8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    png = _png_from_matplotlib(fig)
    plt.close(fig)
    return png


def _camera(pts: np.ndarray, direction=(0.5, -1.0, 0.3), angle: float = 24.0):
    """A camera (position, focal point, view up) that frames the points from ``direction``, z up."""
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre = 0.5 * (lo + hi)
    radius = 0.5 * float(np.linalg.norm(hi - lo)) or 1.0
    view = np.asarray(direction, float) / np.linalg.norm(direction)
    return [tuple(centre + view * radius / math.tan(math.radians(angle / 2)) * 1.02), tuple(centre), (0.0, 0.0, 1.0)]


def _colour_range(pts: np.ndarray) -> float:
    """The colour range of y: the 98th percentile of |y| (a few outlying points do not wash the folds out)."""
    y = np.abs(pts[..., 1]).ravel()
    return float(np.percentile(y, 98)) or float(y.max()) or 1.0


def _draw(plotter, pts, ylim, label, lines, font_size):
    """One panel: the surface coloured by y (out of the rest plane), smooth shading, the scene's rods."""
    pv = _pyvista()
    grid = pv.StructuredGrid(pts[..., 0], pts[..., 1], pts[..., 2])
    grid["y (m)"] = pts[..., 1].ravel(order="F")
    plotter.add_mesh(grid, scalars="y (m)", clim=(-ylim, ylim), cmap="coolwarm", smooth_shading=True,
                     show_scalar_bar=False, specular=0.3, ambient=0.25)
    for a, b in lines:
        plotter.add_mesh(pv.Tube(pointa=a, pointb=b, radius=0.008), color="#404040")
    if label:
        plotter.add_text(label, position="upper_left", font_size=font_size, color="black")


def _pyvista():
    from deformable.io.render import offscreen_pyvista as pyvista

    return pyvista()


def _view(points: list[np.ndarray], lines, direction) -> tuple[float, list]:
    """One colour range (:func:`_colour_range`) and one camera (:func:`_camera`) for all the surfaces ``points``."""
    surface = np.concatenate([p.reshape(-1, 3) for p in points])
    return _colour_range(surface), _camera(np.concatenate([surface] + [np.array(seg, float) for seg in lines]),
                                           direction)


def _shoot(frames: list[list[tuple[str, np.ndarray]]], size, lines, ylim, camera, font_size) -> np.ndarray:
    """Rows of (label, points) drawn in a fresh off-screen plotter; the screenshot (H, W, 3) uint8.

    A fresh plotter for every picture: a plotter reused after ``clear()`` gains a light each time and washes the
    colours out.
    """
    pv = _pyvista()
    rows, cols = len(frames), max(len(r) for r in frames)
    plotter = pv.Plotter(off_screen=True, shape=(rows, cols), window_size=[size[0] * cols, size[1] * rows],
                         border=False)
    plotter.set_background("white")
    try:
        for i, row in enumerate(frames):
            for j, (label, pts) in enumerate(row):
                plotter.subplot(i, j)
                _draw(plotter, pts, ylim, label, lines, font_size)
                plotter.camera_position = camera
        return plotter.screenshot(None, return_img=True)
    finally:
        plotter.close()


def render(frames: list[list[tuple[str, np.ndarray]]], size=(300, 260), lines=(), direction=(0.5, -1.0, 0.3)) -> bytes:
    """Render rows of (label, points (M, N, 3)) side by side with pyvista; a PNG (palette) as bytes.

    Colour: the displacement out of the rest plane (y, m), one colour range for the whole picture (the 98th
    percentile of |y|); one camera for every panel, looking from ``direction``; ``lines``: segments ((x, y, z),
    (x, y, z)) drawn as rods in every panel (the curtain's rail, the flag's pole).
    """
    from PIL import Image

    ylim, camera = _view([p for row in frames for _, p in row], lines, direction)
    img = _shoot(frames, size, lines, ylim, camera, 8)
    buf = io.BytesIO()
    Image.fromarray(img).convert("P", palette=Image.ADAPTIVE, colors=128).save(buf, format="png", optimize=True)
    return buf.getvalue()


def animation(frames: list[tuple[str, np.ndarray]], size=(360, 320), lines=(), direction=(0.5, -1.0, 0.3),
              fps: float = 12.0) -> bytes:
    """A GIF of (label, points (M, N, 3)) frames: one camera and one colour range for all (as :func:`render`).

    One palette for the whole animation (96 colours, from a mosaic of every sixth frame), so frames do not
    flicker and the file stays small (about 5 KB a frame at 360 x 320).
    """
    from PIL import Image

    if not frames:
        raise ValueError("an animation needs at least one frame")
    ylim, camera = _view([p for _, p in frames], lines, direction)
    images = [Image.fromarray(_shoot([[frame]], size, lines, ylim, camera, 10)) for frame in frames]
    picked = images[::6]
    mosaic = Image.new("RGB", (size[0] * len(picked), size[1]))
    for k, im in enumerate(picked):
        mosaic.paste(im.convert("RGB"), (k * size[0], 0))
    palette = mosaic.convert("P", palette=Image.ADAPTIVE, colors=96)
    gif = [im.convert("RGB").quantize(palette=palette, dither=Image.Dither.NONE) for im in images]
    buf = io.BytesIO()
    gif[0].save(buf, format="gif", save_all=True, append_images=gif[1:], duration=int(1000 / fps), loop=0,
                optimize=True)
    return buf.getvalue()
