"""Helpers of the fabric-file tests (SI files, KES-F / FAST sheets, ARCSim materials)."""

from __future__ import annotations

import json
import math

from hypothesis import strategies as st

from patternfit.sim.fabrics import RANGES, FabricError, load_fabric


def write(tmp_path, data, name: str = "fabric.json"):
    """``data`` (a dict, written as JSON, or the file's text) at ``tmp_path / name``."""
    path = tmp_path / name
    path.write_text(data if isinstance(data, str) else json.dumps(data))
    return path


def within(key: str):
    """Floats inside the plausible range of the Fabric field ``key``."""
    lo, hi, _ = RANGES[key]
    return st.floats(max(lo, 1e-9) * 1.01, hi * 0.99, allow_nan=False)


def read_or_refused_by_name(path) -> None:
    """The fabric file ``path`` reads to finite values, or is refused naming the file and a
    field or two (weight and thickness; or, for an infinity, which JSON does not allow, the
    line and column)."""
    try:
        fab = load_fabric(path)
    except FabricError as err:
        assert err.file == str(path)
        assert (err.place or "").startswith(("field ", "fields ")) or "line 1, column" in str(err)
    else:
        assert all(math.isfinite(v) for v in fab.to_dict().values() if not isinstance(v, str))
