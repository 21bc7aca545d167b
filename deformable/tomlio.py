r"""The project's one TOML round trip: scene files, resolved configs and their tables, read and written.

:func:`loads` reads TOML text with the standard library's ``tomllib``; a
malformed file is an :class:`~deformable.errors.InputError` naming its
source. :func:`dumps` writes a table with ``tomli_w`` (a tuple is written as
an array, a None value is left out, nested tables and arrays of tables as
TOML writes them), after an optional comment line, so that ``loads(dumps(t))``
gives the table back with lists for tuples. What a table may hold is checked
by its reader with :func:`deformable.checks.known_keys`.
"""

from __future__ import annotations

import os
import stat
import tomllib
from pathlib import Path

import tomli_w

from .errors import InputError

__all__ = ["loads", "load", "dumps", "read_text"]

#: what a path that is not a regular file is, by its stat's file type
_KINDS = ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a named pipe"), (stat.S_ISCHR, "a device"),
          (stat.S_ISBLK, "a device"), (stat.S_ISSOCK, "a socket"))


def loads(text: str, source: str = "<string>") -> dict:
    """The table of TOML ``text``; InputError naming ``source`` when it is not valid TOML."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"scene file {source!r} is not valid TOML: {err}", field="file", value=source) from None


def read_text(path, what: str = "scene file", field: str = "file") -> str:
    """The text of the regular file ``path``; InputError naming it when it cannot be read.

    A path that is not a regular file (a named pipe, a device, a folder) is refused before it is opened:
    reading a pipe would wait for a writer for ever.
    """
    path = Path(path)
    try:
        mode = os.stat(path).st_mode
        kind = next((name for test, name in _KINDS if test(mode)), None)
        if kind is not None:
            raise InputError(f"cannot read {what} {str(path)!r}: it is {kind}, not a regular file", field=field,
                             value=str(path))
        return path.read_text()
    except (OSError, UnicodeDecodeError) as err:
        raise InputError(f"cannot read {what} {str(path)!r}: {getattr(err, 'strerror', None) or err}",
                         field=field, value=str(path)) from None


def load(path) -> tuple[dict, str]:
    """The table of the TOML file ``path`` and its text; InputError naming the file when it cannot be read."""
    text = read_text(path)
    return loads(text, str(path)), text


def _plain(value):
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items() if v is not None}
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    return value


def dumps(table: dict, header: str | None = None) -> str:
    """TOML text of ``table`` (module docstring), after the comment line ``header`` when given."""
    text = tomli_w.dumps(_plain(table))
    return f"# {header}\n{text}" if header else text
