r"""Pictures of the paper study: stability maps and line panels (matplotlib), side-by-side renders (pyvista)."""

from __future__ import annotations

import io
import math

import numpy as np

from .cases import VISIBLE

__all__ = ["map_figure", "line_figure", "render"]

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


def render(frames: list[list[tuple[str, np.ndarray]]], size=(300, 260)) -> bytes:
    """Render rows of (label, points (M, N, 3)) side by side with pyvista; a PNG (palette) as bytes.

    Colour: the displacement out of the rest plane (y, m), one colour range for the whole picture;
    one camera for every panel.
    """
    from PIL import Image

    from deformable.output.render import _pyvista

    pv = _pyvista()
    rows, cols = len(frames), max(len(r) for r in frames)
    allp = np.concatenate([p.reshape(-1, 3) for row in frames for _, p in row])
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    ylim = float(np.max(np.abs(allp[:, 1]))) or 1.0
    centre = 0.5 * (lo + hi)
    radius = 0.5 * float(np.linalg.norm(hi - lo)) or 1.0
    view = np.array([0.55, -1.0, 0.35])
    view /= np.linalg.norm(view)
    camera = [tuple(centre + view * radius / math.tan(math.radians(15)) * 1.02), tuple(centre), (0.0, 0.0, 1.0)]
    plotter = pv.Plotter(off_screen=True, shape=(rows, cols), window_size=[size[0] * cols, size[1] * rows],
                         border=False)
    plotter.set_background("white")
    try:
        for i, row in enumerate(frames):
            for j, (label, pts) in enumerate(row):
                plotter.subplot(i, j)
                grid = pv.StructuredGrid(pts[..., 0], pts[..., 1], pts[..., 2])
                grid["y (m)"] = pts[..., 1].ravel(order="F")
                plotter.add_mesh(grid, scalars="y (m)", clim=(-ylim, ylim), cmap="coolwarm", smooth_shading=True,
                                 show_scalar_bar=False, show_edges=True, edge_color="gray", line_width=0.3)
                plotter.add_text(label, position="upper_left", font_size=7, color="black")
                plotter.camera_position = camera
        img = plotter.screenshot(None, return_img=True)
    finally:
        plotter.close()
    buf = io.BytesIO()
    Image.fromarray(img).convert("P", palette=Image.ADAPTIVE, colors=96).save(buf, format="png", optimize=True)
    return buf.getvalue()
