"""What a time-stepping scheme is: a registered class that advances a state by one step.

A scheme is one class with a ``name`` (the registry of :mod:`deformable.registry`), built as
``Scheme.lookup(name)(model, dt, newton=..., solver=...)``, with :meth:`Scheme.step` ``(state, X0, dt) -> State``
and its ``timings``. The controller (:class:`deformable.dynamics.TimeStepper`) knows no scheme: it asks the class
whether the force model suits it (:meth:`Scheme.check`), whether it adapts its step (``adaptive``) and whether it
solves Newton's method (``implicit``). Registered here: ``"semi-implicit"`` (eq. (22)-(27), :mod:`.semi_implicit`),
``"implicit-euler"`` and ``"newmark"`` (:mod:`.implicit`, :mod:`.implicit_euler`, :mod:`.newmark`).
"""

from __future__ import annotations

from typing import ClassVar

from ..errors import InputError
from ..registry import Registered

__all__ = ["Scheme"]


class Scheme(Registered, family="scheme"):
    """A time-stepping scheme (module docstring).

    Attributes
    ----------
    name : str
    implicit : bool
        Each step minimises an incremental potential by Newton's method: the force model needs an energy.
    adaptive : bool
        A step may be refused (:class:`deformable.dynamics.implicit.StepRejected`) and retried shorter.
    order : int
        The order of accuracy in time.
    """

    implicit: ClassVar[bool] = False
    adaptive: ClassVar[bool] = False
    order: ClassVar[int] = 1

    @classmethod
    def check(cls, force_model) -> None:
        """InputError when ``force_model`` cannot be stepped by this scheme (naming the field)."""
        if cls.implicit and not force_model.has_energy:
            raise InputError(f"scheme {cls.name!r} needs an energy; the {force_model.name} force is not a gradient "
                             "(eq. (14) is not the gradient of eq. (13); use force_model 'variational', or scheme "
                             "'semi-implicit')", field="scheme", value=cls.name)
        if not cls.implicit and not force_model.has_strength_matrix:
            raise InputError(f"scheme {cls.name!r} lags the strength matrix K(r) of eq. (20), which the "
                             f"{force_model.name} model does not have; use 'implicit-euler' or 'newmark'",
                             field="scheme", value=cls.name)

    def step(self, state, X0, dt=None):
        """The state at t + dt (``X0``: the run's constraint reference)."""
        raise NotImplementedError

    #: the keys :meth:`memory` may hold
    remembers: ClassVar[tuple[str, ...]] = ()

    def memory(self) -> dict:
        """What the scheme carries from one step to the next besides the state, as numbers (name -> number or table
        of numbers; its keys among :attr:`remembers`); a checkpoint keeps it. None by default."""
        return {}

    def retune(self, model) -> None:
        """Go on with ``model``, the same grid and constraints with other material values and loads
        (:meth:`deformable.TimeStepper.retune`), keeping what the solver built; this one builds anew."""
        self.__init__(model, self.dt, **self._options)

    def restore(self, memory: dict) -> None:
        """Take up :meth:`memory` of another instance (the controller has checked its keys)."""
