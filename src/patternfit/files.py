"""Atomic file writing: a crash never leaves half a file, and never loses the old one."""

from __future__ import annotations

import codecs
import io
import json
import math
import os
import re
import stat
import tempfile
import zipfile
from pathlib import Path

import numpy as np

from .errors import InputError

_UMASK = os.umask(0)
os.umask(_UMASK)


def writable_target(path) -> Path:
    """``path`` as a :class:`Path` when a file may be written there by a rename: it does not
    exist, or it is a regular file (a link to one counts); else :class:`InputError` naming
    it (a folder, a named pipe or a device such as /dev/null would be replaced by a
    regular file, or, for a folder, the rename fails after the work is done)."""
    path = Path(path)
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        return path
    except OSError as exc:
        raise InputError(f"cannot write there: {exc.strerror or exc}", file=path) from None
    if stat.S_ISDIR(mode):
        raise InputError("is a folder: name a file to write", file=path)
    if not stat.S_ISREG(mode):
        raise InputError("is not a regular file (a pipe or a device): name a file to write",
                         file=path)
    return path


def atomic_write_bytes(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically: a temporary file beside it, then a rename."""
    path = writable_target(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:  # the folder cannot hold a file (/proc, read-only, a file)
        raise InputError(f"cannot write there: {exc.strerror or exc}", file=path) from None
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
    targets = [writable_target(p) for p in files]
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


def _ours(renames, folder) -> bool:
    """Whether a journal's ``renames`` are ones :func:`atomic_write_group` wrote for a group
    with a file in ``folder``: each a temporary file named for its target (``.<name>.*.tmp``)
    in the target's own folder, where it still is a regular file or is gone (renamed)."""
    here = os.path.realpath(folder)
    mine = False
    for tmp, target in renames:
        t, g = Path(tmp), Path(target)
        if not (t.is_absolute() and g.is_absolute() and t.parent == g.parent
                and t.name.startswith(f".{g.name}.") and t.name.endswith(".tmp")):
            return False
        if os.path.lexists(t) and not (t.is_file() and not t.is_symlink()):
            return False
        mine = mine or os.path.realpath(g.parent) == here
    return mine


def recover_group_writes(folder) -> int:
    """Finish the group writes (:func:`atomic_write_group`) a crash left half done in
    ``folder``; the number of journals found and finished.

    Only a journal that names this group's own renames is carried out (:func:`_ours`): one
    that came with a downloaded folder and names files elsewhere would otherwise replace
    them at the next read. A journal that is not ours, or whose renames fail (a target
    made a folder since), is left for a person to look at, and the read goes on."""
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
            continue
        if not _ours(renames, folder):
            continue
        others = {str(Path(b).parent / n) for _, b in renames}
        try:
            _finish(renames, [path, *others])
        except OSError:
            continue
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
    error = error or InputError
    path = Path(path)
    recover_group_writes(path.parent)
    try:
        # opened without blocking: a blocking open of a named pipe waits for a writer, for
        # ever; what was opened is then checked (no race with a stat before the open), and
        # a regular file reads the same either way
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        with os.fdopen(fd, "rb") as f:
            if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):
                raise error("not a regular file", file=path)
            data = f.read(limit + 1)
    except OSError as exc:
        raise error(f"cannot read file: {exc.strerror or exc}", file=path) from None
    if len(data) > limit:
        raise error(f"file is larger than the limit of {limit} bytes", file=path)
    return data


_NPY_HEADERS = {(1, 0): np.lib.format.read_array_header_1_0,
                (2, 0): np.lib.format.read_array_header_2_0}


def _read_npy(fh, size: int, *, error, file, place=None) -> np.ndarray:
    """The array in the open ``.npy`` stream ``fh`` of ``size`` bytes; the header is checked
    before any data is read, so that a damaged or hostile header allocates nothing."""
    try:
        version = np.lib.format.read_magic(fh)
    except Exception:  # zlib, zipfile and numpy raise many kinds for damaged bytes
        raise error("damaged, or not a NumPy array", file=file, place=place) from None
    if version not in _NPY_HEADERS:
        raise error(f".npy format version {version} is not read", file=file, place=place)
    try:
        shape, _, dtype = _NPY_HEADERS[version](fh)
    except Exception:
        raise error("damaged, or not a NumPy array", file=file, place=place) from None
    if dtype.hasobject:
        raise error("holds Python objects (a pickle), which are never loaded", file=file,
                    place=place)
    need, have = math.prod(shape) * dtype.itemsize, size - fh.tell()
    if need != have:
        raise error(f"truncated or damaged: shape {shape} of {dtype} needs {need} bytes, the "
                    f"file holds {have}", file=file, place=place)
    try:
        fh.seek(0)
        array = np.lib.format.read_array(fh, allow_pickle=False)
        fh.read()  # reaching the end makes zipfile check the member's CRC
    except Exception:
        raise error("damaged data", file=file, place=place) from None
    return array


