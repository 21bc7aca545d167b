"""Newton's method on a potential (deformable.solve.newton), shared by the implicit steps and equilibrium."""

import numpy as np
import pytest
import scipy.sparse as sp

import deformable as dm
from deformable.algebra.solvers import available
from deformable.errors import ConvergenceError, SingularMatrix
from deformable.solve.newton import Newton, NewtonSettings
from deformable.solve.potential import FlatEnergy, flat, unflat
from deformable.solve.search import WATCHDOG, LineSearch

from ...conftest import flat_model


def test_flat_vectors_are_coordinate_blocked(rng):
    X = rng.normal(size=(4, 3))
    x = flat(X)
    assert x[2 * 4 + 1] == X[1, 2]
    np.testing.assert_array_equal(unflat(x, 4), X)


class Diagonal:
    """A stand-in for FlatEnergy: phi = sum w(x_i - c_i), Hessian diag(w''), masses one; the first entry held."""

    def __init__(self, c, w, dw, d2w, d2w_definite=None):
        self.c, self.w, self.dw, self.d2w = np.asarray(c, float), w, dw, d2w
        self.d2w_definite = d2w_definite or d2w
        n = self.c.size
        self.n = n
        self.M = self.C = sp.identity(n, format="csr")
        self.free = np.ones(n, bool)
        self.free[0] = False
        self.fixed = np.array([0])
        self.linear = False
        self.filter = None  # no direction filter (no obstacles): Newton's directions are not clipped
        self.hessians = []

    def phi(self, x):
        return float(np.sum(self.w(x - self.c)))

    def grad(self, x):
        return self.dw(x - self.c)

    def hessian(self, x, kind):
        self.hessians.append(kind)
        f = self.d2w_definite if kind == "definite" else self.d2w
        n = self.n  # an explicit CSR diagonal: the same pattern whatever the values (zeros included)
        return sp.csr_matrix((f(x - self.c), np.arange(n), np.arange(n + 1)), shape=(n, n))

    def hessian_elements(self, x, kind):
        return self.hessian(x, kind), None  # no element Hessians: the whole matrix

    def extra_hessians(self, x, damping=None, kind="newton"):
        return [] if damping is None else [damping]

    def loose_hessians(self, x):
        return []

    def loose_reserve(self):
        return np.zeros(0, np.int64), np.zeros(0, np.int64)


def cosh_problem():
    c = [0.0, 0.5, -1.0, 2.0]
    return Diagonal(c, np.cosh, np.sinh, np.cosh)


@pytest.mark.parametrize("solver", available())
def test_minimise_converges_quadratically_and_keeps_held_entries(solver):
    p = cosh_problem()
    newton = Newton(p, NewtonSettings(rtol=0.0, atol=1e-13, solver=solver, reuse=False))
    x0 = np.array([7.0, 0.0, 0.0, 0.0])
    x, report = newton.minimise(p.phi, p.grad, x0, label="test")
    assert report.converged and x[0] == 7.0
    np.testing.assert_allclose(x[1:], p.c[1:], rtol=0, atol=1e-12)
    r = np.array(report.residuals)
    assert report.iterations == len(r) - 1 <= 8 and report.factorisations == report.iterations
    assert r[-2] < 1e-6 and r[-1] <= 10 * r[-2] ** 2  # quadratic near the end


class FirstSolveFails:
    """A solver whose first solve finds its factorisation unusable, as PARDISO's single-precision Cholesky does when
    it passed a matrix that double precision then finds indefinite (SingularMatrix from ``solve``)."""

    def __init__(self, inner):
        self.inner, self.failed, self.factors = inner, False, 0

    def factor(self, A):
        self.factors += 1
        self.inner.factor(A)
        return self

    def solve(self, b):
        if not self.failed:
            self.failed = True
            raise SingularMatrix("PARDISO: the matrix is not positive definite (error -4)")
        return self.inner.solve(b)

    def __getattr__(self, name):
        return getattr(self.inner, name)


