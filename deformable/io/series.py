"""Run output: an XDMF time series for ParaView.

:class:`XDMFWriter` is a :class:`deformable.Tracker` that writes one frame of an XDMF 3 time series (meshio's layout,
HDF5 heavy data beside the .xdmf). The mesh is the node grid as quads, stored in the first frame and included by the
others; each frame carries its own geometry and the point fields

- ``G11, G12, G22``: the metric of eq. (4)-(5) (FD: eq. (18)),
- ``B11, B12, B22``: the curvature of eq. (8) (FD: eq. (19)),
- ``speed``: |r_t| (m/s), from the stepper's V of eq. (27),
- ``energy_density``: the integrand of eq. (13), ``sum_ij eta_ij (G_ij - G0_ij)^2 + xi_ij (B_ij - B0_ij)^2``
  (J/m^2), or the density of the scene's energy model (:meth:`deformable.physics.ForceModel.density_field`),
- ``compatibility_ratio``, ``compatibility_cosine``: the paper's compatibility test (section 3.2, eq. (10);
  :func:`deformable.geometry.check_compatibility`) on the frame's own G and B at the nodes, the ratio |u| / |v| and
  the cosine of u = (r_11)_2 against v = (r_12)_1; NaN where a compared vector vanishes (the test's guard), within
  two nodes of an edge and on grids under 6 x 6 nodes,
- ``displacement``: r - r(start of the run) (m), so readers that keep the first geometry (meshio's TimeSeriesReader)
  recover the positions; a resumed run measures it from the original start.

Cadence. A frame every ``every`` steps, or every ``interval`` seconds of simulated time, plus the first and the last
state. With an ``interval`` the frames are on its multiples: the writer asks the stepper for each of them
(:meth:`~deformable.dynamics.trackers.Tracker.next_time`), and :meth:`deformable.TimeStepper.run` ends a step on each,
so a frame is a state of the run, never interpolated. Driven by another loop that does not ask (``handle`` called
state by state), the writer writes the first state at or past each multiple. Frame times are the step times rounded
to 12 significant digits (:func:`frame_time`). Each frame says what it is in an XDMF ``Information`` element
(``frame``: ``first``, ``cadence`` or ``last``), which readers skip.

Resume. ``append=True`` continues an existing series: the frames after the state the run resumes from are dropped
(with a warning that says how many), and so is a ``last`` frame at it, so that the continued series equals the one an
uninterrupted run writes. A series that ends before the state is refused (:func:`continuation`).

Compression. ``compress=True`` writes the HDF5 datasets gzip-compressed (:data:`GZIP_LEVEL`, with the byte shuffle),
lossless; None (the default) compresses grids of more than :data:`COMPRESS_NODES` nodes.

Everything is taken through the backend protocol (``model.grid``, ``model.sample``), so the writer serves both
backends. The .xdmf file is rewritten, and the HDF5 file flushed, after every frame, so a run that is killed keeps
every frame written before. A frame that would not fit (the free disk space, or ``ulimit -f``) is refused before HDF5
writes any of it (HDF5 cannot recover from a write that fails half-way), and a failed write raises
:class:`~deformable.errors.WriteError` naming the file.
"""

from __future__ import annotations

import logging
import os
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from ..checks import count, real
from ..dynamics.trackers import REMAINDER, Tracker
from ..errors import InputError, WriteError
from ..geometry.compatibility import check_compatibility
from ..limits import DATASET_BYTES, check_room
from ..physics.material import TENSORS

__all__ = ["XDMFWriter", "NodeFields", "node_fields", "frame_time", "continuation"]

log = logging.getLogger(__name__)

#: gzip level of a compressed series (1 fastest .. 9 smallest)
GZIP_LEVEL = 4
#: compress by default above this many nodes (32 x 32)
COMPRESS_NODES = 32 * 32


