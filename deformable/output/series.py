r"""Run output: an XDMF time series for ParaView.

:class:`XDMFWriter` is a :class:`deformable.Tracker` that writes, every
``every`` steps, one frame of an XDMF 3 time series (meshio's layout, HDF5
heavy data beside the .xdmf). The mesh is the node grid as quads, stored in
the first frame and included by the others; each frame carries its own
geometry (the sheet moves; ParaView's XDMF3 reader shows it as is) and the
point fields

- ``G11, G12, G22``: the metric of eq. (4)-(5) (FD: eq. (18)),
- ``B11, B12, B22``: the curvature of eq. (8) (FD: eq. (19)),
- ``speed``: |r_t| (m/s), from the stepper's V of eq. (27),
- ``energy_density``: the integrand of eq. (13),
  ``sum_ij eta_ij (G_ij - G0_ij)^2 + xi_ij (B_ij - B0_ij)^2`` (J/m^2)
  (:func:`deformable.elasticity.energy_density`),
- ``displacement``: r - r(first frame) (m), so readers that keep the first
  geometry (meshio's TimeSeriesReader) recover the positions.

Everything is taken through the backend protocol: ``model.grid`` for positions
and velocities at the nodes, ``model.sample`` at the node coordinates for G and
B, so the writer serves the FD and the FE backend alike.

The .xdmf (XML) file is rewritten, and the HDF5 file flushed, after every
frame, so a run that is killed keeps every frame written before.
(meshio's own TimeSeriesWriter writes the XML only on exit, and puts the .h5
file in the working directory; this writer fixes both.)
"""

from __future__ import annotations

import logging
import os
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from ..dynamics.trackers import Tracker
from ..elasticity import energy_density

__all__ = ["XDMFWriter", "NodeFields", "node_fields"]

log = logging.getLogger(__name__)


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
        mat = scene.material
        self.eta = mat.tensor("eta", (M, N)).reshape(2, 2, -1)  # (2, 2, P)
        self.xi = mat.tensor("xi", (M, N)).reshape(2, 2, -1)
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
        stretching, bending = energy_density(self.eta, self.xi, _components_first(G), self.G0,
                                             _components_first(B), self.B0)
        density = stretching + bending
        return {
            "G11": G[:, 0, 0], "G12": G[:, 0, 1], "G22": G[:, 1, 1],
            "B11": B[:, 0, 0], "B12": B[:, 0, 1], "B22": B[:, 1, 1],
            "speed": np.linalg.norm(vel, axis=1), "energy_density": density,
        }


def node_fields(model, X, V) -> dict[str, np.ndarray]:
    """The point fields of the module docstring for one state: name -> (M N,) array."""
    return NodeFields(model)(X, V)


def _components_first(T: np.ndarray) -> np.ndarray:
    """(P, 2, 2) -> (2, 2, P)."""
    return np.moveaxis(T, 0, -1)


class XDMFWriter(Tracker):
    """Write an XDMF time series, one frame every ``every`` steps (and the first and last state).

    Parameters
    ----------
    path : str or Path
        The .xdmf file; the heavy data goes to the .h5 file of the same stem beside it.
    every : int
        Cadence in steps.
    """

    def __init__(self, path, every: int = 1):
        self.path = Path(path)
        self.h5_path = self.path.with_suffix(".h5")
        self.every = int(every)
        if self.every < 1:
            raise ValueError(f"every must be a positive integer, got {every!r}")
        self.frames = 0
        self._h5 = None
        self._last_step = None

    # -- XML -------------------------------------------------------------------
    def _data_item(self, parent, array: np.ndarray):
        name = f"data{self._counter}"
        self._counter += 1
        self._h5.create_dataset(name, data=array)
        dims = " ".join(str(d) for d in array.shape)
        kind = "Float" if array.dtype.kind == "f" else "Int"
        item = ET.SubElement(parent, "DataItem", DataType=kind, Dimensions=dims, Format="HDF",
                             Precision=str(array.dtype.itemsize))
        item.text = f"{self.h5_path.name}:/{name}"
        return item

    def _flush(self):
        self._h5.flush()
        tmp = self.path.with_name(self.path.name + ".tmp")
        ET.ElementTree(self._root).write(tmp, xml_declaration=True, encoding="utf-8")
        os.replace(tmp, self.path)

    def initialize(self, state, stepper, steps):
        import h5py

        super().initialize(state, stepper, steps)
        self.fields = NodeFields(stepper.model)
        self._counter = 0
        self._h5 = h5py.File(self.h5_path, "w")
        self._root = ET.Element("Xdmf", Version="3.0")
        ET.register_namespace("xi", "http://www.w3.org/2001/XInclude")
        domain = ET.SubElement(self._root, "Domain")
        self.P0 = self.fields.positions(state.X)
        self._series = ET.SubElement(domain, "Grid", Name="TimeSeries_sheet", GridType="Collection",
                                     CollectionType="Temporal")
        self._mesh_name = None
        self._frame(state)

    def _frame(self, state):
        name = f"step{state.step}"
        grid = ET.SubElement(self._series, "Grid", Name=name, GridType="Uniform")
        if self._mesh_name is None:  # the first frame holds the topology, the others include it
            self._mesh_name = name
            topo = ET.SubElement(grid, "Topology", TopologyType="Quadrilateral",
                                 NumberOfElements=str(len(self.fields.cells)), NodesPerElement="4")
            self._data_item(topo, self.fields.cells.astype(np.int64))
        else:
            ET.SubElement(grid, "{http://www.w3.org/2001/XInclude}include",
                          xpointer=f'xpointer(//Grid[@Name="{self._mesh_name}"]/*[self::Topology])')
        ET.SubElement(grid, "Time", Value=repr(float(state.t)))
        P = self.fields.positions(state.X)
        geo = ET.SubElement(grid, "Geometry", GeometryType="XYZ")
        self._data_item(geo, P)
        data = self.fields(state.X, state.V)
        data["displacement"] = P - self.P0
        for name, values in data.items():
            kind = "Vector" if values.ndim == 2 else "Scalar"
            att = ET.SubElement(grid, "Attribute", Name=name, AttributeType=kind, Center="Node")
            self._data_item(att, np.ascontiguousarray(values, dtype=float))
        self.frames += 1
        self._last_step = state.step
        self._flush()

    def handle(self, state):
        if state.step != self._last_step:
            self._frame(state)

    def finalize(self, result):
        if self._h5 is None:
            return
        if result.state.step != self._last_step:
            self._frame(result.state)  # the last good state of a stopped or diverged run
        self._h5.close()
        self._h5 = None


