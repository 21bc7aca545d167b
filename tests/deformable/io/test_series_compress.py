"""A gzip-compressed XDMF series (deformable.io.series, ``compress``): lossless, read back by meshio and pyvista,
on by default above 32 x 32 nodes, and a continued series keeps working."""

import h5py
import meshio
import numpy as np
import pytest

import deformable as dm
from deformable.io import XDMFWriter
from validation.harness.backends import make_model


def _model(nodes=(7, 6)):
    return make_model(dm.Scene(dm.Sheet(nodes=nodes), dm.Material(mu=0.1, eta=50.0), forces=[dm.Gravity()],
                               constraints=[dm.Pin("top")]), "fd")


def _write(path, nodes=(7, 6), steps=8, **kw):
    model = _model(nodes)
    writer = XDMFWriter(path, every=2, **kw)
    dm.TimeStepper(model, 1e-3).run(model.initial_state(), steps=steps, trackers=[writer])
    return writer


def _meshio_frames(xdmf):
    with meshio.xdmf.TimeSeriesReader(str(xdmf)) as reader:
        points, cells = reader.read_points_cells()
        return points, cells[0].data, [reader.read_data(k) for k in range(reader.num_steps)]


def _pyvista_frames(xdmf):
    from deformable.io.render import offscreen_pyvista

    reader = offscreen_pyvista().XdmfReader(str(xdmf))
    out = []
    for t in reader.time_values:
        reader.set_active_time_value(t)
        mesh = reader.read()
        out.append((t, np.array(mesh.points), {k: np.array(mesh.point_data[k]) for k in mesh.point_data}))
    return out


def _compressed(h5) -> set:
    with h5py.File(h5) as f:
        return {f[name].compression for name in f}


def test_a_compressed_series_reads_back_equal_to_an_uncompressed_one(tmp_path):
    plain = _write(tmp_path / "plain" / "sheet.xdmf", compress=False)
    packed = _write(tmp_path / "packed" / "sheet.xdmf", compress=True)
    assert _compressed(plain.h5_path) == {None} and _compressed(packed.h5_path) == {"gzip"}
    with h5py.File(packed.h5_path) as f:
        assert all(f[name].shuffle for name in f)
    # meshio's time-series reader: the same float64 values, bit for bit
    p0, c0, frames0 = _meshio_frames(plain.path)
    p1, c1, frames1 = _meshio_frames(packed.path)
    assert p1.dtype == np.float64 and np.array_equal(p0, p1) and np.array_equal(c0, c1)
    assert len(frames1) == len(frames0) == 5
    for (t0, d0, _), (t1, d1, _) in zip(frames0, frames1):
        assert t0 == t1 and set(d0) == set(d1)
        for name in d0:
            assert d1[name].dtype == np.float64
            np.testing.assert_array_equal(d1[name], d0[name], err_msg=name)  # NaN where NaN, else equal
    # pyvista's (VTK's) XDMF reader: each frame's geometry and point fields
    v0, v1 = _pyvista_frames(plain.path), _pyvista_frames(packed.path)
    assert [t for t, _, _ in v1] == [t for t, _, _ in v0] == [t for t, _, _ in frames0]
    for (_, q0, f0), (_, q1, f1) in zip(v0, v1):
        assert q1.dtype == np.float64 and np.array_equal(q0, q1)
        assert set(f0) == set(f1) and "displacement" in f1
        for name in f0:
            np.testing.assert_array_equal(f1[name], f0[name], err_msg=name)
    np.testing.assert_array_equal(v1[-1][2]["displacement"], frames1[-1][1]["displacement"])


@pytest.mark.parametrize("nodes, compressed", [((32, 32), None), ((33, 32), "gzip")])
def test_compression_is_on_by_default_above_32_by_32_nodes(tmp_path, nodes, compressed):
    writer = _write(tmp_path / "sheet.xdmf", nodes=nodes, steps=1)
    assert writer.compress is None and _compressed(writer.h5_path) == {compressed}


def test_a_continued_compressed_series_equals_an_uninterrupted_one(tmp_path):
    """A run cut at step 7 and continued with append=True: its frames equal an uninterrupted run's; the part
    written before is compressed, the continuation may be either."""
    whole = _write(tmp_path / "whole" / "sheet.xdmf", steps=11, compress=True)
    model = _model()
    X0 = model.initial_state()
    path = tmp_path / "cut" / "sheet.xdmf"
    stepper = dm.TimeStepper(model, 1e-3)
    first = stepper.run(X0, steps=7, trackers=[XDMFWriter(path, every=2, compress=True)])
    more = XDMFWriter(path, every=2, reference=X0, append=True, compress=False)
    again = dm.TimeStepper(model, 1e-3).run(X0, steps=4, resume=first.state, trackers=[more])
    assert again.state.step == 11 and more.frames == 7  # steps 0, 2, 4, 6 kept (the last at 7 dropped); 8, 10, 11
    assert _compressed(path.with_suffix(".h5")) == {"gzip", None}
    _, _, cont = _meshio_frames(path)
    _, _, ref = _meshio_frames(whole.path)
    assert [t for t, _, _ in cont] == [t for t, _, _ in ref]
    for (_, d, _), (_, e, _) in zip(cont, ref):
        assert set(d) == set(e)
        for name in d:
            np.testing.assert_array_equal(d[name], e[name], err_msg=name)
    assert len(_pyvista_frames(path)) == len(cont)
