"""An obstacle of any shape, from a mesh file: a cloth dropped on a stool
========================================================================

A user's obstacle, a chair, a mannequin, a scanned table, is a triangle mesh. Here a stool (a seat and four
legs, twelve triangles a box) is written as an OBJ file with meshio, as any modelling tool would write it, and
read back as a :class:`deformable.MeshObstacle`. The sheet meets it triangle against triangle (the IPC barrier
on one IPC Toolkit mesh, with a line search bounded by continuous collision detection: no step passes the sheet
through a face, nor a corner of the stool through the sheet between its nodes). A square cloth dropped from
2 cm above the seat drapes over its corners. At every step the example measures the clearance between the
sheet and the stool (``deformable.clearance``, -inf if they intersected).

    python examples/mesh_obstacle.py [OUT]      # OUT defaults to $EXAMPLES_OUT or examples/out/
    EXAMPLES_FINE=1 python examples/mesh_obstacle.py    # a finer grid
"""

import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import meshio
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

import deformable as dm
from deformable.geometry.surfaces import Plane

OUT = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("EXAMPLES_OUT") or Path(__file__).with_name("out"))
NODES = (25, 25) if os.environ.get("EXAMPLES_FINE") == "1" else (13, 13)


def box(lower, upper):
    """An axis-aligned box: its 8 corners and 12 outward triangles."""
    lo, hi = np.asarray(lower, float), np.asarray(upper, float)
    V = np.array([[(lo, hi)[i][0], (lo, hi)[j][1], (lo, hi)[k][2]] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    F = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6],
                  [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    return V, F


# The stool: a 30 cm square seat 2 cm thick, its top at z = 0, on four legs 40 cm long; one mesh of five boxes.
parts = [box((0.2, 0.2, -0.02), (0.5, 0.5, 0.0))] + [
    box((x, y, -0.42), (x + 0.03, y + 0.03, -0.02)) for x in (0.21, 0.46) for y in (0.21, 0.46)]
V = np.concatenate([p[0] for p in parts])
F = np.concatenate([p[1] + 8 * k for k, p in enumerate(parts)])
OUT.mkdir(parents=True, exist_ok=True)
meshio.write(OUT / "stool.obj", meshio.Mesh(V, [("triangle", F)]))
stool = dm.MeshObstacle(path=str(OUT / "stool.obj"))  # or dm.MeshObstacle(vertices=V, faces=F)

# A 0.7 m square cloth centred over the seat, 2 cm above it; mu in kg/m^2, gamma in kg/(m^2 s), eta in N/m,
# xi in N m, full weight tensors; friction 0.3 against the stool, a barrier within 1 mm.
sheet = dm.Sheet(size=(0.7, 0.7), nodes=NODES, initial=Plane(origin=(0.0, 0.0, 0.02)))
material = dm.Material(mu=0.2, gamma=0.5, eta=np.full((2, 2), 20.0), xi=np.full((2, 2), 1e-4))
scene = dm.Scene(sheet, material, forces=[dm.Gravity()], force_model="variational", obstacles=[stool],
                 contact=dm.Contact(distance=1e-3, friction=0.3), name="stool")
sim = dm.Simulation(scene, backend="fd", dt=5e-3)  # implicit Euler: Newton's method each step, the barrier in it
model = sim.model

clearances = []
result = sim.run(t_end=0.6, trackers=[dm.Callback(lambda s: clearances.append(dm.clearance(model, s.X, t=s.t)))])
r = model.grid(result.state.X)
print(f"mesh obstacle: {result.status} after {result.steps} steps; {len(stool.triangles)} triangles read from "
      f"{(OUT / 'stool.obj').name}; smallest clearance {min(clearances):.3g} m over every step; the cloth's corners "
      f"hang {-np.mean(r[[0, 0, -1, -1], [0, -1, 0, -1], 2]):.3f} m below the seat")

fig = plt.figure(figsize=(5, 4))
ax = fig.add_subplot(projection="3d")
ax.add_collection3d(Poly3DCollection(V[F], facecolor="lightgrey", edgecolor="grey", linewidth=0.2, alpha=0.6))
ax.plot_surface(r[..., 0], r[..., 1], r[..., 2], cmap="viridis", edgecolor="k", linewidth=0.2, alpha=0.9)
ax.set(xlim=(0.0, 0.7), ylim=(0.0, 0.7), zlim=(-0.45, 0.05), xlabel="x (m)", ylabel="y (m)", zlabel="z (m)",
       title=f"a cloth on a stool read from a mesh file, t = {result.state.t:g} s")
ax.set_box_aspect((1, 1, 0.7))
fig.savefig(OUT / "mesh_obstacle.png", dpi=80)
print(f"wrote {OUT / 'mesh_obstacle.png'}")
