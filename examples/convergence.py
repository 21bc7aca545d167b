"""A convergence study: errors of G (eq. 4) and B (eq. 8) on an analytic surface, with observed orders
===================================================================================================

Each backend discretises a generic Monge patch z = 0.3 sin(2 a1 + 0.3)
sin(3 a2 + 0.7) (``validation.harness.surfaces``, closed-form derivatives, no
symmetry to hide errors) on grids refined by halving h, and its G and B are
compared with the closed forms at the backend's own points
(``model.points``: FD nodes, FE 4 x 4 Gauss points). The observed order is
the least-squares slope of log(error) against log(h)
(``validation.harness.orders.fit_order``) and, level to level,
``p = log(e_h / e_{h/2}) / log 2`` (``pairwise_orders``).

Theory (docs/design.md; the ``tensors`` study checks it): FD eq. (18)-(19) at
the interior nodes, first order for G and B (forward differences are centred
half a node away); FE bicubic Hermite at the Gauss points, G third order and
B second order (B12 third).

    python examples/convergence.py [OUT]       # OUT defaults to $EXAMPLES_OUT or examples/out/
    EXAMPLES_FINE=1 python examples/convergence.py    # two more levels
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
from validation.harness import surfaces
from validation.harness.orders import fit_order, pairwise_orders

OUT = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("EXAMPLES_OUT") or Path(__file__).with_name("out"))
LEVELS = [9, 17, 33, 65, 129] if os.environ.get("EXAMPLES_FINE") == "1" else [9, 17, 33]  # nodes a side
THEORY = {("FD", "G"): 1, ("FD", "B"): 1, ("FE", "G"): 3, ("FE", "B"): 2}

surface = surfaces.get("monge")
errors = {key: [] for key in THEORY}
spacing = []
for n in LEVELS:
    # the rest shape is the surface itself: its G and B are the scene's G0, B0, and the initial state
    scene = dm.Scene(dm.Sheet(size=surface.size, nodes=(n, n), rest=surface), dm.Material(eta=1.0, xi=1.0))
    spacing.append(surface.size[0] / (n - 1))
    for name, Model in (("FD", FDModel), ("FE", FEModel)):
        model = Model(scene)
        G, B = model.tensors(model.initial_state())  # (2, 2, *points) at model.points
        a1, a2 = model.points
        inner = (slice(None), slice(None), slice(1, -1), slice(1, -1)) if name == "FD" else Ellipsis
        errors[name, "G"].append(np.max(np.abs(G - surface.G(a1, a2))[inner]))
        errors[name, "B"].append(np.max(np.abs(B - surface.B(a1, a2))[inner]))

h = np.array(spacing)
print(f"max errors on the generic Monge patch, {' / '.join(str(n) for n in LEVELS)} nodes a side:")
for (backend, tensor), e in errors.items():
    p = fit_order(h, e)
    pairs = ", ".join(f"{q:.2f}" for q in pairwise_orders(h, e))
    print(f"  {backend} {tensor}: errors {', '.join(f'{x:.2e}' for x in e)}; observed order {p:.2f} "
          f"(pairwise {pairs}), theory {THEORY[backend, tensor]}")

OUT.mkdir(parents=True, exist_ok=True)
fig, ax = plt.subplots(figsize=(4.8, 3.6))
for (backend, tensor), e in errors.items():
    ax.loglog(h, e, "o-" if backend == "FD" else "s--", label=f"{backend} {tensor} (p = {fit_order(h, e):.2f})")
ax.set(xlabel="node spacing h", ylabel="max error", title="G and B on a generic surface")
ax.legend(fontsize=7)
ax.grid(True, which="both", alpha=0.3)
fig.tight_layout()
fig.savefig(OUT / "convergence.png", dpi=80)
print(f"wrote {OUT / 'convergence.png'}")
