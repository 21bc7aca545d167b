r"""What each field of a scene's config means, and its unit, read from the config classes' docstrings.

The one place the fields are documented is the numpy ``Parameters`` section of
their config class (:class:`~deformable.scenes.config.SceneConfig` for the
fields every scene has, the scene's own class for the fields it adds). Each
entry is ``name : type`` (or ``name, other : type``) and an indented
description whose first sentence ends with the unit in parentheses:
``Stretching weight of eq. (13) (N/m).`` -- the meaning is the text before it.
The unit is ``1`` for a dimensionless number and ``-`` for a value that has
none (a name, a table, a seed). A subclass's entry replaces its base's.

:func:`field_docs` gives name -> :class:`FieldDoc`; :func:`config_table` the
aligned table of a config's fields (value, default, unit, meaning) that
``deformable run --show-config`` prints.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, fields

__all__ = ["FieldDoc", "config_rows", "config_table", "field_docs"]

#: an entry's head line in a Parameters section: "name : type" or "a, b : type"
_HEAD = re.compile(r"^(?P<names>[A-Za-z_][A-Za-z0-9_]*(?:\s*,\s*[A-Za-z_][A-Za-z0-9_]*)*)\s+:\s*(?P<type>.*)$")
#: the first sentence's end: "meaning (unit)." (the first parenthesis followed by a full stop or the end)
_UNIT = re.compile(r"^(?P<meaning>.*?)\s*\((?P<unit>(?:[^()]|\([^()]*\))+)\)(?:\.(?=\s|$)|$)", re.DOTALL)


@dataclass(frozen=True)
class FieldDoc:
    """A config field's documentation: ``meaning`` (one line), ``unit`` ("1" dimensionless, "-" none), ``type``."""

    meaning: str
    unit: str
    type: str = ""


def _section(doc: str) -> list[str]:
    """The lines of a docstring's Parameters section, dedented to the entries' indent."""
    lines = (doc or "").expandtabs().splitlines()
    for k in range(len(lines) - 1):
        if lines[k].strip() == "Parameters" and set(lines[k + 1].strip()) == {"-"}:
            body = []
            for line in lines[k + 2:]:
                if line.strip() and set(line.strip()) == {"-"} and body and body[-1].strip():
                    body.pop()  # the next section's title
                    break
                body.append(line)
            indent = min((len(s) - len(s.lstrip()) for s in body if s.strip()), default=0)
            return [s[indent:] for s in body]
    return []


def parse(doc: str) -> dict[str, FieldDoc]:
    """name -> FieldDoc of a numpy docstring's Parameters section (entries without a unit: unit "")."""
    out, names, head, text = {}, [], "", []

    def flush():
        if names:
            description = " ".join(" ".join(text).split())
            m = _UNIT.match(description)
            meaning, unit = (m["meaning"].strip(), m["unit"].strip()) if m else (description, "")
            for name in names:
                out[name] = FieldDoc(meaning, unit, head)

    for line in _section(doc):
        m = _HEAD.match(line) if line[:1].strip() else None
        if m:
            flush()
            names, head, text = [n.strip() for n in m["names"].split(",")], m["type"].strip(), []
        elif names:
            text.append(line.strip())
    flush()
    return out


def field_docs(cls) -> dict[str, FieldDoc]:
    """name -> FieldDoc of every documented field of a config class (its bases' entries, then its own)."""
    docs = {}
    for klass in reversed(cls.__mro__):
        if "__doc__" in vars(klass):
            docs.update(parse(klass.__doc__))
    return {f.name: docs[f.name] for f in fields(cls) if f.name in docs}


def _cell(value) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, tuple) and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        return "(" + ", ".join(_cell(v) for v in value) + ")"
    if isinstance(value, tuple):
        return f"{len(value)} item{'s' if len(value) != 1 else ''}" if value else "none"
    text = " ".join(str(value).split())
    return text if len(text) <= 28 else text[:25] + "..."


def config_rows(cfg) -> list[tuple[str, str, str, str, str]]:
    """(field, value, default, unit, meaning) of every field of a config; "?" where undocumented."""
    docs = field_docs(type(cfg))
    base = type(cfg)()
    return [(f.name, _cell(getattr(cfg, f.name)), _cell(getattr(base, f.name)),
             docs[f.name].unit if f.name in docs else "?", docs[f.name].meaning if f.name in docs else "?")
            for f in fields(cfg)]


def config_table(cfg) -> list[str]:
    """The lines of an aligned table of a config's fields: value (a ``*`` where it is not the default), default,
    unit and meaning."""
    rows = [(n, v + (" *" if v != d else ""), d, u, m) for n, v, d, u, m in config_rows(cfg)]
    head = ("field", "value", "default", "unit", "meaning")
    widths = [max(len(r[k]) for r in [head, *rows]) for k in range(4)]
    lines = [f"{cfg.scene}: {len(rows)} config fields (* differs from the scene's default)"]
    for r in [head, *rows]:
        lines.append("  ".join(c.ljust(w) for c, w in zip(r[:4], widths)) + "  " + r[4])
    return lines
