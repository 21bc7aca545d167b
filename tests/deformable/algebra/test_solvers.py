"""The sparse direct solvers (deformable.algebra.solvers): both factorise what scipy solves, refuse what they must."""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from deformable.algebra import solvers as linalg
from deformable.algebra.solvers import make_solver
from deformable.errors import SingularMatrix


def laplacian(n: int, shift: float) -> sp.csr_matrix:
    """The 2-D five-point Laplacian on n x n nodes plus shift I: definite for shift > 0, indefinite below -8."""
    T = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    return (sp.kronsum(T, T) + shift * sp.identity(n * n)).tocsr()


@pytest.mark.parametrize("solver", linalg.available())
@pytest.mark.parametrize("definite", [True, False])
def test_each_solver_solves_what_scipy_solves(solver, definite, rng):
    A = laplacian(12, 0.5 if definite else -3.3)
    b = rng.normal(size=(A.shape[0], 3))
    s = make_solver(solver, definite=definite).factor(A)
    assert s.name == solver
    x = s.solve(b)
    np.testing.assert_allclose(x, spla.spsolve(A.tocsc(), b), rtol=0, atol=1e-10 * np.abs(x).max())
    assert s.solve(b[:, 0]).shape == (A.shape[0],)


@pytest.mark.parametrize("solver", linalg.available())
def test_a_refactorisation_with_new_values_on_the_same_pattern_is_exact(solver, rng):
    """The pattern's analysis is kept (PARDISO: phase 11 once); new values give the new solution."""
    s = make_solver(solver, definite=True)
    b = rng.normal(size=144)
    for shift in (0.5, 2.0, 10.0):
        A = laplacian(12, shift)
        x = s.factor(A).solve(b)
        assert np.max(np.abs(A @ x - b)) < 1e-12 * np.abs(b).max() * (8 + shift)


@pytest.mark.parametrize("solver", linalg.available())
def test_a_matrix_declared_definite_that_is_not_is_refused(solver):
    with pytest.raises(SingularMatrix, match="not positive definite|error"):
        make_solver(solver, definite=True).factor(laplacian(8, -3.3))
    make_solver(solver, definite=False).factor(laplacian(8, -3.3))  # as indefinite it is fine


def test_superlu_checks_definiteness_only_with_diagonal_pivots():
    with pytest.raises(ValueError, match="diagonal pivots"):
        linalg.SuperLU(definite=True, options=dict(permc_spec="COLAMD"))


def test_auto_picks_pardiso_for_large_matrices_where_installed_and_names_are_checked():
    small, large = laplacian(8, 0.5), laplacian(70, 0.5)
    assert small.nnz < linalg.PARDISO_FROM <= large.nnz
    assert make_solver("auto").factor(small).name == "superlu"
    assert make_solver("auto").factor(large).name == linalg.available()[-1]
    with pytest.raises(ValueError, match="solver must be one of"):
        make_solver("mumps")
    if "pardiso" not in linalg.available():
        with pytest.raises(ValueError, match=r"pip install 'deformable-sheets\[fast\]'"):
            make_solver("pardiso")


def test_openblas_keeps_one_thread_while_a_solver_loop_runs():
    """PARDISO's factorisations, the Hessian's threads and numpy's OpenBLAS share the cores: OpenBLAS is held to
    one thread inside one_blas_thread, and restored after."""
    import threadpoolctl

    from deformable.algebra.solvers import one_blas_thread

    def openblas_threads():
        return [c.num_threads for c in threadpoolctl.ThreadpoolController().select(internal_api="openblas").lib_controllers]

    before = openblas_threads()
    with one_blas_thread():
        inside = openblas_threads()
    assert openblas_threads() == before
    assert inside == [1] * len(before)


@pytest.mark.skipif("pardiso" not in linalg.available(), reason="PARDISO (pypardiso) is not installed")
def test_single_precision_that_loses_a_pivot_turns_to_double_precision_for_good(rng):
    """A positive definite matrix whose condition float32 cannot hold (the block [[1 + e, 1], [1, 1 + e]],
    e = 1e-9, which float32 rounds to a singular one: a zero pivot): single precision's Cholesky refuses it, as it
    would an indefinite one; ``double()`` factorises the same matrix in double precision, solves it to round-off,
    and stays there. A matrix refused in double precision too is still refused."""
    e = 1e-9
    A = sp.block_diag([np.array([[1 + e, 1.0], [1.0, 1 + e]]), laplacian(12, 0.5)], format="csr")
    n = A.shape[0]
    assert np.min(np.linalg.eigvalsh(A.toarray())) > 0
    s = make_solver("pardiso", definite=True, single=True)
    with pytest.raises(SingularMatrix):
        s.factor(A)
    assert s.double() and not s.single and not s.double()
    b = rng.normal(size=n)
    x = s.solve(b)
    assert np.max(np.abs(A @ x - b)) < 1e-6 * np.abs(b).max()
    np.testing.assert_allclose(x, spla.spsolve(A.tocsc(), b), rtol=1e-6)
    with pytest.raises(SingularMatrix):
        s.factor(laplacian(12, -3.3))
