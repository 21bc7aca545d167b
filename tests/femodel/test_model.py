r"""FEModel (femodel.model): what only the finite-element backend promises, and its analytic benchmarks.

The contract both backends share is tests/deformable/backends/test_contract.py. Benchmarks of the linearised model:

- Prestressed membrane (tpbf87, flat sheet, G0 = 0.81 I, so alpha = eta (1 - 0.81) I, beta = 0): the
  transverse operator is -alpha (w_11 + w_22), so with pinned edges the (1, 1) mode has
  w = pi sqrt(alpha/mu) sqrt(1/L1^2 + 1/L2^2). Bicubic Hermite eigenvalues converge at
  O(h^(2(p+1-m))) = O(h^6) (p = 3, m = 1): on 16 x 16 elements far inside the required 1e-4.
- Frozen-beta plate, alpha = 0, beta_11 = beta_22 = beta, beta_12 = 0, under a uniform load q, values
  pinned on all edges (simply supported): the strong form beta (w_1111 + w_2222) = q with the natural
  conditions w_nn = 0; Navier's double sine series gives the centre deflection. Theory for the FE error:
  energy norm O(h^(p+1-m)) = O(h^2); by duality (Aubin-Nitsche) lower-order quantities gain another
  O(h^2), so the centre deflection (a node) converges at O(h^4). Window [3.5, 4.5].
- The variational model's transverse linearisation about a flat sheet: membrane constant 4 eta (1 - g0),
  bending constant 2 xi (docs/design.md, "Three readings of the model").
"""

import numpy as np
import pytest
import scipy.sparse.linalg as spla

import deformable as dm
from deformable.geometry.surfaces import Plane
from femodel import ELEMENTS, FEModel
from validation.harness.orders import fit_order
from validation.studies.statics import navier_centre

from ..conftest import ALL_EDGES, Polynomial, flat_model, free_dofs


def test_the_mesh_is_the_sheets_grid_with_four_dofs_a_node():
    model = flat_model("fe", nodes=(5, 4))
    assert model.ndof == 4 * 5 * 4 and model.mesh.t.shape[1] == 4 * 3  # (M - 1)(N - 1) skfem elements
    np.testing.assert_array_equal(model.value_dofs, 4 * np.arange(20))
    a1, a2 = model.points
    assert a1.shape == (12, 16)  # 4 x 4 Gauss points per element


def test_mass_and_damping_share_the_stiffness_pattern():
    model = flat_model("fe", nodes=(5, 4), material=dm.Material(mu=1.0, gamma=0.3, eta=1.0))
    K = model.stiffness(model.initial_state())
    for A in (model.mass(), model.damping()):
        assert A.indptr is K.indptr and A.indices is K.indices


# -- constraints act on degrees of freedom ----------------------------------------------------
def dofs(mask, k):
    """Set of the k-th degrees of freedom (0 value, 1 h1 r_1, 2 h2 r_2, 3 h1 h2 r_12) of masked nodes."""
    return set((4 * np.flatnonzero(mask) + k).tolist())


def masks(**rows):
    out = {}
    for name, index in rows.items():
        m = np.zeros((5, 4), bool)
        m[index] = True
        out[name] = m
    return out


def test_pinned_edges_fix_values_and_tangential_derivatives():
    model = flat_model("fe", nodes=(5, 4), constraints=[dm.Pin(["left", "bottom"])])
    m = masks(left=(0, slice(None)), bottom=(slice(None), 0))
    expected = dofs(m["left"] | m["bottom"], 0) | dofs(m["left"], 2) | dofs(m["bottom"], 1)
    for f in model.fixed_dofs():
        assert set(f.tolist()) == expected  # r_12 stays free, also at the corner


def test_pins_by_predicate_or_corner_fix_values_only():
    model = flat_model("fe", nodes=(5, 4), constraints=[dm.Pin(lambda a1, a2: a2 > 0.99), dm.Pin("bottom-left")])
    mask = np.zeros((5, 4), bool)
    mask[:, -1] = mask[0, 0] = True
    for f in model.fixed_dofs():
        assert set(f.tolist()) == dofs(mask, 0)


