r"""The one registry mechanism of the project: every extension point is a family of classes known by name.

A family is declared once, by a class that subclasses :class:`Registered`
with a ``family`` keyword; each of its subclasses that sets a ``name`` is
registered under it when its class statement runs (``__init_subclass__``,
the model of py-pde's solver registry, ``pde/solvers/base.py``)::

    class ForceModel(Registered, family="force model"): ...

    class Variational(EnergyModel):
        name = "variational"

    ForceModel.lookup("variational")      # the class
    ForceModel.from_name("variational")   # an instance
    ForceModel.names()                    # ("tpbf87", "frozen", "variational", ...)

A class defined outside the package (a user's energy, a user's scene)
registers in the same way, by subclassing: nothing else needs to change. An
unknown name is an :class:`~deformable.errors.InputError` that lists the
known ones, after the closest of them (``did you mean 'variational'?``,
:func:`deformable.checks.suggest`). A second class under a name that another
module already holds is refused; redefining a class in the same module (a
notebook cell run again) replaces it.

Families: force models (:class:`deformable.physics.ForceModel`), backends
(:class:`deformable.backends.Discretisation`), time-stepping schemes
(:class:`deformable.dynamics.Scheme`), line searches
(:class:`deformable.solve.LineSearch`), obstacles
(:class:`deformable.contact.Obstacle`) and scenes
(:class:`deformable.scenes.SceneConfig`).
"""

from __future__ import annotations

from typing import ClassVar

from .checks import suggest
from .errors import InputError

__all__ = ["Registered"]


class Registered:
    """Base of every registry family (module docstring).

    Class attributes
    ----------------
    name : str
        The name a subclass is registered under ("" for abstract classes: not registered).
    family : str
        The family's name, for messages ("force model", "backend", ...); set by the family's root.
    rank : int
        Where the class stands when a family is listed (:meth:`names`): by rank, then in registration order.
    """

    name: ClassVar[str] = ""
    family: ClassVar[str] = ""
    rank: ClassVar[int] = 100
    _registry: ClassVar[dict[str, type]]

    def __init_subclass__(cls, family: str | None = None, **kwargs):
        super().__init_subclass__(**kwargs)
        if family is not None:
            cls.family, cls._registry = family, {}
            return
        if not hasattr(cls, "_registry"):
            raise TypeError(f"{cls.__qualname__} subclasses Registered without a family")
        name = cls.__dict__.get("name", "")
        if not name:
            return
        if not isinstance(name, str):
            raise TypeError(f"{cls.__qualname__}.name must be a string, got {name!r}")
        known = cls._registry.get(name)
        if known is not None and (known.__module__, known.__qualname__) != (cls.__module__, cls.__qualname__):
            raise InputError(f"{cls.family} {name!r} is already {known.__module__}.{known.__qualname__}; "
                             f"{cls.__module__}.{cls.__qualname__} needs another name", field="name", value=name)
        cls._registry[name] = cls

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """The registered names of the family (or of the subclasses of ``cls`` in it), by rank, then in
        registration order."""
        known = [(c.rank, k, n) for k, (n, c) in enumerate(cls._registry.items()) if issubclass(c, cls)]
        return tuple(n for _, _, n in sorted(known))

    @classmethod
    def lookup(cls, name) -> type:
        """The registered class called ``name``; InputError listing the known names for any other value."""
        found = cls._registry.get(name) if isinstance(name, str) else None
        if found is None or not issubclass(found, cls):
            raise InputError(f"unknown {cls.family} {name!r}{suggest(name, cls.names())}; choose one of "
                             f"{', '.join(cls.names())}",
                             field=cls.family, value=name)
        return found

    @classmethod
    def from_name(cls, name, **kwargs):
        """An instance of the class registered as ``name`` (keyword arguments go to its constructor)."""
        return cls.lookup(name)(**kwargs)
