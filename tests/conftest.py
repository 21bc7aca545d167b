"""What several test modules share: a flat-sheet scene factory, the random generator, numerical derivatives; and,
before the xdist workers start, the kernels compiled once (:func:`pytest_sessionstart`).

Everything else comes from the package itself: analytic surfaces from
:mod:`validation.harness.surfaces`, the order fit from
:func:`validation.harness.orders.fit_order`, models from
:func:`validation.harness.backends.make_model`.
"""

import os
import subprocess
import sys
import time
import warnings
from pathlib import Path

import meshio
import numpy as np
import pytest

import deformable as dm
from deformable.geometry.surfaces import Plane
from validation.harness.backends import make_model

#: the four edges of the parameter rectangle: pinned together, a simply supported sheet
ALL_EDGES = ["left", "right", "bottom", "top"]
#: full (non-diagonal) weight tensors of eq. (13), so every component of the energy is exercised
FULL_ETA = np.array([[5.0, 1.0], [1.0, 3.0]])
FULL_XI = np.array([[0.5, 0.2], [0.2, 0.1]])


def flat_scene(nodes=(9, 9), size=(1.0, 1.0), **scene) -> dm.Scene:
    """A scene on a flat sheet; keyword arguments go to Scene (default material mu 1, gamma 0, eta 10, xi 0)."""
    material = scene.pop("material", dm.Material(mu=1.0, gamma=0.0, eta=10.0, xi=0.0))
    sheet = scene.pop("sheet", dm.Sheet(size=size, nodes=nodes))
    return dm.Scene(sheet, material, **scene)


def flat_model(backend="fd", nodes=(9, 9), size=(1.0, 1.0), weighting=None, **scene):
    """The model of :func:`flat_scene` on ``backend``; ``weighting`` is FD's option."""
    options = {} if weighting is None else {"weighting": weighting}
    return make_model(flat_scene(nodes, size, **scene), backend, **options)


def vertical_hanging(nodes) -> dm.Scene:
    """A 1 x 1 sheet hanging in the x-z plane from its top edge under gravity (tpbf87; mu 0.1, eta 50)."""
    sheet = dm.Sheet(size=(1.0, 1.0), nodes=(nodes, nodes), rest=Plane(e1=(1.0, 0.0, 0.0), e2=(0.0, 0.0, 1.0)))
    material = dm.Material(mu=0.1, gamma=0.05, eta=50.0, xi=0.0)
    return dm.Scene(sheet, material, forces=[dm.Gravity(9.81)], constraints=[dm.Pin("top")], name="hanging")


def central_differences(f, X, eps=1e-6) -> np.ndarray:
    """Central differences of f over every entry of X (ndof, 3), stacked as columns, coordinate-blocked.

    Column ``a * ndof + k`` is the derivative in X[k, a] (the layout of the energy Hessians).
    """
    cols = []
    for a in range(X.shape[1]):
        for k in range(X.shape[0]):
            Xp, Xm = X.copy(), X.copy()
            Xp[k, a] += eps
            Xm[k, a] -= eps
            cols.append(np.ravel((f(Xp) - f(Xm)) / (2 * eps)))
    return np.array(cols).T


def gradient_error(model, X) -> float:
    """max |energy_gradient - central differences of the energy|, relative to the gradient's largest entry."""
    g = model.energy_gradient(X).T.ravel()
    numeric = central_differences(lambda Y: model.energy(Y).total, X).ravel()
    return float(np.max(np.abs(g - numeric)) / np.max(np.abs(g)))


def hessian_error(model, X):
    """The exact Hessian at X, and its largest difference from central differences of the gradient (relative)."""
    H = model.energy_hessian(X, "newton")
    numeric = central_differences(lambda Y: model.energy_gradient(Y).T.ravel(), X)
    return H, float(np.max(np.abs(H.toarray() - numeric)) / np.max(np.abs(numeric)))


def sine_eigenvalue(k, nodes, L) -> float:
    """Eigenvalue of -D11 (natural rule, pinned ends) for the sine mode k: 4/h^2 sin^2(k pi h / 2L)."""
    h = L / (nodes - 1)
    return 4 / h**2 * np.sin(k * np.pi * h / (2 * L)) ** 2