class NodeFields:
    """Computes the point fields of one state at the nodes of the sheet's grid.

    Parameters
    ----------
    model : a :class:`deformable.Backend`
    """

    def __init__(self, model):
        self.model = model
        scene = model.scene
        sheet = scene.sheet
        self.nodes = M, N = sheet.nodes
        a1, a2 = sheet.coordinates()
        self.a = np.column_stack([a1.ravel(), a2.ravel()])  # (M N, 2), node (m, n) at row m N + n
        rest = model.sample(model.discretize(sheet.rest), self.a)
        G0, B0 = scene.rest_tensors(a1.ravel(), a2.ravel(), _components_first(rest.G), _components_first(rest.B))
        self.G0, self.B0 = G0, B0  # (2, 2, P)
        mat = scene.nodal_material()
        self.fields = {name: mat.tensor(name, (M, N)).reshape(2, 2, -1) for name in TENSORS}
        # quads of the node grid, counter-clockwise in (a1, a2)
        idx = np.arange(M * N).reshape(M, N)
        self.cells = np.column_stack([idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(),
                                      idx[:-1, 1:].ravel()])

    def positions(self, X) -> np.ndarray:
        """Node positions (M N, 3) in m."""
        return np.asarray(self.model.grid(X), float).reshape(-1, 3)

    def __call__(self, X, V) -> dict[str, np.ndarray]:
        """Point fields of state (X, V): name -> (M N,) array."""
        s = self.model.sample(X, self.a)
        G, B = s.G, s.B
        vel = np.asarray(self.model.grid(V), float).reshape(-1, 3)
        stretching, bending = self.model.scene.force_model.density_field(
            self.fields.__getitem__, _components_first(G), self.G0, _components_first(B), self.B0)
        density = stretching + bending
        ratio, cosine = self.compatibility(G, B)
        return {
            "G11": G[:, 0, 0], "G12": G[:, 0, 1], "G22": G[:, 1, 1],
            "B11": B[:, 0, 0], "B12": B[:, 0, 1], "B22": B[:, 1, 1],
            "speed": np.linalg.norm(vel, axis=1), "energy_density": density,
            "compatibility_ratio": ratio, "compatibility_cosine": cosine,
        }

    def compatibility(self, G, B, margin: int = 2) -> tuple[np.ndarray, np.ndarray]:
        """The compatibility test's ratio and cosine at the nodes from G, B (M N, 2, 2): two (M N,) arrays."""
        M, N = self.nodes
        ratio, cosine = np.full((M, N), np.nan), np.full((M, N), np.nan)
        if min(M, N) > 2 * margin + 1:
            T = [np.moveaxis(np.asarray(X, float).reshape(M, N, 2, 2), (2, 3), (0, 1)) for X in (G, B)]
            try:
                test = check_compatibility(T[0], T[1], self.model.scene.sheet.h, margin=margin)
            except InputError:  # a degenerate frame (G not positive definite): nothing to compare
                test = None
            if test is not None:
                inner = (slice(margin, M - margin), slice(margin, N - margin))
                ratio[inner], cosine[inner] = test.fields["ratio1"], test.fields["cosine1"]
        return ratio.ravel(), cosine.ravel()


def node_fields(model, X, V) -> dict[str, np.ndarray]:
    """The point fields of the module docstring for one state: name -> (M N,) array."""
    return NodeFields(model)(X, V)


def _components_first(T: np.ndarray) -> np.ndarray:
    """(P, 2, 2) -> (2, 2, P)."""
    return np.moveaxis(T, 0, -1)


def frame_time(t: float) -> float:
    """A step time as a frame's time: rounded to 12 significant digits (the round-off of summing dt removed)."""
    return float(f"{float(t):.12g}")


