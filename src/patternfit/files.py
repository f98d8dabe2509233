"""Atomic file writing: a crash never leaves half a file, and never loses the old one."""

from __future__ import annotations

import json
import math
import os
import stat
import tempfile
from pathlib import Path

_UMASK = os.umask(0)
os.umask(_UMASK)


def atomic_write_bytes(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically: a temporary file beside it, then a rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.chmod(tmp, 0o666 & ~_UMASK)  # mkstemp makes 0600; give the file normal permissions
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


_JOURNAL = ".patternfit-commit-"


def atomic_write_group(files: dict) -> list[Path]:
    """Replace several files as one step: after a crash at any point, a later read sees
    either all the old contents or all the new ones (never a new pattern beside an old mesh).

    ``files`` maps each target path to its new bytes. Every new content is first written and
    synced beside its target; then a journal naming every rename is written (atomically) into
    each target's folder; then the renames; then the journals are removed. A reader that
    finds a journal (:func:`recover_group_writes`, called by :func:`read_bytes_capped`) finishes
    the renames first.
    """
    targets = [Path(p) for p in files]
    if len({t.resolve() for t in targets}) != len(targets):
        raise ValueError("files: the same target is named twice")
    temps: list[tuple[str, str]] = []
    try:
        for target, data in zip(targets, files.values()):
            target.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp",
                                       dir=target.parent)
            temps.append((tmp, str(target.resolve())))
            os.chmod(tmp, 0o666 & ~_UMASK)
            with os.fdopen(fd, "wb") as f:
                f.write(data)
                f.flush()
                os.fsync(f.fileno())
    except BaseException:
        for tmp, _ in temps:
            Path(tmp).unlink(missing_ok=True)
        raise
    record = json.dumps({"renames": temps}).encode("utf-8")
    name = f"{_JOURNAL}{os.urandom(6).hex()}.json"
    journals = [Path(d) / name for d in dict.fromkeys(str(t.parent.resolve()) for t in targets)]
    for j in journals:
        atomic_write_bytes(j, record)
    _finish(temps, journals)
    return targets


def _finish(renames, journals) -> None:
    for tmp, target in renames:
        if os.path.exists(tmp):
            os.replace(tmp, target)
    for j in journals:
        Path(j).unlink(missing_ok=True)


def recover_group_writes(folder) -> int:
    """Finish the group writes (:func:`atomic_write_group`) a crash left half done in
    ``folder``; the number of journals found."""
    found = 0
    try:
        names = [n for n in os.listdir(folder) if n.startswith(_JOURNAL) and n.endswith(".json")]
    except OSError:
        return 0
    for n in names:
        path = Path(folder) / n
        try:
            record = json.loads(path.read_text(encoding="utf-8"))
            renames = [(str(a), str(b)) for a, b in record["renames"]]
        except (OSError, ValueError, KeyError, TypeError):
            continue  # not ours, or unreadable: leave it for a person to look at
        others = {str(Path(b).parent / n) for _, b in renames}
        _finish(renames, [path, *others])
        found += 1
    return found


def atomic_write_text(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    return atomic_write_bytes(path, text.encode("utf-8"))


#: the largest JSON document any reader accepts [bytes]: patterns, fabrics, side files and
#: session records are far smaller; a larger file (or a device such as /dev/zero) is refused
MAX_JSON_BYTES = 64 * 1024 * 1024

#: the deepest nesting of arrays/objects a JSON document may have (our formats need < 10)
MAX_JSON_DEPTH = 64


def read_bytes_capped(path, *, limit: int, error=None) -> bytes:
    """The bytes of the regular file ``path``, refused with ``error`` (an
    :class:`~patternfit.errors.InputError` class) when it cannot be read, is not a regular
    file (a device, a pipe, a folder) or is larger than ``limit`` bytes."""
    from .errors import InputError

    error = error or InputError
    path = Path(path)
    recover_group_writes(path.parent)
    try:
        with open(path, "rb") as f:
            if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):
                raise error("not a regular file", file=path)
            data = f.read(limit + 1)
    except OSError as exc:
        raise error(f"cannot read file: {exc.strerror or exc}", file=path) from None
    if len(data) > limit:
        raise error(f"file is larger than the limit of {limit} bytes", file=path)
    return data


def _depth(text: str) -> int:
    depth = best = 0
    in_str = esc = False
    for ch in text:
        if in_str:
            if esc:
                esc = False
            elif ch == "\\":
                esc = True
            elif ch == '"':
                in_str = False
        elif ch == '"':
            in_str = True
        elif ch in "[{":
            depth += 1
            best = max(best, depth)
        elif ch in "]}":
            depth -= 1
    return best


def _refuse_constant(name: str):
    raise ValueError(f"{name} is not a number JSON allows")


def _finite_float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"number {text[:20]}... is out of range")
    return value


def _bounded_int(text: str):
    if len(text.lstrip("-")) > 20:
        # a 400-digit integer is no coordinate; read it as a float, refused when out of range
        return _finite_float(text)
    return int(text)


def parse_json_text(text: str, *, file=None, error=None):
    """The parsed JSON document ``text``, refused with ``error`` (an
    :class:`~patternfit.errors.InputError` class) naming ``file`` and the line and column:
    invalid JSON, nesting deeper than :data:`MAX_JSON_DEPTH`, ``NaN``/``Infinity`` and numbers
    beyond float range are all refused."""
    from .errors import InputError

    error = error or InputError
    if len(text) > 2 * MAX_JSON_DEPTH and _depth(text) > MAX_JSON_DEPTH:
        raise error(f"nested deeper than {MAX_JSON_DEPTH} levels", file=file)
    try:
        return json.loads(text, parse_constant=_refuse_constant, parse_float=_finite_float,
                          parse_int=_bounded_int)
    except json.JSONDecodeError as exc:
        raise error(f"not valid JSON (line {exc.lineno}, column {exc.colno}: {exc.msg})",
                    file=file) from None
    except (ValueError, RecursionError) as exc:
        raise error(f"not valid JSON: {exc}", file=file) from None


def read_json_file(path, *, error=None, limit: int = MAX_JSON_BYTES):
    """The parsed JSON document in the file ``path`` (UTF-8, at most ``limit`` bytes), refused
    with ``error`` (an :class:`~patternfit.errors.InputError` class) naming the file and the
    place: unreadable, not a regular file, too large, not UTF-8, or as :func:`parse_json_text`.
    """
    from .errors import InputError

    error = error or InputError
    data = read_bytes_capped(path, limit=limit, error=error)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise error(f"not UTF-8 text (byte {exc.start}: {data[exc.start]:#04x})",
                    file=path) from None
    return parse_json_text(text, file=path, error=error)


def dumps_finite_json(data, **kwargs) -> str:
    """``json.dumps`` that never writes ``NaN`` or ``Infinity``: a non-finite float raises
    ``ValueError`` (callers make the value ``None`` with a failed check instead)."""
    return json.dumps(data, allow_nan=False, default=json_default, **kwargs)


def json_default(o):
    """``json.dumps`` ``default`` for NumPy scalars and arrays."""
    import numpy as np

    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")