def test_a_solve_that_finds_its_factorisation_unusable_factorises_the_same_matrix_again():
    """The paper sheet of deformable.scenes (1e6 N/m, compressed by the drawn rod) diverged with "the Newton matrix
    is singular" from a solve: the float32 Cholesky had passed, double precision refused. The direction is then
    taken from a new factorisation of the same matrix, and the minimisation goes on."""
    p = cosh_problem()
    newton = Newton(p, NewtonSettings(rtol=0.0, atol=1e-13, reuse=False))
    stub = newton.directions.solver = FirstSolveFails(newton.directions.solver)
    x, report = newton.minimise(p.phi, p.grad, np.zeros(4), label="test")
    assert report.converged and stub.failed
    np.testing.assert_allclose(x[1:], p.c[1:], rtol=0, atol=1e-12)
    assert stub.factors == report.factorisations == report.iterations + 1  # the one made again, counted


def test_a_factorisation_is_reused_while_it_contracts_and_not_across_solves_of_a_nonlinear_model():
    """With reuse, an iteration keeps the factorisation at hand while the residual falls tenfold per iteration."""
    p = cosh_problem()
    newton = Newton(p, NewtonSettings(rtol=0.0, atol=1e-13))
    x, report = newton.minimise(p.phi, p.grad, np.zeros(4), label="test")
    assert report.converged and report.factorisations < report.iterations
    _, again = newton.minimise(p.phi, p.grad, np.array([0.0, 0.6, -1.0, 2.0]), label="test")
    assert again.factorisations >= 1  # a nonlinear model refactorises at the start of a new solve


def test_a_linear_models_factorisation_outlives_its_solve():
    """phi quadratic, a linear problem: the second solve (same c_M, c_C) needs no factorisation."""
    p = Diagonal([0.0, 1.0, 2.0], lambda y: 0.5 * 3 * y**2, lambda y: 3 * y, lambda y: 3 + 0 * y)
    p.linear = True
    newton = Newton(p, NewtonSettings(rtol=0.0, atol=1e-12))
    _, first = newton.minimise(p.phi, p.grad, np.zeros(3), label="test")
    _, second = newton.minimise(p.phi, p.grad, np.ones(3), label="test")
    assert first.factorisations == 1 and second.factorisations == 0 and second.converged
    # a new c_M is a new matrix (the potential gains 0.5 |x|^2_M, M the identity here)
    _, third = newton.minimise(lambda x: p.phi(x) + 0.5 * x @ x, lambda x: p.grad(x) + x, np.ones(3), cm=1.0,
                               label="test")
    assert third.factorisations == 1 and third.iterations == 1


def test_auto_uses_the_exact_hessian_where_it_is_definite_and_the_definite_one_elsewhere():
    """phi = y^4/4 - y^2/2 from y = 0.1, where the exact Hessian 3y^2 - 1 is negative: the definite one (3y^2)
    serves there, the exact one near the minimum y = 1; the minimum is reached either way."""
    p = Diagonal([0.0, 0.0], lambda y: y**4 / 4 - y**2 / 2, lambda y: y**3 - y, lambda y: 3 * y**2 - 1,
                 lambda y: 3 * y**2)
    newton = Newton(p, NewtonSettings(rtol=0.0, atol=1e-12, reuse=False))
    assert newton.settings.hessian == "auto"
    x, report = newton.minimise(p.phi, p.grad, np.array([0.0, 0.1]), label="test")
    assert report.converged and abs(x[1] - 1.0) < 1e-10
    assert "definite" in p.hessians and p.hessians[-1] == "newton"
    assert report.fallbacks == p.hessians.count("definite") >= 1  # each one counted in the report


