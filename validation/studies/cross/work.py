r"""Work-precision of whole solves: CPU time against the error of a static solution.

Work is the process CPU time (``time.process_time``, all threads of the process) of one whole solve: the
scene and the model built, the equilibrium found, the output sampled; the best of up to three repetitions
while they take under half a second. Precision is the relative error of one output against a reference:

- the linear clamped plate (:func:`~validation.studies.cross.problems.linear_plate`): the centre deflection
  against ``w_c = 0.00126531909 q a^4 / D``. Methods: FD and FE (the variational model, Newton), and as an
  independent peer scikit-fem's own Kirchhoff plate elements on a triangulated square
  (``MeshTri.init_tensor``, two triangles a cell), ``D integral u_ij v_ij = integral q v`` (nu = 0), the
  clamp on every boundary degree of freedom that the clamp determines:

  - Morley's nonconforming quadratic (Morley 1968; deflection O(h^2));
  - Argyris' C1 quintic (Argyris, Fried and Scharpf 1968; deflection O(h^6) for smooth solutions, here
    limited by the plate's corner singularities), with u_nn left free on the boundary.
- the nonlinear cantilever (P L^2 / EI = 2): the tip deflection against the extensible elastica of the
  model (:func:`~validation.studies.cross.problems.elastica_tip`), FD and FE from the flat strip in one
  load step.

Timings depend on the machine and the moment: they go to the study's run-dependent tables; the verdicts
computed from them (who reaches what first) are stated by grid sizes.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

import deformable as dm
from validation.harness.backends import make_model

from . import problems as pb

__all__ = ["WorkCase", "run_work", "work_cases", "cpu_to_reach", "error_at"]

#: nodes a side of each method's grids, by problem (quick levels: all but the last; full: all)
GRIDS = {
    "plate": {"fd": (9, 17, 33, 65, 129, 257), "fe": (3, 5, 9, 17, 33, 65), "morley": (5, 9, 17, 33, 65, 129),
              "argyris": (3, 5, 9, 17, 33)},
    "cantilever": {"fd": (21, 41, 81, 161, 321), "fe": (6, 11, 21, 41, 81)},
}
#: P L^2 / EI of the work-precision cantilever
LOAD = 2.0


@dataclass(frozen=True)
class WorkCase:
    problem: str
    method: str
    nodes: int


def work_cases(full: bool) -> list[WorkCase]:
    """Every (problem, method, grid); the quick set leaves each method's finest grid out."""
    return [WorkCase(p, m, n) for p, methods in GRIDS.items() for m, grids in methods.items()
            for n in (grids if full else grids[:-1])]


def _kirchhoff(element: str, n: int) -> tuple[float, int]:
    """Centre deflection and number of unknowns of scikit-fem's plate element on the clamped square."""
    import skfem
    from skfem.helpers import dd, ddot

    c = pb.LINEAR_PLATE
    D, q = c["D"], c["q"]
    axis = np.linspace(0.0, c["a"], n)
    mesh = skfem.MeshTri.init_tensor(axis, axis)
    basis = skfem.Basis(mesh, skfem.ElementTriMorley() if element == "morley" else skfem.ElementTriArgyris())

    @skfem.BilinearForm
    def bending(u, v, _):
        return D * ddot(dd(u), dd(v))

    @skfem.LinearForm
    def load(v, _):
        return q * v

    if element == "morley":
        held = basis.get_dofs().all()
    else:  # on an edge x = const u, u_y, u_yy are known and u_x = u_xy = 0; likewise for y = const
        vertical = basis.get_dofs(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], c["a"]))
        horizontal = basis.get_dofs(lambda x: np.isclose(x[1], 0.0) | np.isclose(x[1], c["a"]))
        held = np.unique(np.concatenate([vertical.all(["u", "u_x", "u_y", "u_xy", "u_yy", "u_n"]),
                                         horizontal.all(["u", "u_x", "u_y", "u_xy", "u_xx", "u_n"])]))
    x = skfem.solve(*skfem.condense(bending.assemble(basis), load.assemble(basis), D=held))
    w = float((basis.probes(np.array([[c["a"] / 2], [c["a"] / 2]])) @ x)[0])
    return w, basis.N - held.size


def _solve(case: WorkCase) -> tuple[float, int]:
    """One whole solve: (the output, unknowns)."""
    if case.method in ("morley", "argyris"):
        return _kirchhoff(case.method, case.nodes)
    if case.problem == "plate":
        model = make_model(pb.linear_plate(case.nodes), case.method)
        X, _ = dm.equilibrium(model, model.initial_state(), tol=1e-12, newton=pb.NEWTON)
        out = float(model.sample(X, np.array([[0.5, 0.5]])).r[0, 2])
    else:
        across = 3 if case.method == "fe" else (case.nodes - 1) // 10 + 1
        model = make_model(pb.cantilever((case.nodes, across), LOAD), case.method)
        X, _ = dm.equilibrium(model, model.initial_state(), tol=1e-12, newton=pb.NEWTON)
        out = float(model.sample(X, np.array([[pb.CANTILEVER["L"], pb.CANTILEVER["b"] / 2]])).r[0, 2])
    return out, 3 * model.ndof - sum(len(f) for f in model.fixed_dofs())


def reference(problem: str) -> float:
    """The exact output: the plate's centre deflection, or the cantilever's tip z (m)."""
    if problem == "plate":
        c = pb.LINEAR_PLATE
        return pb.CLAMPED_CENTRE * c["q"] * c["a"] ** 4 / c["D"]
    return float(pb.elastica_tip(LOAD)[1])


def run_work(case: WorkCase) -> dict:
    """CPU time (s, best of up to three repetitions under 0.5 s), relative error and unknowns of one solve."""
    best, spent = np.inf, 0.0
    for _ in range(3):
        t0 = time.process_time()
        out, unknowns = _solve(case)
        dt = time.process_time() - t0
        best, spent = min(best, dt), spent + dt
        if spent > 0.5:
            break
    ref = reference(case.problem)
    return {"cpu": max(best, 1e-4), "error": abs(out / ref - 1.0), "unknowns": unknowns}


def cpu_to_reach(cpu: np.ndarray, err: np.ndarray, target: float) -> float:
    """CPU time at which a method's error first reaches ``target``: log-log interpolation between the two
    measured solves that bracket it; NaN when no measured solve reaches it."""
    cpu, err = np.asarray(cpu, float), np.asarray(err, float)
    below = np.flatnonzero(err <= target)
    if below.size == 0:
        return np.nan
    k = below[0]
    if k == 0:
        return float(cpu[0])
    s = np.log(target / err[k - 1]) / np.log(err[k] / err[k - 1])
    return float(np.exp(np.log(cpu[k - 1]) + s * np.log(cpu[k] / cpu[k - 1])))


def error_at(cpu: np.ndarray, err: np.ndarray, t: float) -> float:
    """A method's error at CPU time t by log-log interpolation of its measured solves (NaN outside their range)."""
    cpu, err = np.asarray(cpu, float), np.asarray(err, float)
    order = np.argsort(cpu)
    lc, le = np.log(cpu[order]), np.log(err[order])
    if not lc[0] <= np.log(t) <= lc[-1]:
        return np.nan
    return float(np.exp(np.interp(np.log(t), lc, le)))
