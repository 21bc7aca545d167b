r"""The catalogue by name: the registered scene configs (:class:`~deformable.scenes.config.SceneConfig`), a scene's
config with overrides, its Scene, and one function per shipped scene.

:data:`SCENES` is a live, read-only view of the registry (a scene a user
registers appears in it): name -> :class:`SceneSpec`, which builds the
scene's config and its Scene::

    scene = scenes.curtain(nodes=(32, 32))             # a Scene
    cfg = scenes.config("curtain", xi=1e-4)            # the config, overridden
    scene = scenes.build(cfg)                          # its Scene
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass

from ..scene.scene import Scene
from .cloth import HangingConfig  # noqa: F401  (registers the scenes)
from .config import SceneConfig
from .contact import DrapeConfig, FloorConfig, SphereConfig  # noqa: F401
from .curtain import CurtainConfig, PaperConfig, SilkyCurtainConfig  # noqa: F401
from .flag import FlagConfig  # noqa: F401
from .panel import PanelConfig, SoftPanelConfig  # noqa: F401
from .strip import CoilConfig  # noqa: F401

__all__ = ["SCENES", "SceneSpec", "config", "build", "hanging", "curtain", "curtain_silky", "paper", "flag", "floor",
           "sphere", "drape", "coil", "panel", "panel_soft"]


@dataclass(frozen=True)
class SceneSpec:
    """A scene of the catalogue: its config class, with the config and the Scene it builds.

    Calling it, ``spec(nodes=(M, N), **fields)``, builds the Scene.
    """

    config_class: type

    @property
    def name(self) -> str:
        return self.config_class.name

    @property
    def summary(self) -> str:
        return self.config_class.summary

    @property
    def dt(self) -> float:
        """The default time step (s)."""
        return self.config().dt

    def config(self, **fields_) -> SceneConfig:
        """The scene's config with some fields overridden (unknown fields: InputError naming them)."""
        base = self.config_class()
        return base.replace(**fields_) if fields_ else base

    def __call__(self, nodes=None, **fields_) -> Scene:
        if nodes is not None:
            fields_["nodes"] = tuple(nodes)
        return self.config(**fields_).build()


class _Catalogue(Mapping):
    """name -> SceneSpec over the registry of scene configs (module docstring)."""

    def __getitem__(self, name) -> SceneSpec:
        if not isinstance(name, str) or name not in SceneConfig.names():
            raise KeyError(name)
        return SceneSpec(SceneConfig.lookup(name))

    def __iter__(self) -> Iterator[str]:
        return iter(SceneConfig.names())

    def __len__(self) -> int:
        return len(SceneConfig.names())


#: the scenes of the catalogue by name (a live view of the registry)
SCENES = _Catalogue()


def config(name: str, **fields_) -> SceneConfig:
    """The config of the named scene with some fields overridden.

    Raises
    ------
    InputError
        Unknown scene name (the message names the known ones), unknown field, or a bad value.
    """
    return SceneSpec(SceneConfig.lookup(name)).config(**fields_)


def build(cfg: SceneConfig) -> Scene:
    """The Scene of a config."""
    return cfg.build()


def hanging(nodes=None, **fields_) -> Scene:
    """Cloth pinned at two top corners, falling from horizontal under gravity (:class:`HangingConfig`)."""
    return SCENES["hanging"](nodes, **fields_)


def curtain(nodes=None, **fields_) -> Scene:
    """The opening curtain of Figs 3-4 (:class:`CurtainConfig`, :mod:`deformable.scenes.curtain`).

    1 m wide, 1.2 m tall, in denim (``fabric = "denim"``: 324 g/m^2, bending lengths 3.1 / 2.7 cm warp / weft),
    gamma = 0.2 kg/(m^2 s), scale 1, on 64 x 64 nodes (its narrowest fold at least 3 grid spacings wide); the rod
    end drawn 0.6 m over 1.6 s; 2 s of motion at dt = 5 ms (implicit Euler).
    """
    return SCENES["curtain"](nodes, **fields_)


def curtain_silky(nodes=None, **fields_) -> Scene:
    """Fig. 5: the curtain in the lightest measured fabric, jacket-polyester, on 80 x 80 nodes
    (:class:`SilkyCurtainConfig`)."""
    return SCENES["curtain-silky"](nodes, **fields_)


def paper(nodes=None, **fields_) -> Scene:
    """Fig. 6: the curtain in paper (ARCSim's estimate), its folds 2.17 times as wide as the silky curtain's by
    theory (:class:`PaperConfig`)."""
    return SCENES["paper"](nodes, **fields_)


def flag(nodes=None, **fields_) -> Scene:
    """The flag of Figs 7-8: pole edge pinned, coils beside the pole, wind and its pull along the flag (:class:`FlagConfig`)."""
    return SCENES["flag"](nodes, **fields_)


def floor(nodes=None, **fields_) -> Scene:
    """A 1 m cloth falling flat from 0.3 m onto the floor and settling (friction 0.3, barrier within 1 mm)."""
    return SCENES["floor"](nodes, **fields_)


def sphere(nodes=None, **fields_) -> Scene:
    """A 1 m cloth dropped from 5 cm above onto a ball of radius 0.25 m (friction 0.3)."""
    return SCENES["sphere"](nodes, **fields_)


def drape(nodes=None, **fields_) -> Scene:
    """The Cusick drape test: a 0.3 m square cloth on a round table 0.18 m across (:class:`DrapeConfig`)."""
    return SCENES["drape"](nodes, **fields_)


def coil(nodes=None, **fields_) -> Scene:
    """A 0.6 m x 0.04 m strip dropped end first onto the floor, folding onto itself (:class:`CoilConfig`)."""
    return SCENES["coil"](nodes, **fields_)


def panel(nodes=None, **fields_) -> Scene:
    """Section 3.2, Fig. 1: a 1 m square, border pinned, under a 10 Pa pressure, eta = 2e4 N/m: stays nearly flat
    (:class:`PanelConfig`, :mod:`deformable.scenes.panel`)."""
    return SCENES["panel"](nodes, **fields_)


def panel_soft(nodes=None, **fields_) -> Scene:
    """Fig. 2: the panel with eta = 20 N/m, 1000 times softer in stretching: stretches and bulges
    (:class:`SoftPanelConfig`)."""
    return SCENES["panel-soft"](nodes, **fields_)
