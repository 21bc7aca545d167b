"""Output of runs: the XDMF time series (ParaView), checkpoints, and rendered frames.

- :mod:`.series`: :class:`XDMFWriter` (a tracker) and the point fields G, B, speed, energy density;
- :mod:`.checkpoint`: save, load and write checkpoints;
- :mod:`.render`: PNG frames and a GIF of a series, offscreen with pyvista;
- :mod:`.folder`: output folders a run owns (no run replaces another's results; a lock).

A series and its frames from one's own script (folders are created as needed)::

    import deformable as dm
    result = dm.TimeStepper(model, dt).run(X0, t_end=1.0, trackers=[dm.XDMFWriter("out/run.xdmf", interval=0.02)])
    dm.render_series("out/run.xdmf", "out/frames", field="speed")
"""

from .checkpoint import CHECKPOINT_KEYS, CheckpointWriter, load_checkpoint, save_checkpoint
from .folder import RunFolder
from .render import FIELDS, read_series, render_frame, render_series
from .series import NodeFields, XDMFWriter, frame_time, node_fields

__all__ = ["XDMFWriter", "NodeFields", "node_fields", "frame_time", "CheckpointWriter", "save_checkpoint",
           "load_checkpoint", "CHECKPOINT_KEYS", "RunFolder", "render_series", "render_frame", "read_series", "FIELDS"]
