r"""The integrand of the energy (13) at points, with its exact derivatives, written once for both backends.

At a point the integrand depends on the surface through a few vectors, its *slots*: the tangents d1, d2 of the
metric (G_ij = d_i . d_j, eq. 4 / 18), the tangents t1, t2 that define the normal (n = t1 x t2 / |t1 x t2|), and the
second derivatives v11, v12, v22 of the curvature (B_ij = n . v_ij, eq. 8 / 19). In FE all are derivatives of one
field and t_i = d_i = r_i (5 slots: r_1, r_2, r_11, r_12, r_22); in FD d_i = D_i+ r (zero where the row is
undefined), t_i the forward (backward on the last row) differences of the normal, v_ij the second differences: 7
slots. The backends map slots to degrees of freedom (FD: difference stencils; FE: basis tables); everything else is
here.

With weights (the quadrature weight w times the material) the integrand is

    W = sum_ij eta_ij (G_ij - G0_ij)^2 + xi_ij (B_ij - B0_ij)^2,

written with the six residuals s = (G11, G22, G12) and b = (B11, B22, B12), weights c^S = w (eta_11, eta_22, eta_12 +
eta_21) and c^B likewise (G and B are symmetric, so 12 and 21 share one residual). Its first derivatives in the
residuals are ``f = dW/ds = 2 c^S s - f0`` and ``g = dW/db = 2 c^B b - g0`` (``f0 = 2 w (eta_11 G0_11, eta_22 G0_22,
eta_12 G0_12 + eta_21 G0_21)``, ``g0`` likewise). The Jacobian of the residuals in the slots:

    s11: (2 d1 | d1),  s22: (2 d2 | d2),  s12: (d2 | d1), (d1 | d2),
    b_ij: (t2 x w_ij | t1), (w_ij x t1 | t2), (n | v_ij),   w_ij = (v_ij - (v_ij . n) n) / |t1 x t2|,

so the gradient is ``sum f J_s + g J_b`` and the Hessian

    Gauss-Newton:  2 J^T diag(c) J                              (positive semi-definite)
    exact:         2 J^T diag(c) J + sum f Hess(s) + sum g Hess(b)

with ``sum f Hess(s)`` = [[2 f11, f12], [f12, 2 f22]] (x I3) on (d1, d2), and ``sum g Hess(b)`` the second
derivative of ``V . n``, ``V = sum g_ij v_ij``, in (t1, t2) (written out in :mod:`deformable.physics.kernels`) plus
its mixed derivative g_ij Q between v_ij and (t1, t2).

A *definite* Newton matrix (``kind="definite"``) keeps what can be made positive semi-definite point by point
without an eigen-decomposition: the Gauss-Newton part, and the membrane part [[2 f11, f12], [f12, 2 f22]] projected
onto its positive part (a 2 x 2 eigenproblem in closed form: the geometric stiffness of a sheet in tension, dropped
in compression, where it would be negative). The bending second-order part, which is indefinite and vanishes with
the bending residual, is left out. ``kind="projected"`` projects each point's whole exact Hessian onto its positive
part by an eigen- decomposition (Teran et al. 2005; the projected Newton of Li et al. 2020): dearer, kept for
comparison.

Gradients and Hessians are computed by the compiled kernels of :mod:`deformable.physics.kernels` (one loop body per
point, and the projection onto the elements); G, B and the energy are numpy.

Layout: points first; slot vectors ``v`` are (P, S, 3); gradients (P, S, 3); Hessians (P, S, 3, S, 3) with index
(slot, coordinate).
"""

from __future__ import annotations

import concurrent.futures
import functools
import os

import numpy as np

from ..errors import InputError
from ..geometry import tensors
from . import kernels, pointhessian
from .energy import Energy
from .force_models.base import RESIDUALS as RESIDUAL_NAMES

__all__ = ["Integrand", "DensityIntegrand", "slot_tensors", "for_blocks", "hessian_threads", "HESSIANS", "FE_SLOTS",
           "FD_SLOTS"]

