"""What the commands share of their arguments: the options of ``run`` and ``sweep`` (``--backend``,
``--force-model``, ``--grid``, ``--dt``, ``--t-end``, ...), the one grid grammar (``MxN``, ``[M, N]``, ``N``),
``KEY=VALUE`` scene fields, and a scene given by name or as a TOML file."""

from __future__ import annotations

import math
import re
import tomllib

from deformable import scenes, tomlio
from deformable.backends.registry import Discretisation
from deformable.dynamics import Scheme
from deformable.errors import InputError
from deformable.physics.force_models import ForceModel

__all__ = ["backend_option", "force_model_option", "run_options", "show_config_option", "print_config",
           "check_backend", "check_force_model", "option_fields", "parse_grid", "parse_overrides", "scene_config",
           "scene_source", "sets_grid", "positive"]


def backend_option(parser, default=None, default_text="the scene file's [run] backend, else fd",
                   many: bool = False) -> None:
    """``--backend``, its choices (the registered backends) in its help."""
    names = Discretisation.names()
    choices = f"one of {', '.join(names)}" + (f", or several comma-separated (e.g. {','.join(names)})" if many else "")
    parser.add_argument("--backend", default=default, metavar="NAME" + (",..." if many else ""),
                        help=f"discretisation: {choices} (default: {default_text})")


def force_model_option(parser, default_text="the scene's, variational") -> None:
    """``--force-model``, its choices (the registered force models) in its help."""
    parser.add_argument("--force-model", default=None, metavar="MODEL",
                        help=f"force model: one of {', '.join(ForceModel.names())} (default: {default_text}); frozen "
                        "takes the scene keys alpha and beta")


def run_options(parser, sweep: bool = False) -> None:
    """The options ``deformable run`` and ``deformable sweep`` share: --backend, --force-model, --grid, --dt,
    --t-end (and, for run only, --scheme and --steps); :func:`option_fields` reads them."""
    if sweep:
        backend_option(parser, default="fd", default_text="fd", many=True)
    else:
        backend_option(parser)
    force_model_option(parser)
    if not sweep:  # (a sweep's cases step with the backend's default scheme: validation.harness.sweep)
        parser.add_argument("--scheme", default=None, metavar="SCHEME",
                            help=f"time-stepping scheme: one of {', '.join(Scheme.names())} (default: the scene file's "
                            "[run] scheme, else implicit-euler "
                            "for the variational model, semi-implicit for tpbf87 and frozen)")
    length = parser if sweep else parser.add_mutually_exclusive_group()
    if not sweep:
        length.add_argument("--steps", type=str, default=None,
                            help="run until this step number (default: run to t_end)")
    length.add_argument("--t-end", type=str, default=None, metavar="T",
                        help="run until this time (s), exactly (default: the scene's t_end)")
    parser.add_argument("--dt", type=str, default=None,
                        help="time step (s) (default: the scene's, or half the backend's stable step if smaller)")
    parser.add_argument("--grid", default=None, metavar="MxN",
                        help="node grid MxN (default: the scene's nodes on fd; on fe half as many elements a side, "
                        "e.g. 64x64 nodes -> 32x32 elements, 33x33 nodes)")


def show_config_option(parser) -> None:
    """``--show-config``: print the scene's config, field by field, and exit (:func:`print_config`)."""
    parser.add_argument("--show-config", action="store_true",
                        help="print every field of the scene's config (value after KEY=VALUE, the scene file and "
                        "the options; default; unit; meaning) and exit without running (default: off)")


def print_config(cfg: scenes.SceneConfig) -> int:
    """Print the aligned table of a config's fields (:func:`deformable.scenes.config_table`); 0."""
    print("\n".join(scenes.config_table(cfg)))
    return 0


def _registered(family, name, field: str) -> str:
    """``name`` if ``family`` (a registry) knows it; else its lookup's InputError, prefixed by the field."""
    try:
        family.lookup(name)
    except InputError as err:
        raise InputError(f"{field}: {err}", field=field, value=name) from None
    return name


def check_backend(name, field: str = "--backend") -> str:
    """``name`` if it is a registered backend; else InputError naming the field, the value and the choices."""
    return _registered(Discretisation, name, field)


def check_force_model(name, field: str = "--force-model") -> str:
    """``name`` if it is a registered force model; else InputError naming the field, the value and the choices."""
    return _registered(ForceModel, name, field)


