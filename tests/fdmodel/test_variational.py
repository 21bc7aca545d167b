"""The variational force model: exact gradient and Hessian of the discrete energy (13),
its linearisation about a flat sheet, the implicit schemes and static equilibrium."""

import contextlib
from dataclasses import dataclass

import numpy as np
import pytest
import scipy.linalg as sla

import deformable as dm
from deformable.implicit import ConvergenceError, equilibrium
from fdmodel import FDModel
from validation.orders import fit_order
from validation.surfaces import get

from .conftest import flat_model
from .test_dynamics import lam

FULL_ETA = np.array([[5.0, 1.0], [1.0, 3.0]])
FULL_XI = np.array([[0.5, 0.2], [0.2, 0.1]])


def curved_model(weighting):
    sheet = dm.Sheet(size=(1.0, 0.8), nodes=(7, 6), rest=get("monge"))
    return FDModel(dm.Scene(sheet, dm.Material(eta=FULL_ETA, xi=FULL_XI), force_model="variational"),
                   weighting=weighting)


def central(f, X, eps=1e-6):
    """Central differences of f over every entry of X, stacked as columns (coordinate-blocked)."""
    n = X.shape[0]
    cols = []
    for a in range(3):
        for k in range(n):
            Xp, Xm = X.copy(), X.copy()
            Xp[k, a] += eps
            Xm[k, a] -= eps
            cols.append((f(Xp) - f(Xm)) / (2 * eps))
    return np.array(cols).T


@pytest.mark.parametrize("weighting", ["pointwise", "control-area"])
def test_gradient_matches_finite_differences_of_the_energy(weighting, rng):
    model = curved_model(weighting)
    X = model.initial_state() + 0.05 * rng.normal(size=(model.ndof, 3))
    g = model.energy_gradient(X).T.ravel()
    numeric = central(lambda Y: model.energy(Y).total, X).ravel()
    err = np.max(np.abs(g - numeric)) / np.max(np.abs(g))
    assert err < 1e-6, f"relative gradient error {err:.2e}"


def test_exact_hessian_matches_finite_differences_of_the_gradient(rng):
    model = curved_model("control-area")
    X = model.initial_state() + 0.05 * rng.normal(size=(model.ndof, 3))
    H = model.energy_hessian(X, "newton").toarray()
    numeric = central(lambda Y: model.energy_gradient(Y).T.ravel(), X)
    err = np.max(np.abs(H - numeric)) / np.max(np.abs(numeric))
    assert err < 1e-6, f"relative Hessian error {err:.2e}"
    assert np.max(np.abs(H - H.T)) < 1e-12 * np.max(np.abs(H))


def test_gauss_newton_hessian_is_psd_and_exact_where_residuals_vanish(rng):
    model = curved_model("pointwise")
    X = model.initial_state() + 0.05 * rng.normal(size=(model.ndof, 3))
    GN = model.energy_hessian(X, "gauss-newton").toarray()
    assert np.min(np.linalg.eigvalsh(GN)) > -1e-10 * np.max(np.abs(GN))
    rest = model.initial_state()  # rest state: all residuals zero, so the exact Hessian is Gauss-Newton
    diff = model.energy_hessian(rest, "newton") - model.energy_hessian(rest, "gauss-newton")
    assert abs(diff).max() < 1e-12 * abs(model.energy_hessian(rest, "newton")).max()


@dataclass(frozen=True)
class LinearCase:
    """Transverse operator about a flat sheet (DESIGN.md table): e_z = -a (w11 + w22) + b (w1111 + w2222)."""

    force_model: str
    g0: float
    b0: float
    a: float
    b: float


ETA, XI = 3.0, 0.02
LINEAR_CASES = [
    LinearCase("tpbf87", 0.81, 0.0, ETA * (1 - 0.81), 0.0),
    LinearCase("tpbf87", 0.81, -0.5, ETA * (1 - 0.81), -XI * -0.5),
    LinearCase("variational", 0.81, 0.0, 4 * ETA * (1 - 0.81), 2 * XI),
]


@pytest.mark.parametrize("case", LINEAR_CASES, ids=lambda c: f"{c.force_model}-b0={c.b0}")
def test_linear_transverse_operator_about_a_flat_sheet(case):
    """With all edges pinned the sine modes are exact eigenvectors: the eigenvalues of the z-block
    against M are (a (l1 + l2) + b (l1^2 + l2^2)) / mu, the DESIGN.md table's constants."""
    M, N, mu = 9, 8, 1.7
    # B0 = b0 I on a flat sheet is incompatible on purpose (the tpbf87 reading's bending stiffness)
    with pytest.warns(dm.IncompatibleRestState) if case.b0 else contextlib.nullcontext():
        model = flat_model(nodes=(M, N), force_model=case.force_model, material=dm.Material(mu=mu, eta=ETA, xi=XI),
                           rest_metric=case.g0, rest_curvature=case.b0,
                           constraints=[dm.Pin(["left", "right", "bottom", "top"])])
    X = model.initial_state()
    free = np.setdiff1d(np.arange(model.ndof), model.fixed_dofs()[2])
    if case.force_model == "variational":
        n = model.ndof
        Kz = model.energy_hessian(X).toarray()[2 * n:, 2 * n:] / model.measure
    else:
        Kz = model.stiffness(X).toarray()
    Kz = Kz[np.ix_(free, free)]
    computed = np.sort(sla.eigh(Kz, model.mass().toarray()[np.ix_(free, free)], eigvals_only=True))
    l1 = np.array([lam(j, M, 1.0) for j in range(1, M - 1)])[:, None]
    l2 = np.array([lam(k, N, 1.0) for k in range(1, N - 1)])[None, :]
    exact = np.sort((case.a * (l1 + l2) + case.b * (l1**2 + l2**2)).ravel() / mu)
    assert np.max(np.abs(computed - exact) / exact) < 1e-9


