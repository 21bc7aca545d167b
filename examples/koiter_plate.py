"""Koiter's shell as a plate: the simply supported square under a uniform load, against Navier's series
====================================================================================================

``deformable.Koiter(E, nu, h)`` is Koiter's isotropic shell energy (docs/design.md, "Koiter's shell"): its
bending stiffness is the plate's D = E h^3 / (12 (1 - nu^2)), Poisson's ratio included, which eq. (13) cannot
give (it has no Poisson coupling). The script linearises the energy about the flat plate (its Hessian at rest,
where the membrane carries no transverse stiffness), solves for the deflection under q = 1 N/m^2 with the four
edges pinned (simply supported) on FE and FD at three grids each, and compares the centre deflection with
Navier's double sine series for D (``validation.harness.plates.navier_centre``).

FE (bicubic Hermite elements) converges at order 4; FD is first order at nu > 0 (second at nu = 0), the open
work of docs/design.md, "Koiter's shell".

Run: ``python examples/koiter_plate.py [OUT]`` (OUT: the folder of the PNG).
"""

import os
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import scipy.sparse.linalg as spla
from matplotlib.ticker import NullFormatter

import deformable as dm
from validation.harness.backends import make_model
from validation.harness.orders import fit_order
from validation.harness.plates import navier_centre

OUT = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("EXAMPLES_OUT") or Path(__file__).parent / "out")
E, NU, H, Q = 1e6, 0.3, 1e-2, 1.0  # Pa, -, m, N/m^2
GRIDS = {"fe": (5, 9, 17), "fd": (17, 33, 65)}  # nodes a side (FE: 4, 8, 16 elements)


def centre_deflection(backend: str, nodes: int) -> float:
    """The linear plate's centre deflection (m) on one grid."""
    sheet = dm.Sheet(size=(1.0, 1.0), nodes=(nodes, nodes))
    unused = np.ones((2, 2))  # Koiter reads E, nu and h, not eta and xi
    scene = dm.Scene(sheet, dm.Material(mu=1.0, eta=unused, xi=unused), force_model=dm.Koiter(E=E, nu=NU, h=H),
                     forces=[dm.BodyForce(f=(0.0, 0.0, Q))], constraints=[dm.Pin(["left", "right", "bottom", "top"])])
    model = make_model(scene, backend)
    X = model.initial_state()
    n = model.ndof
    free = np.setdiff1d(np.arange(n), model.fixed_dofs()[2])
    Hzz = model.energy_hessian(X).tocsr()[2 * n:, 2 * n:][free][:, free]  # the z block of the flat plate
    w = np.zeros(n)
    w[free] = spla.spsolve(Hzz.tocsc(), model.load(X, 0.0)[free, 2])
    return float(model.sample(X + np.outer(w, [0.0, 0.0, 1.0]), np.array([[0.5, 0.5]])).r[0, 2])


D = dm.Koiter(E=E, nu=NU, h=H).stiffnesses[1]
exact = navier_centre(D, Q)
print(f"D = {D:.6g} N m (E h^3 / (12 (1 - nu^2)) at nu = {NU}); Navier's centre deflection {exact:.6g} m")
OUT.mkdir(parents=True, exist_ok=True)
fig, ax = plt.subplots(figsize=(5.5, 3.8))
for backend, grids in GRIDS.items():
    h = np.array([1.0 / (g - 1) for g in grids])
    errors = np.array([abs(centre_deflection(backend, g) / exact - 1) for g in grids])
    order = fit_order(h, errors)  # the least-squares slope of log error against log h
    for g, e in zip(grids, errors):
        print(f"{backend.upper()} {g} nodes a side: relative error {e:.3g}")
    print(f"{backend.upper()}: observed order {order:.2f}")
    ax.loglog(h, errors, "o-", label=f"{backend.upper()} (order {order:.2f})")
ax.xaxis.set_minor_formatter(NullFormatter())  # decades only: the minor labels overlap
ax.set_xlabel("grid spacing h (m)")
ax.set_ylabel("relative error of the centre deflection")
ax.set_title(f"Koiter plate, nu = {NU}, simply supported, against Navier", fontsize=10)
ax.legend()
fig.tight_layout()
fig.savefig(OUT / "koiter_plate.png", dpi=100)
print(f"wrote {OUT / 'koiter_plate.png'}")