def option_fields(args, dt=None, t_end: bool = True) -> dict:
    """The scene fields the shared options set (--grid: nodes, --dt, --t-end, --force-model), checked;
    ``dt`` the checked --dt where the caller has it; ``t_end`` False leaves --t-end out (a run's length, which
    :func:`validation.commands.run.prepare` sets)."""
    out = {}
    if getattr(args, "grid", None) is not None:
        out["nodes"] = parse_grid(args.grid)
    dt = dt if dt is not None else positive("dt", getattr(args, "dt", None))
    if dt is not None:
        out["dt"] = dt
    end = positive("t-end", getattr(args, "t_end", None)) if t_end else None
    if end is not None:
        out["t_end"] = end
    if getattr(args, "force_model", None) is not None:
        out["force_model"] = check_force_model(args.force_model)
    return out


# -- parsing -------------------------------------------------------------------------
#: a node grid as text: MxN, or a TOML array [M, N] (as a scene file and the resolved config write it)
GRID = re.compile(r"\s*(\d+)\s*[xX]\s*(\d+)\s*|\s*\[\s*(\d+)\s*,\s*(\d+)\s*,?\s*\]\s*")


def parse_grid(text: str, field: str = "--grid", square: bool = False) -> tuple[int, int]:
    """A node grid (M, N) from ``"MxN"`` or ``"[M, N]"``; with ``square`` (the KEY=VALUE form of run and sweep,
    ``nodes=...``) also ``"N"`` for N x N. The one grid grammar of the commands. InputError naming ``field``
    unless two integers >= 3."""
    text = str(text)
    m = GRID.fullmatch(text) or (re.fullmatch(r"\s*(\d+)\s*", text) if square else None)
    if not m:
        raise InputError(f"{field}: malformed grid {text!r}: expected MxN or [M, N], e.g. 32x32"
                         + (" (or N for NxN)" if square else ""), field=field, value=text)
    numbers = [int(g) for g in m.groups() if g is not None]
    M, N = numbers if len(numbers) == 2 else numbers * 2
    if min(M, N) < 3:
        raise InputError(f"{field}: grid {text!r} needs at least 3 nodes a side", field=field, value=text)
    return M, N


def parse_overrides(items) -> dict:
    """``["eta=25", "nodes=16x16", "force_model=frozen"]`` -> a dict of scene fields.

    Values are TOML, a bare word is text; ``nodes`` is a grid, ``MxN``, ``[M, N]`` or ``N`` (:func:`parse_grid`,
    as ``deformable sweep`` reads it). InputError for an item without ``=``, a malformed grid or a key given
    twice; unknown keys are refused by the scene's config.
    """
    out = {}
    for item in items:
        key, sep, text = str(item).partition("=")
        key = key.strip()
        if not sep or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", key):
            raise InputError(f"expected KEY=VALUE, e.g. eta=25, got {item!r}", field="KEY=VALUE", value=item)
        if key in out:
            raise InputError(f"scene field {key} is given twice on the command line", field=key, value=text)
        if key == "nodes":
            out[key] = parse_grid(text, field=key, square=True)
            continue
        try:
            value = tomllib.loads(f"v = {text}")["v"]
        except tomllib.TOMLDecodeError:
            value = text.strip()  # a bare word: a string (force_model=frozen)
        out[key] = tuple(value) if isinstance(value, list) else value
    return out


def scene_config(scene: str, **overrides) -> scenes.SceneConfig:
    """The config of a scene name or a TOML scene file (``*.toml``), with overrides; InputError naming what is wrong."""
    if scene.endswith(".toml"):
        return scenes.read_toml(scene, **overrides)
    return scenes.config(scene, **overrides)


def scene_source(scene: str) -> tuple[str | None, str]:
    """(the text of a scene file, its name) or (None, a scene name)."""
    if not scene.endswith(".toml"):
        return None, scene
    return tomlio.read_text(scene, field="scene"), scene


def sets_grid(text: str | None, source: str) -> bool:
    """Whether a scene file's text (None for a scene name: no) sets the grid, ``nodes``: a grid so set is taken as
    is on every backend (:class:`deformable.Simulation`)."""
    return text is not None and "nodes" in tomlio.loads(text, source)


def positive(name: str, text, kind=float):
    """``text`` as a positive finite ``kind`` (float or int), None for None; InputError naming ``--name``."""
    if text is None:
        return None
    try:
        value = kind(text)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"--{name} must be a positive {'integer' if kind is int else 'number'}, got {text!r}",
                     field=f"--{name}", value=text) from None
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"--{name} must be positive, got {text!r}", field=f"--{name}", value=text)
    return value
