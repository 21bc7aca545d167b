"""Energy models (deformable.physics.force_models.EnergyModel): a density W(s, b) is one class, on both backends.

- eq. (13) written as a user's class goes through the generic path (DensityIntegrand and its kernels) and gives
  the energy, gradient and Hessians of the built-in compiled path to round-off, on FD and FE;
- densities that couple residuals (the membrane's three, all six) have exact gradients and Hessians on both
  backends (against central differences of the discrete energy), and a positive semi-definite "definite" Hessian;
- the registry takes them by name in a Scene, refuses a taken name, and names the known ones on a miss.
"""

from dataclasses import dataclass

import numpy as np
import pytest

import deformable as dm
from deformable.geometry.surfaces import Plane
from deformable.physics.force_models import RESIDUALS, EnergyModel, ForceModel
from validation.harness.backends import make_model

from ...conftest import FULL_ETA, FULL_XI, gradient_error, hessian_error


class Eq13(EnergyModel):
    """Eq. (13) as a user would write it: the weights of the residuals, no coupling."""

    name = "test-eq13"
    couples = ()

    @staticmethod
    def _w(p):
        e, x = p["eta"], p["xi"]
        return np.stack([e[0, 0], e[1, 1], e[0, 1] + e[1, 0], x[0, 0], x[1, 1], x[0, 1] + x[1, 0]])

    def density(self, s, b, p):
        r = np.concatenate([s, b])
        return np.sum(self._w(p) * r * r, axis=0)

    def gradient(self, s, b, p):
        return 2 * self._w(p) * np.concatenate([s, b])

    def hessian(self, s, b, p):
        H = np.zeros((6, 6, s.shape[1]))
        H[np.arange(6), np.arange(6)] = 2 * self._w(p)
        return H


@dataclass(frozen=True)
class Saturating(EnergyModel):
    """A membrane whose tension saturates, eta k^2 ln(1 + |s|^2 / k^2), coupling the metric; bending as eq. (13)."""

    name = "test-saturating"
    couples = (("s11", "s22", "s12"),)
    k: float = 0.05

    def _q(self, s):
        return s[0] ** 2 + s[1] ** 2 + 2 * s[2] ** 2

    def density(self, s, b, p):
        x = p["xi"]
        bending = x[0, 0] * b[0] ** 2 + x[1, 1] * b[1] ** 2 + (x[0, 1] + x[1, 0]) * b[2] ** 2
        return p["eta"][0, 0] * self.k**2 * np.log1p(self._q(s) / self.k**2) + bending

    def gradient(self, s, b, p):
        eta, x = p["eta"][0, 0], p["xi"]
        f = eta / (1 + self._q(s) / self.k**2)
        return np.stack([2 * f * s[0], 2 * f * s[1], 4 * f * s[2],
                         2 * x[0, 0] * b[0], 2 * x[1, 1] * b[1], 2 * (x[0, 1] + x[1, 0]) * b[2]])

    def hessian(self, s, b, p):
        eta, x = p["eta"][0, 0], p["xi"]
        u = 1 + self._q(s) / self.k**2
        dq = np.stack([2 * s[0], 2 * s[1], 4 * s[2]])
        H = np.zeros((6, 6, s.shape[1]))
        H[:3, :3] = -eta / (self.k**2 * u**2) * dq[:, None] * dq[None, :]
        H[np.arange(3), np.arange(3)] += eta / u * np.array([2.0, 2.0, 4.0])[:, None]
        H[3, 3], H[4, 4], H[5, 5] = 2 * x[0, 0], 2 * x[1, 1], 2 * (x[0, 1] + x[1, 0])
        return H


class Coupled(EnergyModel):
    """Every residual coupled: eq. (13) plus c (s11 + s22)(b11 + b22) + d s12 b12 (all six in one group)."""

    name = "test-coupled"

    def _c(self, p):
        return 0.3 * np.sqrt(p["eta"][0, 0] * p["xi"][0, 0])

    def density(self, s, b, p):
        c = self._c(p)
        return Eq13().density(s, b, p) + c * (s[0] + s[1]) * (b[0] + b[1]) + 0.5 * c * s[2] * b[2]

    def gradient(self, s, b, p):
        c = self._c(p)
        g = Eq13().gradient(s, b, p)
        g[0] += c * (b[0] + b[1])
        g[1] += c * (b[0] + b[1])
        g[2] += 0.5 * c * b[2]
        g[3] += c * (s[0] + s[1])
        g[4] += c * (s[0] + s[1])
        g[5] += 0.5 * c * s[2]
        return g

    def hessian(self, s, b, p):
        c = self._c(p)
        H = Eq13().hessian(s, b, p)
        for i in (0, 1):
            for j in (3, 4):
                H[i, j] += c
                H[j, i] += c
        H[2, 5] += 0.5 * c
        H[5, 2] += 0.5 * c
        return H


def clamped_sheet(force_model, backend, nodes=(6, 5), clamp=True):
    """A curved sheet, clamped on one edge (FD's ghost rows) or pinned at two corners, full weight tensors."""
    sheet = dm.Sheet(size=(1.0, 0.8), nodes=nodes, rest=Plane(),
                     initial=lambda a1, a2: np.stack([a1, a2 + 0.05 * a1**2, 0.2 * np.sin(a1) * (1 + a2)], axis=-1))
    material = dm.Material(mu=1.0, eta=FULL_ETA, xi=FULL_XI)
    constraints = [dm.Clamp("left")] if clamp else [dm.Pin(["top-left", "top-right"])]
    return make_model(dm.Scene(sheet, material, constraints=constraints, force_model=force_model), backend)