class XDMFWriter(Tracker):
    """Write an XDMF time series: a frame every ``every`` steps or ``interval`` seconds, and the first and last state.

    Parameters
    ----------
    path : str or Path
        The .xdmf file; the heavy data goes to the .h5 file of the same stem beside it. Its folder is created if needed.
    every : int
        Cadence in steps (default 1), when no ``interval`` is given.
    interval : float, optional
        Cadence in simulated time (s): a frame at each multiple of it, on which the stepper ends a step (module
        docstring).
    reference : array (ndof, 3), optional
        The positions ``displacement`` is measured from (default: the first state's); a resumed run passes its original
        start.
    append : bool
        Continue the series at ``path`` from the state the run starts at (module docstring); without a series there,
        start one.
    compress : bool, optional
        Write the HDF5 datasets gzip-compressed (level :data:`GZIP_LEVEL`, with HDF5's byte shuffle), lossless: readers
        get the same float64 values, and every HDF5 reader (meshio, ParaView, h5py) decompresses them by itself. None
        (the default): compress when the grid has more than 32 x 32 nodes. A continued series may mix compressed and
        uncompressed frames.
    """

    def __init__(self, path, every: int = 1, *, interval: float | None = None, reference=None, append: bool = False,
                 compress: bool | None = None):
        self.path = Path(path)
        if self.path.suffix != ".xdmf":
            raise InputError(f"XDMFWriter.path must end in .xdmf, got {str(path)!r}", field="path", value=str(path))
        self.h5_path = self.path.with_suffix(".h5")
        self.interval = None if interval is None else real("XDMFWriter.interval", interval, positive=True)
        self.every = 1 if self.interval is not None else count("XDMFWriter.every", every)
        self._step_cadence = count("XDMFWriter.every", every)
        self.reference = None if reference is None else np.array(reference, dtype=float)
        self.append = bool(append)
        self.compress = None if compress is None else bool(compress)
        self._gzip = False
        self.frames = 0
        self._h5 = None
        self._last_step = None

    # -- XML -------------------------------------------------------------------
    def _data_item(self, parent, array: np.ndarray):
        name = f"data{self._counter}"
        self._counter += 1
        options = {"compression": "gzip", "compression_opts": GZIP_LEVEL, "shuffle": True} if self._gzip else {}
        self._h5.create_dataset(name, data=array, **options)
        dims = " ".join(str(d) for d in array.shape)
        kind = "Float" if array.dtype.kind == "f" else "Int"
        item = ET.SubElement(parent, "DataItem", DataType=kind, Dimensions=dims, Format="HDF",
                             Precision=str(array.dtype.itemsize))
        item.text = f"{self.h5_path.name}:/{name}"
        return item

    def _flush(self):
        tmp = self.path.with_name(self.path.name + ".tmp")
        try:
            self._h5.flush()
            ET.ElementTree(self._root).write(tmp, xml_declaration=True, encoding="utf-8")
            os.replace(tmp, self.path)
        except (OSError, RuntimeError) as err:
            tmp.unlink(missing_ok=True)
            raise WriteError(f"cannot write the series {str(self.path)!r}: {_reason(err)}") from None

    def initialize(self, state, stepper, steps):
        super().initialize(state, stepper, steps)
        self.fields = NodeFields(stepper.model)
        M, N = self.fields.nodes
        self._gzip = M * N > COMPRESS_NODES if self.compress is None else self.compress
        self.P0 = self.fields.positions(state.X if self.reference is None else self.reference)
        self._next = None if self.interval is None else self._after(state.t)
        self._t = state.t  # the time of the last state seen (s)
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            if self.append and self.path.exists():
                self._reopen(state)
                return
            self._start(state)
        except OSError as err:
            self.close()
            raise WriteError(f"cannot write the series {str(self.path)!r}: {_reason(err)}") from None

    def _start(self, state):
        import h5py

        self._counter = 0
        self._h5 = h5py.File(self.h5_path, "w")
        self._root = ET.Element("Xdmf", Version="3.0")
        ET.register_namespace("xi", "http://www.w3.org/2001/XInclude")
        domain = ET.SubElement(self._root, "Domain")
        self._series = ET.SubElement(domain, "Grid", Name="TimeSeries_sheet", GridType="Collection",
                                     CollectionType="Temporal")
        self._mesh_name = None
        self._frame(state, "first")

    def _reopen(self, state):
        """Continue the series at self.path from ``state``: drop the frames after it (module docstring)."""
        import h5py

        self._root, self._series = _parse(self.path)  # the XML is read once, checked and cut back here
        frames = list(self._series.findall("Grid"))
        kept, dropped = _continuation(self.path, _frames(self._series, self.path), state.step, state.t,
                                      self.interval, self._step_cadence)
        for g in frames[kept:]:
            self._series.remove(g)
        if dropped:
            log.warning("continuing the series %s from step %d (t = %.6g s): dropped its %d later frames", self.path,
                        state.step, state.t, dropped)
        kept = frames[:kept]
        self._mesh_name = kept[0].get("Name")
        used = {item.text.split(":/")[-1] for item in self._root.iter("DataItem")}
        self._h5 = h5py.File(self.h5_path, "a")
        for name in list(self._h5.keys()):  # the data of dropped frames
            if name not in used:
                del self._h5[name]
        self._counter = 1 + max(int(name[len("data"):]) for name in used)
        self.frames = len(kept)
        self._last_step = int(kept[-1].get("Name")[len("step"):])
        self._flush()

    def _after(self, t: float) -> float:
        """The first cadence time after t (interval cadence)."""
        return (np.floor(t / self.interval + 1e-9) + 1) * self.interval

    def _frame(self, state, kind: str):
        name = f"step{state.step}"
        P = self.fields.positions(state.X)
        data = self.fields(state.X, state.V)
        data["displacement"] = P - self.P0
        need = P.nbytes + sum(np.asarray(v).nbytes for v in data.values()) + DATASET_BYTES * (len(data) + 2)
        check_room(self.h5_path, need + (0 if self._mesh_name is not None else self.fields.cells.size * 8))
        grid = ET.SubElement(self._series, "Grid", Name=name, GridType="Uniform")
        try:
            if self._mesh_name is None:  # the first frame holds the topology, the others include it
                self._mesh_name = name
                topo = ET.SubElement(grid, "Topology", TopologyType="Quadrilateral",
                                     NumberOfElements=str(len(self.fields.cells)), NodesPerElement="4")
                self._data_item(topo, self.fields.cells.astype(np.int64))
            else:
                ET.SubElement(grid, "{http://www.w3.org/2001/XInclude}include",
                              xpointer=f'xpointer(//Grid[@Name="{self._mesh_name}"]/*[self::Topology])')
            ET.SubElement(grid, "Time", Value=repr(frame_time(state.t)))
            ET.SubElement(grid, "Information", Name="frame", Value=kind)
            geo = ET.SubElement(grid, "Geometry", GeometryType="XYZ")
            self._data_item(geo, P)
            for field, values in data.items():
                rank = "Vector" if values.ndim == 2 else "Scalar"
                att = ET.SubElement(grid, "Attribute", Name=field, AttributeType=rank, Center="Node")
                self._data_item(att, np.ascontiguousarray(values, dtype=float))
        except (OSError, RuntimeError) as err:
            self._series.remove(grid)
            raise WriteError(f"cannot write the series {str(self.h5_path)!r}: {_reason(err)}") from None
        self.frames += 1
        self._last_step = state.step
        self._flush()

    def next_time(self, state):
        """The next frame time (s), a multiple of ``interval``, on which the stepper is to end a step (None without
        an interval)."""
        return self._next

    def handle(self, state):
        step, self._t = state.t - self._t, state.t
        if state.step == self._last_step:
            return
        if self.interval is None:
            self._frame(state, "cadence" if state.step % self._step_cadence == 0 else "last")
        elif state.t >= self._next - max(1e-9 * self.interval, REMAINDER * step):  # the stepper's rule of reaching it
            self._frame(state, "cadence")
            self._next = self._after(max(state.t, self._next))

    def finalize(self, result):
        if self._h5 is None:
            return
        try:
            if result.state.step != self._last_step:
                self._frame(result.state, "last")  # the last good state of a stopped or diverged run
        finally:
            self.close()

    def close(self):
        """Close the HDF5 file (finalize does; a run that fails in between calls it)."""
        if self._h5 is not None:
            try:
                self._h5.close()
            except (OSError, RuntimeError):
                pass
            self._h5 = None


