"""Write a run as an XDMF time series, then read it back with meshio and with pyvista
==================================================================================

``deformable.io.XDMFWriter`` is a tracker of :class:`deformable.TimeStepper`:
every ``every`` steps it writes one frame (node positions and the point
fields G11, G12, G22 of eq. (4), B11, B12, B22 of eq. (8), speed,
energy_density, the integrand of eq. (13), and displacement) to an .xdmf file
with its .h5 beside it: what ``deformable run`` writes and ParaView opens.

meshio reads the series frame by frame (``meshio.xdmf.TimeSeriesReader``; it
keeps the first frame's points, so a frame's positions are points +
displacement); pyvista (VTK's XDMF reader) reads it as a mesh with time
steps. Both are dependencies of the package; the pyvista part is skipped with
a one-line message where pyvista is not installed.

    python examples/read_back.py [OUT]         # OUT defaults to $EXAMPLES_OUT or examples/out/
"""

import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import meshio
import numpy as np

import deformable as dm
from deformable import scenes
from deformable.io import XDMFWriter

OUT = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("EXAMPLES_OUT") or Path(__file__).with_name("out"))
NODES = (24, 24) if os.environ.get("EXAMPLES_FINE") == "1" else (12, 12)

# 1. the run: the hanging cloth for 1 s, a frame every 10 steps (0.05 s)
sim = dm.Simulation(scenes.hanging(nodes=NODES), backend="fd", dt=5e-3)
model = sim.model
series = OUT / "read_back" / "hanging.xdmf"
series.parent.mkdir(parents=True, exist_ok=True)  # XDMFWriter does not create its folder
result = sim.run(t_end=1.0, trackers=[XDMFWriter(series, every=10)])
print(f"run: {result.status} ({result.message}); series {series}")

# 2. meshio: the frames one by one; the free corner's height over time
corner = NODES[0] * NODES[1] - NODES[1]  # node (M-1, 0) at row m N + n: the free corner at a1 = L1, a2 = 0
times, heights = [], []
with meshio.xdmf.TimeSeriesReader(str(series)) as reader:
    points, cells = reader.read_points_cells()
    for k in range(reader.num_steps):
        t, point_data, _ = reader.read_data(k)
        times.append(t)
        heights.append((points + point_data["displacement"])[corner, 2])
print(f"meshio: {len(times)} frames, t = {times[0]:g} .. {times[-1]:g} s, {cells[0].type} cells, point fields "
      f"{', '.join(sorted(point_data))}; free corner from z = {heights[0]:.3f} m to {heights[-1]:.3f} m")

OUT.mkdir(parents=True, exist_ok=True)
fig, axes = plt.subplots(1, 2, figsize=(7.5, 3.2))
axes[0].plot(times, heights, "o-", ms=3)
axes[0].set(xlabel="t (s)", ylabel="z (m)", title="free corner, read with meshio")

# 3. pyvista: VTK's XDMF reader, the last time step as a mesh
if not os.environ.get("DISPLAY"):  # headless: VTK renders through EGL (as deformable.io.render does)
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
try:
    import pyvista as pv
except ImportError:
    pv = None
    print("pyvista: not installed, skipping its part (pip install pyvista)")
if pv is not None:
    reader = pv.get_reader(str(series))
    reader.set_active_time_value(reader.time_values[-1])
    mesh = reader.read()
    mesh = mesh[0] if isinstance(mesh, pv.MultiBlock) else mesh
    speed = mesh.point_data["speed"]
    print(f"pyvista: {len(reader.time_values)} time steps, last t = {reader.time_values[-1]:g} s: {mesh.n_points} "
          f"points, {mesh.n_cells} cells, node speeds up to {speed.max():.3g} m/s")
    # pyvista's own picture (offscreen), and the same mesh drawn by matplotlib in the summary figure
    try:
        plotter = pv.Plotter(off_screen=True, window_size=(480, 360))
        plotter.add_mesh(mesh, scalars="speed", cmap="viridis", show_edges=True,
                         scalar_bar_args=dict(title="speed (m/s)", vertical=True, position_x=0.85))
        plotter.screenshot(OUT / "read_back_pyvista.png")
        plotter.close()
        print(f"pyvista: rendered {OUT / 'read_back_pyvista.png'}")
    except Exception as err:  # no OpenGL context on this machine: the matplotlib picture below still shows it
        print(f"pyvista: cannot render here ({type(err).__name__}), drawing with matplotlib only")
    P = np.asarray(mesh.points).reshape(NODES[0], NODES[1], 3)
    S = np.asarray(speed).reshape(NODES)
    ax = fig.add_subplot(1, 2, 2, projection="3d")
    axes[1].remove()
    ax.plot_surface(P[..., 0], P[..., 1], P[..., 2], facecolors=plt.cm.viridis(S / S.max()), edgecolor="k",
                    linewidth=0.2)
    ax.set_box_aspect(np.ptp(P.reshape(-1, 3), axis=0) + 0.05)
    ax.set(xlabel="x (m)", ylabel="y (m)", zlabel="z (m)",
           title=f"read with pyvista: t = {reader.time_values[-1]:g} s,\ncoloured by speed")
else:
    axes[1].axis("off")
fig.tight_layout()
fig.savefig(OUT / "read_back.png", dpi=80)
print(f"wrote {OUT / 'read_back.png'}")
