"""Fixed-pattern assembly (deformable.algebra.patterns) against plain scipy assembly."""

import numpy as np
import pytest
import scipy.sparse as sp

from deformable.algebra.elements import SymmetricElements, element_vectors
from deformable.algebra.patterns import FixedPattern, canonical
from deformable.algebra.reduced import ReducedSystem


def test_fixed_pattern_sums_contributions_like_coo(rng):
    rows, cols = rng.integers(0, 7, size=(2, 60))
    values = rng.normal(size=60)
    pat = FixedPattern(rows, cols, (7, 9))
    A = pat.matrix(pat.data(values))
    B = canonical(sp.coo_matrix((values, (rows, cols)), shape=(7, 9)))
    assert np.array_equal(A.indptr, B.indptr) and np.array_equal(A.indices, B.indices)
    np.testing.assert_allclose(A.data, B.data, rtol=1e-14)
    np.testing.assert_allclose(pat.scatter @ values, A.data, rtol=1e-14)
    A2 = pat.matrix(pat.data(2 * values))
    assert A2.indptr is A.indptr and A2.indices is A.indices  # the very arrays: a pattern check by identity


def test_symmetric_elements_equal_the_sum_of_full_element_matrices(rng):
    E, nl, n = 6, 5, 12
    ldofs = np.array([rng.choice(n, nl, replace=False) for _ in range(E)])
    Ke = rng.normal(size=(E, nl, nl))
    Ke = Ke + np.swapaxes(Ke, 1, 2)
    el = SymmetricElements(ldofs, n)
    A = el.matrix(el.collect(Ke[:, el.upper[0], el.upper[1]]))
    rows = np.repeat(ldofs, nl, axis=1).ravel()
    cols = np.tile(ldofs, (1, nl)).ravel()
    reference = sp.coo_matrix((Ke.ravel(), (rows, cols)), shape=(n, n)).toarray()
    np.testing.assert_allclose(A.toarray(), reference, rtol=0, atol=1e-13)
    # templates: a coefficient per element and point times per-point tables
    C, nq = 2, 3
    T = rng.normal(size=(C, nq, nl, nl))
    T = T + np.swapaxes(T, 2, 3)
    w, coef = rng.uniform(size=nq), rng.normal(size=(E, C, nq))
    B = el.matrix(el.data(coef.reshape(E, C * nq), el.templates(T, w)))
    Ke2 = np.einsum("ecq,q,cqlm->elm", coef, w, T)
    np.testing.assert_allclose(B.toarray(), sp.coo_matrix((Ke2.ravel(), (rows, cols)), shape=(n, n)).toarray(),
                               rtol=0, atol=1e-12)
    v = rng.normal(size=(E, nl))
    np.testing.assert_allclose(element_vectors(ldofs, n) @ v.ravel(), np.bincount(ldofs.ravel(), v.ravel(), n))


def symmetric_values(K, rng):
    """A symmetric matrix on K's (symmetric, canonical) pattern with random values."""
    B = K.copy()
    B.data = rng.normal(size=K.nnz)
    B = canonical(B + B.T)
    assert np.array_equal(B.indptr, K.indptr) and np.array_equal(B.indices, K.indices)
    return B


def test_reduced_system_gives_the_blocks_of_K_plus_cm_M_plus_cc_C(rng):
    n = 10
    K = sp.random(n, n, density=0.4, random_state=2, format="csr")
    K = canonical(K + K.T)
    M, C = sp.diags(rng.uniform(1, 2, n), format="csr"), sp.diags(rng.uniform(0, 1, n), format="csr")
    fixed = np.array([0, 4, 7])
    system = ReducedSystem(K, M, C, 3.0, 0.5, [fixed])
    A = (K + 3.0 * M + 0.5 * C).toarray()
    free = np.setdiff1d(np.arange(n), fixed)
    K2 = symmetric_values(K, rng)
    for k in (K, K2):
        Aff, Afc = system.matrices(system.data(k), system.blocks[0])
        ref = (k + 3.0 * M + 0.5 * C).toarray()
        np.testing.assert_allclose(Aff.toarray(), ref[np.ix_(free, free)], rtol=0, atol=1e-14)
        np.testing.assert_allclose(Afc.toarray(), ref[np.ix_(free, fixed)], rtol=0, atol=1e-14)
    assert np.allclose(A[np.ix_(free, free)], system.matrices(system.data(K), system.blocks[0])[0].toarray())
    other = canonical(K + sp.identity(n))  # a new diagonal entry: another pattern
    with pytest.raises(ValueError, match="changed its sparsity pattern"):
        system.data(other)


