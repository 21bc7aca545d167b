"""A scene from a TOML file, with overrides from Python, run and its resolved config written back
==============================================================================================

``deformable.scenes.read_toml(path)`` reads ``scene = "flag"`` plus fields
(examples/breezy_flag.toml) and returns the scene's config: a frozen
dataclass of plain numbers that says every value the run will use;
``config.replace(key=value)`` overrides fields after the file (as ``deformable
run`` applies its options). ``deformable.Simulation(config, backend="fd")``
runs it as ``deformable run`` does (``scenes.build(config)`` alone gives the
Scene); ``scenes.to_toml(config)`` is the resolved file, which ``read_toml`` reads
back to an equal config.

The flag: its pole edge pinned, two coils (springs, the paper's section 5)
from its free corners to anchors that swing across it, gravity, and wind
pressure on its normal (``deformable.Wind``), under the variational model
stepped by implicit Euler.

    python examples/toml_scene.py [OUT]        # OUT defaults to $EXAMPLES_OUT or examples/out/
    EXAMPLES_FINE=1 python examples/toml_scene.py
"""

import dataclasses
import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import deformable as dm
from deformable import scenes

OUT = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("EXAMPLES_OUT") or Path(__file__).with_name("out"))
FINE = os.environ.get("EXAMPLES_FINE") == "1"
FILE = Path(globals().get("__file__", "toml_scene.py")).with_name("breezy_flag.toml")  # (the gallery runs it in examples/)

# the file, then overrides: a small grid and a short run (the file says t_end = 1). ``replace`` checks the
# keys like the file does. (read_toml(FILE, t_end=0.4) raises a TypeError when the file sets t_end too.)
config = scenes.read_toml(FILE).replace(nodes=(20, 12) if FINE else (10, 6), t_end=1.0 if FINE else 0.4)
defaults = scenes.config(config.scene)
changed = {f.name: getattr(config, f.name) for f in dataclasses.fields(config)
           if getattr(config, f.name) != getattr(defaults, f.name)}
print(f"{FILE.name}: scene {config.scene!r}, changed from its defaults: "
      + ", ".join(f"{k} = {v}" for k, v in changed.items()))

# the run as one object, as ``deformable run`` takes it: the config's grid and step on FD (a Simulation with
# out="folder" would also write the series, the resolved config and checkpoints)
sim = dm.Simulation(config, backend="fd", nodes=config.nodes, dt=config.dt)
model, result = sim.model, sim.run(t_end=config.t_end)
r = model.grid(result.state.X)
out_of_plane = np.max(np.abs(r[..., 1]))  # the flag hangs in the x-z plane; y is across it
print(f"flag: {result.status} ({result.message}); largest excursion across the plane {out_of_plane:.3f} m, "
      f"free edge at x = {r[-1, :, 0].mean():.3f} m")

OUT.mkdir(parents=True, exist_ok=True)
resolved = OUT / "toml_scene.toml"
resolved.write_text(scenes.to_toml(config))
assert scenes.read_toml(resolved) == config  # the resolved file reads back to the same config
print(f"wrote {resolved} (reads back to the same config)")

fig = plt.figure(figsize=(5, 3.6))
ax = fig.add_subplot(projection="3d")
across = r[..., 1] / max(out_of_plane, 1e-12)  # colour by the excursion across the plane, -1 .. 1
ax.plot_surface(r[..., 0], r[..., 1], r[..., 2], facecolors=plt.cm.coolwarm(0.5 + 0.5 * across), edgecolor="k", shade=False,
                linewidth=0.3)
ax.plot([0, 0], [0, 0], [-0.3, config.size[1] + 0.2], "k-", lw=3)  # the pole
ax.set(xlabel="x (m)", ylabel="y (m)", zlabel="z (m)", title=f"{FILE.name} at t = {result.state.t:g} s")
ax.set_box_aspect((config.size[0], 0.5, config.size[1] + 0.5))
fig.savefig(OUT / "toml_scene.png", dpi=80)
print(f"wrote {OUT / 'toml_scene.png'}")