def free_dofs(model, component=2) -> np.ndarray:
    """The degrees of freedom of one coordinate that no constraint holds."""
    return np.setdiff1d(np.arange(model.ndof), model.fixed_dofs()[component])


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


class Polynomial:
    """r = sum_pq c[p, q] a1^p a2^q with c (P, Q, 3): a surface with exact derivatives, for element exactness."""

    def __init__(self, c):
        self.c = np.asarray(c, float)

    def _eval(self, a1, a2, d1, d2):
        from numpy.polynomial import polynomial as P

        c = P.polyder(P.polyder(self.c, d1, axis=0), d2, axis=1) if (d1 or d2) else self.c
        return np.stack([P.polyval2d(a1, a2, c[..., k]) for k in range(3)], axis=-1)

    def r(self, a1, a2):
        return self._eval(a1, a2, 0, 0)

    def r1(self, a1, a2):
        return self._eval(a1, a2, 1, 0)

    def r2(self, a1, a2):
        return self._eval(a1, a2, 0, 1)

    def r12(self, a1, a2):
        return self._eval(a1, a2, 1, 1)


def checks_pass(res):
    """A study's result, after asserting that every one of its checks passed (the failures listed)."""
    failed = [f"{c.name}: expected {c.expectation}, observed {c.observed}" for c in res.checks if not c.passed]
    assert not failed, "\n".join(failed)
    assert res.checks, f"study {res.study} made no check"
    return res


def series_frames(xdmf):
    """(t, points, point data) of every frame of a series."""
    with meshio.xdmf.TimeSeriesReader(str(xdmf)) as reader:
        points, _ = reader.read_points_cells()
        return [(t, points, data) for t, data, _ in (reader.read_data(k) for k in range(reader.num_steps))]


def assert_same_series(a, b):
    """Two XDMF series have the same frames, times, positions and point data, bit for bit."""
    fa, fb = series_frames(a), series_frames(b)
    assert len(fa) == len(fb) > 1
    for (ta, pa, da), (tb, pb, db) in zip(fa, fb):
        assert ta == tb and set(da) == set(db)
        np.testing.assert_array_equal(pa, pb)
        for name in da:
            np.testing.assert_array_equal(da[name], db[name], err_msg=f"{name} at t = {ta}")


def kernel_entry_points() -> list:
    """The compiled kernels the tests call from Python (each has one signature): every one the library calls, and
    the general block kernel that tests/deformable/physics/test_kernels.py compares the library's with."""
    from deformable.algebra import elements
    from deformable.physics import kernels, pointhessian

    return [kernels.energy_sums, kernels.point_gradients, kernels.point_hessians, kernels.point_residuals,
            kernels.point_gradients_general, kernels.point_hessians_general, kernels.element_upper,
            pointhessian.point_hessians, pointhessian.element_hessians, pointhessian.slot_blocks,
            elements.scatter_upper]


def uncached_kernels() -> list[str]:
    """The entry points numba's on-disk cache does not hold for their current source (empty: nothing to compile)."""
    return [f.__name__ for f in kernel_entry_points() if not f._cache._cache_file._load_index()]


#: the halves of :func:`compile_kernels`, compiled side by side: eq. (13)'s block kernels, and a density's general ones
#: (with the general block kernel, which no model calls); measured on a cold cache, 9.2 and 12.8 s of CPU time against
#: 17.8 s for the whole (2026-12, two idle cores)
HALVES = {"eq13": ("variational",), "density": ("koiter",)}


