"""Sparse direct solvers behind one small interface: factor a symmetric matrix, then solve.

Every system the project solves is symmetric (the step matrix A_t of eq. (25), the Newton matrices of the implicit
schemes) and keeps its sparsity pattern for a whole run, so a solver may analyse the pattern once (ordering,
symbolic factorisation) and redo only the numerical factorisation when the values change.

- :class:`SuperLU` (SciPy, always available): a symmetric fill-reducing ordering (minimum degree on A^T + A,
  ``SymmetricMode``, diagonal pivots), much faster than SuperLU's default COLAMD on these matrices. SciPy's SuperLU
  keeps no symbolic analysis, so each factorisation orders again.
- :class:`Pardiso` (Intel MKL PARDISO through the optional ``pypardiso`` package, ``pip install
  'deformable-sheets[fast]'``): nested-dissection ordering and symbolic analysis once per pattern (phase 11), numerical
  factorisation per matrix (phase 22), Cholesky when the matrix is known to be positive definite (matrix type 2),
  symmetric indefinite Bunch-Kaufman otherwise (type -2). The Cholesky's solves skip MKL's iterative refinement
  (``iparm[7] = 0``): a Cholesky perturbs no pivot, and Newton's next iteration corrects what a solve leaves; the
  indefinite factorisation (perturbed pivots) keeps it.

:func:`make_solver` picks the one named, or (``solver="auto"``) PARDISO when ``pypardiso`` is importable and the
matrix has at least :data:`PARDISO_FROM` stored entries, SuperLU otherwise (PARDISO's per-call overhead outweighs
its speed on small systems).

Single precision. In time steps Newton's matrices are factorised by PARDISO's Cholesky in single precision
(``single=True``, MKL's iparm[27]: the factor in float32). Each solve is refined in double precision (the residual
from the matrix's double values) until it is at most :data:`SINGLE_RTOL` of the right-hand side (Wilkinson's
iterative refinement, as in Buttari et al. 2007), a Newton direction as inexact as a forcing term of 1e-5 allows
(Dembo, Eisenstat and Steihaug 1982); where refinement does not converge in :data:`SINGLE_REFINEMENTS` steps the
solver turns to double precision for good. A float32 Cholesky that meets a non-positive pivot proves nothing of a
matrix whose condition exceeds 1e7: Newton then falls back to its definite matrix, and where that one fails too in
single precision, :meth:`Pardiso.double` turns to double precision for good (:mod:`deformable.solve.directions`).
Equilibrium's matrices have no inertia to bound their condition and are factorised in double precision.

Two thread pools. PARDISO runs on MKL's threads, numpy's products on OpenBLAS's, whose idle threads keep spinning
after a product on the cores the next factorisation needs. :func:`one_blas_thread` keeps OpenBLAS to one thread
while a solver loop runs (through ``threadpoolctl``), whatever the solver; the Hessian's blocks run on threads of
their own (:func:`deformable.physics.integrand.for_blocks`).
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import os

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import InputError, SingularMatrix
from .patterns import same_pattern
from .upper import SymmetricUpper

__all__ = ["SuperLU", "Pardiso", "Auto", "make_solver", "SOLVERS", "available", "SPLU_OPTIONS"]

# MKL's OpenMP threads spin for 200 ms after each parallel region by default, taking a core from the numpy
# work between factorisations. Set before MKL starts (with the first PARDISO solver); a value the user set is kept.
os.environ.setdefault("KMP_BLOCKTIME", "0")

#: SuperLU options for symmetric systems: minimum degree on A^T + A and diagonal pivots
SPLU_OPTIONS = dict(permc_spec="MMD_AT_PLUS_A", options=dict(SymmetricMode=True), diag_pivot_thresh=0.0)
SOLVERS = ("auto", "superlu", "pardiso")
#: "auto" takes PARDISO (where installed) for matrices with at least this many stored entries
PARDISO_FROM = 20_000
#: PARDISO's iparm[33] (reproducibility): the same bits on any number of MKL threads, those of this many
PARDISO_CNR_THREADS = 4
#: a single-precision solve is refined until its residual is at most this much of its right-hand side (max-norms)
SINGLE_RTOL = 1e-5
#: at most this many refinements, else double precision for good
SINGLE_REFINEMENTS = 2


class SuperLU:
    """SciPy's SuperLU with a symmetric ordering (module docstring).

    Parameters
    ----------
    definite : bool
        Refuse (SingularMatrix) a matrix that is not positive definite. With diagonal pivots and a symmetric
        ordering, P A P^T = L U has U = D L^T, so A is positive definite exactly when the diagonal of U is positive.
    options : dict, optional
        Keyword arguments of :func:`scipy.sparse.linalg.splu` (default :data:`SPLU_OPTIONS`).
    """

    name = "superlu"

    def __init__(self, definite: bool = False, options: dict | None = None):
        self.definite = definite
        self.options = SPLU_OPTIONS if options is None else options
        if definite and self.options.get("diag_pivot_thresh", 1.0) != 0:
            raise ValueError("SuperLU tells a definite matrix only with diagonal pivots (diag_pivot_thresh=0)")
        self._lu = None

    def factor(self, A) -> "SuperLU":
        """Factorise A (square, symmetric; any scipy sparse format)."""
        if isinstance(A, SymmetricUpper):
            A = A.tocsc()
        try:
            lu = spla.splu(sp.csc_matrix(A), **self.options)
        except RuntimeError as err:  # "Factor is exactly singular"
            raise SingularMatrix(str(err)) from None
        if self.definite and not np.all(lu.U.diagonal() > 0):
            raise SingularMatrix("SuperLU: the matrix is not positive definite")
        self._lu = lu
        return self

    #: SciPy's SuperLU reports no flop count, and factorises in double precision
    cost_ratio = None
    single = False

    def double(self) -> bool:
        """Already in double precision (:meth:`Pardiso.double`)."""
        return False

    def solve(self, b: np.ndarray) -> np.ndarray:
        """A^-1 b for b (n,) or (n, k)."""
        return self._lu.solve(np.asarray(b, float))


class Pardiso:
    """MKL PARDISO, found through ``pypardiso``, called directly (ctypes, zero-based indices, arguments built once
    per pattern), with the symbolic analysis kept while the pattern stays the same.

    Parameters
    ----------
    definite : bool
        The matrices are symmetric positive definite: Cholesky (type 2); otherwise symmetric indefinite (type -2).
    single : bool
        With ``definite``: factorise and solve in single precision (MKL's iparm[27]; module docstring).
    """

    name = "pardiso"

    def __init__(self, definite: bool = False, single: bool = False):
        import pypardiso

        self.definite = definite
        self._solver = s = pypardiso.PyPardisoSolver(mtype=2 if definite else -2)
        # pypardiso looks for MKL by a recursive glob of the environment at every construction; its variable
        # PYPARDISO_MKL_RT skips the search: the library found
        os.environ.setdefault("PYPARDISO_MKL_RT", s.libmkl._name)
        # MKL's defaults, but bit-identical whatever the number of MKL threads (fixed when MKL starts, from
        # OMP_NUM_THREADS / MKL_NUM_THREADS: 1 on Dask's workers): conditional numerical reproducibility
        # (iparm[33] > 0) with the sequential METIS ordering (iparm[1] = 2; the parallel one rules CNR out)
        s.libmkl.pardisoinit(s.pt.ctypes.data_as(ctypes.c_void_p), ctypes.byref(ctypes.c_int32(s.mtype)),
                             s.iparm.ctypes.data_as(ctypes.c_void_p))
        s.iparm[1], s.iparm[33] = 2, PARDISO_CNR_THREADS
        s.iparm[34] = 1  # zero-based indices
        if definite:  # Cholesky perturbs no pivot: no iterative refinement (MKL's default: 2 steps)
            s.iparm[7] = 0
        self.single = bool(single and definite)  # single precision: Cholesky only (module docstring)
        if self.single:
            s.iparm[27] = 1
        self._pattern = None  # what the analysis is of: an SymmetricUpper's version, or a scipy matrix's arrays
        self._upper = None  # (indptr, indices) of the analysed upper triangle, kept alive for MKL
        self._n = 0
        self._data = None  # the factorised values (MKL reads them again in the solves)
        self._exact = None  # the last matrix's values in double precision (the refinement's products)
        i32 = ctypes.POINTER(ctypes.c_int32)
        self._fixed = (s.pt.ctypes.data_as(ctypes.POINTER(s._pt_type[0])), ctypes.byref(ctypes.c_int32(1)),
                       ctypes.byref(ctypes.c_int32(1)), ctypes.byref(ctypes.c_int32(s.mtype)))
        self._iparm = s.iparm.ctypes.data_as(i32)
        self._perm = s.perm.ctypes.data_as(i32)
        self._msglvl = ctypes.byref(ctypes.c_int32(0))
        self._empty = np.zeros(1, np.float32 if self.single else float)

    def _call(self, phase: int, data: np.ndarray, b: np.ndarray, x: np.ndarray, nrhs: int = 1) -> None:
        error = ctypes.c_int32(0)
        indptr, indices = self._upper
        self._solver._mkl_pardiso(*self._fixed, ctypes.byref(ctypes.c_int32(phase)),
                                  ctypes.byref(ctypes.c_int32(self._n)), data.ctypes.data_as(ctypes.c_void_p),
                                  indptr.ctypes.data_as(ctypes.POINTER(ctypes.c_int32)),
                                  indices.ctypes.data_as(ctypes.POINTER(ctypes.c_int32)), self._perm,
                                  ctypes.byref(ctypes.c_int32(nrhs)), self._iparm, self._msglvl,
                                  b.ctypes.data_as(ctypes.c_void_p), x.ctypes.data_as(ctypes.c_void_p),
                                  ctypes.byref(error))
        if error.value != 0:
            raise SingularMatrix(f"PARDISO: {'the matrix is not positive definite' if self.definite else 'failed'} "
                                 f"(error {error.value})")

    def _analyse(self, indptr: np.ndarray, indices: np.ndarray, data: np.ndarray) -> None:
        """Symbolic analysis (phase 11) of an upper triangle's pattern."""
        self._upper = (np.ascontiguousarray(indptr, np.int32), np.ascontiguousarray(indices, np.int32))
        self._n = indptr.size - 1
        rows = np.repeat(np.arange(self._n), np.diff(indptr))
        self._diagonal = (rows[indices == rows], np.flatnonzero(indices == rows))  # (rows, positions in the data)
        self._call(11, data, self._empty, self._empty)

    def factor(self, A) -> "Pardiso":
        """Factorise A (square, symmetric): an :class:`deformable.algebra.upper.SymmetricUpper` as it is, or any
        scipy sparse matrix (its upper triangle); the pattern's analysis is reused while it stays the same."""
        if isinstance(A, SymmetricUpper):
            if self._pattern != ("upper", A.version, A.indptr.size) or self._upper[1].size != A.indices.size:
                self._analyse(A.indptr, A.indices, A.data.astype(self._dtype))
                self._pattern = ("upper", A.version, A.indptr.size)
            exact = np.ascontiguousarray(A.data, float)
        else:
            exact = self._scipy_upper(A)
        data = exact.astype(self._dtype) if self.single else exact
        self._exact = exact
        self._call(22, data, self._empty, self._empty)  # Cholesky (type 2) stops at a non-positive pivot: error -4
        self._data = data
        return self

    @property
    def _dtype(self):
        return np.float32 if self.single else float

    def _product(self, x: np.ndarray) -> np.ndarray:
        """A x in double precision, from the factorised matrix's upper triangle (x (n, k))."""
        indptr, indices = self._upper
        U = sp.csr_matrix((self._exact, indices, indptr), shape=(self._n, self._n))
        d = np.zeros(self._n)
        d[self._diagonal[0]] = self._exact[self._diagonal[1]]
        return U @ x + U.T @ x - d[:, None] * x

    def double(self) -> bool:
        """Single precision does not resolve this problem's matrices (refinement did not converge, or a matrix
        positive definite by construction lost a pivot in float32): double precision from now on, the matrix at hand
        analysed and factorised again: True where that was done (False where it already was in double precision, or
        had no matrix at hand)."""
        if not self.single:
            return False
        self.single = False
        self._solver.iparm[27] = 0
        self._empty = np.zeros(1)
        if self._exact is None:
            return False
        self._call(-1, self._empty, self._empty, self._empty)  # MKL's state, after a failed phase too: released
        self._call(11, self._exact, self._empty, self._empty)
        self._call(22, self._exact, self._empty, self._empty)
        self._data = self._exact
        return True

    def _scipy_upper(self, A) -> np.ndarray:
        """The data of a scipy matrix's upper triangle, analysing its pattern when it is new."""
        if sp.issparse(A) and A.format == "csc":  # symmetric: its CSC arrays are its CSR ones (no transposing copy)
            A = sp.csr_matrix((A.data, A.indices, A.indptr), shape=A.shape)
        A = sp.csr_matrix(A)
        A.sort_indices()
        if self._pattern is None or self._pattern[0] != "scipy" or not same_pattern(A, *self._pattern[1:]):
            n = A.shape[0]
            rows = np.repeat(np.arange(n), np.diff(A.indptr))
            keep = A.indices >= rows
            self._keep = np.flatnonzero(keep)
            indptr = np.concatenate([[0], np.cumsum(np.bincount(rows[keep], minlength=n))])
            self._analyse(indptr, A.indices[keep], A.data[keep])
            self._pattern = ("scipy", A.indptr, A.indices)
        return np.ascontiguousarray(A.data[self._keep], float)

    @property
    def cost_ratio(self) -> float | None:
        """What one factorisation costs in solves, from the analysis's own counts (MKL's iparm[18], the
        factorisation's MFlops, and iparm[17], the factor's entries; a solve is about 4 flops an entry): a count,
        the same on every machine. None before an analysis."""
        entries, mflops = int(self._solver.iparm[17]), int(self._solver.iparm[18])
        return mflops * 1e6 / (4.0 * entries) if self._pattern is not None and entries > 0 else None

    def _solve(self, b: np.ndarray) -> np.ndarray:
        """The factorisation's own solve of b (n, k), returned in double precision."""
        rhs = np.asfortranarray(b, self._dtype)
        x = np.empty_like(rhs, order="F")
        self._call(33, self._data, rhs, x, rhs.shape[1])
        return np.asarray(x, float)

    def solve(self, b: np.ndarray) -> np.ndarray:
        """A^-1 b for b (n,) or (n, k); in single precision refined in double until the residual is at most
        :data:`SINGLE_RTOL` of b (max-norms), else double precision from then on (module docstring)."""
        b = np.asarray(b, float)
        B = b.reshape(b.shape[0], -1)
        x = self._solve(B)
        if self.single:
            scale = SINGLE_RTOL * np.max(np.abs(B), initial=0.0)
            for _ in range(SINGLE_REFINEMENTS + 1):
                r = B - self._product(x)
                if np.max(np.abs(r), initial=0.0) <= scale:
                    break
                x += self._solve(r)
            else:
                self.double()
                x = self._solve(B)
        return np.ascontiguousarray(x).reshape(b.shape)


class Auto:
    """PARDISO (where installed) for a matrix with at least :data:`PARDISO_FROM` entries, else SuperLU.

    The choice is made at the first factorisation and kept (the pattern stays the same).
    """

    def __init__(self, definite: bool = False, single: bool = False):
        self.definite, self._single = definite, single
        self._solver = None

    @property
    def name(self) -> str:
        return "auto" if self._solver is None else self._solver.name

    def factor(self, A) -> "Auto":
        if self._solver is None:
            big = (A.nnz if isinstance(A, SymmetricUpper) else sp.csr_matrix(A).nnz) >= PARDISO_FROM and \
                "pardiso" in available()
            self._solver = Pardiso(self.definite, self._single) if big else SuperLU(self.definite)
        self._solver.factor(A)
        return self

    @property
    def cost_ratio(self) -> float | None:
        return None if self._solver is None else self._solver.cost_ratio

    @property
    def single(self) -> bool:
        return self._single if self._solver is None else self._solver.single

    def double(self) -> bool:
        if self._solver is None:
            self._single = False
            return False
        return self._solver.double()

    def solve(self, b: np.ndarray) -> np.ndarray:
        return self._solver.solve(b)


def available() -> tuple[str, ...]:
    """The solvers that can be used here ("superlu" always; "pardiso" when pypardiso imports)."""
    try:
        import pypardiso  # noqa: F401
    except ImportError:
        return ("superlu",)
    return ("superlu", "pardiso")


def make_solver(solver: str = "auto", definite: bool = False, single: bool = False):
    """A solver by name: "auto" (module docstring), "superlu" or "pardiso".

    ``definite``: the matrices to factor must be positive definite (refused with SingularMatrix otherwise; PARDISO
    uses Cholesky). ``single``: PARDISO's Cholesky in single precision (SuperLU stays in double).
    """
    if solver not in SOLVERS:
        raise InputError(f"solver must be one of {SOLVERS}, got {solver!r}")
    if solver == "auto":
        return Auto(definite, single)
    if solver == "pardiso":
        if "pardiso" not in available():
            raise InputError("solver 'pardiso' needs the pypardiso package: pip install 'deformable-sheets[fast]'")
        return Pardiso(definite, single)
    return SuperLU(definite)


@functools.lru_cache(maxsize=1)
def _openblas():
    """threadpoolctl's handle on numpy's OpenBLAS, or None where numpy's BLAS is another one."""
    from threadpoolctl import ThreadpoolController

    chosen = ThreadpoolController().select(internal_api="openblas")
    return chosen if chosen.lib_controllers else None


def one_blas_thread():
    """A context in which OpenBLAS uses one thread (module docstring); a no-op where numpy's BLAS is not OpenBLAS."""
    blas = _openblas()
    return contextlib.nullcontext() if blas is None else blas.limit(limits=1)
