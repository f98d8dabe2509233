"""The one argument checker: numbers and arrays handed to a public function.

Every refusal is a ``ValueError`` whose message starts with the argument's name and says
what was expected and what came (``"sx: expected a number in [0.1, 10], got 0.0"``), before
any work is done with the value. Callers that raise their own error kind (a
:class:`~patternfit.pattern.PatternError` naming the panel) catch it and pass the message on.
"""

from __future__ import annotations

import math
import numbers
import os

import numpy as np

__all__ = ["array", "instance", "number", "path", "source"]

#: the longest value repr shown in a message [characters]
_SHOWN = 60


def _shown(value) -> str:
    text = repr(value)
    return text if len(text) <= _SHOWN else text[:_SHOWN - 3] + "..."


def _span(low, high, low_open: bool, high_open: bool, unit: str, *, many: str = "") -> str:
    """`` in [low, high] unit`` (or ``> low``, ``<= high``...) for a message; ``many``
    (``"both values "``, ``"every value "``) goes before it for arrays."""
    low = None if low is None or low == -math.inf else low
    high = None if high is None or high == math.inf else high
    if low is None and high is None:
        return ""
    unit = f" {unit}" if unit else ""
    if low is not None and high is not None:
        return f" {'with ' + many if many else ''}in {'(' if low_open else '['}{low:g}, " \
               f"{high:g}{')' if high_open else ']'}{unit}"
    text = f"{'> ' if low_open else '>= '}{low:g}" if low is not None else \
        f"{'< ' if high_open else '<= '}{high:g}"
    return f" {'with ' + many if many else ''}{text}{unit}"


def _within(v, low, high, low_open: bool, high_open: bool) -> bool:
    """Every value of ``v`` within the bounds (NaN is not)."""
    ok = np.ones(np.shape(v), dtype=bool)
    if low is not None:
        ok &= (v > low) if low_open else (v >= low)
    if high is not None:
        ok &= (v < high) if high_open else (v <= high)
    return bool(ok.all())


def number(value, name: str, *, low: float | None = None, high: float | None = None,
           low_open: bool = False, high_open: bool = False, integer: bool = False,
           unit: str = "", rule: str | None = None) -> float | int:
    """``value`` as a finite ``float`` (``int`` with ``integer``) within ``[low, high]``
    (``low_open``, ``high_open``: that bound excluded; None: no bound).

    A Python or numpy number is accepted; a bool, a string, ``None``, NaN or an infinity is
    refused, and with ``integer`` so is a number with a fractional part. The refusal reads
    ``"{name}: expected a number in [low, high] unit, got {value!r}"``; ``rule`` replaces
    the part after the name and before ``, got`` (``"must be a positive number"``) where a
    caller's wording is established.
    """
    want = rule or (f"expected {'an integer' if integer else 'a number'}"
                    f"{_span(low, high, low_open, high_open, unit)}")
    ok = isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))
    if ok:
        v = float(value)
        ok = math.isfinite(v) and _within(v, low, high, low_open, high_open) \
            and (not integer or v.is_integer())
    if not ok:
        raise ValueError(f"{name}: {want}, got {_shown(value)}")
    return int(v) if integer else v


def _shape_text(shape) -> str:
    dims = ["k" if d is None else str(d) for d in shape]
    return f"({dims[0]},)" if len(dims) == 1 else f"({', '.join(dims)})"


def _fits(have: tuple, want: tuple) -> bool:
    return len(have) == len(want) and all(w is None or h == w for h, w in zip(have, want))


