"""The compatibility test of eq. (10): exact fields pass and converge, an incompatible rest state is flagged."""

import warnings

import numpy as np
import pytest

import deformable as dm
from deformable.geometry.compatibility import (
    IncompatibleRestState,
    brioschi,
    check_compatibility,
    check_rest_state,
    warn_if_incompatible,
)
from validation.harness import surfaces as sf
from validation.harness.orders import fit_order


def exact_fields(name, n):
    s = sf.get(name)
    a = np.linspace(0, 1, n)
    a1, a2 = np.meshgrid(a, a, indexing="ij")
    return s.G(a1, a2), s.B(a1, a2), 1 / (n - 1), s.gaussian_curvature(a1, a2)


@pytest.mark.parametrize("name", ["monge", "sphere", "torus"])
def test_brioschi_converges_to_det_B_over_det_G_at_second_order(name):
    hs, errs = [], []
    for n in (17, 33, 65):
        G, B, h, K = exact_fields(name, n)
        errs.append(np.max(np.abs(brioschi(G, (h, h)) - K)[2:-2, 2:-2]))
        hs.append(h)
    p = fit_order(hs, errs)
    assert 1.7 <= p <= 2.3, f"{name}: Brioschi residual order {p:.2f}, theory 2"


def test_exact_generic_fields_are_compatible_and_residuals_converge():
    hs, gauss, codazzi = [], [], []
    for n in (17, 33, 65):
        G, B, h, _ = exact_fields("monge", n)
        c = check_compatibility(G, B, h)
        hs.append(h)
        gauss.append(c.gauss)
        codazzi.append(max(c.codazzi))
    assert c.compatible, c.summary()
    for label, e in (("Gauss", gauss), ("Codazzi", codazzi)):
        p = fit_order(hs, e)
        assert 1.7 <= p <= 2.3, f"{label} residual order {p:.2f}, theory 2"
    for comparison in c.comparisons.values():
        assert comparison.resolved > 0.5 * comparison.points and comparison.passed
        assert abs(comparison.ratio[0] - 1) < 0.01 and comparison.cosine[0] > 0.99


def test_incompatible_rest_state_is_flagged_with_gauss_residual_a_quarter():
    with pytest.warns(IncompatibleRestState):  # when the scene is made
        scene = dm.Scene(dm.Sheet(), dm.Material(eta=1.0, xi=1.0), rest_metric=1.0, rest_curvature=0.5)
    c = check_rest_state(scene)
    assert not c.compatible
    assert abs(c.gauss - 0.25) < 1e-14
    assert c.codazzi == (0.0, 0.0)
    # (r_11)_2 = -0.25 r_2 against (r_12)_1 = 0: no ratio, no angle; the guarded residual fails the test
    first = c.comparisons["(r_11)_2 vs (r_12)_1"]
    assert first.resolved == 0 and first.ratio is None and first.residual > 0.5 and not first.passed
    assert "nan" not in c.summary() and "inf" not in c.summary()
    with pytest.warns(IncompatibleRestState, match="not the metric and curvature of any surface"):
        warn_if_incompatible(scene)


def test_compatible_rest_shape_does_not_warn():
    scene = dm.Scene(dm.Sheet(rest=sf.get("torus")), dm.Material(eta=1.0, xi=1.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert warn_if_incompatible(scene).compatible


@pytest.mark.parametrize("name", ["plane", "cylinder"])
def test_plane_and_cylinder_are_guarded_and_tested_by_their_residual(name):
    G, B, h, _ = exact_fields(name, 17)
    c = check_compatibility(G, B, h)
    assert c.compatible and c.guarded == 1.0, c.summary()
    for comparison in c.comparisons.values():
        assert comparison.ratio is None and comparison.cosine is None and comparison.resolved == 0
        assert 0 <= comparison.residual <= 0.05
    assert "nan" not in c.summary() and "inf" not in c.summary()


def test_bad_fields_are_clear_errors():
    G, B, h, _ = exact_fields("monge", 9)
    with pytest.raises(ValueError, match=r"\(2, 2, M, N\)"):
        check_compatibility(G[:, :, :3], B[:, :, :3], h)
    with pytest.raises(ValueError, match="positive definite"):
        check_compatibility(-G, B, h)
