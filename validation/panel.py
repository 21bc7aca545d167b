r"""The panel of section 3.2 (Figs 1-2; :mod:`deformable.scenes.panel`) measured and drawn: its node tensors, what
they show (area increase, curvature, Laplace's law), its equilibria on a backend and the README's picture.

    python -m validation.panel [OUT]        # docs/scenes/panel.png by default
"""

from __future__ import annotations

import numpy as np

import deformable as dm
from deformable.io.render import Panel, camera, frame_image, png_bytes
from deformable.scenes.panel import PanelConfig, SoftPanelConfig, start

from .harness.backends import make_model

__all__ = ["node_tensors", "measure", "equilibria", "picture", "main"]


def node_tensors(model, X) -> tuple[np.ndarray, np.ndarray]:
    """G (1) and B (1/m) of a state at the sheet's nodes, two (2, 2, M, N) arrays, on any backend
    (``model.sample`` at the node coordinates: FD its node tensors, FE its surface's)."""
    a1, a2 = model.scene.sheet.coordinates()
    M, N = a1.shape
    s = model.sample(X, np.stack([a1.ravel(), a2.ravel()], axis=1))
    return (np.moveaxis(np.asarray(s.G), 0, -1).reshape(2, 2, M, N),
            np.moveaxis(np.asarray(s.B), 0, -1).reshape(2, 2, M, N))


def measure(cfg: PanelConfig, G: np.ndarray, B: np.ndarray) -> dict:
    """What the panel shows, from its node tensors G, B ((2, 2, M, N), :func:`node_tensors`) on the config's grid.

    Returns
    -------
    dict
        ``area``: the area increase int sqrt(det G) da / (L1 L2) - 1 (1, trapezoidal rule); ``H``, ``K``: the
        mean curvature tr(G^-1 B) / 2 (1/m; negative where the sheet bulges along its normal, the pressure's
        side) and the Gaussian curvature det B / det G (1/m^2) at the centre node (M and N odd: the centre);
        ``strain``: the largest fibre stretch sqrt(G_ii) - 1 at the centre (1); ``laplace``: Laplace's law's
        residual (sum_ij 4 eta_ij (G_ij - delta_ij) B_ij + p sqrt(det G)) / p at the centre (1, module
        docstring); ``laplace_inner``: its largest magnitude over the nodes at least a quarter of the side
        from the border.
    """
    M, N = G.shape[2:]
    L1, L2 = cfg.size
    detG = G[0, 0] * G[1, 1] - G[0, 1] * G[1, 0]
    w = np.outer(_trapezoid(M), _trapezoid(N)) * (L1 / (M - 1)) * (L2 / (N - 1))
    area = float(np.sum(w * np.sqrt(detG)) / (L1 * L2) - 1.0)
    H = 0.5 * (G[1, 1] * B[0, 0] - G[0, 1] * B[1, 0] - G[1, 0] * B[0, 1] + G[0, 0] * B[1, 1]) / detG
    K = (B[0, 0] * B[1, 1] - B[0, 1] * B[1, 0]) / detG
    eta = cfg.material().eta
    p = cfg.scale * cfg.pressure
    tension = sum(4.0 * eta[i, j] * (G[i, j] - (i == j)) * B[i, j] for i in range(2) for j in range(2))
    laplace = (tension + p * np.sqrt(detG)) / p if p else np.zeros_like(detG)
    c = (M // 2, N // 2)
    inner = (slice(M // 4, M - M // 4), slice(N // 4, N - N // 4))
    return {"area": area, "H": float(H[c]), "K": float(K[c]),
            "strain": float(max(np.sqrt(G[0, 0][c]), np.sqrt(G[1, 1][c])) - 1.0),
            "laplace": float(laplace[c]), "laplace_inner": float(np.abs(laplace[inner]).max())}


def _trapezoid(n: int) -> np.ndarray:
    w = np.ones(n)
    w[[0, -1]] = 0.5
    return w


def equilibria(backend: str = "fd", nodes: tuple = (33, 33)) -> dict:
    """The equilibria of ``panel`` and ``panel-soft`` on a backend ("fd" or "fe") and node grid: name -> (config,
    model, X), solved by :func:`deformable.equilibrium` from :func:`start`."""
    out = {}
    for cls in (PanelConfig, SoftPanelConfig):
        cfg = cls(nodes=tuple(nodes))
        model = make_model(cfg.build(), backend)
        X, _ = dm.equilibrium(model, start(cfg, model), check_stability=False)
        out[cls.name] = (cfg, model, X)
    return out


def picture(solved: dict, size=(400, 330)) -> bytes:
    """PNG of the panels' equilibria side by side (``solved`` from :func:`equilibria`): one camera and one colour
    range, z (m), for both, seen from low (the bulge's profile), the held border drawn as a frame; each labelled
    with its eta and its measured area increase. ``size``: each panel's (width, height) in pixels."""
    panels = []
    for name, (cfg, model, X) in solved.items():
        pts = model.grid(X)
        area = measure(cfg, *node_tensors(model, X))["area"]
        label = f"{name} (Fig. {1 if name == 'panel' else 2}): eta = {cfg.eta:g} N/m\narea +{100 * area:.2g} %"
        panels.append(Panel(pts, pts[..., 2].ravel(), label))
    L1, L2 = next(iter(solved.values()))[0].size
    corners = [(0.0, 0.0, 0.0), (L1, 0.0, 0.0), (L1, L2, 0.0), (0.0, L2, 0.0)]
    frame = [(corners[k], corners[(k + 1) % 4]) for k in range(4)]
    pts = np.concatenate([np.reshape(p.points, (-1, 3)) for p in panels])
    view = camera(np.array([pts.min(axis=0), pts.max(axis=0)]), direction=(0.7, -1.0, 0.3))  # low: the dome's profile
    return png_bytes(frame_image([panels], size=size, field="z", rods=frame, view=view))


def main(argv=None) -> int:
    """Draw :func:`picture` of the FD 33 x 33 equilibria to OUT (default docs/scenes/panel.png), from the project's
    folder: ``python -m validation.panel [OUT]``."""
    import sys

    args = sys.argv[1:] if argv is None else list(argv)
    out = args[0] if args else "docs/scenes/panel.png"
    data = picture(equilibria("fd", (33, 33)))
    with open(out, "wb") as f:
        f.write(data)
    print(f"{out}: {len(data) / 1e3:.0f} kB")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
