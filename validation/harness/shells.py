r"""Shell benchmark problems shared by the tests and the ``shells`` study (issue 28).

The rolled cantilever (Sze, Liu and Lo 2004, FEAD 40, 1551-1569, test 3.2): a strip of length L, clamped at
a1 = 0, rolled by an end moment about its width (:class:`deformable.EdgeMoment`) into a circle of radius EI / M; at M = 2 pi EI / L the free end comes back
to the clamp. With Koiter's energy at nu = 0 (no anticlastic coupling) the strip bends cylindrically, its
bending stiffness per unit width D = E h^3 / 12. Koiter's bending measure is B = n . r_11, the curvature times
the stretch of the axis, so the moment also stretches the axis by about kappa^2 D / (E h) (3e-6 here, h / R
= 0.006): the circle is the exact solution up to that.

The buckled column: the same strip clamped at a1 = 0 under an axial compressive edge load at its free end,
twice Euler's load P_cr = pi^2 EI / (4 L^2) at load factor 1. Its post-buckling path is the elastica
(Timoshenko and Gere 1961, *Theory of Elastic Stability*, section 2.7): with k = sin(theta_tip / 2) and K the
complete elliptic integral of the first kind, P / P_cr = 4 K(k)^2 / pi^2 and the tip's lateral deflection
delta / L = 2 k / K(k) (:func:`elastica_load`).

The shallow arch: the strip with the rest shape z = H sin(pi a1 / L), pinned (hinged) at both ends, under a
line load across its middle; it snaps through a limit point (the test of the arc-length path).

The hinged cylindrical roof (Sabir and Lock 1972; Sze, Liu and Lo 2004, section 3.8, the isotropic roof of
thickness 12.7): a cylindrical panel of radius R = 2540, length L = 508 and half angle theta = 0.1 rad, its
straight edges hinged, its curved edges free, under a central point load P = lambda P_max, P_max = 3000,
E = 3102.75, nu = 0.3 (the data as given in the hinged-roof demo of PENGoLINS, hanzhao2020/PENGoLINS,
demos/hinged_cylin_roof/hinged_cylin_iso.py at 0f44368b, and the Kratos documentation page "Hinged cylindrical
roof snapthrough", both citing Sze et al. 2004). Modelled as a quarter with two symmetry planes. The
published path (:data:`ROOF_TABLE`: P / P_max against the centre's deflection -W_C, ABAQUS S4R) is read from
the MBDyn test suite, zanoni-mbdyn/MBDyn, tests/plates/sze2004/sze38/sze38_ref_a.dat at 425115db ("# 12.7
Unit thick, isotropic"), whose README cites Sze, Liu and Lo (2004).

The pull-out of an open-ended cylinder (Sze, Liu and Lo 2004, section 3.5): a cylinder of radius R = 4.953,
length L = 10.35 and thickness h = 0.094, E = 10.5e6, nu = 0.3125, its ends free, pulled outwards at mid-length
by two opposite radial point forces P = lambda P_max, P_max = 40000 (the data of MBDyn's
tests/plates/sze2004/sze.tex at 1d739212 and sze35/sze35.awk, which also gives the octant and the points:
A the loaded point, B on the mid-plane 90 degrees from A, C at the free end on B's generator). Modelled as
an octant with three symmetry planes, a quarter of P at A. :data:`PULLOUT_TABLE` (P / P_max, w_A, -u_B, -u_C,
ABAQUS S4R on 24 x 36) is MBDyn's tests/plates/sze2004/sze35/sze35_ref.dat at 425115db.

The pinched cylinder mounted over rigid diaphragms (Sze, Liu and Lo 2004, section 3.6): a cylinder of radius
R = 100, length L = 200 and thickness h = 1, E = 30e3, nu = 0.3, its ends on diaphragms rigid in their plane
(the radial and circumferential displacements held, the axial one free), pinched at mid-length by two
opposite inward radial point forces P = lambda P_max, P_max = 12000 (the data of MBDyn's sze.tex, and the
octant of sze36/sze36.awk at 425115db: the diaphragm at y = 0 holding x and z, symmetry planes x = 0, z = 0
and y = L / 2, a quarter of P at A, the drive "(Pmax/4)" of sze36/sze36 at 3f0d44f5; A the loaded point,
B on the mid-plane 90 degrees from A). :data:`PINCHED_TABLE` (P / P_max, -W_A, U_B, ABAQUS S4R on 48 x 48,
as sze.tex states) is MBDyn's tests/plates/sze2004/sze36/sze36_ref.dat at 425115db.

Looked for and not used: the pinched semi-cylinder (section 3.7): its table is MBDyn's sze37/sze37_ref.dat
and its data in sze.tex, but MBDyn has no model of it (sze.tex: "todo") and no public source read here
states its boundary conditions; the hemisphere (section 3.4): MBDyn has no table (sze.tex: "not
implemented"), and the table in Elmer's test suite has unlabelled columns.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipk

import deformable as dm

__all__ = ["PINCHED", "PINCHED_TABLE", "PULLOUT", "PULLOUT_TABLE", "ROLL", "ROOF", "ROOF_TABLE", "pullout_cylinder", "column", "elastica_load", "hinged_roof", "pinched_cylinder", "rolled_cantilever", "shallow_arch",
           "tip_gap"]

#: the rolled strip: length, width (m), Young's modulus (Pa), thickness (m); D = E h^3 / 12 = 1 N m
ROLL = dict(L=1.0, b=0.1, E=1.2e10, h=1e-3)


def rolled_cantilever(nodes: int, fraction: float = 1.0, width_nodes: int = 3) -> dm.Scene:
    """The strip on ``nodes`` x ``width_nodes`` nodes under ``fraction`` of the moment that closes the circle,
    m = fraction 2 pi D / L per unit width (N m/m)."""
    D = ROLL["E"] * ROLL["h"] ** 3 / 12
    return _strip(nodes, width_nodes, constraints=[dm.Clamp("left")],
                  forces=[dm.EdgeMoment("right", m=fraction * 2 * np.pi * D / ROLL["L"])])


def tip_gap(model, X) -> float:
    """The distance of the free end's midpoint from the clamped end's, over L."""
    R = model.grid(X)
    return float(np.linalg.norm(R[-1].mean(axis=0) - R[0].mean(axis=0)) / ROLL["L"])


def _strip(nodes, width_nodes=3, rest=None, constraints=(), forces=()) -> dm.Scene:
    L, b, E, h = ROLL["L"], ROLL["b"], ROLL["E"], ROLL["h"]
    unused = np.ones((2, 2))  # Koiter reads E, nu and h, not eta and xi
    return dm.Scene(dm.Sheet(size=(L, b), nodes=(nodes, width_nodes), rest=rest),
                    dm.Material(mu=1.0, eta=unused, xi=unused), force_model=dm.Koiter(E=E, nu=0.0, h=h),
                    constraints=list(constraints), forces=list(forces))


def euler_load() -> float:
    """P_cr = pi^2 EI / (4 L^2) of the clamped-free strip (N), EI = E h^3 b / 12."""
    L, b, E, h = ROLL["L"], ROLL["b"], ROLL["E"], ROLL["h"]
    return float(np.pi**2 * E * h**3 * b / 12 / (4 * L**2))


def column(nodes: int) -> dm.Scene:
    """The clamped strip under 2 P_cr of axial compression at its free end at load factor 1 (module docstring)."""
    b = ROLL["b"]
    return _strip(nodes, constraints=[dm.Clamp("left")], forces=[dm.EdgeLoad("right", f=(-2 * euler_load() / b, 0, 0))])


#: the elastica's largest tip deflection over L (reached at m = k^2 = 0.7013): a deflection has one load below it
_PEAK_M = 0.7013


def elastica_load(deflection: float) -> float:
    """P / P_cr on the elastica at the tip's lateral deflection delta / L (module docstring), for 0 < delta / L
    below the peak 0.806."""
    m = brentq(lambda m: 2 * np.sqrt(m) / ellipk(m) - deflection, 1e-14, _PEAK_M)
    return float(4 * ellipk(m) ** 2 / np.pi**2)


def shallow_arch(nodes: int, rise: float = 1.5e-3) -> dm.Scene:
    """The hinged shallow arch z = rise sin(pi a1 / L) under a line load of peak 1 N/m across its middle
    (a Gaussian of width L / 20) at load factor 1 (module docstring)."""
    L = ROLL["L"]

    def load(a1, a2, t):
        return np.stack([0 * a1, 0 * a1, -np.exp(-(((a1 - L / 2) / (0.05 * L)) ** 2))], axis=-1)

    return _strip(nodes, rest=lambda a1, a2: np.stack([a1, a2, rise * np.sin(np.pi * a1 / L)], -1),
                  constraints=[dm.Pin(["left", "right"])], forces=[dm.EdgeLoad("top", f=load)])


#: the isotropic hinged roof of thickness 12.7 (module docstring; units of the source: N, mm)
ROOF = dict(R=2540.0, L=508.0, theta=0.1, P_max=3000.0, h=12.7, E=3102.75, nu=0.3)

#: (P / P_max, -W_C) of Sze, Liu and Lo (2004) for the isotropic roof of thickness 12.7, as read from
#: zanoni-mbdyn/MBDyn tests/plates/sze2004/sze38/sze38_ref_a.dat (commit 425115db39e00a06b4ea5c6dab4c19754953d852)
ROOF_TABLE = np.array([
    [0.0000, 0.000], [0.0877, 0.693], [0.1980, 1.638], [0.3473, 3.087], [0.4686, 4.477], [0.5647, 5.802],
    [0.6381, 7.057], [0.6908, 8.237], [0.7246, 9.339], [0.7412, 10.358], [0.7421, 11.293], [0.7286, 12.141],
    [0.7023, 12.903], [0.6649, 13.583], [0.6182, 14.188], [0.5643, 14.728], [0.5055, 15.217], [0.4442, 15.676],
    [0.3830, 16.125], [0.3245, 16.590], [0.2717, 17.094], [0.2272, 17.657], [0.1940, 18.299], [0.1750, 19.028],
    [0.1729, 19.852], [0.1905, 20.771], [0.2303, 21.780], [0.2950, 22.875], [0.3871, 24.049], [0.4443, 24.663],
    [0.5093, 25.293], [0.5826, 25.940], [0.6644, 26.601], [0.7551, 27.276], [0.8549, 27.964], [0.9643, 28.663],
    [1.0835, 29.374]])


def hinged_roof(nodes: int) -> dm.Scene:
    """A quarter of the hinged roof on ``nodes`` x ``nodes`` nodes (FE; module docstring): a1 along the arc
    from the hinged edge ("left") to the crown ("right", the symmetry plane x = 0), a2 along the axis from the
    free edge ("bottom") to the middle ("top", the plane y = L / 2); a quarter of the load at the corner."""
    R, L, th = ROOF["R"], ROOF["L"], ROOF["theta"]

    def roof(a1, a2):
        phi = th - a1 / R
        return np.stack([-R * np.sin(phi), a2, R * np.cos(phi) - R * np.cos(th)], axis=-1)

    unused = np.ones((2, 2))
    return dm.Scene(dm.Sheet(size=(R * th, L / 2), nodes=(nodes, nodes), rest=roof),
                    dm.Material(mu=1.0, eta=unused, xi=unused),
                    force_model=dm.Koiter(E=ROOF["E"], nu=ROOF["nu"], h=ROOF["h"]),
                    constraints=[dm.Pin("left"), dm.Symmetry("right", "x"), dm.Symmetry("top", "y")],
                    forces=[dm.PointLoad(at=(R * th, L / 2), f=(0.0, 0.0, -ROOF["P_max"] / 4))], name="hinged roof")


#: the pull-out cylinder (module docstring; the source's units)
PULLOUT = dict(R=4.953, L=10.35, h=0.094, E=10.5e6, nu=0.3125, P_max=40000.0)

#: (P / P_max, w_A, -u_B, -u_C) of Sze, Liu and Lo (2004), as read from zanoni-mbdyn/MBDyn
#: tests/plates/sze2004/sze35/sze35_ref.dat (commit 425115db39e00a06b4ea5c6dab4c19754953d852), header "# P/Pmax wA -uB -uC"
PULLOUT_TABLE = np.array([
    [0.00, 0.000, 0.000, 0.000], [0.025, 0.819, 0.864, 0.872], [0.05, 1.260, 1.471, 1.493],
    [0.075, 1.527, 1.901, 1.946], [0.10, 1.707, 2.217, 2.293], [0.15, 1.936, 2.641, 2.792],
    [0.20, 2.079, 2.904, 3.106], [0.25, 2.180, 3.087, 3.310], [0.30, 2.257, 3.227, 3.452],
    [0.35, 2.321, 3.342, 3.556], [0.40, 2.376, 3.443, 3.632], [0.45, 2.425, 3.539, 3.688],
    [0.50, 2.473, 3.653, 3.718], [0.525, 2.543, 4.061, 3.580], [0.55, 2.577, 4.171, 3.518],
    [0.60, 2.618, 4.274, 3.452], [0.65, 2.648, 4.338, 3.410], [0.70, 2.672, 4.385, 3.378],
    [0.75, 2.692, 4.423, 3.353], [0.80, 2.710, 4.455, 3.332], [0.85, 2.726, 4.483, 3.313],
    [0.90, 2.741, 4.508, 3.297], [0.95, 2.755, 4.530, 3.283], [1.00, 2.768, 4.551, 3.269]])


def pullout_cylinder(around: int, along: int) -> dm.Scene:
    """An octant of the pull-out cylinder (FE; module docstring) on ``around`` x ``along`` nodes: a1 the arc from
    C's generator (theta = 0, "left", the plane z = 0) to A's (theta = pi / 2, "right", the plane x = 0), a2
    from the free end ("bottom") to the mid-plane ("top", y = L / 2); the points A = (R pi / 2, L / 2),
    B = (0, L / 2), C = (0, 0) in (a1, a2)."""
    return _octant(PULLOUT, (around, along), [], +1.0, "pull-out cylinder")


def _octant(data: dict, nodes, held: list, sign: float, name: str) -> dm.Scene:
    """An octant of a cylinder of ``data``'s R, L, E, nu, h: a1 the arc from theta = 0 ("left", the plane z = 0)
    to theta = pi / 2 ("right", the plane x = 0), a2 from the end ("bottom") to the mid-plane ("top", y = L / 2),
    the constraints ``held`` besides the three symmetry planes, a quarter of ``sign`` P_max along z at
    (R pi / 2, L / 2)."""
    R, L = data["R"], data["L"]

    def cylinder(a1, a2):
        return np.stack([R * np.cos(a1 / R), a2, R * np.sin(a1 / R)], axis=-1)

    unused = np.ones((2, 2))
    arc = R * np.pi / 2
    return dm.Scene(dm.Sheet(size=(arc, L / 2), nodes=tuple(nodes), rest=cylinder),
                    dm.Material(mu=1.0, eta=unused, xi=unused),
                    force_model=dm.Koiter(E=data["E"], nu=data["nu"], h=data["h"]),
                    constraints=[*held, dm.Symmetry("left", "z"), dm.Symmetry("right", "x"), dm.Symmetry("top", "y")],
                    forces=[dm.PointLoad(at=(arc, L / 2), f=(0.0, 0.0, sign * data["P_max"] / 4))], name=name)


#: the pinched cylinder over rigid diaphragms (module docstring; the source's units)
PINCHED = dict(R=100.0, L=200.0, h=1.0, E=30e3, nu=0.3, P_max=12000.0)

#: (P / P_max, -W_A, U_B) of Sze, Liu and Lo (2004), as read from zanoni-mbdyn/MBDyn
#: tests/plates/sze2004/sze36/sze36_ref.dat (commit 425115db39e00a06b4ea5c6dab4c19754953d852), header "# P/Pmax -WA UB"
PINCHED_TABLE = np.array([
    [0.00, 0.000, 0.000], [0.05, 9.561, -0.233], [0.075, 15.648, -0.922], [0.10, 23.164, -2.391],
    [0.125, 29.375, -3.872], [0.15, 36.208, -2.154], [0.175, 51.499, 6.792], [0.20, 56.373, 10.448],
    [0.25, 61.877, 14.905], [0.30, 65.498, 17.979], [0.35, 68.229, 20.365], [0.40, 70.424, 22.321],
    [0.45, 72.204, 23.916], [0.50, 73.790, 25.381], [0.55, 75.139, 26.631], [0.60, 76.331, 27.735],
    [0.65, 77.472, 28.843], [0.70, 78.451, 29.772], [0.75, 79.339, 30.604], [0.80, 80.218, 31.471],
    [0.85, 81.045, 32.299], [0.90, 81.766, 32.989], [0.95, 82.435, 33.619], [1.00, 83.102, 34.272]])


def pinched_cylinder(nodes: int) -> dm.Scene:
    """An octant of the pinched cylinder (FE; module docstring) on ``nodes`` x ``nodes`` nodes: a1 the arc from
    B's generator (theta = 0, "left", the plane z = 0) to A's (theta = pi / 2, "right", the plane x = 0), a2
    from the diaphragm ("bottom", x and z held) to the mid-plane ("top", y = L / 2); A = (R pi / 2, L / 2) and
    B = (0, L / 2) in (a1, a2)."""
    return _octant(PINCHED, (nodes, nodes), [dm.Pin("bottom", axes=("x", "z"))], -1.0, "pinched cylinder")