def compile_kernels(half: str | None = None) -> None:
    """Call every entry point of :func:`kernel_entry_points` once (or those of one of the :data:`HALVES`), on small FD
    and FE models of eq. (13) and of a density (koiter) with every Hessian kind, so that numba compiles them into its
    on-disk cache (18 s of CPU time on a cold cache, measured on an idle machine; nothing on a warm one)."""
    from deformable.physics import kernels, pointhessian

    if not uncached_kernels():
        return
    rng = np.random.default_rng(0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the scenes are well posed; a warning here is no test's business
        for backend in ("fd", "fe"):
            for force_model in HALVES[half] if half else sum(HALVES.values(), ()):
                model = flat_model(backend, nodes=(6, 6), material=dm.Material(mu=1.0, gamma=0.0, eta=FULL_ETA,
                                                                                  xi=FULL_XI), force_model=force_model)
                X = model.initial_state() + 1e-2 * rng.standard_normal(model.initial_state().shape)
                model.energy(X)
                model.energy_gradient(X)
                for kind in ("newton", "gauss-newton", "definite", "projected"):
                    model.energy_hessian(X, kind)
        if half != "eq13":
            P, S = 2, 9  # the general block kernel, which no model calls: arrays of the types the library's take
            v, c = rng.standard_normal((P, S, 3)), np.ones((6, P))
            sl, bend = np.arange(4, dtype=np.int64), np.arange(4, 7, dtype=np.int64)
            kernels.point_hessians(v, sl, bend, c, np.zeros((6, P)), 0, True)
            pointhessian.slot_blocks(S, sl, bend, True)


def pytest_configure(config):
    """An xdist worker's BLAS (numpy's OpenBLAS) on its share of the cores: with every core a worker, OpenBLAS's
    default of a thread a core runs each worker's dense products on all cores at once, and its threads wait for a
    core the other worker holds (tests/deformable/contact/test_selfpotential.py's dense eigendecomposition, 0.2 s
    alone, took 10 s in a whole run on a loaded machine; with both cores busy, 3.3 and 0.85 s on two threads
    against 0.17 and 0.28 s on one)."""
    if hasattr(config, "workerinput"):
        from threadpoolctl import threadpool_limits

        share = max(1, (os.cpu_count() or 1) // int(config.workerinput.get("workercount", 1)))
        config._blas_limits = threadpool_limits(limits=share, user_api="blas")  # held for the worker's life


def pytest_sessionstart(session):
    """On the xdist controller, before its workers start (xdist starts them in its own, later, sessionstart): the
    kernels compiled once into numba's on-disk cache, which every worker then reads, instead of each worker compiling
    them for itself while the cache is cold (measured in a fresh clone: two tests of 7 and 15 s took 129 and 134 s).
    The two :data:`HALVES` compile side by side, one here and one in a subprocess that imports the same copy of the
    package (the installed one: pyproject's filterwarnings imports it before the rootdir is on sys.path). A
    subprocess a test starts in the checkout imports the checkout's copy, which has a cache of its own: the one test
    that does so compiles the few kernels it calls (about 6 s)."""
    config = session.config
    if hasattr(config, "workerinput") or config.option.collectonly or config.getoption("dist", "no") == "no":
        return  # a worker, or one process: it compiles what it calls, once
    cold = uncached_kernels()
    if not cold:
        return
    import deformable

    start, said = time.perf_counter(), []
    home = Path(deformable.__file__).resolve().parents[1]  # where this process's deformable, fdmodel, ... come from
    code = ("import importlib.util, deformable; "
            f"spec = importlib.util.spec_from_file_location('warmup', {__file__!r}); "
            "m = importlib.util.module_from_spec(spec); spec.loader.exec_module(m); m.compile_kernels('density'); "
            "print(deformable.__file__)")
    paths = [str(home), str(config.rootpath), *filter(None, [os.environ.get("PYTHONPATH")])]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(paths)}
    other = subprocess.Popen([sys.executable, "-c", code], cwd=home, env=env, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True)
    try:
        compile_kernels("eq13")
    except Exception as err:  # noqa: BLE001 - the tests that call the kernels will say what is wrong
        said.append(f"compiling the kernels failed (the tests compile them): {err!r}")
    out = other.communicate(timeout=900)[0]
    if other.returncode or Path(out.strip().splitlines()[-1] if out.strip() else "").resolve() != \
            Path(deformable.__file__).resolve():
        said.append(f"compiling half the kernels in a subprocess failed or compiled another copy of the package (the "
                    f"tests compile them):\n{out}")
    said.append(f"compiled the numba kernels once for the workers in {time.perf_counter() - start:.1f} s ({len(cold)} "
                "entry points were not in the cache)")
    reporter = config.pluginmanager.get_plugin("terminalreporter")
    for line in said:
        if reporter is not None:
            reporter.write_line(line)