HESSIANS = ("newton", "gauss-newton", "definite", "projected")
#: slot names in the order of the slot axis: (d1, d2, t1, t2, v11, v12, v22) -> position
FD_SLOTS = {"d1": 0, "d2": 1, "t1": 2, "t2": 3, "v11": 4, "v12": 5, "v22": 6}
#: the FE slots: the normal's tangents are the metric's (r_1, r_2, r_11, r_12, r_22)
FE_SLOTS = {"d1": 0, "d2": 1, "t1": 0, "t2": 1, "v11": 2, "v12": 3, "v22": 4}
#: residual order: s11, s22, s12, b11, b22, b12; the second derivative slot of each b
_BEND = ("v11", "v22", "v12")
#: points per block of :meth:`Integrand.add_element_hessians` (small enough for the cache)
_BLOCK = 512


def hessian_threads() -> int:
    """Threads that assemble a Hessian (:func:`for_blocks`, both backends): the cores this process may use (at most
    4), or OMP_NUM_THREADS where it is set (1 on Dask's workers and the validation runner's, a core each). The result
    is bit-identical to one thread's, each block writing rows of its own."""
    if os.environ.get("OMP_NUM_THREADS", "").isdigit():
        return max(1, int(os.environ["OMP_NUM_THREADS"]))
    return max(1, min(4, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1))


@functools.cache
def _pool(threads: int) -> concurrent.futures.ThreadPoolExecutor:
    return concurrent.futures.ThreadPoolExecutor(threads, thread_name_prefix="deformable-hessian")


if hasattr(os, "register_at_fork"):  # a forked child has none of the parent's threads: it makes a pool of its own
    os.register_at_fork(after_in_child=_pool.cache_clear)


def for_blocks(work, starts, parallel: bool = True) -> None:
    """``work(lo)`` for every block start, on :func:`hessian_threads` threads when ``parallel`` (the blocks must
    write disjoint parts of their output; the compiled kernels and BLAS release the GIL), else in turn."""
    threads = hessian_threads() if parallel else 1
    if threads > 1 and len(starts) > 1:
        list(_pool(threads).map(work, starts))  # list: a block's exception is raised here
    else:
        for lo in starts:
            work(lo)