def read_npy(path, *, limit: int, error) -> np.ndarray:
    """The array in the ``.npy`` file ``path`` (at most ``limit`` bytes), refused with
    ``error`` (an :class:`~patternfit.errors.InputError` class) naming the file when it is
    unreadable, too large, damaged, truncated or holds Python objects (never unpickled)."""
    data = read_bytes_capped(path, limit=limit, error=error)
    return _read_npy(io.BytesIO(data), len(data), error=error, file=path)


def read_npz(path, *, limit: int, error) -> dict[str, np.ndarray]:
    """Every array of the ``.npz`` file ``path``, by name, refused with ``error`` (an
    :class:`~patternfit.errors.InputError` class) naming the file and the array: unreadable,
    not a zip archive, damaged, truncated, holding Python objects (never unpickled), or
    larger than ``limit`` bytes as a file or unpacked."""
    data = read_bytes_capped(path, limit=limit, error=error)
    try:
        archive = zipfile.ZipFile(io.BytesIO(data))
        members = archive.infolist()
    except Exception:  # zipfile raises many kinds for damaged archives
        raise error("not a NumPy .npz archive (damaged or truncated)", file=path) from None
    if sum(m.file_size for m in members) > limit:
        raise error(f"its arrays unpack to more than the limit of {limit} bytes", file=path)
    arrays = {}
    for m in members:
        name = m.filename.removesuffix(".npy")
        try:
            fh = archive.open(m)
        except Exception:  # a damaged, encrypted or oddly compressed member
            raise error("damaged data", file=path, place=f"array '{name}'") from None
        with fh:
            arrays[name] = _read_npy(fh, m.file_size, error=error, file=path,
                                     place=f"array '{name}'")
    return arrays



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


class _Refused(ValueError):
    """A JSON number the readers refuse; ``token`` is its text, to find its line."""

    def __init__(self, message: str, token: str):
        super().__init__(message)
        self.token = token


def _refuse_constant(name: str):
    raise _Refused(f"{name} is not a number JSON allows", name)


def _finite_float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise _Refused(f"number {text[:20]}{'...' if len(text) > 20 else ''} is out of range",
                       text)
    return value


def _bounded_int(text: str):
    if len(text.lstrip("-")) > 20:
        # a 400-digit integer is no coordinate; read it as a float, refused when out of range
        return _finite_float(text)
    return int(text)


class _Duplicate(ValueError):
    """A key given twice in one JSON object; ``key`` is it."""

    def __init__(self, key: str):
        super().__init__(f"the key {json.dumps(key)[:80]} appears twice in one object (the "
                         "second copy would silently replace the first)")
        self.key = key


def _unique_keys(pairs):
    """``object_pairs_hook`` refusing a key given twice (another tool's export that repeats
    a panel lost it without a word)."""
    out = dict(pairs)
    if len(out) != len(pairs):
        seen = set()
        for k, _ in pairs:
            if k in seen:
                raise _Duplicate(k)
            seen.add(k)
    return out


def _second_key_line(text: str, key: str) -> str:
    """'line L: ' of the second place the key ``key`` is written, or ''."""
    found = list(re.finditer(re.escape(json.dumps(key)) + r"\s*:", text))
    if len(found) < 2:
        return ""
    return f"line {text.count(chr(10), 0, found[1].start()) + 1}: "


def _at(text: str, index: int) -> str:
    """'line L, column C' (from 1) of the character ``index`` of ``text``."""
    return (f"line {text.count(chr(10), 0, index) + 1}, column "
            f"{index - text.rfind(chr(10), 0, index)}")


def _line_column(text: str, token: str) -> str:
    """'line L, column C: ' of the first ``token`` outside a string, or ''."""
    for match in re.finditer(re.escape(token), text):
        before = text[:match.start()]
        if before.count('"') - before.count('\\"') & 1:
            continue  # inside a string
        return f"{_at(text, match.start())}: "
    return ""


