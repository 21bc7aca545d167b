"""The Newton matrix's free block as one upper triangle (deformable.algebra.upper): element Hessians, fixed-pattern
and loose matrices land exactly where the whole matrix has them, held rows and columns dropped; a loose matrix's
pattern is kept while it covers its entries and grows (a new version) when one falls outside it."""

import numpy as np
import pytest
import scipy.sparse as sp

from deformable.algebra.elements import SymmetricElements
from deformable.algebra.solvers import available, make_solver
from deformable.algebra.upper import FreeUpper


def _chain(n=8):
    """Elements of two neighbouring degrees of freedom, (k, k + 1), with random symmetric 2 x 2 matrices."""
    ldofs = np.stack([np.arange(n - 1), np.arange(1, n)], axis=1)
    return SymmetricElements(ldofs, n)


def _loose(n, pairs, value=1.0):
    rows, cols = zip(*[(i, j) for a, b in pairs for i, j in ((a, a), (a, b), (b, a), (b, b))])
    return sp.csr_matrix((np.full(len(rows), value), (rows, cols)), shape=(n, n))


def test_element_fixed_and_loose_parts_land_where_the_whole_matrix_has_them(rng):
    n = 8
    elements = _chain(n)
    M = sp.diags(rng.uniform(1, 2, n), format="csr")
    spring = sp.csr_matrix(([5.0, -5.0, -5.0, 5.0], ([1, 1, 6, 6], [1, 6, 1, 6])), shape=(n, n))
    block = FreeUpper(n, np.array([0, 4]), M, 2 * M, 3.0, 0.5, elements, [spring])
    free = np.setdiff1d(np.arange(n), [0, 4])
    uppers = rng.normal(size=(n - 1, 3)) + np.array([4.0, 0.0, 4.0])
    H = elements.matrix(elements.collect(uppers))
    whole = lambda L: (H + 4.0 * M + spring + L).toarray()[np.ix_(free, free)]  # noqa: E731
    A1 = block.assemble(uppers, [spring], loose=[_loose(n, [(2, 6)])])
    np.testing.assert_allclose(A1.tocsc().toarray(), whole(_loose(n, [(2, 6)])), rtol=0, atol=1e-12)
    version = A1.version
    A2 = block.assemble(uppers, [spring], loose=[_loose(n, [(2, 6)], 3.0)])  # the same pairs: the same pattern
    assert A2.version == version and A2.indices is A1.indices
    np.testing.assert_allclose(A2.tocsc().toarray(), whole(_loose(n, [(2, 6)], 3.0)), rtol=0, atol=1e-12)
    A0 = block.assemble(uppers, [spring])  # no pairs: still the grown pattern, zeros where the pairs were
    assert A0.version == version
    np.testing.assert_allclose(A0.tocsc().toarray(), whole(sp.csr_matrix((n, n))), rtol=0, atol=1e-12)
    L3 = _loose(n, [(0, 3), (1, 7)])  # a new pair grows it; one with a held degree of freedom adds nothing
    A3 = block.assemble(uppers, [spring], loose=[L3])
    assert A3.version == version + 1 and A3.data.size > A1.data.size
    np.testing.assert_allclose(A3.tocsc().toarray(), whole(L3), rtol=0, atol=1e-12)
    np.testing.assert_allclose(A3.diagonal(), np.diag(whole(L3)), rtol=0, atol=1e-12)
    v = rng.normal(size=free.size)
    np.testing.assert_allclose(A3 @ v, whole(L3) @ v, rtol=1e-12)


def test_every_solver_factorises_the_upper_triangle_and_follows_its_growth(rng):
    n = 10
    elements = _chain(n)
    M = sp.identity(n, format="csr")
    block = FreeUpper(n, np.array([9]), M, M, 1.0, 0.0, elements)
    uppers = np.tile([3.0, -1.0, 3.0], (n - 1, 1))
    b = rng.normal(size=n - 1)
    for name in available():
        solver = make_solver(name, definite=True)
        for loose in ([], [_loose(n, [(0, 5)], 0.5)], [_loose(n, [(2, 7)], 0.5)]):
            A = block.assemble(uppers, loose=loose)
            x = solver.factor(A).solve(b)
            np.testing.assert_allclose(A.tocsc() @ x, b, rtol=0, atol=1e-12)


def test_a_hessian_given_whole_and_an_extra_matrix_with_few_entries(rng):
    """The path of a model without element Hessians (the frozen model's constant matrix): the Hessian given whole,
    with entries the block's other parts lack, and a spring's matrix with a few; rescaled multipliers of M and C."""
    n = 12
    K0 = sp.random(n, n, density=0.3, random_state=3, format="csr")
    K0 = (K0 + K0.T).tocsr()
    M, C = sp.diags(rng.uniform(1, 2, n), format="csr"), sp.diags(rng.uniform(0, 1, n), format="csr")
    S = sp.csr_matrix(([1.0, -1.0, -1.0, 1.0], ([2, 2, 9, 9], [2, 9, 2, 9])), shape=(n, n))
    fixed = np.array([1, 5])
    free = np.setdiff1d(np.arange(n), fixed)
    block = FreeUpper(n, fixed, M, C, 3.0, 0.5, K0, [S])
    for scale in (1.0, 2.5):
        k = K0.copy()
        k.data = rng.normal(size=k.nnz)
        k = (k + k.T).tocsr()  # symmetric values on the same pattern
        k.sort_indices()
        s = S.copy()
        s.data = scale * S.data
        block.rescale(3.0 * scale, 0.5)
        ref = (k + s + 3.0 * scale * M + 0.5 * C).toarray()[np.ix_(free, free)]
        np.testing.assert_allclose(block.assemble(k, [s]).tocsc().toarray(), ref, rtol=0, atol=1e-14)
    with pytest.raises(ValueError, match="extra matrices"):
        block.assemble(k)
    with pytest.raises(ValueError, match="changed its sparsity pattern"):
        block.assemble((k + sp.csr_matrix(([1.0, 1.0], ([0, 11], [11, 0])), shape=(n, n))).tocsr(), [s])