def test_full_newton_steps_may_raise_the_potential_for_a_while_then_the_watchdog_steps_back():
    """phi = sqrt(1 + y^2) - y/2 (minimum y = 1/sqrt(3)): from y = 3 pure Newton overshoots and diverges
    (|y| grows); the watchdog allows WATCHDOG such steps, then backtracks from the best point and converges."""
    c = 0.0
    w = lambda y: np.hypot(1.0, y) - 0.5 * y  # noqa: E731
    dw = lambda y: y / np.hypot(1.0, y) - 0.5  # noqa: E731
    d2w = lambda y: np.hypot(1.0, y) ** -3.0  # noqa: E731
    p = Diagonal([c, c], w, dw, d2w)
    values = []

    def phi(x):
        values.append(p.phi(x))
        return values[-1]

    x, report = Newton(p, NewtonSettings(rtol=0.0, atol=1e-12, reuse=False)).minimise(phi, p.grad,
                                                                                      np.array([0.0, 3.0]))
    assert report.converged and abs(x[1] - 1 / np.sqrt(3)) < 1e-9
    assert max(values) > values[0]  # full steps were taken although phi grew ...
    assert report.iterations <= 2 * WATCHDOG + 10  # ... and the search recovered


def test_a_failed_line_search_is_a_convergence_error():
    p = cosh_problem()
    phi = lambda x: 0.0 if np.all(x[1:] == 0) else np.nan  # noqa: E731
    with pytest.raises(ConvergenceError, match="thing: line search failed at iteration 1"):
        Newton(p, NewtonSettings(rtol=0.0)).minimise(phi, p.grad, np.zeros(4), label="thing")


def test_the_armijo_search_descends_monotonically_where_the_watchdog_lets_phi_grow():
    """The same problem as above under the registered "armijo" search: every accepted iterate lowers phi by at
    least c times the step's slope (Nocedal and Wright's algorithm 3.1), and Newton still converges."""
    w = lambda y: np.hypot(1.0, y) - 0.5 * y  # noqa: E731
    dw = lambda y: y / np.hypot(1.0, y) - 0.5  # noqa: E731
    d2w = lambda y: np.hypot(1.0, y) ** -3.0  # noqa: E731
    p = Diagonal([0.0, 0.0], w, dw, d2w)
    iterates = []

    def grad(x):
        iterates.append(x.copy())
        return p.grad(x)

    settings = NewtonSettings(rtol=0.0, atol=1e-12, reuse=False, search="armijo", armijo=0.25)
    x, report = Newton(p, settings).minimise(p.phi, grad, np.array([0.0, 3.0]))
    assert report.converged and abs(x[1] - 1 / np.sqrt(3)) < 1e-9
    values = [p.phi(y) for y in iterates]
    assert all(b < a for a, b in zip(values, values[1:])), "Armijo backtracking never lets phi grow"
    assert LineSearch.names() == ("watchdog", "armijo")


@pytest.mark.parametrize("field, value, message", [
    ("rtol", -1.0, "rtol must be a finite non-negative"), ("max_iter", 1.5, "max_iter must be a non-negative integer"),
    ("hessian", "exact", "hessian must be 'auto' or one of"), ("solver", "umfpack", "solver must be one of"),
    ("search", "wolfe", "search must be one of watchdog, armijo"), ("armijo", 0.5, r"armijo must lie in \(0, 1/2\)"),
])
def test_bad_settings_name_the_field(field, value, message):
    with pytest.raises(ValueError, match=message):
        NewtonSettings(**{field: value})


def test_flat_energy_holds_the_constrained_coordinates():
    model = flat_model("fd", nodes=(4, 4), force_model="variational",
                       constraints=[dm.Pin("left", motion=lambda t: (0.0, 0.0, t))])
    fl = FlatEnergy(model)
    held = np.concatenate([a * model.ndof + f for a, f in enumerate(model.fixed_dofs())])
    assert not fl.free[held].any() and fl.free.sum() == 3 * model.ndof - held.size
    X0 = model.initial_state()
    x = fl.hold(np.zeros(3 * model.ndof), X0, 2.0)
    np.testing.assert_array_equal(x[held], flat(model.prescribed(X0, 2.0))[held])
    assert not x[fl.free].any()
    with pytest.raises(ValueError, match="no energy gradient"):
        FlatEnergy(flat_model("fd", nodes=(4, 4)))
