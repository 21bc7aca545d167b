"""The compiled Hessian kernels (deformable.physics.kernels) against finite differences and their own definitions.

Whole-model Hessians are checked against finite differences of the gradient in
test_backend; here each point's Hessian is, for both slot layouts, with random
weights and rest terms (so that every residual, and the bending part, is
non-zero), and the element projection against the dense ``B^T H B``.
"""

import numpy as np
import pytest

from deformable.errors import InputError
from deformable.physics import kernels, pointhessian
from deformable.physics.integrand import FD_SLOTS, FE_SLOTS, HESSIANS, Integrand, slot_tensors


def random_integrand(rng, slots, P):
    S = max(slots.values()) + 1
    w = lambda: rng.uniform(0.5, 2.0, size=(2, 2, P))  # noqa: E731
    G0, B0 = rng.normal(size=(2, 2, 2, P))
    G0 = 0.5 * (G0 + G0.transpose(1, 0, 2)) + 2.0 * np.eye(2)[..., None]
    B0 = 0.5 * (B0 + B0.transpose(1, 0, 2))
    v = rng.normal(size=(P, S, 3))
    return Integrand(w(), w(), G0, B0, slots), v


@pytest.mark.parametrize("slots", [FD_SLOTS, FE_SLOTS], ids=["fd", "fe"])
def test_point_hessian_is_the_derivative_of_the_gradient(slots, rng):
    w, v = random_integrand(rng, slots, P=6)
    H = w.hessian(v).reshape(6, 3 * w.S, 3 * w.S)
    eps = 1e-6
    fd = np.zeros_like(H)
    for i in range(3 * w.S):
        d = np.zeros(3 * w.S)
        d[i] = eps
        d = d.reshape(w.S, 3)
        fd[:, :, i] = ((w.gradient(v + d) - w.gradient(v - d)) / (2 * eps)).reshape(6, -1)
    assert np.max(np.abs(H - fd)) < 1e-7 * np.max(np.abs(H))
    np.testing.assert_allclose(H, np.swapaxes(H, 1, 2), rtol=0, atol=1e-12 * np.max(np.abs(H)))


@pytest.mark.parametrize("slots", [FD_SLOTS, FE_SLOTS], ids=["fd", "fe"])
def test_definite_kinds_are_positive_semidefinite_and_exact_at_rest(slots, rng):
    w, v = random_integrand(rng, slots, P=20)
    lowest = {k: np.linalg.eigvalsh(w.hessian(v, k).reshape(20, 3 * w.S, -1)).min(axis=1)
              for k in ("gauss-newton", "definite", "projected", "newton")}
    scale = np.max(np.abs(w.hessian(v)))
    for k in ("gauss-newton", "definite", "projected"):
        assert lowest[k].min() > -1e-10 * scale, k
    assert lowest["newton"].min() < -1e-3 * scale  # the random states are far from rest: exact is indefinite
    # at rest (every residual zero) all four are the Gauss-Newton matrix
    rest = Integrand(w.eta, w.xi, *slot_tensors(v, w.slots), w.slots)
    ref = rest.hessian(v, "gauss-newton")
    for k in HESSIANS:
        np.testing.assert_allclose(rest.hessian(v, k), ref, rtol=0, atol=1e-9 * np.max(np.abs(ref)))


