"""The same scene on both backends, side by side: finite differences (fdmodel) and finite elements (femodel)
=========================================================================================================

``deformable.Simulation(scene, backend="fd")`` discretises eq. (11) by the paper's differences (section
2.3, eq. 16-20; ``FDModel(scene)``); ``backend="fe"`` by bicubic Hermite elements on the same
node grid, so FD nodes and FE vertices coincide and ``model.grid(X)`` gives
the node positions of either. The scene is the library's ``hanging`` cloth
(pinned at its two top corners, falling from horizontal), on the
energy-consistent model its config names; both are stepped by implicit
Euler at the same dt. The script prints each backend's wall time and how
far apart the two sheets end up.

    python examples/fd_vs_fe.py [OUT]          # OUT defaults to $EXAMPLES_OUT or examples/out/
    EXAMPLES_FINE=1 python examples/fd_vs_fe.py
"""

import os
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import deformable as dm
from deformable import scenes

OUT = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("EXAMPLES_OUT") or Path(__file__).with_name("out"))
NODES = (17, 17) if os.environ.get("EXAMPLES_FINE") == "1" else (9, 9)
T_END = 0.4  # s

scene = scenes.hanging(nodes=NODES)  # a Scene; scenes.config("hanging") shows its fields
final, history = {}, {}
for name in ("FD", "FE"):
    sim = dm.Simulation(scene, backend=name.lower(), dt=scenes.SCENES["hanging"].dt)  # the scene on a backend by name
    model = sim.model  # an FDModel(scene), an FEModel(scene)
    trace = history[name] = []  # (t, height of the free corner at a1 = L1, a2 = 0) every step
    watch = dm.Callback(lambda state, model=model, trace=trace: trace.append((state.t, model.grid(state.X)[-1, 0, 2])))
    start = time.perf_counter()
    result = sim.run(t_end=T_END, trackers=[watch])
    wall = time.perf_counter() - start
    final[name] = model.grid(result.state.X)
    print(f"{name}: {model.ndof} degrees of freedom per coordinate, {result.status} ({result.message}) "
          f"in {wall:.2f} s; free corner at z = {final[name][-1, 0, 2]:.4f} m")

gap = np.max(np.linalg.norm(final["FD"] - final["FE"], axis=-1))
print(f"FD vs FE on {NODES[0]} x {NODES[1]} nodes at t = {T_END:g} s: node positions differ by at most {gap:.4f} m")

OUT.mkdir(parents=True, exist_ok=True)
fig = plt.figure(figsize=(7.5, 3.4))
ax = fig.add_subplot(1, 2, 1, projection="3d")
for (name, r), colour in zip(final.items(), ("tab:blue", "tab:orange")):
    ax.plot_wireframe(r[..., 0], r[..., 1], r[..., 2], color=colour, linewidth=0.8, label=name)
ax.set(xlabel="x (m)", ylabel="y (m)", zlabel="z (m)", title=f"t = {T_END:g} s")
ax.view_init(elev=10, azim=-30)
ax.legend(fontsize=8)
ax = fig.add_subplot(1, 2, 2)
for name, trace in history.items():
    ax.plot(*np.array(trace).T, label=name)
ax.set(xlabel="t (s)", ylabel="z (m)", title="free corner")
ax.legend(fontsize=8)
fig.suptitle(f"hanging cloth, {NODES[0]} x {NODES[1]} nodes: FD and FE differ by {gap:.3f} m at the end", fontsize=9)
fig.tight_layout()
fig.savefig(OUT / "fd_vs_fe.png", dpi=80)
print(f"wrote {OUT / 'fd_vs_fe.png'}")
