"""Requests about draping: start a drape or the automatic correction, follow and stop it,
the draped garment with its fit maps, and the exports."""

from __future__ import annotations

import mimetypes

from fastapi import APIRouter, Depends, HTTPException, Request
from fastapi.responses import Response

from ..exports import EXPORTS, export as export_bytes, verdict as verdict_of
from ..requests import Revisioned, body, in_worker, studio_of
from ..jobs import Refused
from ..state import Studio

router = APIRouter(prefix="/api")


async def _start(kind: str, revision: int | None, studio: Studio) -> dict:
    def run():
        studio.start_drape(kind=kind, revision=revision)
        return studio.job.as_dict()
    return await in_worker(run)


@router.post("/drape")
async def drape(req: Revisioned = Depends(body(Revisioned)),
                studio: Studio = Depends(studio_of)):
    return await _start("drape", req.revision, studio)


@router.post("/correct")
async def correct(req: Revisioned = Depends(body(Revisioned)),
                  studio: Studio = Depends(studio_of)):
    return await _start("correct", req.revision, studio)


@router.get("/drape")
def drape_progress(studio: Studio = Depends(studio_of)):
    return studio.job.as_dict()


@router.post("/drape/stop")
def drape_stop(studio: Studio = Depends(studio_of)):
    studio.stop_drape()
    return studio.job.as_dict()


@router.get("/garment3d")
async def garment3d(request: Request, studio: Studio = Depends(studio_of)):
    def read():
        st = studio.current()  # no lock, as the geometry
        if st.positions is None:
            raise Refused("nothing draped yet")
        return studio.views.get("garment3d", st)
    return (await in_worker(read)).response(request)


@router.get("/verdict")
async def verdict(studio: Studio = Depends(studio_of)):
    """The drape's fit verdict where the report gives one (``verdict``,
    ``region_verdicts``); ``{}`` otherwise."""
    return await in_worker(verdict_of, studio)


@router.get("/export/{name}")
async def export(name: str, studio: Studio = Depends(studio_of)):
    if name not in EXPORTS:
        raise HTTPException(404, f"export: one of {', '.join(EXPORTS)}")
    data = await in_worker(export_bytes, studio, name)
    return Response(data, media_type=mimetypes.guess_type(name)[0] or
                    "application/octet-stream",
                    headers={"Content-Disposition": f'attachment; filename="{name}"'})
