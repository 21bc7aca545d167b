"""The pure tensor functions (deformable.geometry.tensors); G and B on whole models are in test_backend and the surfaces."""

import numpy as np

from deformable.geometry import tensors


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
