"""The analytic surfaces: closed-form derivatives against finite differences, and Gauss's theorem."""

import numpy as np
import pytest

from validation.harness import surfaces as sf

NAMES = list(sf.SURFACES)


def grid(s, n=7):
    a = np.linspace(0.1, 0.9, n)
    return np.meshgrid(a * s.size[0], a * s.size[1], indexing="ij")


@pytest.mark.parametrize("name", NAMES)
def test_derivatives_match_central_differences_of_r(name):
    s = sf.get(name)
    a1, a2 = grid(s)
    e = 1e-4  # central differences: error ~ e^2 |r'''| ~ 1e-7 for these O(10)-derivative surfaces
    d1 = lambda f: (f(a1 + e, a2) - f(a1 - e, a2)) / (2 * e)  # noqa: E731
    d2 = lambda f: (f(a1, a2 + e) - f(a1, a2 - e)) / (2 * e)  # noqa: E731
    for exact, approx in ((s.r1, d1(s.r)), (s.r2, d2(s.r)), (s.r11, d1(s.r1)), (s.r12, d2(s.r1)),
                          (s.r12, d1(s.r2)), (s.r22, d2(s.r2))):
        err = np.max(np.abs(exact(a1, a2) - approx))
        assert err < 1e-6, f"{name}: derivative mismatch {err:.2e}"


@pytest.mark.parametrize("name", NAMES)
def test_gauss_theorem_det_B_over_det_G_equals_K_exact(name):
    s = sf.get(name)
    if s.K_exact is None:
        pytest.skip(f"{name} has no closed-form K")
    a1, a2 = grid(s)
    K = s.gaussian_curvature(a1, a2)
    err = np.max(np.abs(K - s.K_exact(a1, a2)))
    assert err < 1e-12 * (1 + np.max(np.abs(K))), f"{name}: |det B/det G - K| = {err:.2e}"


@pytest.mark.parametrize("name", [n for n in NAMES if sf.get(n).G_exact is not None])
def test_textbook_G_and_B_match_the_derivatives(name):
    s = sf.get(name)
    a1, a2 = grid(s)
    G = np.moveaxis(s.G_exact(a1, a2), (-2, -1), (0, 1))
    B = np.moveaxis(s.B_exact(a1, a2), (-2, -1), (0, 1))
    assert np.max(np.abs(G - s.G(a1, a2))) < 1e-13
    assert np.max(np.abs(B - s.B(a1, a2))) < 1e-13


def test_skew_is_not_orthogonal():
    s = sf.get("skew")
    a1, a2 = grid(s)
    assert np.min(np.abs(s.G(a1, a2)[0, 1])) > 0.1


def test_unknown_surface_is_a_clear_error():
    with pytest.raises(ValueError, match="unknown surface 'nope'; known: plane"):
        sf.get("nope")
