"""The pure tensor functions (deformable.tensors); G and B on whole models are in test_backend and the surfaces."""

import numpy as np

from deformable import tensors


def test_skew_is_the_cross_product(rng):
    a, b = rng.normal(size=(2, 7, 3))
    np.testing.assert_allclose((tensors.skew(a) @ b[..., None])[..., 0], np.cross(a, b), rtol=0, atol=1e-15)


def test_frame_gives_the_unit_normal_and_the_area_element(rng):
    dr = rng.normal(size=(3, 2, 5))
    n, area = tensors.frame(dr[:, 0], dr[:, 1], axis=0)
    np.testing.assert_allclose(np.linalg.norm(n, axis=0), 1.0, rtol=1e-15)
    np.testing.assert_allclose(area**2, tensors.det2(tensors.metric(dr)), rtol=1e-13)
    np.testing.assert_allclose(tensors.dot(n, dr[:, 0], axis=0), 0.0, atol=1e-15)
    np.testing.assert_array_equal(tensors.normal(dr), n)


def test_gaussian_curvature_is_det_B_over_det_G():
    G = np.array([[4.0, 0.0], [0.0, 1.0]])[..., None]
    B = np.array([[2.0, 1.0], [1.0, 3.0]])[..., None]
    np.testing.assert_allclose(tensors.gaussian_curvature(G, B), [5.0 / 4.0])


def test_normal_hessian_matches_finite_differences(rng):
    """Htt and Q of f = V . n(t1, t2): second derivatives in (t1, t2) and mixed ones in (V, (t1, t2))."""
    t1, t2, V = rng.normal(size=(3, 3))

    def f(x):
        n, _ = tensors.frame(x[0:3], x[3:6])
        return tensors.dot(x[6:9], n)

    x0 = np.concatenate([t1, t2, V])
    e = 1e-4
    H = np.zeros((9, 9))
    for i in range(9):
        for j in range(9):
            d = np.zeros((4, 9))
            d[:, i] += e * np.array([1, 1, -1, -1])
            d[:, j] += e * np.array([1, -1, 1, -1])
            H[i, j] = (f(x0 + d[0]) - f(x0 + d[1]) - f(x0 + d[2]) + f(x0 + d[3])) / (4 * e * e)
    Htt, Q = tensors.normal_hessian(t1, t2, V)
    assert np.max(np.abs(Htt - H[:6, :6])) < 1e-6 * np.max(np.abs(H))
    assert np.max(np.abs(Q - H[6:, :6])) < 1e-6 * np.max(np.abs(H))
    assert np.max(np.abs(H[6:, 6:])) < 1e-6 * np.max(np.abs(H))  # f is linear in V
