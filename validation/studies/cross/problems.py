r"""The well-posed problems of the cross study, built here from the library's parts, and their references.

Every problem is well posed for the energy-consistent model (docs/design.md): force model
"variational", full weight tensors (eta_12 = eta, xi_12 = xi: shear and twist cost energy, so equilibria are
unique), bending stiffness xi > 0, edges held (pinned or clamped) rather than points, smooth loads. With
full tensors the model is the St Venant-Kirchhoff plate with E h = 8 eta and D = 2 xi, nu = 0
(docs/design.md, "Three readings of the model"); :func:`material` takes (E h, D).

Statics

- ``cantilever``: Sze, Liu and Lo (2004), "Popular benchmark problems for geometric nonlinear analysis of
  shells" (Finite Elements in Analysis and Design 40), the cantilever under an end shear force: L = 10,
  b = 1, E h = 1.2e5, D = 100, a dead tip load P with P L^2 / EI = 1 to 4, EI = D b. With nu = 0 the strip
  bends cylindrically (no anticlastic coupling: G22 = 1, B22 = B12 = 0), so the 2-D solution is the
  extensible elastica of the model's own energy per unit width, ``eta (lambda^2 - 1)^2 + xi (lambda
  theta')^2`` (lambda the stretch, theta the slope: G11 = lambda^2, B11 = n . r_11 = lambda theta'),
  :func:`elastica_tip`. Its tip differs from the inextensible elastica of the literature ((-u/L, w/L) =
  (0.3289, 0.6700) at P L^2/EI = 4) by the axial strain, about 3e-5.
- ``plate``: the square a = 1 clamped on its four edges under a uniform dead load q, D = 1, E h = 8e3
  (thickness sqrt(12 D / E h) = 0.039): at q = 30 the centre deflection is 0.78 of the linear plate's,
  a membrane-stiffened (nonlinear) plate. ``linear_plate``: E h = 8e4, q = 1e-3 (w / thickness = 1e-4,
  the membrane correction below 1e-9): Timoshenko's w_c = 0.00126 q a^4 / D, whose further digits
  (:data:`CLAMPED_CENTRE`) come from a bicubic Hermite solution on 256 x 256 elements (order 4,
  Richardson-extrapolated; Taylor and Govindjee (2004), "Solution of clamped rectangular plate problems",
  give the same 0.00126532).
- ``hanging``: a sheet 1 x 1 in the x-z plane hanging under gravity from its pinned top edge, D = 0.02,
  E h = 800, mu = 1, pushed sideways by ``f_y = 2 (1 - a2) sin(pi a1)`` (N/m^2, zero at the pinned edge): it
  bulges out of its plane (B about 0.3 1/m).

Dynamics (Newmark, the trapezoidal rule: second order in time, no numerical damping)

- ``swing``: the hanging sheet released: the lateral load is removed at t = 0 and the sheet swings back
  through its plane. The load vanishes on the pinned edge, so the initial acceleration is compatible
  with the boundary.
- ``flag``: a sheet 1.2 x 0.8 in the x-z plane on a pole (its left edge pinned), D = 0.1, E h = 400,
  mu = 0.1, in a steady wind: a drag of 5 N/m^2 along x (the tension that keeps it spread). From that
  equilibrium a gust ``f_y = s(t) sin(2 pi (2 t - a1 / 2.4)) (a1 / L1) (1/2 + a2 / L2)`` travels down the
  flag, s(t) the quintic smoothstep over 0.2 s (zero with two derivatives at t = 0), zero at the pole and
  stronger at the top (so the flag twists as well as bends). Its weight is left out: loaded in its own
  plane along the pole, a sheet held on one edge carries a shear whose stresses are singular at the
  corners where the pole meets the free edges (measured: the L2 self-convergence of FD's G fell to 1.4
  with gravity, 1.9 without).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_bvp

import deformable as dm
from deformable.geometry.surfaces import Plane

__all__ = ["CANTILEVER", "LOADS", "CLAMPED_CENTRE", "NEWTON", "material", "cantilever", "elastica_tip",
           "plate", "linear_plate", "hanging", "flag", "VERTICAL"]

#: Sze, Liu and Lo's cantilever
CANTILEVER = dict(L=10.0, b=1.0, Eh=1.2e5, D=100.0)
#: P L^2 / EI of the cantilever family
LOADS = (1.0, 2.0, 3.0, 4.0)
#: the clamped square plate's centre deflection w_c D / (q a^4) (Timoshenko: 0.00126)
CLAMPED_CENTRE = 0.00126531909
#: the nonlinear and the linear clamped plate: side a, D, E h, load q
PLATE = dict(a=1.0, D=1.0, Eh=8e3, q=30.0)
LINEAR_PLATE = dict(a=1.0, D=1.0, Eh=8e4, q=1e-3)
#: Newton for the statics: a fresh factorisation every iteration (quadratic convergence to the round-off
#: floor; reusing a factorisation stopped the stiff-membrane cantilever 1e-5 m short)
NEWTON = {"reuse": False}
#: a sheet in the x-z plane: a1 along x, a2 up
VERTICAL = Plane(e1=(1.0, 0.0, 0.0), e2=(0.0, 0.0, 1.0))
ALL_EDGES = ["left", "right", "bottom", "top"]


def material(Eh: float, D: float, mu: float = 1.0, gamma: float = 0.0) -> dm.Material:
    """Full weight tensors of the St Venant-Kirchhoff plate (nu = 0): eta = E h / 8, xi = D / 2."""
    return dm.Material(mu=mu, gamma=gamma, eta=np.full((2, 2), Eh / 8), xi=np.full((2, 2), D / 2))


def cantilever(nodes: tuple[int, int], load: float) -> dm.Scene:
    """The cantilever clamped at a1 = 0 under the tip shear with P L^2 / EI = ``load``."""
    c = CANTILEVER
    P = load * c["D"] * c["b"] / c["L"] ** 2
    return dm.Scene(dm.Sheet(size=(c["L"], c["b"]), nodes=nodes), material(c["Eh"], c["D"]),
                    force_model="variational", forces=[dm.EdgeLoad("right", f=(0.0, 0.0, -P / c["b"]))],
                    constraints=[dm.Clamp("left")], name="cantilever")


def elastica_tip(load: float, steps: int = 8) -> np.ndarray:
    """Tip (x, z) (m) of the extensible elastica of the model's energy (module docstring), P L^2 / EI = load.

    With theta the slope, m = 2 xi lambda^2 theta' the moment per unit width and p = P / b:
    ``m' = p lambda cos(theta)``, ``theta' = m / (2 xi lambda^2)``, ``x' = lambda cos(theta)``,
    ``z' = lambda sin(theta)``; lambda solves ``4 eta lambda (lambda^2 - 1) + m^2 / (2 xi lambda^3)
    = -p sin(theta)`` (the stationarity in the stretch); theta(0) = 0, m(L) = 0. By collocation
    (scipy's solve_bvp, tolerance 1e-10) under load continuation.
    """
    c = CANTILEVER
    eta, xi, L = c["Eh"] / 8, c["D"] / 2, c["L"]
    p_full = load * c["D"] / L**2

    def stretch(m, theta, p):
        lam = np.ones_like(m)
        for _ in range(20):  # Newton on the cubic, from the unstretched state
            g = 4 * eta * lam * (lam**2 - 1) + m**2 / (2 * xi * lam**3) + p * np.sin(theta)
            lam = lam - g / (4 * eta * (3 * lam**2 - 1) - 1.5 * m**2 / (xi * lam**4))
        return lam

    s = np.linspace(0.0, L, 401)
    y = np.zeros((4, s.size))
    y[2] = s
    for k in range(1, steps + 1):
        p = p_full * k / steps

        def rhs(_, y, p=p):
            lam = stretch(y[1], y[0], p)
            return np.vstack([y[1] / (2 * xi * lam**2), p * lam * np.cos(y[0]), lam * np.cos(y[0]),
                              lam * np.sin(y[0])])

        sol = solve_bvp(rhs, lambda ya, yb: np.array([ya[0], yb[1], ya[2], ya[3]]), s, y, tol=1e-10,
                        bc_tol=1e-12, max_nodes=500_000)
        if not sol.success:
            raise RuntimeError(f"extensible elastica at P L^2/EI = {load * k / steps:g}: {sol.message}")
        s, y = sol.x, sol.y
    return np.array([y[2, -1], y[3, -1]])


def _plate(nodes: int, a: float, D: float, Eh: float, q: float) -> dm.Scene:
    return dm.Scene(dm.Sheet(size=(a, a), nodes=(nodes, nodes)), material(Eh, D), force_model="variational",
                    forces=[dm.BodyForce((0.0, 0.0, q))], constraints=[dm.Clamp(ALL_EDGES)], name="clamped plate")


def plate(nodes: int) -> dm.Scene:
    """The nonlinear clamped plate (:data:`PLATE`)."""
    return _plate(nodes, **PLATE)


def linear_plate(nodes: int) -> dm.Scene:
    """The clamped plate under a load small enough to be linear (:data:`LINEAR_PLATE`)."""
    return _plate(nodes, **LINEAR_PLATE)


def _sideways(a1, a2, t):
    """The hanging sheet's lateral push (N/m^2): 2 (1 - a2) sin(pi a1) along y."""
    a1, a2 = np.broadcast_arrays(a1, a2)
    return np.stack([0 * a1, 2.0 * (1.0 - a2) * np.sin(np.pi * a1), 0 * a1], axis=-1)


def hanging(nodes: int, stage: str = "pushed") -> dm.Scene:
    """The sheet hanging from its pinned top edge: "weight" (gravity only), "pushed" (and the lateral push),
    "released" (gravity only, the swing's model)."""
    forces = [dm.Gravity(9.81)] + ([dm.BodyForce(_sideways)] if stage == "pushed" else [])
    return dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(nodes, nodes), rest=VERTICAL), material(800.0, 0.2),
                    force_model="variational", forces=forces, constraints=[dm.Pin("top")], name=f"hanging, {stage}")


