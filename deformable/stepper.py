r"""Semi-implicit time stepping of the semi-discrete system (21), eq. (22)-(27).

    A_t R_{t+dt} = G_t,                                           (24)
    A_t = K(r_t) + M/dt^2 + C/(2 dt),                             (25)
    G_t = F_t + (M/dt^2 + C/(2 dt)) R_t + (M/dt - C/2) V_t,       (26)
    V_t = (R_t - R_{t-dt})/dt.                                    (27)

The stiffness is lagged (evaluated at r_t) and the force at t, so each step
is one linear solve. The stepper is written once, over the
:class:`~deformable.backend.Backend` protocol; backends differ only in space.

Numerics (DESIGN.md, findings): for one undamped linear mode of frequency w
the amplification per step is ``(1 + w^2 dt^2)^(-1/2)`` and the phase advance
``atan(w dt)``: first order in time, numerically damped. Lagging alpha makes
the step only conditionally stable on stretching (dt below about
``h sqrt(mu / (2 eta G))``).

Cost: K(r) keeps its sparsity pattern, so A_t lives on one fixed pattern
whose data is refilled each step; constrained degrees of freedom are
eliminated through precomputed gathers; each group of coordinates that
shares its constraints is factorised once per step and solved for all its
right-hand sides together. When the model is linear (the "frozen" force
model) the factorisation is done once for the whole run.
"""

from __future__ import annotations

import logging
import time as _time
from dataclasses import dataclass, field
from typing import Iterator, Sequence

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["TimeStepper", "State", "RunResult", "DivergenceError", "SCHEMES"]

log = logging.getLogger(__name__)
SCHEMES = ("tpbf87", "implicit-euler", "newmark")
#: SuperLU options of the step's factorisation: A_t is symmetric, so a symmetric
#: ordering (minimum degree on A^T + A) and diagonal pivots
SPLU_OPTIONS = dict(permc_spec="MMD_AT_PLUS_A", options=dict(SymmetricMode=True), diag_pivot_thresh=0.0)


@dataclass(frozen=True)
class State:
    """A point of the trajectory: time t (s), positions X and velocities V, (ndof, 3)."""

    t: float
    X: np.ndarray
    V: np.ndarray
    step: int = 0


class DivergenceError(RuntimeError):
    """The run left the range of finite numbers or a tracker's bound; ``state`` is the last good one."""

    def __init__(self, message: str, state: State):
        super().__init__(message)
        self.state = state


@dataclass
class RunResult:
    """Outcome of :meth:`TimeStepper.run`.

    ``state`` is the last good state; ``status`` is "finished", "stopped" (a
    tracker asked to stop) or "diverged"; ``message`` says why.
    """

    state: State
    status: str
    message: str
    steps: int
    wall_time: float
    trackers: list = field(default_factory=list)


def _keys(A: sp.csr_matrix) -> np.ndarray:
    rows = np.repeat(np.arange(A.shape[0], dtype=np.int64), np.diff(A.indptr))
    return rows * A.shape[1] + A.indices.astype(np.int64)


def _canonical(A) -> sp.csr_matrix:
    A = sp.csr_matrix(A)
    A.sum_duplicates()
    A.sort_indices()
    return A


class _ReducedSystem:
    """A = K + c_m M + c_c C on a fixed pattern, split into free/fixed blocks.

    Built once from the patterns of K, M and C; afterwards each step only
    gathers data arrays (no sparse-sparse products, no slicing).
    """

    def __init__(self, K, M, C, cm: float, cc: float, fixed_sets):
        n = K.shape[0]
        self.n = n
        K = _canonical(K)
        M, C = _canonical(M), _canonical(C)
        kK, kM, kC = _keys(K), _keys(M), _keys(C)
        ukeys = np.union1d(np.union1d(kK, kM), kC)
        self.rows, self.cols = ukeys // n, ukeys % n
        self.idxK = np.searchsorted(ukeys, kK)
        self.K_pattern = (K.indptr, K.indices)
        base = np.zeros(ukeys.size)
        np.add.at(base, np.searchsorted(ukeys, kM), cm * M.data)
        np.add.at(base, np.searchsorted(ukeys, kC), cc * C.data)
        self.base = base
        self.blocks = [self._block(np.asarray(f, dtype=np.int64)) for f in fixed_sets]

    def _block(self, fixed):
        n = self.n
        isfree = np.ones(n, bool)
        isfree[fixed] = False
        free = np.flatnonzero(isfree)
        new = np.cumsum(isfree) - 1
        newfix = np.cumsum(~isfree) - 1
        r, c = self.rows, self.cols
        ff = np.flatnonzero(isfree[r] & isfree[c])
        rr, cc = new[r[ff]], new[c[ff]]
        order = np.lexsort((rr, cc))  # column-major for CSC
        gather_ff = ff[order]
        nf = free.size
        indptr = np.concatenate([[0], np.cumsum(np.bincount(cc[order], minlength=nf))])
        fc = np.flatnonzero(isfree[r] & ~isfree[c])
        return dict(
            free=free,
            fixed=fixed,
            gather_ff=gather_ff,
            indices=rr[order].astype(np.int32),
            indptr=indptr.astype(np.int32),
            gather_fc=fc,
            fc_rows=new[r[fc]],
            fc_cols=newfix[c[fc]],
            shape_fc=(nf, fixed.size),
        )

    def data(self, K) -> np.ndarray:
        if not (np.array_equal(K.indptr, self.K_pattern[0]) and np.array_equal(K.indices, self.K_pattern[1])):
            raise ValueError("the backend changed the sparsity pattern of K between steps")
        A = self.base.copy()
        A[self.idxK] += K.data
        return A

    def matrices(self, A: np.ndarray, block):
        nf = block["free"].size
        Aff = sp.csc_matrix((A[block["gather_ff"]], block["indices"], block["indptr"]), shape=(nf, nf))
        Afc = sp.csr_matrix(
            (A[block["gather_fc"]], (block["fc_rows"], block["fc_cols"])), shape=block["shape_fc"]
        )
        return Aff, Afc


