r"""Analytic surfaces with closed-form derivatives, G (eq. 4), B (eq. 8) and Gaussian curvature.

Each :class:`AnalyticSurface` gives r and its first and second derivatives in
closed form on a parameter rectangle; G and B follow from them through
:mod:`deformable.geometry.tensors`, and surfaces with a textbook answer (plane,
cylinder, sphere, torus) also carry that answer (``G_exact``, ``B_exact``,
``K_exact``) so the two can be checked against each other.

All callables take (a1, a2) arrays of one shape S and return S + (3,).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from deformable.geometry import tensors

__all__ = ["AnalyticSurface", "SURFACES", "monge", "cylinder", "get"]


def _stack(*c):
    c = np.broadcast_arrays(*c)
    return np.stack(c, axis=-1)


@dataclass(frozen=True)
class AnalyticSurface:
    """A surface on ``[0, size[0]] x [0, size[1]]`` with exact r, r_i, r_ij."""

    name: str
    size: tuple[float, float]
    r: Callable
    r1: Callable
    r2: Callable
    r11: Callable
    r12: Callable
    r22: Callable
    G_exact: Callable | None = None  # (a1, a2) -> S + (2, 2), textbook closed form
    B_exact: Callable | None = None
    K_exact: Callable | None = None
    description: str = ""

    def derivatives(self, a1, a2):
        """dr (3, 2, *S) and ddr (3, 2, 2, *S) in the layout of deformable.geometry.tensors."""
        m = lambda f: np.moveaxis(f(a1, a2), -1, 0)  # noqa: E731
        r1, r2, r11, r12, r22 = m(self.r1), m(self.r2), m(self.r11), m(self.r12), m(self.r22)
        dr = np.stack([r1, r2], axis=1)
        ddr = np.stack([np.stack([r11, r12], axis=1), np.stack([r12, r22], axis=1)], axis=1)
        return dr, ddr

    def G(self, a1, a2) -> np.ndarray:
        """Metric tensor (2, 2, *S) from the exact derivatives, eq. (4)."""
        dr, _ = self.derivatives(a1, a2)
        return tensors.metric(dr)

    def B(self, a1, a2) -> np.ndarray:
        """Curvature tensor (2, 2, *S) from the exact derivatives, eq. (8)."""
        dr, ddr = self.derivatives(a1, a2)
        return tensors.curvature(ddr, tensors.normal(dr))

    def gaussian_curvature(self, a1, a2) -> np.ndarray:
        """K = det B / det G, shape S."""
        return tensors.gaussian_curvature(self.G(a1, a2), self.B(a1, a2))


def _tensor(*rows):
    """(2, 2, *S) from four component arrays given row by row."""
    a, b, c, d = np.broadcast_arrays(*rows)
    return np.array([[a, b], [c, d]])


def monge(f, f1, f2, f11, f12, f22, name, size=(1.0, 1.0), description="") -> AnalyticSurface:
    """The Monge patch r = (a1, a2, f(a1, a2)) from f and its derivatives."""
    z = lambda a1, a2: np.zeros(np.broadcast(a1, a2).shape)  # noqa: E731
    o = lambda a1, a2: np.ones(np.broadcast(a1, a2).shape)  # noqa: E731
    return AnalyticSurface(
        name=name, size=size,
        r=lambda a1, a2: _stack(a1, a2, f(a1, a2)),
        r1=lambda a1, a2: _stack(o(a1, a2), z(a1, a2), f1(a1, a2)),
        r2=lambda a1, a2: _stack(z(a1, a2), o(a1, a2), f2(a1, a2)),
        r11=lambda a1, a2: _stack(z(a1, a2), z(a1, a2), f11(a1, a2)),
        r12=lambda a1, a2: _stack(z(a1, a2), z(a1, a2), f12(a1, a2)),
        r22=lambda a1, a2: _stack(z(a1, a2), z(a1, a2), f22(a1, a2)),
        K_exact=lambda a1, a2: (f11(a1, a2) * f22(a1, a2) - f12(a1, a2) ** 2)
        / (1 + f1(a1, a2) ** 2 + f2(a1, a2) ** 2) ** 2,
        description=description,
    )


def _generic_monge() -> AnalyticSurface:
    """z = 0.3 sin(2 a1 + 0.3) sin(3 a2 + 0.7): no symmetry to hide errors."""
    A, p, q, c1, c2 = 0.3, 2.0, 3.0, 0.3, 0.7
    s1 = lambda a: np.sin(p * a + c1)  # noqa: E731
    k1 = lambda a: np.cos(p * a + c1)  # noqa: E731
    s2 = lambda a: np.sin(q * a + c2)  # noqa: E731
    k2 = lambda a: np.cos(q * a + c2)  # noqa: E731
    return monge(
        f=lambda a1, a2: A * s1(a1) * s2(a2),
        f1=lambda a1, a2: A * p * k1(a1) * s2(a2),
        f2=lambda a1, a2: A * q * s1(a1) * k2(a2),
        f11=lambda a1, a2: -A * p * p * s1(a1) * s2(a2),
        f12=lambda a1, a2: A * p * q * k1(a1) * k2(a2),
        f22=lambda a1, a2: -A * q * q * s1(a1) * s2(a2),
        name="monge",
        description="generic Monge patch z = 0.3 sin(2 a1 + 0.3) sin(3 a2 + 0.7) on the unit square",
    )


def _saddle() -> AnalyticSurface:
    """Hyperbolic paraboloid z = (a1 - 1/2)(a2 - 1/2)... shifted: z = 0.5 (a1^2 - a2^2) + 0.3 a1 a2."""
    return monge(
        f=lambda a1, a2: 0.5 * (a1**2 - a2**2) + 0.3 * a1 * a2,
        f1=lambda a1, a2: a1 + 0.3 * a2,
        f2=lambda a1, a2: -a2 + 0.3 * a1,
        f11=lambda a1, a2: np.ones(np.broadcast(a1, a2).shape),
        f12=lambda a1, a2: 0.3 * np.ones(np.broadcast(a1, a2).shape),
        f22=lambda a1, a2: -np.ones(np.broadcast(a1, a2).shape),
        name="saddle",
        description="saddle z = (a1^2 - a2^2)/2 + 0.3 a1 a2 (negative Gaussian curvature)",
    )


def _plane() -> AnalyticSurface:
    zero = lambda a1, a2: np.zeros(np.broadcast(a1, a2).shape)  # noqa: E731
    s = monge(zero, zero, zero, zero, zero, zero, name="plane", description="the plane z = 0")
    eye = lambda a1, a2: np.moveaxis(_tensor(1.0 + zero(a1, a2), 0.0, 0.0, 1.0), (0, 1), (-2, -1))  # noqa: E731
    return AnalyticSurface(**{**s.__dict__, "G_exact": eye,
                              "B_exact": lambda a1, a2: np.zeros(np.broadcast(a1, a2).shape + (2, 2))})


def cylinder(R: float = 0.6) -> AnalyticSurface:
    """Cylinder of radius R by arc length: r = (R cos(a1/R), R sin(a1/R), a2); G = I, B = diag(-1/R, 0)."""
    c = lambda a: np.cos(a / R)  # noqa: E731
    s = lambda a: np.sin(a / R)  # noqa: E731
    z = lambda a1, a2: np.zeros(np.broadcast(a1, a2).shape)  # noqa: E731
    one = lambda a1, a2: np.ones(np.broadcast(a1, a2).shape)  # noqa: E731
    return AnalyticSurface(
        name="cylinder", size=(1.0, 1.0),
        r=lambda a1, a2: _stack(R * c(a1), R * s(a1), a2 + z(a1, a2)),
        r1=lambda a1, a2: _stack(-s(a1), c(a1), z(a1, a2)),
        r2=lambda a1, a2: _stack(z(a1, a2), z(a1, a2), one(a1, a2)),
        r11=lambda a1, a2: _stack(-c(a1) / R, -s(a1) / R, z(a1, a2)),
        r12=lambda a1, a2: _stack(z(a1, a2), z(a1, a2), z(a1, a2)),
        r22=lambda a1, a2: _stack(z(a1, a2), z(a1, a2), z(a1, a2)),
        G_exact=lambda a1, a2: np.moveaxis(_tensor(one(a1, a2), 0.0, 0.0, 1.0), (0, 1), (-2, -1)),
        B_exact=lambda a1, a2: np.moveaxis(_tensor(-one(a1, a2) / R, 0.0, 0.0, 0.0), (0, 1), (-2, -1)),
        K_exact=lambda a1, a2: z(a1, a2),
        description=f"cylinder of radius {R} parametrised by arc length (outward normal)",
    )


def _sphere(R: float = 0.8) -> AnalyticSurface:
    """Sphere patch by longitude a1 and latitude a2 - 1/2 (off the poles); B = -G/R (outward normal)."""
    def ang(a1, a2):
        return a1, a2 - 0.5

    def r(a1, a2):
        p, t = ang(a1, a2)
        return R * _stack(np.cos(t) * np.cos(p), np.cos(t) * np.sin(p), np.sin(t))

    def r1(a1, a2):
        p, t = ang(a1, a2)
        return R * _stack(-np.cos(t) * np.sin(p), np.cos(t) * np.cos(p), 0 * p * t)

    def r2(a1, a2):
        p, t = ang(a1, a2)
        return R * _stack(-np.sin(t) * np.cos(p), -np.sin(t) * np.sin(p), np.cos(t) + 0 * p)

    def r11(a1, a2):
        p, t = ang(a1, a2)
        return R * _stack(-np.cos(t) * np.cos(p), -np.cos(t) * np.sin(p), 0 * p * t)

    def r12(a1, a2):
        p, t = ang(a1, a2)
        return R * _stack(np.sin(t) * np.sin(p), -np.sin(t) * np.cos(p), 0 * p * t)

    def G(a1, a2):
        p, t = ang(a1, a2)
        return np.moveaxis(_tensor(R**2 * np.cos(t) ** 2 + 0 * p, 0.0, 0.0, R**2 + 0 * p * t), (0, 1), (-2, -1))

    return AnalyticSurface(
        name="sphere", size=(1.0, 1.0), r=r, r1=r1, r2=r2, r11=r11, r12=r12, r22=lambda a1, a2: -r(a1, a2),
        G_exact=G, B_exact=lambda a1, a2: -G(a1, a2) / R,
        K_exact=lambda a1, a2: np.full(np.broadcast(a1, a2).shape, 1 / R**2),
        description=f"sphere of radius {R}, longitude a1, latitude a2 - 1/2 (outward normal)",
    )


def _torus(Rc: float = 1.0, rt: float = 0.4) -> AnalyticSurface:
    """Torus patch r = ((Rc + rt cos a2) cos a1, (Rc + rt cos a2) sin a1, rt sin a2)."""
    def rho(a2):
        return Rc + rt * np.cos(a2)

    def r(a1, a2):
        return _stack(rho(a2) * np.cos(a1), rho(a2) * np.sin(a1), rt * np.sin(a2) + 0 * a1)

    def r1(a1, a2):
        return _stack(-rho(a2) * np.sin(a1), rho(a2) * np.cos(a1), 0 * a1 * a2)

    def r2(a1, a2):
        return _stack(-rt * np.sin(a2) * np.cos(a1), -rt * np.sin(a2) * np.sin(a1), rt * np.cos(a2) + 0 * a1)

    def r11(a1, a2):
        return _stack(-rho(a2) * np.cos(a1), -rho(a2) * np.sin(a1), 0 * a1 * a2)

    def r12(a1, a2):
        return _stack(rt * np.sin(a2) * np.sin(a1), -rt * np.sin(a2) * np.cos(a1), 0 * a1 * a2)

    def r22(a1, a2):
        return _stack(-rt * np.cos(a2) * np.cos(a1), -rt * np.cos(a2) * np.sin(a1), -rt * np.sin(a2) + 0 * a1)

    def G(a1, a2):
        return np.moveaxis(_tensor(rho(a2) ** 2 + 0 * a1, 0.0, 0.0, rt**2 + 0 * a1 * a2), (0, 1), (-2, -1))

    def B(a1, a2):  # r1 x r2 is the outward normal (cos a1 cos a2, sin a1 cos a2, sin a2)
        return np.moveaxis(_tensor(-rho(a2) * np.cos(a2) + 0 * a1, 0.0, 0.0, -rt + 0 * a1 * a2), (0, 1), (-2, -1))

    return AnalyticSurface(
        name="torus", size=(1.0, 1.0), r=r, r1=r1, r2=r2, r11=r11, r12=r12, r22=r22, G_exact=G, B_exact=B,
        K_exact=lambda a1, a2: np.cos(a2) / (rt * rho(a2)) + 0 * a1,
        description=f"torus patch, centre-circle radius {Rc}, tube radius {rt}",
    )


def _helicoid(c: float = 0.5) -> AnalyticSurface:
    """Helicoid r = (u cos v, u sin v, c v) with u = a1 + 0.2, v = 2 a2 (minimal, K < 0)."""
    def uv(a1, a2):
        return a1 + 0.2, 2.0 * a2

    def r(a1, a2):
        u, v = uv(a1, a2)
        return _stack(u * np.cos(v), u * np.sin(v), c * v + 0 * u)

    def r1(a1, a2):
        u, v = uv(a1, a2)
        return _stack(np.cos(v) + 0 * u, np.sin(v) + 0 * u, 0 * u * v)

    def r2(a1, a2):
        u, v = uv(a1, a2)
        return 2.0 * _stack(-u * np.sin(v), u * np.cos(v), c + 0 * u * v)

    def r11(a1, a2):
        u, v = uv(a1, a2)
        return _stack(0 * u * v, 0 * u * v, 0 * u * v)

    def r12(a1, a2):
        u, v = uv(a1, a2)
        return 2.0 * _stack(-np.sin(v) + 0 * u, np.cos(v) + 0 * u, 0 * u * v)

    def r22(a1, a2):
        u, v = uv(a1, a2)
        return 4.0 * _stack(-u * np.cos(v), -u * np.sin(v), 0 * u * v)

    return AnalyticSurface(
        name="helicoid", size=(1.0, 1.0), r=r, r1=r1, r2=r2, r11=r11, r12=r12, r22=r22,
        K_exact=lambda a1, a2: -(c**2) / ((a1 + 0.2) ** 2 + c**2) ** 2 + 0 * a2,
        description=f"helicoid (u cos v, u sin v, {c} v), u = a1 + 0.2, v = 2 a2",
    )


def _skew() -> AnalyticSurface:
    """Non-orthogonal parametrisation of a wavy sheet: r = (a1 + 0.4 a2, a2, 0.2 sin(2 a1 + a2 + 0.1)); G12 != 0."""
    def ph(a1, a2):
        return 2.0 * a1 + a2 + 0.1

    z = lambda a1, a2: 0 * ph(a1, a2)  # noqa: E731
    return AnalyticSurface(
        name="skew", size=(1.0, 1.0),
        r=lambda a1, a2: _stack(a1 + 0.4 * a2, a2 + z(a1, a2), 0.2 * np.sin(ph(a1, a2))),
        r1=lambda a1, a2: _stack(1 + z(a1, a2), z(a1, a2), 0.4 * np.cos(ph(a1, a2))),
        r2=lambda a1, a2: _stack(0.4 + z(a1, a2), 1 + z(a1, a2), 0.2 * np.cos(ph(a1, a2))),
        r11=lambda a1, a2: _stack(z(a1, a2), z(a1, a2), -0.8 * np.sin(ph(a1, a2))),
        r12=lambda a1, a2: _stack(z(a1, a2), z(a1, a2), -0.4 * np.sin(ph(a1, a2))),
        r22=lambda a1, a2: _stack(z(a1, a2), z(a1, a2), -0.2 * np.sin(ph(a1, a2))),
        K_exact=lambda a1, a2: z(a1, a2),  # a ruled surface along the wave crests: developable
        description="non-orthogonal parametrisation (G12 != 0) of a developable wavy sheet",
    )


SURFACES: dict[str, Callable[[], AnalyticSurface]] = {
    "plane": _plane,
    "cylinder": cylinder,
    "sphere": _sphere,
    "torus": _torus,
    "helicoid": _helicoid,
    "saddle": _saddle,
    "monge": _generic_monge,
    "skew": _skew,
}


def get(name: str) -> AnalyticSurface:
    """The analytic surface called ``name``; ValueError naming the known ones otherwise."""
    try:
        return SURFACES[name]()
    except KeyError:
        raise ValueError(f"unknown surface {name!r}; known: {', '.join(SURFACES)}") from None