def test_slide_and_clamp():
    """A clamp of the flat sheet's left edge holds r and r_2 in every coordinate, r_1 and r_12 in z (the
    clamp's normal) only: the in-plane stretch across the edge stays free."""
    model = flat_model("fe", nodes=(5, 4), constraints=[dm.Slide("top", "x"), dm.Clamp("left")])
    m = masks(top=(slice(None), -1), left=(0, slice(None)))
    position = dofs(m["left"], 0) | dofs(m["left"], 2)
    slope = dofs(m["left"], 1) | dofs(m["left"], 3)
    fx, fy, fz = (set(f.tolist()) for f in model.fixed_dofs())
    assert fx == position
    assert fy == position | dofs(m["top"], 0) | dofs(m["top"], 1)
    assert fz == position | slope | dofs(m["top"], 0) | dofs(m["top"], 1)


def test_a_clamp_whose_normal_is_no_coordinate_axis_holds_the_whole_slope(caplog):
    tilted = Plane(e1=(0.6, 0.0, 0.8), e2=(0.0, 1.0, 0.0))
    model = FEModel(dm.Scene(dm.Sheet(nodes=(5, 4), rest=tilted), dm.Material(), constraints=[dm.Clamp("left")]))
    left = masks(left=(0, slice(None)))["left"]
    clamp = set().union(*(dofs(left, k) for k in range(4)))
    assert all(set(f.tolist()) == clamp for f in model.fixed_dofs())
    assert "not a coordinate axis" in caplog.text


# -- bad input ----------------------------------------------------------------------------------
def test_unknown_element_names_the_valid_ones():
    with pytest.raises(ValueError, match="element.*hermite.*'bfs'"):
        FEModel(dm.Scene(dm.Sheet(nodes=(4, 4)), dm.Material()), element="bfs")
    assert ELEMENTS == ("hermite",)


def test_bad_input_names_field_and_value():
    model = flat_model("fe", nodes=(4, 4))
    with pytest.raises(ValueError, match=r"X has shape \(16, 3\), expected \(64, 3\)"):
        model.stiffness(np.zeros((16, 3)))
    with pytest.raises(ValueError, match=r"V has shape"):
        model.kinetic_energy(np.zeros(64))
    with pytest.raises(ValueError, match=r"Material.mu"):
        flat_model("fe", nodes=(4, 4), material=dm.Material(mu=np.ones((3, 4))))


# -- the energy by the Gauss rule -------------------------------------------------------------
def test_tpbf87_energy_of_a_stretched_sheet_is_exact():
    """r = (s a1, a2, 0), rest flat: G11 = s^2, so eq. (13) gives eta (s^2 - 1)^2 L1 L2."""
    s, eta = 1.2, 3.0
    sheet = dm.Sheet(size=(1.0, 1.3), nodes=(5, 6), initial=lambda a1, a2: np.stack(
        np.broadcast_arrays(s * a1, a2, 0 * a1), -1))
    model = flat_model("fe", sheet=sheet, material=dm.Material(eta=eta, xi=1.0))
    e = model.energy(model.initial_state())
    assert abs(e.stretching - eta * (s**2 - 1) ** 2 * 1.3) < 1e-12 and e.bending == 0


def test_tpbf87_bending_energy_of_a_cylinder_converges():
    """A flat sheet rolled to radius R: B11 = 1/R, energy xi L1 L2 / R^2 (+ O(h^2) from B)."""
    R, xi = 0.8, 2.0
    cyl = lambda a1, a2: np.stack(np.broadcast_arrays(  # noqa: E731
        R * np.sin(a1 / R), a2, R * (1 - np.cos(a1 / R))), -1)
    errs = []
    for n in (8, 16):
        sheet = dm.Sheet(size=(1.0, 1.3), nodes=(n + 1, n + 1), initial=cyl)
        model = flat_model("fe", sheet=sheet, material=dm.Material(eta=1.0, xi=xi))
        e = model.energy(model.initial_state())
        errs.append(abs(e.bending / (xi * 1.3 / R**2) - 1))
        assert e.stretching < 1e-8
    assert errs[1] < 2e-4 and errs[1] < errs[0] / 3, errs


def test_frozen_energy_is_half_RKR_split():
    """Frozen alpha = a I, beta = b I on r = (a1, a2, a1^2 a2) over the unit square:
    stretching a/2 (2 + 29/45), bending b/2 (4/3)."""
    a, b = 3.0, 0.7
    c = np.zeros((4, 4, 3))
    c[1, 0, 0] = c[0, 1, 1] = c[2, 1, 2] = 1.0
    model = flat_model("fe", sheet=dm.Sheet(size=(1.0, 1.0), nodes=(5, 5), initial=Polynomial(c)),
                       material=dm.Material(alpha=a, beta=b), force_model="frozen")
    e = model.energy(model.initial_state())
    assert abs(e.stretching - a / 2 * (2 + 29 / 45)) < 1e-12 and abs(e.bending - b / 2 * 4 / 3) < 1e-12