def _not_a_series(path) -> InputError:
    return InputError(f"cannot continue the series {str(path)!r}: it is not a series this writer wrote", field="path",
                      value=str(path))


def _parse(path):
    """(root, series) of the XDMF file ``path``: its Xdmf element and its temporal collection."""
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError):
        raise _not_a_series(path) from None
    series = root.find("Domain/Grid")
    if series is None:
        raise _not_a_series(path)
    return root, series


def _frames(series, path) -> list[tuple[int, float, str]]:
    """(step, time, kind) of each frame of a series this writer wrote; InputError when it is not one."""
    try:
        out = []
        for g in series.findall("Grid"):
            kind = g.find("Information[@Name='frame']")
            out.append((int(g.get("Name", "")[len("step"):]), float(g.find("Time").get("Value")),
                        "" if kind is None else kind.get("Value")))
    except (AttributeError, TypeError, ValueError):
        raise _not_a_series(path) from None
    return out


def continuation(path, step: int, t: float, interval: float | None = None, every: int = 1) -> tuple[int, int]:
    """How the series at ``path`` continues from the state at ``step``, time ``t`` (s): (frames kept, dropped).

    Kept are its frames up to the state (but a ``last`` frame at it); they must reach as far as an uninterrupted
    run's would: with an ``interval`` (s), the frame at or past the last multiple of it up to ``t``; else the last
    multiple of ``every`` steps up to ``step``. A series that ends earlier (a run resumed from an earlier state and
    killed before it got this far) has a hole the resumed run would not fill: InputError naming the times, and
    nothing is changed. Frames after the state (a run killed after its checkpoint) are what a continuation drops.
    Reads only.
    """
    return _continuation(path, _frames(_parse(path)[1], path), step, t, interval, every)


def _continuation(path, frames, step, t, interval, every) -> tuple[int, int]:
    """:func:`continuation` of the frames (step, time, kind) of the series at ``path``."""
    kept = [f for f in frames if f[0] < step or (f[0] == step and f[2] != "last")]
    if not kept:
        raise InputError(f"cannot continue the series {str(path)!r}: it has no frame before step {step}",
                         field="path", value=str(path))
    last_step, last_t, _ = kept[-1]
    if interval is not None:
        due = np.floor(t / interval + 1e-9) * interval  # the last cadence time up to t
        short = last_t < due - 1e-9 * interval - 1e-12 * abs(due)
    else:
        short = last_step < step - step % every
    if short:
        raise InputError(f"cannot continue the series {str(path)!r} from step {step} (t = {frame_time(t):.6g} s): "
                         f"its frames end at step {last_step} (t = {last_t:.6g} s), so those in between are missing "
                         "(the series was cut back by a resume from an earlier state); resume from a checkpoint "
                         f"at or before step {last_step}", field="resume", value=str(path))
    return len(kept), len(frames) - len(kept)


def _reason(err) -> str:
    return getattr(err, "strerror", None) or str(err) or type(err).__name__
