"""The base under the backend contract (deformable.backends.BackendBase): both backends stand on it, the methods
they wrote alike are written there once, and a backend that writes only the hooks satisfies the contract."""

import numpy as np
import scipy.sparse as sp

import deformable as dm
from deformable.backends import Backend, BackendBase, Discretisation
from deformable.geometry.sheet import CELL_CORNERS, bilinear_weights
from deformable.geometry.surfaces import as_surface
from fdmodel import FDModel
from femodel import FEModel
from validation.harness.backends import make_model

from ...conftest import flat_scene

#: the contract's methods written once, in the base
INHERITED = {"initial_state", "stiffness", "mass", "damping", "load", "internal_force", "fixed_dofs", "prescribed",
             "stable_step", "energy", "kinetic_energy", "energy_gradient", "energy_hessian", "energy_elements",
             "point_dofs", "point_matrix"}
#: what a backend writes: the rest of the contract, and the base's own hooks
HOOKS = {"discretize", "grid", "tensors", "sample", "integrate", "at_points", "density_matrix", "edge_rule", "patches",
         "_point_weights", "_strain_tensors"}


class Toy(BackendBase):
    """Nodal values, each node standing for a cell h1 h2 (FD's pointwise rows without its differences): the hooks
    the checks below reach, computed; the others written, as a backend must, but not needed here."""

    def __init__(self, scene):
        super().__init__(scene)
        M, N, mat = self.M, self.N, scene.material
        self.ndof, self.value_dofs = M * N, np.arange(M * N)
        self.points = scene.sheet.coordinates()
        self.mu = mat.field_at("mu", (M, N), self.points, lambda f: f)
        self.fields = {"eta": mat.tensor_at("eta", (M, N), self.points, lambda f: f)}
        self.eta = self.fields["eta"]
        self._M = self._C = sp.diags((self.h1 * self.h2 * self.mu).ravel(), format="csr")
        self._complete(node_dofs=np.flatnonzero, edge_dofs=lambda edge: np.array([], int),
                       clamp_dofs=lambda edge: np.flatnonzero(scene.sheet.edge_nodes(edge)))

    def discretize(self, surface):
        return as_surface(surface).r(*self.points).reshape(self.ndof, 3)

    def grid(self, X):
        return np.asarray(X).reshape(self.M, self.N, 3)

    def integrate(self, density):
        return self.h1 * self.h2 * np.asarray(density).reshape(self.ndof, 3)

    def density_matrix(self, c):
        return sp.diags(self.h1 * self.h2 * np.ravel(c), format="csr")

    def _point_weights(self, a, what):
        i, j, s, u = self.scene.sheet.locate(a, what)
        dofs = np.stack([(i + di) * self.N + j + dj for di, dj in CELL_CORNERS], axis=1)
        return dofs, np.stack(bilinear_weights(s, u), axis=1)

    def _not_here(self, *args, **kwargs):
        raise NotImplementedError("the toy backend computes only what its test reaches")

    tensors = sample = at_points = edge_rule = patches = _strain_tensors = _not_here


class ToyBackend(Discretisation):  # no name: not registered, yet the toy's descriptor
    model = Toy
    bytes_per_node = {"implicit": 1.0, "semi-implicit": 1.0}


def test_both_backends_stand_on_the_base_and_write_none_of_its_methods_again():
    for cls in (FDModel, FEModel):
        assert issubclass(cls, BackendBase)
        assert INHERITED.isdisjoint(vars(cls)) and HOOKS <= set(vars(cls))
        assert not cls.__abstractmethods__
    assert BackendBase.__abstractmethods__ == HOOKS


def test_both_models_are_instances_of_the_base_and_the_contract():
    for backend in ("fd", "fe"):
        model = make_model(flat_scene((5, 4)), backend)
        assert isinstance(model, BackendBase) and isinstance(model, Backend)


def test_a_backend_that_writes_only_the_hooks_satisfies_the_contract_and_inherits_the_rest():
    scene = flat_scene((5, 4), forces=[dm.Gravity(9.81)], constraints=[dm.Pin("left")])
    toy, fd = Toy(scene), FDModel(scene, weighting="pointwise")
    assert isinstance(toy, Backend) and toy.descriptor is ToyBackend
    X = toy.initial_state()
    # the shared methods over the same hooks give FD's pointwise numbers
    assert np.array_equal(X, fd.initial_state())
    assert (toy.mass() != fd.mass()).nnz == 0
    assert np.array_equal(toy.load(X, 0.0), fd.load(X, 0.0))
    assert toy.stable_step() == fd.stable_step()
    for a, b in zip(toy.fixed_dofs(), fd.fixed_dofs()):
        assert np.array_equal(a, b)
    a = np.random.default_rng(0).uniform(0.0, 1.0, size=(6, 2))
    W = toy.point_matrix(a)
    assert np.allclose(W @ X, np.c_[a, np.zeros(6)], rtol=0, atol=1e-15)  # bilinear is exact on the flat sheet
    dofs, w = toy.point_dofs(a[0])
    assert np.array_equal(W[0].toarray()[0, dofs], w)