def wobbled(model, rng, size=0.02):
    return model.initial_state() + size * rng.normal(size=(model.ndof, 3))


@pytest.mark.parametrize("backend", ["fd", "fe"])
@pytest.mark.parametrize("clamp", [True, False])
def test_eq13_through_the_generic_path_is_the_compiled_one(backend, clamp, rng):
    builtin, generic = (clamped_sheet(fm, backend, clamp=clamp) for fm in ("variational", "test-eq13"))
    X = wobbled(builtin, rng)
    eb, eg = builtin.energy(X), generic.energy(X)
    assert eg.stretching == pytest.approx(eb.stretching, rel=1e-13, abs=1e-15)
    assert eg.bending == pytest.approx(eb.bending, rel=1e-13, abs=1e-15)
    gb, gg = builtin.energy_gradient(X), generic.energy_gradient(X)
    assert np.max(np.abs(gg - gb)) <= 1e-13 * np.max(np.abs(gb))
    for kind in ("newton", "gauss-newton", "definite", "projected"):
        Hb, Hg = builtin.energy_hessian(X, kind), generic.energy_hessian(X, kind)
        assert np.max(np.abs((Hg - Hb).data), initial=0.0) <= 1e-12 * np.max(np.abs(Hb.data)), kind


@pytest.mark.parametrize("backend", ["fd", "fe"])
@pytest.mark.parametrize("model_name", ["test-saturating", "test-coupled"])
def test_a_coupled_density_has_its_exact_gradient_and_hessian(backend, model_name, rng):
    model = clamped_sheet(model_name, backend, nodes=(5, 4))
    X = wobbled(model, rng, 0.05)  # strains near and past k = 0.05: the saturating tension is nonlinear there
    assert gradient_error(model, X) < 1e-6
    H, err = hessian_error(model, X)
    assert err < 1e-5
    assert np.max(np.abs((H - H.T).data), initial=0.0) <= 1e-12 * np.max(np.abs(H.data))


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_the_definite_hessian_of_a_nonconvex_density_is_positive_semi_definite(backend, rng):
    model = clamped_sheet("test-saturating", backend, nodes=(5, 4))
    X = model.initial_state() * 1.3 + 0.02 * rng.normal(size=(model.ndof, 3))  # 30 % stretched: W concave there
    exact = np.linalg.eigvalsh(model.energy_hessian(X, "newton").toarray())
    definite = np.linalg.eigvalsh(model.energy_hessian(X, "definite").toarray())
    assert exact.min() < -1e-6 * exact.max(), "the exact Hessian is indefinite in the saturated range"
    assert definite.min() >= -1e-10 * definite.max()


def test_a_density_runs_in_time_on_both_backends():
    for backend in ("fd", "fe"):
        model = clamped_sheet("test-saturating", backend, nodes=(5, 4), clamp=False)
        result = dm.TimeStepper(model, dt=0.01).run(model.initial_state(), t_end=0.05)
        assert result.status == "finished" and np.all(np.isfinite(result.state.X))


def test_energy_models_are_registered_by_subclassing_and_refused_twice():
    assert {"tpbf87", "frozen", "variational", "test-eq13"} <= set(ForceModel.names())
    scene = dm.Scene(dm.Sheet(nodes=(4, 4)), dm.Material(eta=1.0, xi=1e-3), force_model="test-saturating")
    assert isinstance(scene.force_model, Saturating) and scene.force_model.k == 0.05
    custom = dm.Scene(dm.Sheet(nodes=(4, 4)), dm.Material(eta=1.0), force_model=Saturating(k=0.2))
    assert custom.force_model == Saturating(k=0.2) and custom.force_model != Saturating()
    with pytest.raises(dm.InputError, match="force model 'test-eq13' is already .*Eq13"):
        type("Other", (EnergyModel,), {"name": "test-eq13", "__module__": "elsewhere"})
    with pytest.raises(dm.InputError, match="must be one of tpbf87, frozen, variational"):
        dm.Scene(dm.Sheet(nodes=(4, 4)), dm.Material(eta=1.0), force_model="koiterr")
    with pytest.raises(TypeError, match="residuals are"):
        type("Bad", (EnergyModel,), {"couples": (("s11", "g22"),)})
    assert Eq13.groups() == tuple((k,) for k in range(6)) and EnergyModel.groups() == (tuple(range(6)),)
    assert Saturating.groups() == ((0, 1, 2), (3,), (4,), (5,)) and len(RESIDUALS) == 6


def test_a_model_answers_what_the_code_used_to_ask_with_a_string():
    tpbf87, frozen, variational = (ForceModel.from_name(n) for n in ("tpbf87", "frozen", "variational"))
    assert (tpbf87.has_energy, frozen.has_energy, variational.has_energy) == (False, True, True)
    assert (tpbf87.has_strength_matrix, frozen.has_strength_matrix, variational.has_strength_matrix) == \
        (True, True, False)
    assert (tpbf87.scheme, frozen.scheme, variational.scheme) == ("semi-implicit", "semi-implicit", "implicit-euler")
    assert frozen.weights == ("alpha", "beta") and frozen.linear and not variational.linear
    assert variational.stiffness == (4.0, 2.0) and tpbf87.stiffness == (1.0, 1.0) and tpbf87.lags_alpha
    assert variational == "variational" and str(tpbf87) == "tpbf87"  # a name still compares equal