# -- benchmarks of the linearised model -----------------------------------------------------
def lowest_eigenvalue(model, K):
    """Lowest eigenvalue of K against the mass on the free z degrees of freedom."""
    free = free_dofs(model)
    Kf, Mf = K.tocsr()[free][:, free], model.mass()[free][:, free]
    return float(spla.eigsh(Kf.tocsc(), k=1, M=Mf.tocsc(), sigma=0.0, which="LM", return_eigenvectors=False).min())


def test_prestressed_membrane_frequency():
    L1, L2, eta, mu = 1.0, 1.3, 10.0, 0.7
    model = flat_model("fe", nodes=(17, 17), size=(L1, L2), material=dm.Material(mu=mu, gamma=0.0, eta=eta),
                       constraints=[dm.Pin(ALL_EDGES)], rest_metric=0.81)
    w = np.sqrt(lowest_eigenvalue(model, model.stiffness(model.initial_state())))
    exact = np.pi * np.sqrt(eta * (1 - 0.81) / mu) * np.sqrt(1 / L1**2 + 1 / L2**2)
    rel = abs(w / exact - 1)
    assert rel < 1e-4, f"(1,1) frequency {w:.10f} vs {exact:.10f}: relative error {rel:.2e}"


@pytest.mark.parametrize("eta, xi, g0", [(3.0, 0.02, 0.81), (0.0, 0.05, 1.0), (3.0, 0.0, 0.81)],
                         ids=["both", "bending", "membrane"])
def test_variational_transverse_linearisation_about_a_flat_sheet(eta, xi, g0):
    """Membrane constant 4 eta (1 - g0), bending constant 2 xi: the (1, 1) eigenvalue of the z-block of
    the Hessian against the consistent mass on 16 x 16 elements. FE eigenvalue error: O(h^6) for the
    membrane part, O(h^4) for the bending part (2 (p + 1 - m), p = 3, m = 2), so about 3e-7 here."""
    L1, L2, mu = 1.0, 1.3, 1.7
    model = flat_model("fe", nodes=(17, 17), size=(L1, L2), material=dm.Material(mu=mu, gamma=0.0, eta=eta, xi=xi),
                       constraints=[dm.Pin(ALL_EDGES)], force_model="variational", rest_metric=g0)
    n = model.ndof
    lam = lowest_eigenvalue(model, model.energy_hessian(model.initial_state())[2 * n:, 2 * n:])
    exact = (4 * eta * (1 - g0) * np.pi**2 * (1 / L1**2 + 1 / L2**2)
             + 2 * xi * np.pi**4 * (1 / L1**4 + 1 / L2**4)) / mu
    rel = abs(lam / exact - 1)
    assert rel < 1e-5, f"lowest eigenvalue {lam:.10g} vs {exact:.10g}: relative error {rel:.2e}"


def test_navier_series_is_converged():
    a, b = navier_centre(0.5, 2.0, 1.0, 1.3, 800), navier_centre(0.5, 2.0, 1.0, 1.3, 1600)
    assert abs(a - b) < 1e-15


def test_frozen_beta_plate_centre_deflection():
    L1, L2, q, beta = 1.0, 1.3, 2.0, 0.5
    exact = navier_centre(beta, q, L1, L2)
    levels, errors = (4, 8, 16, 32), []
    for n in levels:
        model = flat_model("fe", nodes=(n + 1, n + 1), size=(L1, L2), force_model="frozen",
                           material=dm.Material(mu=1.0, alpha=0.0, beta=beta), forces=[dm.BodyForce((0, 0, q))],
                           constraints=[dm.Pin(ALL_EDGES)])
        X = model.initial_state()
        free = free_dofs(model)
        X[free, 2] = spla.spsolve(model.stiffness(X).tocsc()[free][:, free], model.load(X, 0.0)[free, 2])
        errors.append(abs(model.sample(X, np.array([[L1 / 2, L2 / 2]])).r[0, 2] - exact))
    p = fit_order([1 / n for n in levels], errors)
    table = ", ".join(f"{n}: {e:.2e}" for n, e in zip(levels, errors))
    assert 3.5 <= p <= 4.5, f"observed order p = {p:.3f} outside [3.5, 4.5]; errors {table}"
    assert errors[-1] < 2e-8, f"centre error {errors[-1]:.2e} at 32 x 32 (exact {exact:.6f})"

