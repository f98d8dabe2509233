"""What every row of a batch folder was draped with, kept in ``batch.json`` beside the rows:
the mesh size, the solver's time limit and a digest of each pattern, fabric or body file. A resume
with other settings would put the rows of two batches side by side under one matrix (rows at
1,200 and at 300 triangles, nothing in them to tell which), so it is refused.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

from ..errors import InputError
from ..files import atomic_write_text, read_json_file

#: the settings file of a batch folder
SETTINGS_NAME = "batch.json"
SETTINGS_FORMAT = "patternfit-batch-settings"


def file_digests(names) -> dict[str, str]:
    """``{name: sha256}`` of those of ``names`` that are regular files, read already by the
    batch (the others are built-in garments and fabric presets, which come with the
    installed version)."""
    out = {}
    for n in names:
        if Path(n).is_file():
            with open(n, "rb") as fh:
                out[str(n)] = hashlib.file_digest(fh, "sha256").hexdigest()
    return out


def saved_files(folder) -> dict[str, str]:
    """``{name: sha256}`` of the files a batch folder's rows were draped from, as its
    ``batch.json`` keeps them (empty without one of ours)."""
    path = Path(folder) / SETTINGS_NAME
    if not path.is_file():
        return {}
    saved = read_json_file(path, error=InputError)
    files = saved.get("files") if isinstance(saved, dict) \
        and saved.get("format") == SETTINGS_FORMAT else None
    return {str(k): str(v) for k, v in files.items()} if isinstance(files, dict) else {}


def keep_settings(folder, settings: dict, *, resume: bool) -> None:
    """Write ``settings`` (JSON values: ``triangles``, ``time_limit`` [s], ``files``: their
    digests) to ``folder/batch.json``; with ``resume`` first check them against the file
    there. Raises :class:`InputError` naming the file and the first setting that differs,
    or a file of that name that is not ours (never replaced). A folder without the file (a
    batch from before it was written) takes this run's."""
    path = Path(folder) / SETTINGS_NAME
    if not path.exists():
        resume = False
    else:
        saved = read_json_file(path, error=InputError)
        if not isinstance(saved, dict) or saved.get("format") != SETTINGS_FORMAT:
            raise InputError("is not a batch settings file patternfit wrote, and the batch "
                             "would replace it: move it, or give another --out folder",
                             file=path)
    if resume:
        for key, value in settings.items():
            why = _differs(key, saved.get(key), value)
            if why:
                raise InputError(why + ": resume it with the same settings and files, or give "
                                 "another --out folder", file=path)
        # a resume may name fewer inputs or more: every file a row was draped from is kept
        settings = {**settings, "files": {**saved.get("files", {}), **settings["files"]}}
    atomic_write_text(path, json.dumps({"format": SETTINGS_FORMAT, "version": 1, **settings},
                                       indent=1) + "\n")


def _differs(key: str, saved, value) -> str | None:
    """A setting of the batch that this run changes, in words, or None. Of the files, only
    one given both times with other contents: a resume may leave inputs out or add some."""
    if key == "files" and isinstance(saved, dict):
        changed = sorted(n for n in value if n in saved and saved[n] != value[n])
        return (f"the file {changed[0]} is not the one the batch was draped with (its "
                "contents changed since)") if changed else None
    if saved == value:
        return None
    return f"the batch in this folder was draped with {key} = {saved!r}, this run with {value!r}"