def parse_json_text(text: str, *, file=None, error=None):
    """The parsed JSON document ``text``, refused with ``error`` (an
    :class:`~patternfit.errors.InputError` class) naming ``file`` and the line and column:
    invalid JSON, nesting deeper than :data:`MAX_JSON_DEPTH`, ``NaN``/``Infinity``, numbers
    beyond float range and a key given twice in one object are all refused."""
    error = error or InputError
    if len(text) > 2 * MAX_JSON_DEPTH and _depth(text) > MAX_JSON_DEPTH:
        raise error(f"nested deeper than {MAX_JSON_DEPTH} levels", file=file)
    try:
        return json.loads(text, parse_constant=_refuse_constant, parse_float=_finite_float,
                          parse_int=_bounded_int, object_pairs_hook=_unique_keys)
    except json.JSONDecodeError as exc:
        raise error(f"not valid JSON (line {exc.lineno}, column {exc.colno}: {exc.msg})",
                    file=file) from None
    except _Refused as exc:
        raise error(f"not valid JSON ({_line_column(text, exc.token)}{exc})",
                    file=file) from None
    except _Duplicate as exc:
        raise error(f"{_second_key_line(text, exc.key)}{exc}", file=file) from None
    except (ValueError, RecursionError) as exc:
        raise error(f"not valid JSON: {exc}", file=file) from None


#: the files people pick by mistake for a JSON one, by their first bytes
_BINARY_KINDS = ((b"\x89PNG", "a PNG image"), (b"\xff\xd8\xff", "a JPEG image"),
                 (b"%PDF", "a PDF document"), (b"PK\x03\x04", "a ZIP archive (.zip, .npz, "
                                                          "CLO's .zfab, Office)"),
                 (b"\x1f\x8b", "a gzip archive"))


def without_comments(text: str) -> str:
    """``text`` with its ``//`` and ``/* */`` comments blanked out (strings kept; each
    comment's characters become spaces, its line breaks stay, so the lines and columns of
    what is left are as they were): the JSON that ARCSim's reader, jsoncpp, takes. Raises
    ValueError giving the line and column of a ``/*`` that is never closed: blanked to the
    end, it hid the rest of the file, and a file cut short read as if whole."""
    out, i, n = list(text), 0, len(text)
    while i < n:
        c = text[i]
        if c == '"':
            i += 1
            while i < n and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
        elif text.startswith(("//", "/*"), i):
            line = text[i + 1] == "/"
            end = text.find("\n" if line else "*/", i + 2)
            if end < 0 and not line:
                raise ValueError(f"{_at(text, i)}: a /* comment not closed by */")
            end = n if end < 0 else end + (0 if line else 2)
            for j in range(i, end):
                if out[j] != "\n":
                    out[j] = " "
            i = end
            continue
        i += 1
    return "".join(out)


def read_json_file(path, *, error=None, limit: int = MAX_JSON_BYTES, comments: bool = False):
    """The parsed JSON document in the file ``path`` (UTF-8, a byte-order mark allowed, at
    most ``limit`` bytes; with ``comments``, ``//`` and ``/* */`` comments allowed:
    :func:`without_comments`), refused
    with ``error`` (an :class:`~patternfit.errors.InputError` class) naming the file and the
    place: unreadable, not a regular file, too large, not UTF-8, or as :func:`parse_json_text`.
    """
    error = error or InputError
    data = read_bytes_capped(path, limit=limit, error=error)
    if not data or data.isspace():
        raise error("empty file: expected a JSON document", file=path)
    kind = next((name for magic, name in _BINARY_KINDS if data.startswith(magic)), None)
    if kind:
        raise error(f"{kind}, not a JSON text file", file=path)
    # the byte-order mark Windows tools (Notepad, Excel) put first is not text (RFC 8259
    # lets a reader ignore it)
    skip = len(codecs.BOM_UTF8) if data.startswith(codecs.BOM_UTF8) else 0
    try:
        text = data[skip:].decode("utf-8")
    except UnicodeDecodeError as exc:
        at = skip + exc.start
        raise error(f"not UTF-8 text (byte {at}: {data[at]:#04x})", file=path) from None
    if comments:
        try:
            text = without_comments(text)
        except ValueError as exc:
            raise error(f"not valid JSON ({exc})", file=path) from None
    return parse_json_text(text, file=path, error=error)


def dumps_finite_json(data, **kwargs) -> str:
    """``json.dumps`` that never writes ``NaN`` or ``Infinity``: a non-finite float raises
    ``ValueError`` (callers make the value ``None`` with a failed check instead)."""
    return json.dumps(data, allow_nan=False, default=json_default, **kwargs)


def json_default(o):
    """``json.dumps`` ``default`` for NumPy scalars and arrays."""
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")