def bump_model(nodes=(9, 9)):
    model = flat_model(nodes=nodes, force_model="variational", material=dm.Material(mu=1.0, gamma=0.0, eta=20.0, xi=0.05),
                       constraints=[dm.Pin(["left", "right"])], rest_metric=0.9)
    X0 = model.initial_state()
    X0[:, 2] = 0.05 * (np.sin(np.pi * model.a1) * np.sin(np.pi * model.a2)).ravel()
    return model, X0


def total_energy(model, state):
    return model.energy(state.X).total + model.kinetic_energy(state.V)


def test_implicit_euler_never_lets_the_energy_grow():
    model, X0 = bump_model()
    stepper = dm.TimeStepper(model, dt=5e-3)
    assert stepper.scheme == "implicit-euler"
    energies = [total_energy(model, s) for s in stepper.iterate(X0, 60)]
    energies.insert(0, model.energy(X0).total)
    growth = np.max(np.diff(energies))
    assert growth <= 1e-10 * energies[0], f"energy grew by {growth:.3e}"
    assert energies[-1] < 0.999 * energies[0]  # and it does dissipate (first order scheme)
    reports = stepper.newton_reports
    assert len(reports) == 60 and all(r.converged for r in reports)


@pytest.mark.parametrize("scheme, order", [("implicit-euler", 1), ("newmark", 2)])
def test_temporal_order_of_the_implicit_schemes(scheme, order):
    """A linear (frozen) membrane mode at T = 0.6 s against a 16x finer reference of the same scheme."""
    model = flat_model(nodes=(7, 7), force_model="frozen", material=dm.Material(mu=1.0, alpha=2.0),
                       constraints=[dm.Pin(["left", "right", "bottom", "top"])])
    X0 = model.initial_state()
    X0[:, 2] = 0.1 * (np.sin(np.pi * model.a1) * np.sin(np.pi * model.a2)).ravel()
    T = 0.6

    def final(dt):
        return dm.TimeStepper(model, dt=dt, scheme=scheme).run(X0, t_end=T).state.X[:, 2]

    dts = [0.04, 0.02, 0.01]
    ref = final(dts[-1] / 16)
    errors = [np.max(np.abs(final(dt) - ref)) for dt in dts]
    p = fit_order(dts, errors)
    assert order - 0.25 <= p <= order + 0.35, f"{scheme}: observed order {p:.2f}, theory {order}"


@pytest.mark.parametrize("kappa", [2.0, -2.0])
def test_clamped_strip_curls_into_the_arc_of_its_rest_curvature(kappa):
    """B0_11 = kappa, full weight tensors (eta_12 = eta, xi_12 = xi: shear and twist cost energy, so the
    equilibrium is unique): the tip goes to (sin(theta)/kappa, (1 - cos(theta))/kappa), theta = kappa L;
    the two-row clamp makes the error O(h)."""
    L, W = 1.0, 0.2
    hs, errors = [], []
    for n in (11, 21, 41):
        sheet = dm.Sheet(size=(L, W), nodes=(n, 5))
        scene = dm.Scene(sheet, dm.Material(eta=np.full((2, 2), 100.0), xi=np.full((2, 2), 1.0)),
                         force_model="variational", rest_curvature=np.diag([kappa, 0.0]),
                         constraints=[dm.Clamp("left")])
        model = FDModel(scene, weighting="control-area")
        X, history = equilibrium(model, model.initial_state())
        theta = kappa * L
        exact = np.array([np.sin(theta) / kappa, W / 2, (1 - np.cos(theta)) / kappa])
        hs.append(L / (n - 1))
        errors.append(np.max(np.abs(model.grid(X)[-1, 2] - exact)))
        assert history[-1] < 1e-8
    p = fit_order(hs, errors)
    assert 0.8 <= p <= 1.3, f"tip error order {p:.2f}, theory 1"
    assert errors[-1] < 1.0 * hs[-1]


def test_equilibrium_says_when_it_does_not_converge():
    L, W = 1.0, 0.2
    scene = dm.Scene(dm.Sheet(size=(L, W), nodes=(11, 5)),
                     dm.Material(eta=np.full((2, 2), 100.0), xi=np.full((2, 2), 1.0)), force_model="variational",
                     rest_curvature=np.diag([3.0, 0.0]), constraints=[dm.Clamp("left")])
    model = FDModel(scene)
    with pytest.raises(ConvergenceError, match="did not converge in 2 Newton iterations"):
        equilibrium(model, model.initial_state(), max_iter=2)
    with pytest.raises(ValueError, match="no energy gradient"):
        equilibrium(FDModel(dm.Scene(scene.sheet, scene.material)), model.initial_state())
