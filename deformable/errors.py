r"""The project's exceptions: bad input, damaged or foreign files, numerical failure.

One hierarchy, so that a caller can tell "you asked for something wrong" from
"the numbers gave out" without parsing messages::

    DeformableError
    |-- InputError (a ValueError)          a bad value; ``field`` and ``value`` name it
    |   |-- CheckpointError                a checkpoint that is damaged, foreign, or does not fit the run
    |   |-- OutputFolderError              an output folder owned by another run, in use, or not writable
    |   `-- ResourceError                  more memory, disk or steps than the machine or the caps allow
    |-- WriteError (an OSError)            a file system failure while writing (disk full, file-size limit)
    `-- NumericalError (a RuntimeError)    the numerics failed
        |-- DivergenceError, StalledError  (:mod:`deformable.dynamics`; ``state``: the last good one)
        `-- ConvergenceError               (:mod:`deformable.solve.newton`)

Every message of an :class:`InputError` names the field and the value it
refuses, so the command line prints it as it is, in one line (exit code 2).
A run whose numerics fail never raises a SciPy error: the time stepper turns
a singular factorisation or a non-finite state into the status "diverged"
with the last good state (:class:`deformable.TimeStepper`).
"""

from __future__ import annotations

__all__ = ["DeformableError", "InputError", "CheckpointError", "OutputFolderError", "ResourceError", "WriteError",
           "NumericalError"]


class DeformableError(Exception):
    """Base of every exception the project raises on purpose."""


class InputError(DeformableError, ValueError):
    """A bad value given to the library or the command line.

    Parameters
    ----------
    message : str
        One line naming the field and the refused value.
    field, value : optional
        The field (e.g. ``"Material.mu"``, ``"--dt"``) and the value, for callers that act on them.
    """

    def __init__(self, message: str, *, field: str | None = None, value=None):
        super().__init__(message)
        self.field, self.value = field, value


class CheckpointError(InputError):
    """A checkpoint file that cannot be read, is damaged, or does not fit the run it should continue."""


class OutputFolderError(InputError):
    """An output folder that holds another run's results, is used by a running run, or cannot be written."""


class ResourceError(InputError):
    """A run that would need more memory, disk space or steps than the machine has or the caps allow."""


class WriteError(DeformableError, OSError):
    """Writing a result file failed (disk full, file-size limit, folder removed); the message names the file."""


class NumericalError(DeformableError, RuntimeError):
    """The numerics failed (divergence, a step that does not converge, a singular system)."""
