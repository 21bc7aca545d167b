"""A cantilever's load-deflection curve against the elastica (large deflections, both backends)
============================================================================================

A strip of length L = 10 m and width W = 1 m, clamped at a1 = 0, no rest
curvature, under a dead transverse load P at its free edge (an
``EdgeLoad`` of P / W N/m). With the variational model and full weight
tensors the sheet is the St Venant-Kirchhoff plate with bending stiffness
D = 2 xi (docs/design.md, "Three readings of the model"), so the strip's EI
is 2 xi W; eta = 1e3 N/m keeps its axial strain near 1e-5, so it bends like
Euler's inextensible elastica ``EI theta'' = -P cos(theta)``, whose tip
(-u/L, w/L) comes from ``validation.studies.variational.elastica_tip``
(scipy's collocation).

Each load step starts ``deformable.equilibrium`` from the previous
equilibrium (continuation along the curve).

    python examples/cantilever_elastica.py [OUT]    # OUT defaults to $EXAMPLES_OUT or examples/out/
    EXAMPLES_FINE=1 python examples/cantilever_elastica.py
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
from validation.studies.variational import elastica_tip

OUT = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("EXAMPLES_OUT") or Path(__file__).with_name("out"))
FINE = os.environ.get("EXAMPLES_FINE") == "1"
L, W, ETA, XI = 10.0, 1.0, 1e3, 1.0
EI = 2 * XI * W  # N m^2: the variational model's bending constant times the width
LOADS = np.array([0.5, 1.0, 2.0, 4.0, 8.0])  # P L^2 / EI
NODES = {"FD": 41 if FINE else 21, "FE": 21 if FINE else 9}  # nodes along the strip


def strip(load: float, along: int) -> dm.Scene:
    """The clamped strip (``along`` x 3 nodes) under the tip load P = load EI / L^2 (N), pointing down (-z)."""
    P = load * EI / L**2
    sheet = dm.Sheet(size=(L, W), nodes=(along, 3))
    material = dm.Material(mu=1.0, eta=np.full((2, 2), ETA), xi=np.full((2, 2), XI))
    return dm.Scene(sheet, material, forces=[dm.EdgeLoad("right", f=(0.0, 0.0, -P / W))],
                    constraints=[dm.Clamp("left")], force_model="variational", name="cantilever")


reference = np.array([elastica_tip(p) for p in LOADS])  # (-u/L, w/L) per load
curves = {}
for backend, Model in (("FD", lambda s: FDModel(s, weighting="control-area")), ("FE", FEModel)):
    X, tips = None, []
    for load in LOADS:
        model = Model(strip(load, NODES[backend]))
        X, history = dm.equilibrium(model, model.initial_state() if X is None else X)
        tip = model.grid(X)[-1, 1]  # the centre of the free edge
        tips.append(((L - tip[0]) / L, -tip[2] / L))
    curves[backend] = np.array(tips)
    worst = np.max(np.abs(curves[backend] - reference))
    print(f"{backend} ({NODES[backend]} nodes along): largest tip error against the elastica {worst:.1e} L")

print("P L^2/EI   w/L elastica   w/L FD     w/L FE    -u/L elastica")
for p, ref, fd, fe in zip(LOADS, reference, curves["FD"], curves["FE"]):
    print(f"{p:8.2f}   {ref[1]:12.5f}   {fd[1]:8.5f}   {fe[1]:8.5f}   {ref[0]:12.5f}")

OUT.mkdir(parents=True, exist_ok=True)
fine = np.linspace(0.05, LOADS[-1], 25)
exact = np.array([elastica_tip(p) for p in fine])
fig, ax = plt.subplots(figsize=(4.8, 3.6))
ax.plot(fine, exact[:, 1], "k-", lw=1, label="elastica w/L")
ax.plot(fine, exact[:, 0], "k--", lw=1, label="elastica -u/L")
ax.plot(fine, fine / 3, ":", color="0.5", lw=1, label="linear beam P L^2 / 3 EI")
for (name, c), marker in zip(curves.items(), "os"):
    ax.plot(LOADS, c[:, 1], marker, mfc="none", label=f"{name} w/L ({NODES[name]} nodes)")
    ax.plot(LOADS, c[:, 0], marker, mfc="none", color=ax.lines[-1].get_color())
ax.set(xlabel="P L^2 / EI", ylabel="tip deflection / L", ylim=(0, 1), title="cantilever under a tip load")
ax.legend(fontsize=7)
fig.tight_layout()
fig.savefig(OUT / "cantilever_elastica.png", dpi=80)
print(f"wrote {OUT / 'cantilever_elastica.png'}")
