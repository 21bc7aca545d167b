"""A scene of your own, in Python: a hammock, a sheet held along two edges, under gravity and a point load
=======================================================================================================

Everything a backend needs is a :class:`deformable.Scene`: the parameter
rectangle and its node grid (:class:`deformable.Sheet`), the material of
eq. (11) and (13) (mu, gamma, eta_ij, xi_ij), the forces f of eq. (11), the
constraints, and the force model. Here the energy-consistent ("variational")
model with *full* weight tensors (eta_12 = eta, xi_12 = xi): with the paper's
eta_12 = xi_12 = 0 shear and twist cost nothing and the scene warns
(IllPosedScene); under the paper's force (14) ("tpbf87") a flat sheet has no
linear bending stiffness, so a sheet that is pushed into compression crumples.

    python examples/custom_scene.py [OUT]      # OUT defaults to $EXAMPLES_OUT or examples/out/
    EXAMPLES_FINE=1 python examples/custom_scene.py    # a finer grid
"""

import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import deformable as dm

OUT = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("EXAMPLES_OUT") or Path(__file__).with_name("out"))
NODES = (21, 11) if os.environ.get("EXAMPLES_FINE") == "1" else (11, 7)

# A 1 m x 0.5 m sheet, flat and horizontal at rest (the default rest shape is the plane (a1, a2, 0)).
sheet = dm.Sheet(size=(1.0, 0.5), nodes=NODES)
# Light cloth: mu in kg/m^2, gamma in kg/(m^2 s), eta in N/m, xi in N m; full 2 x 2 weight tensors.
material = dm.Material(mu=0.2, gamma=1.0, eta=np.full((2, 2), 20.0), xi=np.full((2, 2), 1e-3))
scene = dm.Scene(
    sheet, material,
    forces=[dm.Gravity(9.81),                                  # mu g per unit area, -z
            dm.PointLoad(at=(0.5, 0.25), f=(0.0, 0.0, -0.5))],  # 0.5 N down at the centre
    constraints=[dm.Pin(["left", "right"])],                   # the edges a1 = 0 and a1 = L1 are held
    force_model="variational", name="hammock")

# The run on FD (an FDModel of the scene, sim.model); the variational model steps by implicit Euler (Newton's
# method each step): stable at any dt.
sim = dm.Simulation(scene, backend="fd", dt=0.05)
model, result = sim.model, sim.run(t_end=3.0)

r = model.grid(result.state.X)  # (M, N, 3) node positions
centre = r[NODES[0] // 2, NODES[1] // 2]  # the loaded node (odd node counts put one at the centre)
energy = model.energy(result.state.X)  # eq. (13): stretching and bending parts (J)
speed = np.max(np.linalg.norm(model.grid(result.state.V), axis=-1))
print(f"custom scene: {result.status} ({result.message}); centre sag {-centre[2]:.4f} m, "
      f"max speed {speed:.3f} m/s, elastic energy {energy.stretching + energy.bending:.3e} J")

OUT.mkdir(parents=True, exist_ok=True)
fig = plt.figure(figsize=(5, 3.6))
ax = fig.add_subplot(projection="3d")
ax.plot_surface(r[..., 0], r[..., 1], r[..., 2], cmap="viridis", edgecolor="k", linewidth=0.3)
ax.scatter(*centre, color="red", s=30, label="point load")
ax.set_box_aspect((2, 1, 0.6))
ax.set(xlabel="x (m)", ylabel="y (m)", zlabel="z (m)", title=f"hammock at t = {result.state.t:g} s")
ax.legend(fontsize=8)
fig.savefig(OUT / "custom_scene.png", dpi=80)
print(f"wrote {OUT / 'custom_scene.png'}")
