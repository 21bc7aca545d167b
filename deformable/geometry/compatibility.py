"""The compatibility test of the paper (section 3.2) on a pair of fields (G_ij, B_ij).

G and B are not independent (paper, eq. 10): a surface exists with metric G and curvature B only if

    (r_11)_2 - (r_12)_1 = 0,   (r_22)_1 - (r_12)_2 = 0,   n_12 - n_21 = 0.       (10)

Written in the moving frame (r_1, r_2, n) with the Gauss-Weingarten equations

    r_ij = Gamma^k_ij r_k + B_ij n,      n_i = -W^k_i r_k,   W^k_i = G^{kl} B_li,

the third derivatives are, with every quantity computed from G and B alone,

    (r_ij)_k = [d_k Gamma^l_ij + Gamma^m_ij Gamma^l_mk - B_ij W^l_k] r_l
               + [Gamma^m_ij B_mk + d_k B_ij] n,

with Gamma^k_ij = G^{kl} (d_i G_lj + d_j G_li - d_l G_ij)/2. The paper's test compares u = (r_11)_2 with
v = (r_12)_1 and u' = (r_22)_1 with v' = (r_12)_2 "through the ratio of its magnitudes and the cosine of its angles
(both numbers must be near to one)", magnitudes taken with the frame's metric |c^l r_l + c^n n|^2 = c^k G_kl c^l +
(c^n)^2. The tangential parts of u - v are the Gauss equation, the normal parts the Mainardi-Codazzi equations:

- Gauss: K from G alone (Brioschi's formula) equals det B / det G;
- Codazzi 1: d_2 B_11 - d_1 B_12 = B_11 Gamma^1_12 + B_12 (Gamma^2_12 - Gamma^1_11) - B_22 Gamma^2_11;
- Codazzi 2: d_2 B_12 - d_1 B_22 = B_11 Gamma^1_22 + B_12 (Gamma^2_22 - Gamma^1_12) - B_22 Gamma^2_12.

Derivatives are central differences (``numpy.gradient``, second order, also at the edges): every residual is O(h^2)
on exact fields. Where a compared vector vanishes (on a plane or a cylinder; where an incompatible pair has
u != 0 = v) the ratio and the cosine are undefined: those points are *guarded* and tested by the residual |u - v|.

Range. Fields whose products or quotients leave double precision make residuals infinite or NaN; the test is then
not computable: :attr:`Compatibility.finite` is False, and so is :attr:`Compatibility.compatible`.

:func:`check_rest_state` evaluates a Scene's G0, B0 on its node grid, and :func:`warn_if_incompatible` turns a failed
check into an :class:`IncompatibleRestState` warning (a scene with rest-tensor overrides is checked when it is made).
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..errors import IncompatibleRestState, InputError
from . import tensors
from .surfaces import as_surface

__all__ = ["Compatibility", "Comparison", "check_compatibility", "brioschi", "christoffel", "third_derivatives",
           "rest_tensors", "check_rest_state", "warn_if_incompatible"]

log = logging.getLogger(__name__)


def _d(f: np.ndarray, h: tuple[float, float]) -> np.ndarray:
    """Central-difference gradient of a field (..., M, N): (2, ..., M, N), index 0 is d/da1."""
    return np.stack([np.gradient(f, h[0], axis=-2, edge_order=2), np.gradient(f, h[1], axis=-1, edge_order=2)])


def _inverse(G: np.ndarray) -> np.ndarray:
    det = tensors.det2(G)
    return np.array([[G[1, 1], -G[0, 1]], [-G[1, 0], G[0, 0]]]) / det


def christoffel(G: np.ndarray, h: tuple[float, float]) -> np.ndarray:
    """Christoffel symbols of the second kind Gamma^k_ij, shape (2, 2, 2, M, N) indexed [k, i, j].

    Parameters
    ----------
    G : array (2, 2, M, N)
        Metric on a uniform grid of spacings h = (h1, h2).
    """
    dG = _d(G, h)  # [l, i, j] = d_l G_ij
    first = 0.5 * (np.einsum("iljxy->lijxy", dG) + np.einsum("jlixy->lijxy", dG) - dG)  # [l, i, j] = Gamma_l,ij
    return np.einsum("klxy,lijxy->kijxy", _inverse(G), first)


def brioschi(G: np.ndarray, h: tuple[float, float]) -> np.ndarray:
    """Gaussian curvature from the metric alone (Brioschi's formula), shape (M, N) (1/length^2)."""
    E, F, Gg = G[0, 0], G[0, 1], G[1, 1]
    (Eu, Ev), (Fu, Fv), (Gu, Gv) = _d(E, h), _d(F, h), _d(Gg, h)
    Evv = _d(Ev, h)[1]
    Guu = _d(Gu, h)[0]
    Fuv = _d(Fu, h)[1]
    z = np.zeros_like(E)
    A = np.array([[-Evv / 2 + Fuv - Guu / 2, Eu / 2, Fu - Ev / 2], [Fv - Gu / 2, E, F], [Gv / 2, F, Gg]])
    Bm = np.array([[z, Ev / 2, Gu / 2], [Ev / 2, E, F], [Gu / 2, F, Gg]])
    det3 = lambda m: np.linalg.det(np.moveaxis(m, (0, 1), (-2, -1)))  # noqa: E731
    return (det3(A) - det3(Bm)) / (E * Gg - F**2) ** 2


def third_derivatives(G: np.ndarray, B: np.ndarray, h: tuple[float, float], Gamma=None) -> np.ndarray:
    """Frame components of (r_ij)_k from G and B: array (3, 2, 2, 2, M, N) indexed [c, i, j, k].

    Components c = 0, 1 multiply r_1, r_2 and c = 2 multiplies n (module docstring).
    """
    Gamma = christoffel(G, h) if Gamma is None else Gamma
    W = np.einsum("klxy,lixy->kixy", _inverse(G), B)  # W^k_i
    dGamma = _d(Gamma, h)  # [k, l, i, j] = d_k Gamma^l_ij
    dB = _d(B, h)  # [k, i, j]
    tang = (np.einsum("klijxy->lijkxy", dGamma) + np.einsum("mijxy,lmkxy->lijkxy", Gamma, Gamma)
            - np.einsum("ijxy,lkxy->lijkxy", B, W))
    norm = np.einsum("mijxy,mkxy->ijkxy", Gamma, B) + np.einsum("kijxy->ijkxy", dB)
    return np.concatenate([tang, norm[None]], axis=0)


def _frame_norm(c: np.ndarray, G: np.ndarray) -> np.ndarray:
    return np.sqrt(np.maximum(np.einsum("kxy,klxy,lxy->xy", c[:2], G, c[:2]) + c[2] ** 2, 0.0))


def _frame_dot(a: np.ndarray, b: np.ndarray, G: np.ndarray) -> np.ndarray:
    return np.einsum("kxy,klxy,lxy->xy", a[:2], G, b[:2]) + a[2] * b[2]


@dataclass(frozen=True)
class Comparison:
    """The paper's comparison of two vectors of eq. (10), u against v, over the checked points.

    Attributes
    ----------
    points : int
        Points checked.
    resolved : int
        Points where both |u| and |v| exceed the guard: there the ratio |u| / |v| and the cosine of the angle
        between u and v are defined and are the test.
    ratio, cosine : (worst, median) or None
        Over the resolved points (worst: farthest from 1, smallest); None when no point is resolved.
    residual : float
        max |u - v| over the other, guarded, points, relative to the vectors' scale (0 when none is guarded): where
        a vector vanishes the ratio and the cosine are undefined and the residual is the test.
    passed : bool
        |ratio - 1| <= rtol and cosine >= 1 - rtol at every resolved point, residual <= rtol, every quantity
        of the test finite (module docstring, "Range").
    """

    points: int
    resolved: int
    ratio: tuple | None
    cosine: tuple | None
    residual: float
    passed: bool

    def describe(self) -> str:
        parts = []
        if self.ratio is not None:
            parts.append(f"ratio {self.ratio[0]:.4g} (median {self.ratio[1]:.4g}), cosine {self.cosine[0]:.4g} "
                         f"(median {self.cosine[1]:.4g}) at {self.resolved} of {self.points} points")
        if self.resolved < self.points:
            parts.append(f"residual {self.residual:.3g} at the {self.points - self.resolved} guarded points")
        return "; ".join(parts)


@dataclass
class Compatibility:
    """Outcome of :func:`check_compatibility` (all maxima over the checked points).

    Attributes
    ----------
    comparisons : dict
        The paper's two comparisons, "(r_11)_2 vs (r_12)_1" and "(r_22)_1 vs (r_12)_2", each a :class:`Comparison`:
        ratio and cosine where both vectors are resolved, the residual elsewhere.
    compatible : bool
        Both comparisons pass (the paper's test, guarded).
    gauss : float
        max |K_Brioschi - det B / det G| (1/length^2), the Gauss equation alone (reported).
    codazzi : (float, float)
        max |residual| of the two Mainardi-Codazzi equations (1/length^2 per parameter unit, reported).
    gauss_relative, mismatch_relative : float
        gauss over the curvature scale max(|K|, |B|^2/|G|); max |u - v| (frame norm) over the vectors' scale at all
        points. Zero for a compatible pair up to discretisation error.
    guarded : float
        Fraction of points where a compared vector is below the guard (ratio and cosine undefined).
    finite : bool
        Every quantity of the test (third derivatives, curvatures, Codazzi residuals, scales) is finite; when not,
        the test is not computable in double precision and ``compatible`` is False (module docstring).
    fields : dict
        Fields (M', N') over the checked points (the grid less ``margin`` rows a side): the residuals "gauss",
        "codazzi1", "codazzi2", and the paper's "ratio1", "cosine1" ((r_11)_2 vs (r_12)_1) and "ratio2", "cosine2"
        ((r_22)_1 vs (r_12)_2), NaN at the guarded points.
    """

    comparisons: dict
    compatible: bool
    gauss: float
    codazzi: tuple[float, float]
    gauss_relative: float
    mismatch_relative: float
    guarded: float
    rtol: float
    finite: bool = True
    fields: dict = field(default_factory=dict, repr=False)

    @property
    def verdict(self) -> str:
        """"compatible", "INCOMPATIBLE", or "NOT COMPUTABLE" (non-finite residuals, module docstring)."""
        return "compatible" if self.compatible else "INCOMPATIBLE" if self.finite else "NOT COMPUTABLE"

    def summary(self) -> str:
        """One line for logs and warnings."""
        parts = "; ".join(f"{name}: {c.describe()}" for name, c in self.comparisons.items())
        if not self.finite:
            parts = f"non-finite residuals (the fields leave double precision); {parts}"
        return (f"{self.verdict} (tolerance {self.rtol:g}): {parts}; "
                f"Gauss residual {self.gauss:.3g}, Codazzi residuals {self.codazzi[0]:.3g}, {self.codazzi[1]:.3g}")


def check_compatibility(G, B, h, margin: int = 2, rtol: float = 0.05, guard: float = 0.05) -> Compatibility:
    """The paper's compatibility test (eq. 10) on fields G, B sampled on a uniform grid (module docstring).

    Parameters
    ----------
    G, B : array (2, 2, M, N)
        Metric (dimensionless for an arc-length-like parametrisation) and curvature (1/length) at the grid points,
        M, N >= 5.
    h : float or (h1, h2)
        Grid spacings (parameter units).
    margin : int
        Rows/columns at each edge left out. The default 2 leaves out the rows where the second derivatives of G
        (differences of one-sided differences) are only first order.
    rtol : float
        Tolerance: |ratio - 1| <= rtol, cosine >= 1 - rtol, guarded residual <= rtol.
    guard : float
        A point is guarded for a comparison where a compared vector is at most ``guard`` times their scale (the largest
        of them, and at least max |B|^2 / |G|^(1/2), Frobenius norms).

    Returns
    -------
    Compatibility
        Not compatible, and ``finite`` False, where a residual is infinite or NaN (module docstring, "Range").
    """
    with np.errstate(all="ignore"):  # an overflow shows as a non-finite residual, which the result reports
        return _check_compatibility(G, B, h, margin, rtol, guard)


def _check_compatibility(G, B, h, margin, rtol, guard) -> Compatibility:
    G, B = np.asarray(G, float), np.asarray(B, float)
    if G.shape != B.shape or G.ndim != 4 or G.shape[:2] != (2, 2) or min(G.shape[2:]) < 5:
        raise InputError(f"G and B must be (2, 2, M, N) fields with M, N >= 5, got {G.shape} and {B.shape}")
    if not (np.all(np.isfinite(G)) and np.all(np.isfinite(B))):
        raise InputError("G and B must be finite")
    h = (float(h), float(h)) if np.ndim(h) == 0 else tuple(float(v) for v in h)
    if np.any(tensors.det2(G) <= 0) or np.any(G[0, 0] <= 0):
        raise InputError("G must be positive definite at every point (G11 > 0, det G > 0)")
    M, N = G.shape[2:]
    if 2 * margin >= min(M, N) - 1:
        raise InputError(f"margin {margin} leaves no points of the {M} x {N} grid")
    inner = (slice(margin, M - margin), slice(margin, N - margin))
    Gamma = christoffel(G, h)
    K_G = brioschi(G, h)
    K_B = tensors.gaussian_curvature(G, B)
    gauss = (K_G - K_B)[inner]
    dB = _d(B, h)
    c1 = (dB[1, 0, 0] - dB[0, 0, 1]) - (B[0, 0] * Gamma[0, 0, 1] + B[0, 1] * (Gamma[1, 0, 1] - Gamma[0, 0, 0])
                                        - B[1, 1] * Gamma[1, 0, 0])
    c2 = (dB[1, 0, 1] - dB[0, 1, 1]) - (B[0, 0] * Gamma[0, 1, 1] + B[0, 1] * (Gamma[1, 1, 1] - Gamma[0, 0, 1])
                                        - B[1, 1] * Gamma[1, 0, 1])
    T = third_derivatives(G, B, h, Gamma)
    pairs = {"(r_11)_2 vs (r_12)_1": (T[:, 0, 0, 1], T[:, 0, 1, 0]),
             "(r_22)_1 vs (r_12)_2": (T[:, 1, 1, 0], T[:, 0, 1, 1])}
    norms = {k: (_frame_norm(u, G)[inner], _frame_norm(v, G)[inner]) for k, (u, v) in pairs.items()}
    # the scale of the compared vectors: the largest of them, and at least the size of the curvature terms
    # they are built from (|B|^2 / |G|^(1/2)), so that vectors that vanish exactly and carry only
    # discretisation error (a saddle's third derivatives) are not their own yardstick
    Gn = np.sqrt(np.einsum("ijxy,ijxy->xy", G, G))[inner]
    Bn = np.sqrt(np.einsum("ijxy,ijxy->xy", B, B))[inner]
    floor = float((Bn**2 / np.sqrt(Gn)).max())
    scale = max(max(float(a.max()), float(b.max())) for a, b in norms.values())
    scale = max(scale, floor)
    # an overflow or a 0/0 anywhere makes the test meaningless (an infinite scale guards every point)
    finite = bool(np.isfinite(scale)
                  and all(np.all(np.isfinite(a[..., inner[0], inner[1]])) for a in (T, K_G, K_B, c1, c2)))
    comparisons, mismatch, guarded, pointwise = {}, 0.0, np.zeros(gauss.shape, bool), {}
    for number, (k, (u, v)) in enumerate(pairs.items(), start=1):
        nu, nv = norms[k]
        diff = _frame_norm(u - v, G)[inner] / scale if scale > 0 else np.zeros(nu.shape)
        mismatch = max(mismatch, float(diff.max()))
        ok = (nu > guard * scale) & (nv > guard * scale) if scale > 0 else np.zeros(nu.shape, bool)
        guarded |= ~ok
        residual = float(diff[~ok].max()) if (~ok).any() else 0.0
        ratio = cosine = None
        passed = finite and residual <= rtol
        pointwise[f"ratio{number}"] = np.where(ok, nu / np.where(ok, nv, 1.0), np.nan)
        pointwise[f"cosine{number}"] = np.where(ok, _frame_dot(u, v, G)[inner] / np.where(ok, nu * nv, 1.0), np.nan)
        if ok.any():
            r = pointwise[f"ratio{number}"][ok]
            c = pointwise[f"cosine{number}"][ok]
            far = int(np.argmax(np.abs(np.log(r))))
            ratio = (float(r[far]), float(np.median(r)))
            cosine = (float(c.min()), float(np.median(c)))
            passed = passed and bool(np.all(np.abs(r - 1) <= rtol) and np.all(c >= 1 - rtol))
        comparisons[k] = Comparison(points=int(nu.size), resolved=int(ok.sum()), ratio=ratio, cosine=cosine,
                                    residual=residual, passed=passed)
    kscale = max(float(np.abs(K_B[inner]).max()), float(np.abs(K_G[inner]).max()), float((Bn**2 / Gn).max()))
    gauss_max = float(np.abs(gauss).max())
    out = Compatibility(
        comparisons=comparisons, compatible=finite and all(c.passed for c in comparisons.values()), gauss=gauss_max,
        codazzi=(float(np.abs(c1[inner]).max()), float(np.abs(c2[inner]).max())),
        gauss_relative=gauss_max / kscale if kscale > 0 else 0.0, mismatch_relative=mismatch,
        guarded=float(guarded.mean()), rtol=rtol, finite=finite,
        fields={"gauss": gauss, "codazzi1": c1[inner], "codazzi2": c2[inner], **pointwise},
    )
    log.debug("compatibility: %s", out.summary())
    return out


def _second(surface, a1, a2, step=1e-5):
    """r_11, r_22 of a surface: exact when it has them (validation.harness.surfaces), central differences of r_i else."""
    if callable(getattr(surface, "r11", None)) and callable(getattr(surface, "r22", None)):
        return surface.r11(a1, a2), surface.r22(a1, a2)
    r11 = (surface.r1(a1 + step, a2) - surface.r1(a1 - step, a2)) / (2 * step)
    r22 = (surface.r2(a1, a2 + step) - surface.r2(a1, a2 - step)) / (2 * step)
    return r11, r22


def rest_tensors(scene, nodes: tuple[int, int] | None = None) -> tuple[np.ndarray, np.ndarray, tuple[float, float]]:
    """The scene's rest metric G0 and curvature B0 on a node grid, (2, 2, M, N) each, and (h1, h2).

    G0, B0 are the scene's ``rest_metric`` / ``rest_curvature`` where given, else those of the continuous rest shape
    (not of any discretisation). ``nodes`` defaults to the sheet's grid (at least 33 a side, where the differencing
    error of a smooth rest shape is well below the default tolerance).
    """
    sheet = scene.sheet
    nodes = nodes or tuple(max(n, 33) for n in sheet.nodes)
    s = sheet.with_nodes(nodes)
    a1, a2 = s.coordinates()
    rest = as_surface(sheet.rest)
    dr = np.moveaxis(np.stack([rest.r1(a1, a2), rest.r2(a1, a2)], axis=-2), (-1, -2), (0, 1))
    r11, r22 = _second(rest, a1, a2)
    r12 = rest.r12(a1, a2)
    ddr = np.moveaxis(np.stack([np.stack([r11, r12], -2), np.stack([r12, r22], -2)], -3), (-1, -3, -2), (0, 1, 2))
    G0, B0 = scene.rest_tensors(a1, a2, tensors.metric(dr), tensors.curvature(ddr, tensors.normal(dr)))
    return G0, B0, s.h


def check_rest_state(scene, nodes=None, rtol: float = 0.05) -> Compatibility:
    """Check that a Scene's rest tensors (G0, B0) are compatible (eq. 10) before simulating it.

    Examples
    --------
    >>> import deformable as dm
    >>> scene = dm.Scene(dm.Sheet(), dm.Material(eta=1.0, xi=1.0), rest_metric=1.0, rest_curvature=0.5)
    >>> check_rest_state(scene).compatible
    False
    """
    G0, B0, h = rest_tensors(scene, nodes)
    return check_compatibility(G0, B0, h, rtol=rtol)


def warn_if_incompatible(scene, nodes=None, rtol: float = 0.05, stacklevel: int = 2) -> Compatibility:
    """:func:`check_rest_state`, warning (:class:`IncompatibleRestState`) when the check fails."""
    result = check_rest_state(scene, nodes, rtol)
    if not result.compatible:
        warnings.warn(f"scene {scene.name!r}: the rest tensors G0, B0 are not the metric and curvature of any "
                      f"surface (eq. 10): {result.summary()}", IncompatibleRestState, stacklevel=stacklevel)
    return result
