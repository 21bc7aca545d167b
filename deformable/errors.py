r"""The project's exceptions and warnings, all of them: bad input, damaged or foreign files, numerical failure.

One hierarchy, so that a caller can tell "you asked for something wrong" from
"the numbers gave out" without parsing messages::

    DeformableError
    |-- InputError (a ValueError)          a bad value; ``field`` and ``value`` name it
    |   |-- CheckpointError                a checkpoint that is damaged, foreign, or does not fit the run
    |   |-- OutputFolderError              an output folder owned by another run, in use, or not writable
    |   `-- ResourceError                  more memory, disk or steps than the machine or the caps allow
    |-- WriteError (an OSError)            a file system failure while writing (disk full, file-size limit)
    `-- NumericalError (a RuntimeError)    the numerics failed
        |-- DivergenceError, StalledError  a run left the finite numbers, or its step shrank to nothing
        |                                  (``state``: the last good one)
        |-- ConvergenceError               Newton's method did not converge (``history``, ``X``)
        |-- StepRejected                   an implicit step's Newton solve fell short (it is retried shorter)
        `-- SingularMatrix (also an ArithmeticError)   a factorisation met a zero or, if definite, a negative pivot

Warnings, all UserWarnings: :class:`IllPosedScene` (deformations that cost no
energy), :class:`IncompatibleRestState` (rest tensors that fail the
compatibility test of eq. (10)), :class:`LoadBelowRoundOff` (a load Newton's
method cannot resolve against the elastic forces' round-off),
:class:`UnstableEquilibrium` (an equilibrium whose Newton matrix has negative
eigenvalues) and :class:`SelfContactIgnored` (self-contact asked of the
semi-implicit scheme, which has none).

Every message of an :class:`InputError` names the field and the value it
refuses, so the command line prints it as it is, in one line (exit code 2).
A run whose numerics fail never raises a SciPy error: the time stepper turns
a singular factorisation or a non-finite state into the status "diverged"
with the last good state (:class:`deformable.TimeStepper`).
"""

from __future__ import annotations

__all__ = ["DeformableError", "InputError", "CheckpointError", "OutputFolderError", "ResourceError", "WriteError",
           "NumericalError", "DivergenceError", "StalledError", "ConvergenceError", "StepRejected", "SingularMatrix",
           "IllPosedScene", "IncompatibleRestState", "LoadBelowRoundOff", "UnstableEquilibrium", "SelfContactIgnored"]


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


class DivergenceError(NumericalError):
    """The run left the range of finite numbers or a tracker's bound; ``state`` is the last good one."""

    def __init__(self, message: str, state):
        super().__init__(message)
        self.state = state


class StalledError(NumericalError):
    """An implicit step did not converge even at the smallest allowed dt; ``state`` is the last good one."""

    def __init__(self, message: str, state):
        super().__init__(message)
        self.state = state


class ConvergenceError(NumericalError):
    """Newton's method did not converge; ``history`` holds the residual norms per iteration, ``X`` the last iterate."""

    def __init__(self, message: str, history=None, X=None):
        super().__init__(message)
        self.history, self.X = history or [], X


class StepRejected(NumericalError):
    """Newton did not reach its tolerance in a step; ``report`` says how far it got (the step is not taken)."""

    def __init__(self, message: str, report=None):
        super().__init__(message)
        self.report = report


class SingularMatrix(NumericalError, ArithmeticError):
    """The factorisation met a zero pivot (or, for a matrix declared definite, a non-positive one)."""


class IllPosedScene(UserWarning):
    """The scene's settings leave deformations that cost no energy (shear or twist of the variational model)."""


class IncompatibleRestState(UserWarning):
    """The rest tensors G0, B0 of a scene fail the compatibility test of eq. (10)."""


class SelfContactIgnored(UserWarning):
    """A scene with self-contact (``Contact.self_distance``) run by the semi-implicit scheme, which has no barrier:
    the sheet may pass through itself."""


class LoadBelowRoundOff(UserWarning):
    """An applied load at or below the round-off floor of the elastic forces that Newton's steps do not resolve: it
    is lost in round-off (the stiffness is too large against the loads and the inertia for double precision)."""


class UnstableEquilibrium(UserWarning):
    """An equilibrium whose Newton matrix has negative eigenvalues: a saddle of the energy, which a perturbation
    leaves for another branch (a column beyond its Euler load, started straight)."""
