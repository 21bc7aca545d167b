r"""Checks of single values at construction time, each failing with an :class:`~deformable.errors.InputError`
that names the field and the refused value; and the one check of a table's keys (:func:`known_keys`).

Every constructor of the library checks its arguments before any work
(docs/design.md, "Input"): numbers are real and finite (a bool or a string
is not a number, ``"9.81"`` included), counts are integers, callables are
callable. These helpers say each rule once.
"""

from __future__ import annotations

import difflib
import importlib
import math
from importlib import metadata
import numbers

import numpy as np

from .errors import InputError

__all__ = ["is_real", "real", "count", "function", "finite_array", "vector", "sequence", "known_keys", "suggest", "extra",
           "DISTRIBUTION", "installed_version"]

#: the project's name on the package registry (``pip install deformable-sheets``); the import names stay
#: deformable, fdmodel, femodel and validation (the registry's own "deformable" is another project)
DISTRIBUTION = "deformable-sheets"


def installed_version() -> str:
    """The installed distribution's version (pyproject.toml is its one source); "0+unknown" for a source tree on
    sys.path that is not installed."""
    try:
        return metadata.version(DISTRIBUTION)
    except metadata.PackageNotFoundError:
        return "0+unknown"


def is_real(value) -> bool:
    """Whether ``value`` is a real number: Python's or numpy's scalars, not a bool (the one test of "a number")."""
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))


def real(field: str, value, *, positive: bool = False, non_negative: bool = False, low: float | None = None,
         high: float | None = None) -> float:
    """``value`` as a finite float; InputError unless it is a real number within the bounds.

    ``positive``: > 0; ``non_negative``: >= 0; ``low``, ``high``: inclusive bounds.
    """
    if not is_real(value):
        raise InputError(f"{field} must be a number, got {value!r}", field=field, value=value)
    x = float(value)
    if not math.isfinite(x):
        raise InputError(f"{field} must be finite, got {value!r}", field=field, value=value)
    if positive and not x > 0:
        raise InputError(f"{field} must be positive, got {value!r}", field=field, value=value)
    if non_negative and not x >= 0:
        raise InputError(f"{field} must be non-negative, got {value!r}", field=field, value=value)
    if (low is not None and x < low) or (high is not None and x > high):
        raise InputError(f"{field} must lie in [{low}, {high}], got {value!r}", field=field, value=value)
    return x


def count(field: str, value, *, minimum: int = 1, maximum: int | None = None) -> int:
    """``value`` as an int; InputError unless it is a whole number (not a bool) in [minimum, maximum]."""
    kind = {0: "a non-negative integer", 1: "a positive integer"}.get(minimum, f"an integer of at least {minimum}")
    if maximum is not None:
        kind = f"an integer in [{minimum}, {maximum}]"
    ok = is_real(value)
    if ok:
        ok = math.isfinite(float(value)) and float(value) == int(value)
    if not ok or int(value) < minimum or (maximum is not None and int(value) > maximum):
        raise InputError(f"{field} must be {kind}, got {value!r}", field=field, value=value)
    return int(value)


def function(field: str, value, optional: bool = True):
    """``value`` if it is callable (or None when ``optional``); InputError otherwise."""
    if (value is None and optional) or callable(value):
        return value
    raise InputError(f"{field} must be a callable{' or None' if optional else ''}, got {value!r}",
                     field=field, value=value)


def finite_array(field: str, value) -> np.ndarray:
    """``value`` as a non-empty float array of finite real numbers; InputError otherwise (no bools, no strings)."""
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):  # ragged nesting
        arr = None
    if arr is None or arr.dtype.kind not in "iuf" or arr.size == 0:
        raise InputError(f"{field} must be a number or a non-empty array of numbers, got {value!r}",
                         field=field, value=value)
    arr = arr.astype(float)
    if not np.all(np.isfinite(arr)):
        bad = arr[~np.isfinite(arr)].flat[0]
        raise InputError(f"{field} must be finite, got {bad!r}", field=field, value=value)
    return arr


def vector(field: str, value, size: int, what: str) -> np.ndarray:
    """``value`` as a float array of ``size`` finite real numbers; InputError saying it must be ``what``."""
    try:
        v = np.asarray(value)
        v = v.astype(float) if v.dtype.kind in "iuf" else None
    except (TypeError, ValueError):  # ragged nesting
        v = None
    if v is None or v.shape != (size,) or not np.all(np.isfinite(v)):
        raise InputError(f"{field} must be {what}, got {value!r}", field=field, value=value)
    return v


def sequence(field: str, value, kinds: tuple, names: str) -> tuple:
    """``value`` (a list or tuple of instances of ``kinds``) as a tuple; InputError naming the first misfit."""
    if isinstance(value, kinds) or not isinstance(value, (list, tuple)):
        raise InputError(f"{field} must be a list of {names}, got {value!r}", field=field, value=value)
    for item in value:
        if not isinstance(item, kinds):
            raise InputError(f"{field}: {item!r} is not a {names}", field=field, value=item)
    return tuple(value)


def suggest(name, known) -> str:
    """``" (did you mean 'eta'?)"`` naming the known name closest to an unknown ``name``
    (:func:`difflib.get_close_matches`, its default cutoff 0.6); "" when none is close or ``name`` is not a string.

    Every refusal of an unknown name puts it right after the refused name, before the list of the known ones
    (``unknown key 'etaa' for scene 'hanging' (did you mean 'eta'?); known keys: ...``): one line still.
    """
    if not isinstance(name, str):
        return ""
    close = difflib.get_close_matches(name, [str(k) for k in known], n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


def known_keys(table, known, where: str, field: str | None = None) -> None:
    """InputError naming the first key of ``table`` that is not one of ``known``, and the known ones.

    ``where`` says whose keys they are, after "unknown key 'k'": "in scene file 'a.toml'", "for scene
    'curtain'", "in the newton settings". The one check of every table and keyword set the project reads.
    """
    known = list(known)
    for key in table:
        if key not in known:
            raise InputError(f"unknown key {key!r} {where}{suggest(key, known)}; known keys: "
                             f"{', '.join(map(str, known))}",
                             field=field or str(key), value=key)


def extra(module: str, name: str, needed_by: str):
    """The optional dependency ``module`` (imported), or an InputError saying in one line how to install it.

    ``name`` is the project's extra that brings it (``render``, ``distributed``, ``fast``, ``docs``, ``peers``:
    pyproject.toml), ``needed_by`` what asked (``"deformable run --render"``). The core install leaves them out
    (VTK alone is most of an install's size).
    """
    try:
        return importlib.import_module(module)
    except ImportError:
        raise InputError(f"{needed_by} needs {module}, which the core install leaves out: pip install "
                         f"'{DISTRIBUTION}[{name}]' (or '.[{name}]' in the project folder)", field=needed_by,
                         value=module) from None