def slot_tensors(v: np.ndarray, slots: dict, curvature: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
    """G (eq. 4) and B (eq. 8) from slot vectors (P, S, 3): (2, 2, P) each.

    B is None with ``curvature=False`` (no normal is formed). The backends take their rest tensors from here, with
    the arithmetic of the energy itself, so that the rest state has residuals exactly zero.
    """
    d1, d2 = v[:, slots["d1"]], v[:, slots["d2"]]
    G = np.stack([tensors.dot(d1, d1), tensors.dot(d2, d2), tensors.dot(d1, d2)])
    B = None
    if curvature:
        n, _ = tensors.frame(v[:, slots["t1"]], v[:, slots["t2"]])
        B = np.stack([tensors.dot(n, v[:, slots[k]]) for k in _BEND])
    sym = lambda T: np.array([[T[0], T[2]], [T[2], T[1]]])  # noqa: E731
    return sym(G), None if B is None else sym(B)


class _Points:
    """What both integrands share: the Hessians of all points carried to their elements (:meth:`add_element_hessians`).

    A subclass gives ``_point_hessians(v, kind, sl)``: the point Hessians (P, 3S, 3S) of the points ``sl``.
    """

    def add_element_hessians(self, v: np.ndarray, kind: str, table: np.ndarray, which: np.ndarray,
                             element: np.ndarray, out: np.ndarray) -> None:
        """Add the Hessian of every point, carried to its element, to the elements' upper triangles ``out`` (E, nu).

        Point p's block is ``B^T H_p B`` (x I3), ``B = table[which[p]]`` (S, L): the coefficients of the element's L
        local nodes (FD: the stencil) or basis functions (FE) in the point's slots; local index ``a L + l``, upper
        entries in ``numpy.triu_indices(3 L)`` order (:class:`deformable.algebra.elements.SymmetricElements`).
        Compiled (:mod:`deformable.physics.kernels`), by blocks of points small enough for the cache.
        """
        def block(lo):
            pts = slice(lo, min(lo + _BLOCK, v.shape[0]))
            kernels.element_upper(self._point_hessians(v[pts], kind, pts), table, which[pts], element[pts], out)

        # in threads when every point has an element of its own (FD: its node): no two blocks add to one row of out
        for_blocks(block, range(0, v.shape[0], _BLOCK), parallel=bool(np.all(np.diff(element) > 0)))


class Integrand(_Points):
    """Eq. (13)'s integrand at P points with its gradient and Hessians in the slot vectors.

    Parameters
    ----------
    eta, xi : arrays (2, 2, *pts)
        Weights of eq. (13), already multiplied by the quadrature weight of each point (and, in FD, by each
        component's row weight).
    G0, B0 : arrays (2, 2, *pts)
        Rest tensors.
    slots : dict
        Slot name -> position (:data:`FE_SLOTS` or :data:`FD_SLOTS`).

    The points are flattened: every method takes slot vectors (P, S, 3) for
    the P = prod(pts) points (or a slice ``sl`` of them).
    """

    def __init__(self, eta, xi, G0, B0, slots: dict):
        self.slots = dict(slots)
        self.S = max(self.slots.values()) + 1
        self.eta, self.xi, self.G0, self.B0 = (np.asarray(a, float).reshape(2, 2, -1) for a in (eta, xi, G0, B0))
        e, x = self.eta, self.xi
        self.cS = np.stack([e[0, 0], e[1, 1], e[0, 1] + e[1, 0]])  # (3, P)
        self.cB = np.stack([x[0, 0], x[1, 1], x[0, 1] + x[1, 0]])
        G0, B0 = self.G0, self.B0
        self.f0 = 2 * np.stack([e[0, 0] * G0[0, 0], e[1, 1] * G0[1, 1], e[0, 1] * G0[0, 1] + e[1, 0] * G0[1, 0]])
        self.g0 = 2 * np.stack([x[0, 0] * B0[0, 0], x[1, 1] * B0[1, 1], x[0, 1] * B0[0, 1] + x[1, 0] * B0[1, 0]])
        self.bending = bool(np.any(x != 0))  # False: no normal is formed (degenerate tangents allowed)
        self.P = self.cS.shape[1]
        # the compiled kernels' view: slot positions, residual weights and rest terms (6, P)
        self._sl = np.array([slots[k] for k in ("d1", "d2", "t1", "t2")], np.int64)
        self._bend = np.array([slots[k] for k in _BEND], np.int64)
        self.c = np.ascontiguousarray(np.concatenate([self.cS, self.cB]))
        self.r0 = np.ascontiguousarray(np.concatenate([self.f0, self.g0]))
        # the energy kernel's view: components (11, 22, 12, 21) of the weights and rest tensors (4, P)
        self._components = tuple(np.ascontiguousarray(np.stack([a[0, 0], a[1, 1], a[0, 1], a[1, 0]]))
                                 for a in (self.eta, self.G0, self.xi, self.B0))

    # -- energy -----------------------------------------------------------------------
    def energy(self, v: np.ndarray) -> Energy:
        """Eq. (13) summed over the points: (stretching, bending) (J) (compiled, :func:`kernels.energy_sums`)."""
        stretching, bending = kernels.energy_sums(np.ascontiguousarray(v, float), self._sl, self._bend,
                                                  *self._components, self.bending)
        return Energy(stretching, bending)

    # -- derivatives ------------------------------------------------------------------
    def gradient(self, v: np.ndarray, sl=slice(None)) -> np.ndarray:
        """dW/d(slots), (P, S, 3) (J per unit of the slot vectors): ``sum_r F_r J_r`` (compiled)."""
        v_, sl_, bend, c, r0, _, bending = self._kernel_args(v, "newton", sl)
        return kernels.point_gradients(v_, sl_, bend, c, r0, bending)

    def _kernel_args(self, v, kind, sl):
        if kind not in HESSIANS:
            raise InputError(f"hessian kind must be one of {HESSIANS}, got {kind!r}")
        c, r0 = (np.ascontiguousarray(a[:, sl]) for a in (self.c, self.r0))  # one compiled signature
        return np.ascontiguousarray(v, float), self._sl, self._bend, c, r0, kernels.KINDS[kind], self.bending

    def _point_hessians(self, v, kind, sl):
        """(P, 3S, 3S), block by block (:mod:`deformable.physics.pointhessian`); "projected" from the exact ones by
        an eigen-decomposition."""
        args = self._kernel_args(v, "newton" if kind == "projected" else kind, sl)
        H = pointhessian.point_hessians(*args)
        return kernels.positive_part(H) if kind == "projected" else H

    def add_element_hessians(self, v, kind, table, which, element, out) -> None:
        """:meth:`_Points.add_element_hessians`, each point's Hessian carried to its element as it is formed
        (:func:`deformable.physics.pointhessian.element_hessians`); "projected" by the point Hessians."""
        if kind == "projected":
            return super().add_element_hessians(v, kind, table, which, element, out)

        def block(lo):
            pts = slice(lo, min(lo + _BLOCK, v.shape[0]))
            pointhessian.element_hessians(*self._kernel_args(v[pts], kind, pts), table, which[pts], element[pts], out)

        for_blocks(block, range(0, v.shape[0], _BLOCK), parallel=bool(np.all(np.diff(element) > 0)))

    def hessian(self, v: np.ndarray, kind: str = "newton", sl=slice(None)) -> np.ndarray:
        """The Hessian of W in the slots at the points ``sl``, (P, S, 3, S, 3); ``kind`` one of :data:`HESSIANS`."""
        P, S = v.shape[0], self.S
        return self._point_hessians(v, kind, sl).reshape(P, S, 3, S, 3)


class DensityIntegrand(_Points):
    """A general energy density's integrand at P points (:class:`deformable.physics.EnergyModel`), with its exact
    gradient and Hessians in the slot vectors: the backends' path for every energy but eq. (13)'s compiled one.

    The residuals r = (s, b) (6, P) come from the slots (:func:`deformable.physics.kernels.point_residuals`) minus
    their rest values; the model gives W, F = dW/dr and Hr = d2W/dr^2; the kernels carry them to the slots: gradient
    ``sum_r q_r F_r J_r``, Hessian ``sum_rq q_r Hr_rq J_r J_q^T + sum_r q_r F_r Hess(r)``.

    Parameters
    ----------
    model : EnergyModel
    params : dict name -> array (2, 2, *pts)
        The Material fields the model reads (``model.fields``) at the points.
    q : array (6, *pts)
        The quadrature weight of each residual at each point (zero for a residual these points do not carry, FD's
        parts; the same weight for every residual of a group the model couples).
    G0, B0 : arrays (2, 2, *pts)
        Rest tensors from the same slots (zero residuals at rest).
    slots : dict
        Slot name -> position (:data:`FE_SLOTS` or :data:`FD_SLOTS`).

    For "gauss-newton" and "definite" the residual Hessian of each point is projected onto its positive
    semi-definite part first (so that ``J^T Hr J`` is; eq. (13)'s is diagonal and positive as it is).
    """

    def __init__(self, model, params: dict, q, G0, B0, slots: dict):
        self.model, self.slots = model, dict(slots)
        self.S = max(self.slots.values()) + 1
        self.params = {k: np.asarray(v, float).reshape(2, 2, -1) for k, v in params.items()}
        self.q = np.ascontiguousarray(np.asarray(q, float).reshape(6, -1))
        G0, B0 = (np.asarray(a, float).reshape(2, 2, -1) for a in (G0, B0))
        self.rest = np.stack([G0[0, 0], G0[1, 1], G0[0, 1], B0[0, 0], B0[1, 1], B0[0, 1]])
        if model.rest and "G0" not in self.params:  # the density reads the rest metric at its points (a backend
            self.params["G0"] = np.ascontiguousarray(G0)  # may give one of its own: fdmodel's node parts)
        self.params = model.prepare(self.params)  # what the density derives once from its fixed points
        self.P = self.q.shape[1]
        # the groups the model couples that these points carry, each with its one weight
        self.groups = []
        same = np.zeros((6, 6))
        for g in model.groups():
            w = self.q[list(g)]
            if not np.any(w):
                continue
            if np.any(w != w[0]):
                raise InputError(f"force model {model.name!r}: the residuals {[RESIDUAL_NAMES[k] for k in g]} it "
                                 "couples are weighted differently at the same points")
            self.groups.append(g)
            same[np.ix_(g, g)] = 1.0
        self._same = same[:, :, None]
        self.bending = bool(np.any(self.q[3:]) and model.bends(self.params))
        self._sl = np.array([slots[k] for k in ("d1", "d2", "t1", "t2")], np.int64)
        self._bend = np.array([slots[k] for k in _BEND], np.int64)
        self._whole = bool(np.all(self.q == self.q[:1]))  # every residual carried, with one weight

    def _residuals(self, v, sl=slice(None)):
        R = kernels.point_residuals(np.ascontiguousarray(v, float), self._sl, self._bend, self.bending)
        r = R - self.rest[:, sl]
        if not self.bending:
            r[3:] = 0.0
        return r

    def _params(self, sl):
        return {k: a[:, :, sl] for k, a in self.params.items()}

    # -- energy -----------------------------------------------------------------------
    def energy(self, v: np.ndarray) -> Energy:
        """The density summed over the points with the weights q: (stretching, bending) (J); stretching is W(s, 0),
        bending the rest (eq. (13): its eta and xi terms)."""
        r, p = self._residuals(v), self.params
        parts = [(None, self.q[0])] if self._whole else [(g, self.q[g[0]]) for g in self.groups]
        total = stretching = 0.0
        zero = np.zeros((3, self.P))
        for g, w in parts:
            rg = r if g is None else r * np.isin(np.arange(6), g)[:, None]
            W = self.model.density(rg[:3], rg[3:], p)
            Ws = self.model.density(rg[:3], zero, p) if self.bending else W
            total += float(w @ W)
            stretching += float(w @ Ws)
        return Energy(stretching, total - stretching)

    # -- derivatives ------------------------------------------------------------------
    def gradient(self, v: np.ndarray, sl=slice(None)) -> np.ndarray:
        """dW/d(slots), (P, S, 3) (J per unit of the slot vectors)."""
        r = self._residuals(v, sl)
        F = np.ascontiguousarray(self.q[:, sl] * self.model.gradient(r[:3], r[3:], self._params(sl)))
        return kernels.point_gradients_general(np.ascontiguousarray(v, float), self._sl, self._bend, F, self.bending)

    def _point_hessians(self, v, kind, sl):
        if kind not in HESSIANS:
            raise InputError(f"hessian kind must be one of {HESSIANS}, got {kind!r}")
        r, p = self._residuals(v, sl), self._params(sl)
        q = self.q[:, sl]
        F = np.ascontiguousarray(q * self.model.gradient(r[:3], r[3:], p))
        Hr = self.model.hessian(r[:3], r[3:], p) * q[:, None, :] * self._same
        if kind in ("gauss-newton", "definite"):
            Hr = np.moveaxis(kernels.positive_part(np.moveaxis(Hr, -1, 0)), 0, -1)
        code = kernels.KINDS["newton" if kind == "projected" else kind]
        H = kernels.point_hessians_general(np.ascontiguousarray(v, float), self._sl, self._bend, F,
                                           np.ascontiguousarray(Hr), code, self.bending)
        return kernels.positive_part(H) if kind == "projected" else H

    def hessian(self, v: np.ndarray, kind: str = "newton", sl=slice(None)) -> np.ndarray:
        """The Hessian of W in the slots at the points ``sl``, (P, S, 3, S, 3); ``kind`` one of :data:`HESSIANS`."""
        P, S = v.shape[0], self.S
        return self._point_hessians(v, kind, sl).reshape(P, S, 3, S, 3)