def array(value, name: str, *, shape: tuple = (None, 3), dtype=np.float64, finite: bool = False,
          low: float | None = None, high: float | None = None, low_open: bool = False,
          high_open: bool = False, unit: str = "", what: str | None = None,
          contiguous: bool = False) -> np.ndarray:
    """``value`` as a numpy array of ``dtype`` and ``shape`` (``None``: any length), not
    copied when it is one already (``np.asanyarray``; with ``contiguous``,
    ``np.ascontiguousarray``, as compiled kernels want).

    With ``finite``, or bounds ``low``/``high`` (``low_open``, ``high_open``: excluded), every value
    must be finite and within them. ``what`` names what is expected (``"a 2-vector 'x,y'"``;
    default ``"a float64 array of shape (k, 3)"``, ``"a number"`` for ``shape=()``). The
    refusal reads ``"{name}: expected {what}[ with every value in [low, high] unit], got
    ..."``: the value (or its shape, or "NaN or infinite values").
    """
    shape = tuple(shape)
    bounded = any(b is not None and math.isfinite(b) for b in (low, high))
    if what is None:
        if shape == ():
            what = "a number"
        else:
            what = f"{'finite ' if finite and not bounded else ''}{np.dtype(dtype).name} " \
                   f"array of shape {_shape_text(shape)}"
            what = ("an " if what[0] in "aeiou" else "a ") + what
    elif (finite or low is not None or high is not None) and not bounded:
        what += " of finite values"
    many = "" if shape == () else "both values " if shape == (2,) else "every value "
    want = f"expected {what}{_span(low, high, low_open, high_open, unit, many=many)}"
    if np.iscomplexobj(value) and not np.issubdtype(np.dtype(dtype), np.complexfloating):
        # numpy casts complex to real with only a warning: the imaginary part was dropped
        raise ValueError(f"{name}: {want}, got complex values")
    try:
        a = np.asanyarray(value, dtype=dtype)
    except (TypeError, ValueError, OverflowError) as exc:
        raise ValueError(f"{name}: {want}, got {_shown(value)} ({exc})") from None
    if not _fits(a.shape, shape):
        got = _shown(value) if a.size <= 4 else f"shape {a.shape}"
        raise ValueError(f"{name}: {want}, got {got}")
    if finite or low is not None or high is not None:
        if not np.isfinite(a).all():
            got = f"{_shown(value)} (NaN or infinite)" if a.size <= 4 else \
                "NaN or infinite values"
            raise ValueError(f"{name}: {want}, got {got}")
        if not _within(a, low, high, low_open, high_open):
            raise ValueError(f"{name}: {want}, got {_shown(value)}")
    return np.ascontiguousarray(a) if contiguous else a


def _kind_name(value) -> str:
    return _shown(value) if isinstance(value, str) else type(value).__name__


def _names_a_place(value) -> bool:
    """A path-like or a non-empty string ("" is the current folder to ``Path``)."""
    return isinstance(value, os.PathLike) or (isinstance(value, str) and bool(value.strip()))


def instance(value, kind: type | tuple, name: str, what: str, *, optional: bool = False):
    """``value`` when it is a ``kind`` (or None, with ``optional``); else a ``ValueError``
    ``"{name}: expected {what}[ or None], got {type}"``, where an attribute error from deep
    inside would otherwise name nothing the caller wrote."""
    if isinstance(value, kind) or (optional and value is None):
        return value
    raise ValueError(f"{name}: expected {what}{' or None' if optional else ''}, "
                     f"got {_kind_name(value)}")


def path(value, name: str, *, what: str = "a file or folder path"):
    """``value`` as a ``pathlib.Path`` when it is a non-empty string or path-like; else a
    ``ValueError`` naming ``name`` ("" is the current folder to ``Path``)."""
    from pathlib import Path

    if _names_a_place(value):
        return Path(value)
    raise ValueError(f"{name}: expected {what}, got {_kind_name(value)}")


def source(value, kind: type, name: str, what: str):
    """``value`` when it is a ``kind`` object, a non-empty name or a path (what a ``read_*``
    function takes); else a ``ValueError`` ``"{name}: expected {what}, got ..."``, not a
    file error whose "file name" is the object's repr."""
    if isinstance(value, kind) or _names_a_place(value):
        return value
    raise ValueError(f"{name}: expected {what}, got {_kind_name(value)}")