def smoothstep(t: float, rise: float = 0.2) -> float:
    """The quintic smoothstep 6 s^5 - 15 s^4 + 10 s^3 of s = t / rise in [0, 1] (C2 at both ends)."""
    s = min(max(t / rise, 0.0), 1.0)
    return s**3 * (10.0 - 15.0 * s + 6.0 * s**2)


FLAG = dict(size=(1.2, 0.8), Eh=400.0, D=0.1, mu=0.1, drag=5.0, gust=1.0, frequency=2.0, wavelength=2.4)


def _gust(a1, a2, t):
    """The travelling gust (N/m^2) along y, zero at the pole and at t = 0 with two time derivatives."""
    a1, a2 = np.broadcast_arrays(a1, a2)
    L1, L2 = FLAG["size"]
    f = FLAG["gust"] * smoothstep(t) * np.sin(2 * np.pi * (FLAG["frequency"] * t - a1 / FLAG["wavelength"]))
    return np.stack([0 * a1, f * (a1 / L1) * (0.5 + a2 / L2), 0 * a1], axis=-1)


def flag(nodes: int, stage: str = "gust") -> dm.Scene:
    """The flag on its pole: "steady" (the drag) or "gust" (and the travelling gust)."""
    L1, L2 = FLAG["size"]
    nodes = ((nodes - 1) * round(L1 / 0.4) // round(L2 / 0.4) + 1, nodes)  # square cells
    forces = [dm.BodyForce((FLAG["drag"], 0.0, 0.0))]
    forces += [dm.BodyForce(_gust)] if stage == "gust" else []
    return dm.Scene(dm.Sheet(size=FLAG["size"], nodes=nodes, rest=VERTICAL),
                    material(FLAG["Eh"], FLAG["D"], mu=FLAG["mu"]), force_model="variational", forces=forces,
                    constraints=[dm.Pin("left")], name=f"flag, {stage}")
