r"""Backends by name: each discretisation declares itself once, in a descriptor the core and the harness read.

A backend package (``fdmodel``, ``femodel``, or one of a user's) subclasses
:class:`Discretisation` with a ``name`` (the project's one registry,
:mod:`deformable.registry`) and states what the core and the harness would
otherwise look up by the backend's name: its model class, the unit of its
grid sizes, its memory per node, its relative cost, its stiffest membrane
mode and its contact points per cell side. Nothing in the core names a
backend: an installed backend declares its descriptor as an entry point of
the group ``deformable.backends`` (``fd = "fdmodel.backend:FiniteDifferences"``
in pyproject.toml), which :meth:`Discretisation.lookup` and
:meth:`Discretisation.names` load on first use; importing a backend's package
registers it as well (a backend defined in a notebook)::

    Discretisation.names()                                # ("fd", "fe", ...): the installed backends
    model = Discretisation.lookup(name).build(scene)      # a model of the backend called name

The model's own class knows its descriptor (``model.descriptor``), so that
it checks a scene against its own memory estimate before it allocates
anything (:func:`check_scene`).
"""

from __future__ import annotations

import logging
from importlib.metadata import entry_points
from typing import ClassVar

from ..errors import InputError
from ..limits import check_memory
from ..registry import Registered
from ..scene.scene import Scene

__all__ = ["Discretisation", "check_scene", "GROUP"]

log = logging.getLogger(__name__)

#: the entry-point group an installed backend declares its descriptor in
GROUP = "deformable.backends"


class Discretisation(Registered, family="backend"):
    """A backend's descriptor (module docstring); a subclass sets the class attributes.

    Class attributes
    ----------------
    name : str
        The registry name (``fdmodel``'s is fd, ``femodel``'s fe).
    label : str
        What it is, in words.
    model : type
        The model class, ``model(scene, **options)`` (it satisfies :class:`deformable.Backend`).
    grid : "nodes" or "elements"
        What a grid size counts a side (FD: nodes; FE: elements, one fewer than nodes).
    bytes_per_node : dict
        Peak resident memory per node (bytes) of a model and its step, for an "implicit" step (Newton on an
        energy's Hessian, 3 ndof) and a "semi-implicit" one (the strength matrix of eq. (20)); measured.
    cost : float
        Work per node and step relative to FD's (sweep estimates order cases by it).
    membrane_eigenvalue : float
        The largest eigenvalue of the membrane operator per unit alpha against the mass, times h^2 (FD 4,
        bicubic Hermite about 91): the stable step of the paper's scheme (eq. 25) scales with it.
    contact_samples : int
        Contact points per cell side by default (:mod:`deformable.contact.points`).
    scene_fraction : float
        A scene's grid, written in FD's nodes, taken as this fraction in the backend's own unit when the user
        did not set it (:meth:`scene_nodes`; FD 1, FE 0.5).
    """

    label: ClassVar[str] = ""
    model: ClassVar[type]
    grid: ClassVar[str] = "nodes"
    bytes_per_node: ClassVar[dict[str, float]] = {}
    cost: ClassVar[float] = 1.0
    membrane_eigenvalue: ClassVar[float] = 4.0
    contact_samples: ClassVar[int] = 1
    scene_fraction: ClassVar[float] = 1.0
    #: the installed backends' entry points have been read in this process (:meth:`discover`)
    _discovered: ClassVar[bool] = False

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if "model" in cls.__dict__:
            cls.model.descriptor = cls

    @classmethod
    def discover(cls) -> None:
        """Load the descriptors of the installed backends (entry points of :data:`GROUP`) not yet registered;
        one that fails to load is left out with a warning naming it. (Reading the installed packages' entry points
        takes about 5 ms: :meth:`names` does it once per process, :meth:`lookup` again only for a name it misses.)"""
        Discretisation._discovered = True
        for point in entry_points(group=GROUP):
            if point.name in Discretisation._registry:
                continue
            try:
                point.load()
            except Exception as err:  # noqa: BLE001 - a broken third-party backend must not take the others down
                log.warning("backend %r (%s) could not be loaded: %s", point.name, point.value, err)

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """The installed backends' names (their entry points loaded), then any registered by an import."""
        if not Discretisation._discovered:
            cls.discover()
        return super().names()

    @classmethod
    def lookup(cls, name) -> type:
        """The descriptor of the backend called ``name``, its entry point loaded when it is not yet registered;
        InputError listing the known names for any other value."""
        if not (isinstance(name, str) and name in Discretisation._registry):
            cls.discover()
        return super().lookup(name)

    @classmethod
    def build(cls, scene, **options):
        """The model of ``scene`` on this backend (``options`` go to the model class, e.g. FD ``weighting``)."""
        return cls.model(scene, **options)

    @classmethod
    def nodes(cls, size: int) -> int:
        """The nodes a side of a grid of ``size`` in the backend's own unit (:attr:`grid`)."""
        return int(size) + (1 if cls.grid == "elements" else 0)

    @classmethod
    def scene_nodes(cls, nodes) -> tuple[int, int]:
        """The nodes a side this backend takes for a scene whose grid ``nodes`` = (M, N) was not set by the user.

        The scenes' grids are written in FD's nodes; a backend whose element is richer (:attr:`scene_fraction`
        below 1) takes that fraction as elements a side, for an accuracy comparable to FD's at a cost closer to
        it (FE: bicubic Hermite elements, half as many a side: the paper and cross studies compare FD 64 x 64
        nodes with FE 32 x 32 elements).
        """
        if cls.scene_fraction == 1.0:
            return tuple(int(n) for n in nodes)
        return tuple(max(3, round(cls.scene_fraction * (int(n) - 1)) + 1) for n in nodes)

    @classmethod
    def memory(cls, nodes, force_model) -> float:
        """Bytes a model of ``nodes`` = (M, N) and its time step need (an estimate, :attr:`bytes_per_node`)."""
        M, N = nodes
        return cls.bytes_per_node["implicit" if force_model.implicit else "semi-implicit"] * float(M) * float(N)


def check_scene(scene, backend: type[Discretisation]) -> None:
    """What a backend checks before it allocates anything: a Scene, whose grid fits in memory on ``backend``."""
    if not isinstance(scene, Scene):
        raise InputError(f"a {backend.name.upper()} model needs a Scene, got {scene!r}", field="scene", value=scene)
    M, N = scene.sheet.nodes
    check_memory(scene.sheet.nodes, backend.memory((1, 1), scene.force_model),
                 f"a {M}x{N} grid on the {backend.name} backend ({scene.force_model} model)")
