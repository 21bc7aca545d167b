"""Loose matrices in a free block (deformable.algebra.reduced): a matrix whose pattern changes between refills is
added exactly, on a pattern that is kept while it covers the loose entries and grows when
one falls outside it."""

import numpy as np
import scipy.sparse as sp

from deformable.algebra.reduced import ReducedSystem


def _system(n=8):
    K = sp.diags([np.full(n - 1, -1.0), np.full(n, 2.0), np.full(n - 1, -1.0)], [-1, 0, 1], format="csr")
    M = sp.identity(n, format="csr")
    return K, M, ReducedSystem(K, M, M, 1.0, 0.5, [np.array([0])])


def _loose(n, pairs, value=1.0):
    rows, cols = zip(*[(i, j) for a, b in pairs for i, j in ((a, a), (a, b), (b, a), (b, b))])
    return sp.csr_matrix((np.full(len(rows), value), (rows, cols)), shape=(n, n))


def test_a_loose_matrix_is_added_exactly_and_its_pattern_kept_until_it_grows():
    n = 8
    K, M, system = _system(n)
    free = np.arange(1, n)
    dense = lambda L: (K + 1.5 * M + L).toarray()[np.ix_(free, free)]  # noqa: E731
    L1 = _loose(n, [(2, 6)])
    A1 = system.free_block(K, loose=[L1])
    np.testing.assert_allclose(A1.toarray(), dense(L1))
    L2 = _loose(n, [(2, 6)], 3.0)  # the same pairs: the same index arrays
    A2 = system.free_block(K, loose=[L2])
    np.testing.assert_allclose(A2.toarray(), dense(L2))
    assert np.array_equal(A2.indices, A1.indices) and np.array_equal(A2.indptr, A1.indptr)
    A0 = system.free_block(K, loose=[])  # no pairs: still the grown pattern, zeros where the pairs were
    assert np.array_equal(A0.indices, A1.indices)
    np.testing.assert_allclose(A0.toarray(), dense(sp.csr_matrix((n, n))))
    L3 = _loose(n, [(0, 3), (1, 7)])  # a new pair grows it; one with a held degree of freedom adds nothing free-free
    A3 = system.free_block(K, loose=[L3])
    np.testing.assert_allclose(A3.toarray(), dense(L3))
    assert A3.nnz > A1.nnz
