r"""Differences between solutions under refinement: FD against FE, and each backend against itself.

For a problem solved on levels k = 0 .. K - 1 by both backends, and by FD on one more (its solves cost
little; :mod:`validation.studies.cross.cases`), and each quantity q of r, G, B:

- the FD-FE difference at level k: the largest over the samples (loads, times) of the L2 norm over the
  sheet and of the max over the interior of ``q_FD - q_FE`` (:func:`validation.studies.cross.measure.difference`);
- each backend's self-difference between levels k and k + 1, the same norms of ``q_k - q_{k+1}``.

For a backend converging at order p the self-differences fall like h^p, and so does the FD-FE difference at
the lower of the two backends' orders once both are in their asymptotic ranges (Roache 1998, "Verification
and validation in computational science and engineering", ch. 5: self-convergence from three grids). The
observed order is the least-squares slope of log(difference) against log(h)
(:func:`validation.harness.orders.fit_order`).
"""

from __future__ import annotations

import numpy as np

from validation.harness.orders import fit_order

from .measure import QUANTITIES, Probe, difference

__all__ = ["Differences", "differences", "NORMS"]

#: the two norms, in report order
NORMS = ("L2", "interior max")


class Differences:
    """FD-FE and self-differences of one problem (module docstring).

    Attributes
    ----------
    h : array (K + 1,)
        The spacing along a1 of each level (the last one FD's only).
    cross : dict (q, norm) -> array (K,)
        FD-FE differences.
    self : dict (backend, q, norm) -> array (K,) for FD, (K - 1,) for FE
        Differences between consecutive levels of one backend, at the coarser one's h.
    """

    def __init__(self, h, cross, self_):
        self.h, self.cross, self.self = np.asarray(h), cross, self_

    def order(self, values: np.ndarray, h: np.ndarray | None = None) -> float:
        """The fitted order of a series over the levels (NaN when a value is not positive)."""
        h = self.h[: len(values)] if h is None else h
        values = np.asarray(values)
        return fit_order(h, values) if values.size >= 2 and np.all(values > 0) else np.nan


def differences(runs: dict, levels: int, probe: Probe) -> Differences:
    """:class:`Differences` from runs {(backend, level): run_case result} of one problem: FE on ``levels``
    levels, FD on those and, when given, one more."""
    fd_levels = levels + 1 if ("fd", levels) in runs else levels
    h = [runs[("fd", k)]["h"] for k in range(fd_levels)]

    def largest(a, b, q):  # the norms of a - b, the largest over the samples: (2,)
        return np.array([difference(x[q], y[q], probe) for x, y in zip(a["samples"], b["samples"])]).max(axis=0)

    cross, self_ = {}, {}
    for q in QUANTITIES:
        d = np.array([largest(runs[("fd", k)], runs[("fe", k)], q) for k in range(levels)])
        for j, norm in enumerate(NORMS):
            cross[(q, norm)] = d[:, j]
        for b, count in (("fd", fd_levels), ("fe", levels)):
            s = np.array([largest(runs[(b, k)], runs[(b, k + 1)], q) for k in range(count - 1)]).reshape(-1, 2)
            for j, norm in enumerate(NORMS):
                self_[(b, q, norm)] = s[:, j]
    return Differences(h, cross, self_)
