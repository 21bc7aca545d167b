"""The trade-off table of docs/models.md: one cloth, every force model x scheme x backend, measured in one run.

The user guide's library example (docs/guide.md: a 1 m x 1 m cloth pinned at its two top corners, falling from
horizontal under gravity; mu = 0.1 kg/m^2, gamma = 0.05 kg/(m^2 s), eta = 50 N/m, xi = 1e-3 N m) for 1 s at
``dt="auto"``: full weight tensors for the variational model, the paper's diagonal ones (eta_12 = xi_12
= 0) for tpbf87. Prints a markdown table: status, steps, wall time (to the end, or to the divergence
guard's stop), its ratio to the first row (FD, implicit Euler), the final elastic energy (eq. 13) and the
largest node speed.

    python docs/tradeoffs.py [NODES]      # default 15 (nodes a side)
"""

from __future__ import annotations

import sys
import time

import numpy as np

import deformable as dm
from fdmodel import FDModel
from femodel import FEModel

ROWS = (("variational", "implicit-euler"), ("variational", "newmark"), ("tpbf87", "semi-implicit"))


def run(force_model: str, scheme: str, cls, nodes: int) -> dict:
    """One row: the cloth under ``force_model`` and ``scheme`` on backend class ``cls``."""
    full = force_model == "variational"
    eta = np.full((2, 2), 50.0) if full else np.diag([50.0, 50.0])
    xi = np.full((2, 2), 1e-3) if full else np.diag([1e-3, 1e-3])
    scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(nodes, nodes)), dm.Material(mu=0.1, gamma=0.05, eta=eta, xi=xi),
                     forces=[dm.Gravity()], constraints=[dm.Pin(["top-left", "top-right"])], force_model=force_model)
    model = cls(scene)
    t0 = time.perf_counter()
    result = dm.TimeStepper(model, dt="auto", scheme=scheme).run(model.initial_state(), t_end=1.0)
    wall = time.perf_counter() - t0
    e = model.energy(result.state.X)
    return dict(force_model=force_model, scheme=scheme, backend=cls.__name__, status=result.status,
                steps=result.steps, wall=wall, energy=e.stretching + e.bending,
                speed=float(np.linalg.norm(model.grid(result.state.V), axis=-1).max()))


def main(nodes: int = 15) -> str:
    rows = [run(fm, scheme, cls, nodes) for fm, scheme in ROWS for cls in (FDModel, FEModel)]
    first = rows[0]["wall"]
    lines = ["| force model | scheme | backend | status | steps | wall (s) | x first row | elastic energy (J) | max speed (m/s) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| `{r['force_model']}` | `{r['scheme']}` | {r['backend']} | {r['status']} | {r['steps']} | "
                     f"{r['wall']:.2f} | {r['wall'] / first:.1f} | {r['energy']:.4g} | {r['speed']:.3g} |")
    return "\n".join(lines)


if __name__ == "__main__":
    print(main(int(sys.argv[1]) if len(sys.argv) > 1 else 15))
