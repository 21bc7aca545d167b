"""A curling strip relaxed to its equilibrium with ``deformable.equilibrium``, against the exact arc
=================================================================================================

A strip [0, L] x [0, W], clamped at a1 = 0, with a flat rest metric and the
rest curvature B0 = diag(kappa, 0): the metric and curvature of a cylinder of
radius 1/kappa (a compatible pair, eq. (10)). Started flat, its equilibrium
is that arc, whose tip on the centre line is at
``(sin(kappa L) / kappa, W / 2, (1 - cos(kappa L)) / kappa)``.

``deformable.equilibrium(model, X0)`` minimises the energy (13) minus the
work of the loads by Newton's method; it needs a model with an energy: the
"variational" force model (the exact gradient of eq. (13)), with full weight
tensors so that shear and twist cost energy too. (Under the paper's force
(14) the flat strip either never curls or is ill-posed, depending on the
sign of xi kappa: docs/design.md, "Findings".) FD is built with the
control-area weighting (the trapezoidal rule for eq. (13) across the strip).

    python examples/curling_strip.py [OUT]     # OUT defaults to $EXAMPLES_OUT or examples/out/
    EXAMPLES_FINE=1 python examples/curling_strip.py
"""

import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import deformable as dm
from fdmodel import FDModel
from femodel import FEModel

OUT = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("EXAMPLES_OUT") or Path(__file__).with_name("out"))
ALONG = 81 if os.environ.get("EXAMPLES_FINE") == "1" else 21  # nodes along the strip
L, W, KAPPA = 1.0, 0.2, 4.0  # m, m, 1/m: the strip curls through kappa L = 4 rad

sheet = dm.Sheet(size=(L, W), nodes=(ALONG, 5))
material = dm.Material(mu=1.0, eta=np.full((2, 2), 100.0), xi=np.full((2, 2), 1.0))
scene = dm.Scene(sheet, material, constraints=[dm.Clamp("left")], force_model="variational",
                 rest_curvature=np.diag([KAPPA, 0.0]), name="curling strip")
theta = KAPPA * L
exact = np.array([np.sin(theta) / KAPPA, W / 2, (1 - np.cos(theta)) / KAPPA])
print(f"curling strip, kappa L = {theta:g} rad, {ALONG} nodes along (h = {L / (ALONG - 1):g} m): the arc's tip is at "
      f"({exact[0]:.4f}, {exact[2]:.4f}) m")
shapes = {}
for name, model in (("FD", FDModel(scene, weighting="control-area")), ("FE", FEModel(scene))):
    X0 = model.initial_state()  # flat
    X, history = dm.equilibrium(model, X0)  # history: the residual max-norm (N) per Newton iteration
    r = shapes[name] = model.grid(X)
    tip = r[-1, 2]  # the centre line's tip (5 nodes across: index 2)
    error = np.max(np.abs(tip - exact))
    print(f"{name}: equilibrium in {len(history) - 1} Newton iterations (residual {history[-1]:.1e} N, energy "
          f"{model.energy(X).total:.1e} J); tip at ({tip[0]:.4f}, {tip[2]:.4f}) m, error {error:.2e} m")
print("FD's clamp holds the edge row and a ghost row outside it by the clamp's slope (second order); FE's holds "
      "every degree of freedom of the edge nodes (docs/design.md, study 'variational')")

OUT.mkdir(parents=True, exist_ok=True)
s = np.linspace(0.0, theta, 200)
fig, ax = plt.subplots(figsize=(4.6, 3.0))
ax.plot(np.sin(s) / KAPPA, (1 - np.cos(s)) / KAPPA, "k-", lw=1, label="arc of radius 1/kappa")
ax.plot(np.linspace(0, L, ALONG), np.zeros(ALONG), "o", ms=3, color="0.6", label="start (flat)")
for (name, r), marker in zip(shapes.items(), "os"):
    ax.plot(r[:, 2, 0], r[:, 2, 2], marker + "-", ms=3, lw=0.8, label=f"{name} equilibrium, {ALONG} nodes")
ax.set(xlabel="x (m)", ylabel="z (m)", aspect="equal", title=f"curling strip, kappa L = {theta:g} rad")
ax.legend(fontsize=7, loc="upper right")
fig.tight_layout()
fig.savefig(OUT / "curling_strip.png", dpi=80)
print(f"wrote {OUT / 'curling_strip.png'}")
