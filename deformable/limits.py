r"""What a run will need, known before it starts: memory for a grid, disk for a series.

A model and its time step need memory roughly in proportion to the nodes:
the sparse Hessian or strength matrix, its factorisation and the assembly
tables. Each backend states its own bytes per node (its descriptor,
:class:`deformable.backends.Discretisation`); :func:`check_memory` refuses a
grid whose estimate exceeds the memory the machine has available, with the
estimate in the message, before anything is allocated (a bare Sheet checks
the least any grid needs, :data:`SHEET_BYTES_PER_NODE`). A series of frames
is checked against the free disk and the file-size limit
(:func:`check_series`, :func:`check_room`).
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from .errors import ResourceError, WriteError

__all__ = ["available_memory", "check_memory", "series_bytes", "check_disk", "file_size_limit", "check_room",
           "check_series", "existing", "DATASET_BYTES", "SHEET_BYTES_PER_NODE"]

#: the least any grid needs per node (bytes): coordinates, a state and its velocity
SHEET_BYTES_PER_NODE = 64.0
#: bytes per node of one frame of the XDMF series: positions, 9 scalar fields and the displacement (float64)
FRAME_BYTES_PER_NODE = 15 * 8
#: HDF5's bookkeeping per dataset (bytes), an allowance (measured: about 0.3 kB)
DATASET_BYTES = 4096
#: bytes of HDF5 bookkeeping per frame: 11 datasets (positions, 9 scalar fields, displacement)
FRAME_OVERHEAD = 11 * DATASET_BYTES


def available_memory() -> float:
    """Memory the machine has available now (bytes): MemAvailable of /proc/meminfo, else the physical memory."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        pass
    try:
        return float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return float("inf")


def _gb(x: float) -> str:
    return f"{x / 1e9:.3g} GB"


def check_memory(nodes, bytes_per_node: float = SHEET_BYTES_PER_NODE, what: str | None = None) -> float:
    """The memory a grid of ``nodes`` = (M, N) needs at ``bytes_per_node`` (bytes); ResourceError when it exceeds
    the memory available.

    The default is the least any grid needs (:data:`SHEET_BYTES_PER_NODE`), the check of a bare Sheet; a
    backend passes its own estimate per node and names itself in ``what``.
    """
    M, N = nodes
    need = bytes_per_node * float(M) * float(N)
    what = what or f"a {M}x{N} grid"
    have = available_memory()
    if need > have:
        raise ResourceError(f"{what} needs about {_gb(need)} of memory, more than the {_gb(have)} this machine has "
                            "available; choose a coarser grid", field="nodes", value=(M, N))
    return need


def series_bytes(nodes, frames: int) -> float:
    """Bytes of an XDMF series of ``frames`` frames on ``nodes`` = (M, N) (the heavy data and HDF5's bookkeeping)."""
    M, N = nodes
    return (FRAME_BYTES_PER_NODE * float(M) * float(N) + FRAME_OVERHEAD) * float(frames)


def existing(path) -> Path:
    """``path`` or the nearest of its parents that exists."""
    path = Path(path)
    while not path.exists() and path != path.parent:
        path = path.parent
    return path


def check_series(path, nodes, frames: int) -> float:
    """The bytes a series of ``frames`` frames on ``nodes`` needs; ResourceError when the file-size limit
    (``ulimit -f``) or the free disk space cannot hold it (a check before a run starts)."""
    need = series_bytes(nodes, frames)
    limit = file_size_limit()
    if need > limit:
        raise ResourceError(f"the series {str(path)!r} of about {frames:,} frames needs about {_mb(need)}, beyond "
                            f"the file-size limit of {_mb(limit)} (ulimit -f); write fewer frames (--every) or "
                            "raise the limit", field="every", value=frames)
    check_disk(Path(path).parent, need, f"the series {str(path)!r} of about {frames:,} frames")
    return need


def check_disk(folder, need: float, what: str) -> None:
    """ResourceError when ``need`` bytes exceed the free space of the file system holding ``folder``."""
    folder = existing(folder)
    try:
        free = shutil.disk_usage(folder).free
    except OSError:
        return
    if need > free:
        raise ResourceError(f"{what} needs about {_gb(need)} of disk, more than the {_gb(free)} free in "
                            f"{str(folder)!r}", field="out", value=str(folder))


def file_size_limit() -> float:
    """The largest file this process may write (bytes): the soft RLIMIT_FSIZE (``ulimit -f``), inf when none."""
    try:
        import resource

        soft = resource.getrlimit(resource.RLIMIT_FSIZE)[0]
    except (ImportError, OSError, ValueError):
        return float("inf")
    return float("inf") if soft == resource.RLIM_INFINITY else float(soft)


def check_room(path, need: float) -> None:
    """WriteError naming ``path`` unless it can grow by ``need`` bytes (file-size limit, free disk space).

    Called before a write that cannot fail half-way safely (an HDF5 file), so nothing is written in vain.
    """
    path = Path(path)
    try:
        size = path.stat().st_size if path.exists() else 0
    except OSError:
        size = 0
    limit = file_size_limit()
    if size + need > limit:
        raise WriteError(f"cannot write {str(path)!r}: it would grow to {_mb(size + need)}, beyond the file-size "
                         f"limit of {_mb(limit)} (ulimit -f)")
    try:
        free = shutil.disk_usage(existing(path.parent)).free
    except OSError:
        return
    if need > free:
        raise WriteError(f"cannot write {str(path)!r}: the disk has {_mb(free)} free, the next frame needs "
                         f"{_mb(need)}")


def _mb(x: float) -> str:
    return f"{x / 1e6:.3g} MB"


