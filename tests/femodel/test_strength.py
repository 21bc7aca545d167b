r"""The FE strength matrix (femodel.strength): the weak forms of eq. (14) and the consistent mass.

On the bicubic space the forms integrate polynomials exactly (the 4 x 4 Gauss rule is exact to degree 7
per direction), so u^T K u is a closed-form integral for u in the space.
"""

import time

import numpy as np
import pytest

import deformable as dm
from validation.harness.backends import make_model

from ..conftest import Polynomial, vertical_hanging

L1, L2 = 1.2, 0.9


def quadratic_form(alpha=None, beta=None, mu=1.0, **coefficients):
    """u^T K u (frozen alpha, beta) and u^T M u for the scalar field u = sum c_pq a1^p a2^q (x component)."""
    model = make_model(dm.Scene(dm.Sheet(size=(L1, L2), nodes=(4, 5)),
                                dm.Material(mu=mu, alpha=0.0 if alpha is None else alpha,
                                            beta=0.0 if beta is None else beta), force_model="frozen"), "fe")
    c = np.zeros((4, 4, 3))
    for key, value in coefficients.items():
        c[int(key[1]), int(key[2]), 0] = value
    u = model.discretize(Polynomial(c))[:, 0]
    return u @ model.stiffness(model.initial_state()) @ u, u @ model.mass() @ u


def test_membrane_form_integrates_alpha_ij_u_i_u_j():
    # u = a1^2 under alpha_11: integral (2 a1)^2 = 4 L1^3 / 3 L2
    assert quadratic_form(alpha=np.diag([1.0, 0.0]), c20=1.0)[0] == pytest.approx(4 * L1**3 / 3 * L2, rel=1e-13)
    # u = a1 a2 under alpha_12 = alpha_21 = 1: integral 2 u_1 u_2 = 2 (L1^2 / 2)(L2^2 / 2)
    assert quadratic_form(alpha=np.array([[0.0, 1.0], [1.0, 0.0]]), c11=1.0)[0] == pytest.approx(
        L1**2 * L2**2 / 2, rel=1e-13)


def test_bending_form_integrates_beta_ij_u_ij_u_ij():
    # u = a1^3 under beta_11: integral (6 a1)^2 = 12 L1^3 L2
    assert quadratic_form(beta=np.diag([1.0, 0.0]), c30=1.0)[0] == pytest.approx(12 * L1**3 * L2, rel=1e-13)
    # u = a1^2 a2^2 under beta_12 = beta_21 = 1: integral 2 (4 a1 a2)^2 = 32 (L1^3 / 3)(L2^3 / 3)
    assert quadratic_form(beta=np.array([[0.0, 1.0], [1.0, 0.0]]), c22=1.0)[0] == pytest.approx(
        32 * L1**3 * L2**3 / 9, rel=1e-12)


def test_consistent_mass_integrates_mu_u_squared():
    # u = a1 a2^3, mu = 2: integral 2 a1^2 a2^6 = 2 (L1^3 / 3)(L2^7 / 7)
    assert quadratic_form(mu=2.0, c13=1.0)[1] == pytest.approx(2 * L1**3 / 3 * L2**7 / 7, rel=1e-13)


@pytest.mark.slow
def test_assembly_is_a_small_part_of_the_step_at_64x64():
    model = make_model(vertical_hanging(65), "fe")
    stepper = dm.TimeStepper(model, dt=2e-5)
    state = stepper.step(stepper.start(model.initial_state()))  # builds the reduced system
    for k in stepper.timings:
        stepper.timings[k] = 0.0
    t0 = time.perf_counter()
    for _ in range(5):
        state = stepper.step(state)
    t = stepper.timings
    fraction = t["assembly"] / sum(t.values())
    split = ", ".join(f"{k} {v / 5 * 1e3:.1f} ms" for k, v in t.items())
    assert fraction <= 0.2, f"assembly fraction {fraction:.3f} of the step ({split}; {time.perf_counter() - t0:.2f} s)"