def test_element_projection_is_BT_H_B_summed_over_the_points(rng):
    w, v = random_integrand(rng, FD_SLOTS, P=10)
    L, E = 5, 3
    table = rng.normal(size=(4, w.S, L)) * (rng.random(size=(4, w.S, L)) < 0.6)  # sparse and dense rows
    which, element = rng.integers(0, 4, size=10), rng.integers(0, E, size=10)
    iu = np.triu_indices(3 * L)
    out = np.zeros((E, iu[0].size))
    w.add_element_hessians(v, "newton", table, which, element, out)
    H = w.hessian(v)  # (P, S, 3, S, 3)
    ref = np.zeros((E, 3, L, 3, L))
    for p in range(10):
        B = table[which[p]]
        ref[element[p]] += np.einsum("sl,satb,tm->albm", B, H[p], B)
    np.testing.assert_allclose(out, ref.reshape(E, 3 * L, 3 * L)[:, iu[0], iu[1]], rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("kind", ["newton", "gauss-newton", "definite"])
@pytest.mark.parametrize("slots", [FD_SLOTS, FE_SLOTS], ids=["fd", "fe"])
def test_the_block_kernels_of_eq13_are_the_general_ones(slots, kind, rng):
    """Eq. (13)'s point Hessian written block by block (deformable.physics.pointhessian) is the general kernels' (a
    dense Jacobian and a residual Hessian 2 c), to round-off, and its fused projection onto elements (sparse and
    dense rows, every slot block) is the general projection of the general point Hessians."""
    w, v = random_integrand(rng, slots, P=12)
    args = w._kernel_args(v, kind, slice(None))
    general = kernels.point_hessians(*args)
    np.testing.assert_allclose(pointhessian.point_hessians(*args), general, rtol=0,
                               atol=1e-13 * np.max(np.abs(general)))
    L, E = 6, 4
    table = rng.normal(size=(5, w.S, L)) * (rng.random(size=(5, w.S, L)) < 0.6)
    which, element = rng.integers(0, 5, size=12), rng.integers(0, E, size=12)
    ref, out = np.zeros((2, E, 3 * L * (3 * L + 1) // 2))
    kernels.element_upper(general, table, which, element, ref)
    pointhessian.element_hessians(*args, table, which, element, out)
    np.testing.assert_allclose(out, ref, rtol=0, atol=1e-13 * np.max(np.abs(ref)))


def test_an_unknown_hessian_kind_is_refused(rng):
    w, v = random_integrand(rng, FD_SLOTS, P=2)
    with pytest.raises(InputError, match="hessian kind"):
        w.hessian(v, "exact")


@pytest.mark.parametrize("m", [(3.0, 1.0, 2.0), (-3.0, 1.0, 2.0), (-3.0, 0.5, -1.0), (1.0, 2.0, 1.0)])
def test_positive_part_of_a_2x2_matrix(m):
    a, b, d = m
    lam, U = np.linalg.eigh(np.array([[a, b], [b, d]]))
    ref = (U * np.maximum(lam, 0)) @ U.T
    got = kernels.positive_part_2x2(a, b, d)
    np.testing.assert_allclose(got, (ref[0, 0], ref[0, 1], ref[1, 1]), atol=1e-12)


@pytest.mark.parametrize("backend", ["fd", "fe"])
@pytest.mark.parametrize("kind", ["newton", "definite"])
def test_hessian_blocks_on_threads_give_the_serial_matrix_bit_for_bit(backend, kind, monkeypatch):
    """The Hessian's blocks run on threads (deformable.physics.integrand.for_blocks); each block writes rows of its own,
    so the matrix is the serial one exactly, on both backends."""
    from deformable import scenes
    from validation.harness.backends import make_model

    nodes = 20 if backend == "fd" else 9  # small grids, cut into small blocks below so that there are several
    model = make_model(scenes.curtain(nodes=(nodes, nodes)), backend)
    X = model.initial_state()
    X = X + 1e-2 * np.sin(np.arange(X.size).reshape(X.shape))
    monkeypatch.setattr("deformable.physics.integrand._BLOCK", 64)
    monkeypatch.setattr("femodel.energy._BLOCK", 4)
    monkeypatch.setenv("OMP_NUM_THREADS", "1")
    serial = model.energy_hessian(X, kind)
    monkeypatch.setenv("OMP_NUM_THREADS", "3")
    threaded = model.energy_hessian(X, kind)
    assert np.array_equal(serial.indptr, threaded.indptr) and np.array_equal(serial.indices, threaded.indices)
    assert np.array_equal(serial.data, threaded.data)


def test_hessian_threads_follow_omp_num_threads(monkeypatch):
    """One thread where OMP_NUM_THREADS=1 (Dask's workers, the validation runner's), else the cores (at most 4)."""
    from deformable.physics.integrand import hessian_threads

    monkeypatch.setenv("OMP_NUM_THREADS", "1")
    assert hessian_threads() == 1
    monkeypatch.delenv("OMP_NUM_THREADS")
    assert 1 <= hessian_threads() <= 4


def test_a_forked_child_assembles_hessians_on_threads_of_its_own():
    """The parent's Hessian threads do not exist in a forked child (multiprocessing's fork, the bench's rows): the
    child makes its own pool instead of waiting forever on the parent's."""
    import multiprocessing as mp

    from deformable import scenes
    from validation.harness.backends import make_model

    model = make_model(scenes.curtain(nodes=(24, 24)), "fd")
    X = model.initial_state()
    expected = model.energy_hessian(X)  # the pool now exists in this process
    _FORKED["case"] = (model, X)  # inherited by the child (a scene's closures do not pickle)
    try:
        with mp.get_context("fork").Pool(1) as pool:
            data = pool.apply_async(_hessian_data).get(timeout=120)
    finally:
        _FORKED.clear()
    assert np.array_equal(data, expected.data)


_FORKED: dict = {}


def _hessian_data():
    model, X = _FORKED["case"]
    return model.energy_hessian(X).data
