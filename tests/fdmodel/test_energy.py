"""The FD discrete energy (13) and its derivatives (fdmodel.energy) under the control-area weighting.

The pointwise weighting's derivatives are checked with the contract (tests/deformable/backends/test_contract.py).
"""

import pytest

import deformable as dm
from deformable.geometry.surfaces import Plane
from validation.harness.backends import make_model
from validation.harness.surfaces import get

from ..conftest import FULL_ETA, FULL_XI, flat_model, gradient_error, hessian_error


@pytest.fixture
def control_area():
    sheet = dm.Sheet(size=(1.0, 0.8), nodes=(7, 6), rest=get("monge"))
    return make_model(dm.Scene(sheet, dm.Material(eta=FULL_ETA, xi=FULL_XI), force_model="variational"), "fd",
                      weighting="control-area")


def test_gradient_matches_finite_differences_of_the_energy(control_area, rng):
    model = control_area
    err = gradient_error(model, model.initial_state() + 0.05 * rng.normal(size=(model.ndof, 3)))
    assert err < 1e-6, f"relative gradient error {err:.2e}"


def test_exact_hessian_matches_finite_differences_of_the_gradient(control_area, rng):
    model = control_area
    H, err = hessian_error(model, model.initial_state() + 0.05 * rng.normal(size=(model.ndof, 3)))
    assert err < 1e-6, f"relative Hessian error {err:.2e}"
    assert abs(H - H.T).max() < 1e-12 * abs(H).max()


@pytest.mark.parametrize("weighting", ["pointwise", "control-area"])
def test_energy_of_a_uniformly_stretched_sheet(weighting):
    """r = (s a1, a2, 0), rest flat: G11 = s^2 wherever D1+ is defined, so eq. (13) sums eta (s^2 - 1)^2
    over the rows of D1+: L1 L2 with the trapezoidal weights, L1 (L2 + h2) with the pointwise ones."""
    s, eta, L1, L2 = 1.2, 3.0, 1.0, 1.3
    model = flat_model("fd", nodes=(5, 6), size=(L1, L2), weighting=weighting,
                       material=dm.Material(eta=eta, xi=1.0), sheet=dm.Sheet(size=(L1, L2), nodes=(5, 6),
                                                                             initial=Plane(e1=(s, 0.0, 0.0))))
    area = L1 * L2 if weighting == "control-area" else L1 * (L2 + model.spacing[1])
    e = model.energy(model.initial_state())
    assert abs(e.stretching - eta * (s**2 - 1) ** 2 * area) < 1e-12 and e.bending == 0
