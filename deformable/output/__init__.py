"""Output of runs: the XDMF time series (ParaView), checkpoints, and rendered frames.

- :mod:`.series`: :class:`XDMFWriter` (a tracker) and the point fields G, B, speed, energy density;
- :mod:`.checkpoint`: save, load and write checkpoints;
- :mod:`.render`: PNG frames and a GIF of a series, offscreen with pyvista.
"""

from .checkpoint import CHECKPOINT_KEYS, CheckpointWriter, load_checkpoint, save_checkpoint
from .series import NodeFields, XDMFWriter, node_fields

__all__ = ["XDMFWriter", "NodeFields", "node_fields", "CheckpointWriter", "save_checkpoint", "load_checkpoint",
           "CHECKPOINT_KEYS"]
