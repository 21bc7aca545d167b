"""The XDMF time series (deformable.io.series): point fields, and a series meshio reads back."""

import meshio
import numpy as np
import pytest

import deformable as dm
from deformable.geometry.surfaces import Plane
from deformable.io import NodeFields, XDMFWriter, node_fields
from validation.harness.backends import make_model
from validation.harness.surfaces import get

FIELDS = {"G11", "G12", "G22", "B11", "B12", "B22", "speed", "energy_density", "compatibility_ratio",
          "compatibility_cosine"}


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_point_fields_at_rest_and_stretched(backend):
    sheet = dm.Sheet(size=(1.0, 1.0), nodes=(6, 5), rest=get("monge"))
    eta = 3.0
    model = make_model(dm.Scene(sheet, dm.Material(eta=eta, xi=0.5)), backend)
    X0 = model.initial_state()
    V = np.zeros_like(X0)
    V[model.value_dofs] = [0.0, 3.0, 4.0]
    f = node_fields(model, X0, V)
    assert set(f) == FIELDS and all(v.shape == (30,) for v in f.values())
    assert np.max(np.abs(f["energy_density"])) < 1e-12 and np.allclose(f["speed"], 5.0)
    G = model.sample(X0, NodeFields(model).a).G
    np.testing.assert_array_equal(f["G12"], G[:, 0, 1])
    # a uniform stretch of the flat sheet by s: G11 = s^2, density eta (s^2 - 1)^2
    flat = make_model(dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(6, 5)), dm.Material(eta=eta)), backend)
    s = 1.2
    X = flat.discretize(Plane(e1=(s, 0.0, 0.0)))
    f = node_fields(flat, X, np.zeros_like(X))
    np.testing.assert_allclose(f["G11"], s**2, rtol=1e-13)
    np.testing.assert_allclose(f["energy_density"], eta * (s**2 - 1) ** 2, rtol=1e-12)


def test_a_run_writes_frames_that_meshio_reads_back(tmp_path):
    model = make_model(dm.Scene(dm.Sheet(nodes=(5, 4)), dm.Material(mu=0.1, eta=50.0), forces=[dm.Gravity()],
                                constraints=[dm.Pin("top")]), "fd")
    writer = XDMFWriter(tmp_path / "sheet.xdmf", every=4)
    result = dm.TimeStepper(model, 1e-3).run(model.initial_state(), steps=10, trackers=[writer])
    assert writer.frames == 4  # steps 0, 4, 8 and the last one, 10
    assert (tmp_path / "sheet.h5").is_file() and not list(tmp_path.glob("*.tmp"))
    with meshio.xdmf.TimeSeriesReader(str(tmp_path / "sheet.xdmf")) as reader:
        points, cells = reader.read_points_cells()
        assert points.shape == (20, 3) and cells[0].type == "quad" and len(cells[0].data) == 4 * 3
        frames = [reader.read_data(k) for k in range(reader.num_steps)]
    assert [t for t, _, _ in frames] == pytest.approx([0.0, 0.004, 0.008, 0.010], abs=1e-12)
    t, data, _ = frames[-1]
    assert FIELDS | {"displacement"} <= set(data)
    np.testing.assert_allclose(points + data["displacement"], model.grid(result.state.X).reshape(-1, 3),
                               rtol=0, atol=1e-15)
    with pytest.raises(ValueError, match="every must be a positive integer"):
        XDMFWriter(tmp_path / "x.xdmf", every=0)


def _cap_fields(backend, force_model, n, R=2.0):
    def cap(a1, a2):
        return np.stack([a1, a2, R - np.sqrt(R * R - (a1 - 0.5) ** 2 - (a2 - 0.5) ** 2)], axis=-1)

    sheet = dm.Sheet(size=(1.0, 1.0), nodes=(n, n), rest=cap)
    model = make_model(dm.Scene(sheet, dm.Material(eta=np.ones((2, 2)), xi=0.1 * np.ones((2, 2))),
                                force_model=force_model), backend)
    X0 = model.initial_state()
    f = node_fields(model, X0, np.zeros_like(X0))
    return (f[k].reshape(n, n) for k in ("compatibility_ratio", "compatibility_cosine"))


@pytest.mark.parametrize("backend, force_model, order, finest", [
    ("fd", "tpbf87", 1, 0.1),       # eq. (18)-(19): forward differences, first order at the nodes
    ("fd", "variational", 2, 1e-3),  # the energy's tensors, centred, second order
])
def test_the_compatibility_fields_converge_at_the_order_of_the_tensors(backend, force_model, order, finest):
    """On a sphere's cap at rest the paper's ratio tends to 1 as the discrete G, B do to the surface's: |ratio - 1|
    at the resolved points falls at the order of the backend's node tensors."""
    from validation.harness.orders import fit_order

    nodes = (13, 25, 49)
    err = [np.nanmax(np.abs(next(_cap_fields(backend, force_model, n)) - 1)) for n in nodes]
    p = fit_order(1.0 / (np.array(nodes) - 1), np.array(err))
    assert order - 0.3 <= p <= order + 0.3 and err[-1] <= finest, (p, err)


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_the_compatibility_fields_are_nan_where_the_test_is_undefined(backend):
    """Within the test's two-node margin, where a compared vector vanishes (the cap's middle line a2 = 1/2, a band
    the guard leaves out), and on a grid too small for the test: NaN; elsewhere a cosine near 1."""
    ratio, cosine = _cap_fields(backend, "variational", 13)
    resolved = np.isfinite(ratio[2:11, 2:11])
    assert 0 < resolved.mean() < 1 and np.all(np.isnan(ratio[:2])) and np.all(np.isnan(cosine[:, -2:]))
    assert np.nanmin(cosine) > 0.99
    small = make_model(dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(5, 5)), dm.Material(eta=1.0)), backend)
    assert np.all(np.isnan(node_fields(small, small.initial_state(), np.zeros((small.ndof, 3)))["compatibility_ratio"]))
