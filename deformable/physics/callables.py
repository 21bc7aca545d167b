"""A user's callable, called: its errors and non-finite values named where they enter (the field it was given for,
the point and the time)."""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["called"]


def called(field: str, fn, *args) -> np.ndarray:
    """``fn(*args)`` as a float array; InputError naming ``field`` when it raises, or returns NaN or inf (the first
    such point: a1, a2 (m) and t (s) where the callable takes them). ``args`` are ``(t,)`` or ``(a1, a2[, t])``."""
    try:
        value = np.asarray(fn(*args), dtype=float)
    except InputError:
        raise
    except Exception as err:  # noqa: BLE001 - a user's code: any error, named with the field it was given for
        raise InputError(f"{field}: the callable raised {type(err).__name__}: {err} ({_where(args)})", field=field,
                         value=fn) from err
    bad = ~np.isfinite(value)
    if bad.any():
        raise InputError(f"{field}: the callable returned {value[bad].flat[0]} ({_where(args, bad)})", field=field,
                         value=fn)
    return value


def _where(args, bad=None) -> str:
    """Where a callable was called: "at t = ... s", or the first bad point of its (a1, a2) arrays."""
    if len(args) == 1:
        return f"at t = {float(args[0]):g} s"
    a1, a2 = np.broadcast_arrays(np.asarray(args[0], float), np.asarray(args[1], float))
    t = f", t = {float(args[2]):g} s" if len(args) > 2 else ""
    if bad is not None and a1.size and bad.size % a1.size == 0 and bad.size >= a1.size:
        k = tuple(np.argwhere(bad.reshape(a1.shape + (-1,)).any(axis=-1))[0])
        return f"at a1 = {a1[k]:g} m, a2 = {a2[k]:g} m{t}"
    return f"on {a1.size} points{t}"
