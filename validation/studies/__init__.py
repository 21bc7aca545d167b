"""The validation studies and their registry :data:`STUDIES` (name -> Study, in the order they run).

Each module defines one :class:`~validation.harness.study.Study` as ``STUDY``.
"""

from __future__ import annotations

from deformable.checks import suggest

from . import (compatibility, contact, cross, fabrics, modes, paper, shells, statics, temporal, tensors, variational,
               work)

__all__ = ["STUDIES", "get_study"]

#: name -> Study, in the order ``deformable validate`` runs them
STUDIES = {m.STUDY.name: m.STUDY for m in (tensors, modes, statics, cross, temporal, compatibility, work,
                                           variational, paper, contact, shells, fabrics)}


def get_study(name: str):
    """The registered study ``name``; ValueError naming the closest and the known ones otherwise."""
    try:
        return STUDIES[name]
    except (KeyError, TypeError):
        raise ValueError(f"unknown study {name!r}{suggest(name, STUDIES)}; known: {', '.join(STUDIES)}") from None
