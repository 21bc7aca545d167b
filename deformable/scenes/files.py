r"""Scene files: a scene config as TOML, read and written through the one round trip, :mod:`deformable.tomlio`.

A scene file names its scene and overrides fields of its config::

    scene = "curtain"
    xi = 2e-4
    nodes = [48, 48]

    [force_model]        # the force model: a name (force_model = "variational"), or a table, kind and its fields
    kind = "koiter"
    E = 2e5
    nu = 0.3
    h = 1e-3

    [contact]            # the contact settings (deformable.Contact), over the scene's own
    friction = 0.5

    [[obstacles]]        # obstacles besides the scene's own (kind and the obstacle's fields)
    kind = "sphere"
    center = [0.5, 0.6, -0.3]
    radius = 0.2

    [[obstacles]]        # a triangle mesh meshio reads (deformable.MeshObstacle), relative to the file's folder
    kind = "mesh"
    path = "chair.obj"

An unknown key is an error naming it and the known ones. :func:`to_toml`
writes a resolved config that :func:`read_toml` reads back to an equal
config, with the command's own settings in a ``[run]`` table
(:func:`run_table`), which the scene readers skip.
"""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path

from .. import tomlio
from ..checks import known_keys, suggest
from ..contact.obstacles import Obstacle
from ..errors import InputError
from .config import SceneConfig, force_model_table
from .registry import SceneSpec

__all__ = ["read_toml", "read_toml_text", "to_toml", "run_table"]


def read_toml(path, **overrides) -> SceneConfig:
    """A scene config from a TOML file: ``scene = "curtain"`` plus fields to override.

    Parameters
    ----------
    path : str or Path
        The file. Keys are the fields of the scene's config (see :class:`SceneConfig` and its subclasses);
        ``size``, ``nodes`` and ``rest_metric`` are two-element arrays.
    **overrides
        Applied after the file (command-line values).

    Raises
    ------
    InputError
        Unreadable or malformed file, missing or unknown ``scene``, an unknown key (named in the message), or a
        bad value.
    """
    _, text = tomlio.load(path)
    return read_toml_text(text, source=str(path), base=Path(path).parent, **overrides)


def read_toml_text(text: str, source: str = "<string>", base=None, **overrides) -> SceneConfig:
    """Like :func:`read_toml`, from TOML text; ``source`` names it in error messages, ``base`` is the folder a
    mesh obstacle's relative ``path`` is relative to (default: the working directory)."""
    data = tomlio.loads(text, source)
    if base is not None and isinstance(data.get("obstacles"), list):
        data["obstacles"] = [_beside(t, Path(base)) for t in data["obstacles"]]
    if "scene" not in data:
        raise InputError(f"scene file {source!r} must name its scene, e.g. scene = \"curtain\"", field="scene")
    name = data.pop("scene")
    table = data.pop("run", None)  # the command's settings (run_table), not scene fields
    if table is not None and not isinstance(table, dict):
        raise InputError(f"scene file {source!r}: run must be a table [run], got {table!r}", field="run")
    if not isinstance(name, str):
        raise InputError(f"scene file {source!r}: scene must be a name, got {name!r}", field="scene", value=name)
    if name not in SceneConfig.names():
        raise InputError(f"unknown scene {name!r} in {source!r}{suggest(name, SceneConfig.names())}; choose one of "
                         f"{', '.join(SceneConfig.names())}",
                         field="scene", value=name)
    cls = SceneConfig.lookup(name)
    known_keys(data, sorted(f.name for f in fields(cls)), f"in scene file {source!r}")
    return SceneSpec(cls).config(**{**data, **overrides})  # the command line wins over the file


def _beside(table, base: Path):
    """An [[obstacles]] table with the file names in it relative to ``base``, the scene file's folder
    (:meth:`deformable.contact.obstacles.Obstacle.beside`, by its kind; anything else as it is, for the reader's
    own message)."""
    kind = table.get("kind") if isinstance(table, dict) else None
    return Obstacle.lookup(kind).beside(table, base) if kind in Obstacle.names() else table


def run_table(text: str, source: str = "<string>") -> dict:
    """The ``[run]`` table of a resolved config (backend, scheme, version, ...; empty when there is none).

    :func:`to_toml` writes it with ``run=``; the scene readers skip it, ``deformable run`` reads it.
    """
    table = tomlio.loads(text, source).get("run", {})
    if not isinstance(table, dict):
        raise InputError(f"scene file {source!r}: run must be a table [run], got {table!r}", field="run")
    return table


def to_toml(cfg: SceneConfig, run: dict | None = None) -> str:
    """The resolved config as TOML text that :func:`read_toml` reads back to an equal config (with a named
    fabric, its name and not the mu, eta, xi and shear it sets).

    The force model is its name (a model with parameters a ``[force_model]`` table), the contact settings follow
    as a ``[contact]`` table and the extra obstacles as ``[[obstacles]]`` tables;
    ``run``: settings that are not scene fields (backend, scheme, package version, ...), written as a
    ``[run]`` table after them (:func:`run_table` reads it back).
    """
    table = {"scene": cfg.scene}
    table.update(cfg.stated({f.name: getattr(cfg, f.name) for f in fields(cfg)
                             if f.name not in ("obstacles", "contact")}))
    table["force_model"] = force_model_table(cfg.force_model)  # a name, or a model's table with its parameters
    if cfg.contact is not None:
        table["contact"] = cfg.contact.table()
    if cfg.obstacles:
        table["obstacles"] = [o.table() for o in cfg.obstacles]
    if run:
        table["run"] = run
    return tomlio.dumps(table, header=f"resolved scene config ({cfg.summary})")
