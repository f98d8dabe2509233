"""What the page draws, as a small JSON header plus typed arrays, and the two ways it travels.

The page asks with ``Accept: application/octet-stream`` and gets one binary body (a 22K
coat's draped session is 1.3 MB instead of 3.7 MB of JSON, and needs no parsing of numbers):

    uint32 LE  n                      length of the header [bytes], a multiple of 4
    n bytes    header                 UTF-8 JSON: the plain fields, and under "arrays" each
                                      array's {"dtype", "shape", "offset", "bytes"}
    ...        array data             each array little-endian, at 4-byte aligned offsets
                                      counted from the end of the header

Any other client gets the same fields as JSON, arrays as (flat) lists. Lengths [m].
"""

from __future__ import annotations

import json
import threading
from collections import OrderedDict
from typing import Callable

import numpy as np
from fastapi import Request
from fastapi.responses import JSONResponse, Response

from .. import api
from ..fit.colormap import FitScale
from ..fit.pictures import FAILED_GREY, fit_colours
from ..fit.report import failure

BINARY = "application/octet-stream"
#: relative stretch at which the warp/weft colours saturate [-]
STRETCH_SCALE = FitScale(limit=0.10, band=0.01)
#: history states whose payloads are kept (the current one, the last few undone)
KEPT_STATES = 4
#: the typed arrays the page reads: numpy dtype -> the header's name (JS typed array)
DTYPES = {"<f4": "float32", "<i4": "int32", "|u1": "uint8"}


class Payload:
    """A JSON header and named arrays (sent flat; ``shape`` in the binary header). A dotted
    array name puts the array inside the header's objects: ``maps.warp.values`` is
    ``header["maps"]["warp"]["values"]`` once read."""

    def __init__(self, header: dict, arrays: dict[str, np.ndarray]):
        self.header, self.arrays = header, arrays
        self._binary: bytes | None = None

    def binary(self) -> bytes:
        """The binary body (made once: a payload is never changed after it is made)."""
        if self._binary is None:
            self._binary = self._pack()
        return self._binary

    def _pack(self) -> bytes:
        table, parts, offset = {}, [], 0
        for name, a in self.arrays.items():
            a = np.ascontiguousarray(a)
            data = a.tobytes()
            table[name] = {"dtype": DTYPES[a.dtype.str], "shape": list(a.shape),
                           "offset": offset, "bytes": len(data)}
            pad = -len(data) % 4
            parts.append(data + b"\0" * pad)
            offset += len(data) + pad
        head = json.dumps({**self.header, "arrays": table}, allow_nan=False,
                          separators=(",", ":")).encode()
        head += b" " * (-len(head) % 4)
        return len(head).to_bytes(4, "little") + head + b"".join(parts)

    def as_json(self) -> dict:
        out = json.loads(json.dumps(self.header))  # a deep copy to put the arrays into
        for name, a in self.arrays.items():
            *path, last = name.split(".")
            place = out
            for key in path:
                place = place.setdefault(key, {})
            place[last] = a.ravel().tolist()
        return out

    def response(self, request: Request) -> Response:
        """Binary when the client asks for it (``Accept``), JSON otherwise."""
        if BINARY in request.headers.get("accept", ""):
            return Response(self.binary(), media_type=BINARY)
        return JSONResponse(self.as_json())


def f4(a) -> np.ndarray:
    return np.asarray(a, dtype="<f4")


def i4(a) -> np.ndarray:
    return np.asarray(a, dtype="<i4")


def rgb(colors) -> np.ndarray:
    """Colours in [0, 1] (m, 3) as bytes 0..255, sRGB."""
    return np.round(np.asarray(colors) * 255).astype("|u1")


def stale_maps(st) -> bool:
    """Whether history state ``st`` shows the 3D state of an older drape: after an edit (or
    a stopped drape) the state keeps the last drape's positions as the next re-drape's
    start, and its ϖ is unknown until re-draped. Its maps are not the edited pattern's fit."""
    return st.positions is not None and st.fitting_ratio is None


