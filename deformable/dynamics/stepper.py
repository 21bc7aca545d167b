r"""The time stepper: a controller that runs a scheme under trackers (py-pde's controller pattern).

:class:`TimeStepper` chooses the scheme for the model's force model, starts a
run (the constraint reference X0), advances it step by step
(:meth:`~TimeStepper.iterate`), and runs it under trackers
(:meth:`~TimeStepper.run`: progress, output, energy, divergence guard), each
of which watches at its own cadence and may stop the run. The schemes know
nothing of the run:

- ``"semi-implicit"``: the paper's eq. (22)-(27) (:mod:`deformable.dynamics.semi_implicit`),
  for the tpbf87 and frozen force models (their default);
- ``"implicit-euler"`` and ``"newmark"``: Newton steps on an incremental
  potential (:mod:`deformable.dynamics.implicit`), for models with an energy
  (the variational model's default is implicit Euler).

The old name of the paper's scheme, ``"tpbf87"`` (also a force model's name),
is still accepted with a DeprecationWarning.
"""

from __future__ import annotations

import logging
import time
import warnings
from typing import Iterator, Sequence

import numpy as np

from .implicit import IMPLICIT_SCHEMES, Implicit
from .semi_implicit import SemiImplicit
from .state import DivergenceError, RunResult, State
from .trackers import DivergenceGuard, ProgressBar, Stop

__all__ = ["TimeStepper", "SCHEMES"]

log = logging.getLogger(__name__)
SCHEMES = ("semi-implicit",) + IMPLICIT_SCHEMES
#: former scheme names -> current ones
_RENAMED = {"tpbf87": "semi-implicit"}


class TimeStepper:
    """Integrate ``model`` in time with one of :data:`SCHEMES`.

    Parameters
    ----------
    model : Backend
        FDModel or FEModel (anything satisfying :class:`deformable.Backend`).
    dt : float
        Time step (s), positive.
    scheme : str, optional
        "semi-implicit" (eq. 22-27, the default for the tpbf87 and frozen
        models), "implicit-euler" (the default for the variational model) or
        "newmark" (second order): Newton steps on an incremental potential,
        for models with an energy (:mod:`deformable.dynamics.implicit`).
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
        if scheme in _RENAMED:
            warnings.warn(f"scheme {scheme!r} is now called {_RENAMED[scheme]!r}", DeprecationWarning, stacklevel=2)
            scheme = _RENAMED[scheme]
        scheme = scheme or ("implicit-euler" if force_model == "variational" else "semi-implicit")
        if scheme not in SCHEMES:
            raise ValueError(f"scheme must be one of {SCHEMES}, got {scheme!r}")
        if scheme == "semi-implicit" and force_model == "variational":
            raise ValueError("scheme 'semi-implicit' lags the strength matrix K(r) of eq. (20), which the variational "
                             "model does not have; use 'implicit-euler' or 'newmark'")
        if scheme != "semi-implicit" and force_model == "tpbf87":
            raise ValueError(f"scheme {scheme!r} needs an energy; the tpbf87 force (14) is not a gradient "
                             "(use force_model 'variational', or scheme 'semi-implicit')")
        self.model, self.dt, self.scheme = model, dt, scheme
        self._scheme = (SemiImplicit(model, dt) if scheme == "semi-implicit"
                        else Implicit(model, dt, scheme, **(newton or {})))

    @property
    def timings(self) -> dict:
        """Seconds per part of the steps so far: semi-implicit "assembly", "factorisation", "solve"; implicit "solve"."""
        return self._scheme.timings

    @property
    def newton_reports(self) -> list:
        """Newton iterations and residuals per step of the implicit schemes (empty for the semi-implicit one)."""
        return getattr(self._scheme, "reports", [])

    def step(self, state: State) -> State:
        """Advance one step; the state at t + dt."""
        return self._scheme.step(state, self._X0)

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

        Trackers (see :mod:`deformable.dynamics.trackers`) watch the run at their own
        cadence and may stop it. A :class:`~deformable.dynamics.trackers.DivergenceGuard`
        is added unless one is given; a diverging run stops at that step and
        the result holds the last good state.
        """
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
        start = time.perf_counter()
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
        wall = time.perf_counter() - start
        if status == "finished":
            message = f"{steps} steps to t = {state.t:.6g} s"
        result = RunResult(state=state, status=status, message=message, steps=state.step, wall_time=wall,
                           trackers=trackers)
        for tr in trackers:
            tr.finalize(result)
        if status == "diverged":
            log.warning("run %s; last good state at t = %.6g s", message, state.t)
        return result