class TimeStepper:
    """Integrate ``model`` in time with the semi-implicit scheme of eq. (22)-(27).

    Parameters
    ----------
    model : Backend
        FDModel or FEModel (anything satisfying :class:`deformable.Backend`).
    dt : float
        Time step (s), positive.
    scheme : str, optional
        "tpbf87" (eq. 22-27, the default for the tpbf87 and frozen models),
        "implicit-euler" (the default for the variational model) or "newmark"
        (second order): Newton steps on an incremental potential, for models
        with an energy (:mod:`deformable.implicit`).
    newton : dict, optional
        rtol, atol, max_iter of the Newton solves of the implicit schemes.
    """

    def __init__(self, model, dt: float, scheme: str | None = None, newton: dict | None = None):
        try:
            dt = float(dt)
        except (TypeError, ValueError):
            raise ValueError(f"dt must be a positive number, got {dt!r}") from None
        if not np.isfinite(dt) or dt <= 0:
            raise ValueError(f"dt must be positive and finite, got {dt!r}")
        force_model = model.scene.force_model
        scheme = scheme or ("implicit-euler" if force_model == "variational" else "tpbf87")
        if scheme not in SCHEMES:
            raise ValueError(f"scheme must be one of {SCHEMES}, got {scheme!r}")
        if scheme == "tpbf87" and force_model == "variational":
            raise ValueError("scheme 'tpbf87' lags the strength matrix K(r) of eq. (20), which the variational "
                             "model does not have; use 'implicit-euler' or 'newmark'")
        if scheme != "tpbf87" and force_model == "tpbf87":
            raise ValueError(f"scheme {scheme!r} needs an energy; the tpbf87 force (14) is not a gradient "
                             "(use force_model 'variational', or scheme 'tpbf87')")
        self.model, self.dt, self.scheme = model, dt, scheme
        self.timings = {"assembly": 0.0, "factorisation": 0.0, "solve": 0.0}
        self._implicit = None
        if scheme != "tpbf87":
            from .implicit import ImplicitIntegrator

            self._implicit = ImplicitIntegrator(model, dt, scheme, **(newton or {}))
            return
        M, C = model.mass(), model.damping()
        self._B1 = (M / dt**2 + C / (2 * dt)).tocsr()  # multiplies R_t in (26)
        self._B2 = (M / dt - C / 2).tocsr()  # multiplies V_t in (26)
        fixed = model.fixed_dofs()
        # components that share their constraints share one factorisation
        groups: dict[bytes, list[int]] = {}
        sets: dict[bytes, np.ndarray] = {}
        for c, f in enumerate(fixed):
            f = np.unique(np.asarray(f, dtype=np.int64))
            groups.setdefault(f.tobytes(), []).append(c)
            sets[f.tobytes()] = f
        self._groups = [(sets[k], comps) for k, comps in groups.items()]
        self._system = None
        self._lu_cache = None

    # -- one step -----------------------------------------------------------
    def _factorise(self, X):
        model = self.model
        if self._lu_cache is not None:
            return self._lu_cache
        t0 = _time.perf_counter()
        K = model.stiffness(X)
        if self._system is None:
            self._system = _ReducedSystem(
                K, model.mass(), model.damping(), 1 / self.dt**2, 1 / (2 * self.dt), [f for f, _ in self._groups]
            )
        A = self._system.data(K)
        t1 = _time.perf_counter()
        factors = []
        for block in self._system.blocks:
            Aff, Afc = self._system.matrices(A, block)
            lu = spla.splu(Aff, **SPLU_OPTIONS)
            factors.append((block, lu, Afc))
        t2 = _time.perf_counter()
        self.timings["assembly"] += t1 - t0
        self.timings["factorisation"] += t2 - t1
        if getattr(model, "linear", False):
            self._lu_cache = factors
        return factors

    @property
    def newton_reports(self) -> list:
        """Newton iterations and residuals per step of the implicit schemes (empty for tpbf87)."""
        return self._implicit.reports if self._implicit is not None else []

    def step(self, state: State) -> State:
        """Advance one step: eq. (24), or a Newton step of the implicit schemes; the state at t + dt."""
        if self._implicit is not None:
            t0 = _time.perf_counter()
            new = self._implicit.step(state, self._X0)
            self.timings["solve"] += _time.perf_counter() - t0
            return new
        dt, model = self.dt, self.model
        factors = self._factorise(state.X)
        t0 = _time.perf_counter()
        G = model.load(state.X, state.t) + self._B1 @ state.X + self._B2 @ state.V
        Xn = np.array(model.prescribed(self._X0, state.t + dt), dtype=float)
        for (block, lu, Afc), (_, comps) in zip(factors, self._groups):
            free, fixed = block["free"], block["fixed"]
            rhs = G[np.ix_(free, comps)] - Afc @ Xn[np.ix_(fixed, comps)]
            Xn[np.ix_(free, comps)] = lu.solve(rhs)
        self.timings["solve"] += _time.perf_counter() - t0
        if not np.all(np.isfinite(Xn)):
            raise DivergenceError(
                f"diverged at step {state.step + 1} (t = {state.t + dt:.6g} s): non-finite positions", state
            )
        return State(t=state.t + dt, X=Xn, V=(Xn - state.X) / dt, step=state.step + 1)

    def start(self, X0: np.ndarray, V0: np.ndarray | None = None, t0: float = 0.0) -> State:
        """The initial state; also fixes the reference positions of the constraints."""
        X0 = np.array(X0, dtype=float)
        if X0.shape != (self.model.ndof, 3):
            raise ValueError(f"X0 has shape {X0.shape}, expected ({self.model.ndof}, 3)")
        V0 = np.zeros_like(X0) if V0 is None else np.array(V0, dtype=float)
        if V0.shape != X0.shape:
            raise ValueError(f"V0 has shape {V0.shape}, expected {X0.shape}")
        self._X0 = X0
        return State(t=float(t0), X=X0, V=V0, step=0)

    def iterate(self, X0, steps: int, V0=None, t0: float = 0.0) -> Iterator[State]:
        """Yield the states after each of ``steps`` steps from (X0, V0) at t0.

        Raises DivergenceError (with the last good state) if positions become non-finite.
        """
        state = X0 if isinstance(X0, State) else self.start(X0, V0, t0)
        if isinstance(X0, State) and not hasattr(self, "_X0"):
            self._X0 = X0.X
        for _ in range(int(steps)):
            state = self.step(state)
            yield state

    # -- a controlled run ---------------------------------------------------
    def run(
        self,
        X0,
        *,
        t_end: float | None = None,
        steps: int | None = None,
        V0=None,
        t0: float = 0.0,
        trackers: Sequence = (),
        progress: bool = False,
        resume: State | None = None,
    ) -> RunResult:
        """Run to ``t_end`` (s) or for ``steps`` steps under a set of trackers.

        Trackers (see :mod:`deformable.trackers`) watch the run at their own
        cadence and may stop it. A :class:`~deformable.trackers.DivergenceGuard`
        is added unless one is given; a diverging run stops at that step and
        the result holds the last good state.
        """
        from .trackers import DivergenceGuard, ProgressBar, Stop

        state = self.start(X0, V0, t0)
        if resume is not None:
            state = resume
        if (t_end is None) == (steps is None):
            raise ValueError("give exactly one of t_end and steps")
        if steps is None:
            if not np.isfinite(t_end) or t_end <= state.t:
                raise ValueError(f"t_end must be later than the start time {state.t}, got {t_end!r}")
            steps = int(round((t_end - state.t) / self.dt))
        elif int(steps) != steps or steps < 0:
            raise ValueError(f"steps must be a non-negative integer, got {steps!r}")
        steps = int(steps)
        trackers = list(trackers)
        if not any(isinstance(tr, DivergenceGuard) for tr in trackers):
            trackers.insert(0, DivergenceGuard())
        if progress:
            trackers.append(ProgressBar())
        for tr in trackers:
            tr.initialize(state, self, steps)
        status, message = "finished", ""
        start = _time.perf_counter()
        last = state.step + steps
        try:
            for new in self.iterate(state, steps):
                stop = None
                for tr in trackers:
                    if new.step % tr.every == 0 or new.step == last:
                        stop = tr.handle(new) or stop
                        if isinstance(stop, Stop) and stop.diverged:
                            break
                if isinstance(stop, Stop) and stop.diverged:
                    status, message = "diverged", stop.reason
                    break
                state = new
                if isinstance(stop, Stop):
                    status, message = "stopped", stop.reason
                    break
        except DivergenceError as err:
            status, message, state = "diverged", str(err), err.state
        wall = _time.perf_counter() - start
        if status == "finished":
            message = f"{steps} steps to t = {state.t:.6g} s"
        result = RunResult(state=state, status=status, message=message, steps=state.step, wall_time=wall,
                           trackers=trackers)
        for tr in trackers:
            tr.finalize(result)
        if status == "diverged":
            log.warning("run %s; last good state at t = %.6g s", message, state.t)
        return result
