"""Requests of the 2D editor: the pattern and mesh to draw, an edit, and the live preview
of a drag (raw float32 vertices, and the drag's linear basis)."""

from __future__ import annotations

import numpy as np
from fastapi import APIRouter, Depends, Request
from fastapi.responses import Response

from ..payload import BINARY
from ..requests import Edit, body, in_worker, studio_of
from ..state import Studio

router = APIRouter(prefix="/api")


@router.get("/geometry")
async def geometry(request: Request, studio: Studio = Depends(studio_of)):
    # no lock: a state's pattern and mesh are never replaced, so the geometry does not wait
    # for the background saver (0.4 s at 22K) or an edit
    payload = await in_worker(lambda: studio.views.get("geometry", studio.current()))
    return payload.response(request)


@router.post("/edit")
async def edit(req: Edit = Depends(body(Edit)), studio: Studio = Depends(studio_of)):
    def run():
        with studio.lock:
            result = studio.apply(req.op, req.args, req.revision)
            return {"ok": True, "revision": studio.revision, **result}
    return await in_worker(run)


def _float32(a) -> bytes:
    return np.ascontiguousarray(a, dtype="<f4").tobytes()


@router.post("/drag")
async def drag(req: Edit = Depends(body(Edit)), studio: Studio = Depends(studio_of)):
    vertices, moved = await in_worker(studio.drag, req.op, req.args)
    # the preview travels as raw float32 (n, 2): the page maps it straight onto its mesh
    return Response(_float32(vertices), media_type=BINARY,
                    headers={"X-Moved": ",".join(moved)})


@router.post("/drag/basis")
async def drag_basis(req: Edit = Depends(body(Edit)), studio: Studio = Depends(studio_of)):
    return Response(_float32(await in_worker(studio.drag_basis, req.op, req.args)),
                    media_type=BINARY)