class Views:
    """What the page draws of the last few history states, each made once: a state's
    pattern and mesh are never replaced, and its positions only by a whole new array (a
    re-drape), so an entry holds while the state keeps the positions it was made from.

    ``get(kind, state)`` makes ``kind`` (one of ``MAKERS``, or any name with ``make``)
    on first use; two requests for the same one wait for one making, so the studio can make
    them in the background after a change while the page already asks. The fit evaluation
    (``api.evaluate_drape``) is shared by the 2D and 3D payloads of a state.
    """

    def __init__(self, keep: int = KEPT_STATES):
        self.keep = keep
        self._lock = threading.Lock()
        self._items: OrderedDict = OrderedDict()  # state key -> {kind: [lock, value]}

    def _slot(self, st, kind: str) -> list:
        with self._lock:
            entry = self._items.get(st.key)
            if entry is None or entry["positions"] is not st.positions:
                entry = self._items[st.key] = {"positions": st.positions}
            self._items.move_to_end(st.key)
            while len(self._items) > self.keep:
                self._items.popitem(last=False)
            return entry.setdefault(kind, [threading.Lock(), None])

    def get(self, kind: str, st, make: Callable | None = None):
        """``kind`` of history state ``st``: ``make(st, views)`` (default ``MAKERS[kind]``)
        on first use, kept while ``st`` keeps its positions."""
        slot = self._slot(st, kind)
        with slot[0]:
            if slot[1] is None:
                slot[1] = (make or MAKERS[kind])(st, self)
            return slot[1]

    def fit(self, st):
        """The fit evaluation of ``st``'s drape (``api.evaluate_drape``; None: not draped)."""
        return self.get("fit", st, lambda s, _: None if s.positions is None else
                        api.evaluate_drape(s.mesh, s.positions))


def geometry(s, views: Views | None = None) -> Payload:
    """The 2D picture of history state ``s`` (a session's ``state``, whose pattern and mesh
    are never replaced: read without the session's lock): pattern outlines, the mesh (flat
    vertices (n, 2) [m], triangles (m, 3), the panel of each triangle), and the fit colours
    of the last drape (``stale`` when they are not this pattern's). ``views``: where the fit
    evaluation is kept (shared with :func:`garment3d`)."""
    mesh = s.mesh
    panels = []
    for p in s.pattern.panels:
        loops = [{"name": lp.name, "edges": [{"name": e.name, "kind": e.kind,
                                              "length": e.length,
                                              "points": np.asarray(e.points).tolist(),
                                              "polyline": e.point_at(np.linspace(0, 1, 24)
                                                                     ).tolist()}
                                             for e in lp.edges]}
                 for lp in p.loops]
        panels.append({"name": p.name, "loops": loops})
    seams = [{"name": sm.name, "a": [sm.a.panel, sm.a.edge], "b": [sm.b.panel, sm.b.edge],
              "spans": [[sm.a.start, sm.a.end], [sm.b.start, sm.b.end]],
              "lengths": [s.pattern.seam_side_length(sm.a), s.pattern.seam_side_length(sm.b)],
              "ease": sm.ease, "reverse": sm.reverse}
             for sm in s.pattern.seams]
    arrays = {"vertices": f4(mesh.vertices), "triangles": i4(mesh.triangles),
              "triangle_panel": i4(mesh.triangle_panel)}
    header = {"panels": panels, "seams": seams, "panel_names": list(mesh.panel_names),
              "colors": None, "stale": stale_maps(s)}
    if s.positions is not None:
        fit = (views or Views()).fit(s)
        del header["colors"]
        # a failed drape is grey, as in the CLI's pictures: no fit colour may suggest a fit
        arrays["colors"] = rgb(fit_colours(FitScale(), fit.area_change, failure(s.checks)))
        arrays["area_change"] = f4(fit.area_change)
    return Payload(header, arrays)


def garment3d(s, views: Views | None = None) -> Payload:
    """The draped garment of history state ``s``: positions (n, 3) [m], triangles, the
    three fit maps (values and colours per triangle) with their legends; ``stale`` as in
    :func:`geometry`, ``views`` too."""
    fit = (views or Views()).fit(s)
    scale = FitScale()
    failed = failure(s.checks)
    maps = {"area_change": (fit.area_change, scale), "warp": (fit.warp - 1, STRETCH_SCALE),
            "weft": (fit.weft - 1, STRETCH_SCALE)}

    def legend(sc):
        if failed:  # one grey swatch: the maps of a failed drape are no fit
            return [{"value": None, "rgb": rgb(FAILED_GREY).tolist(),
                     "label": "the drape failed its checks: not a fit"}]
        return [{"value": val, "rgb": rgb(c).tolist(), "label": label}
                for val, c, label in sc.legend()]

    header = {"fitting_ratio": fit.fitting_ratio, "stale": stale_maps(s), "failed": failed,
              "maps": {k: {"legend": legend(sc)} for k, (_, sc) in maps.items()}}
    arrays = {"positions": f4(s.positions), "triangles": i4(s.mesh.triangles)}
    for k, (v, sc) in maps.items():
        arrays[f"maps.{k}.values"] = f4(v)
        arrays[f"maps.{k}.colors"] = rgb(fit_colours(sc, v, failed))
    return Payload(header, arrays)


def body(b) -> Payload:
    """The body mesh: vertices (n, 3) [m], faces (m, 3)."""
    return Payload({"name": b.name}, {"vertices": f4(b.vertices), "faces": i4(b.faces)})


#: the payloads :class:`Views` makes by name
MAKERS = {"geometry": geometry, "garment3d": garment3d}
