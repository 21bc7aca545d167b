r"""``deformable scenes``: the scene catalogue, one line a scene (its name and what it is).

The scenes are the registered scene configs (:data:`deformable.scenes.SCENES`, a live view of the registry),
so a scene a module registers is listed without changing this command. ``deformable run SCENE --show-config``
gives a scene's fields, their values, units and meanings.
"""

from __future__ import annotations

from deformable import scenes

__all__ = ["catalogue", "configure", "execute"]


def configure(parser) -> None:
    """``deformable scenes`` takes no arguments."""


def catalogue() -> list[str]:
    """One line a registered scene: its name, padded, and its one-line summary."""
    names = list(scenes.SCENES)
    width = max((len(n) for n in names), default=0)
    return [f"{n.ljust(width)}  {scenes.SCENES[n].summary or '(no summary)'}" for n in names]


def execute(args) -> int:
    """``deformable scenes``: prints the catalogue; 0."""
    print("\n".join(catalogue()))
    return 0
