"""Requests about the session as a whole: what can be chosen, the session's state, a new
session, an uploaded pattern/body/fabric, undo and redo."""

from __future__ import annotations

from fastapi import APIRouter, Depends, HTTPException, Request

from ... import api
from ...body.builtin import list_bodies
from ...pattern.library import GARMENTS
from ...pattern.sizes import SIZE_NAMES
from ...sim.fabrics import FABRICS
from ..exports import EXPORTS
from ..guard import MULTIPART_SLACK, multipart_file, read_capped
from ..payload import body as body_payload
from ..requests import NewSession, Revisioned, body, in_worker, studio_of
from ..state import DRAG_OPS, ENGINES, UPLOAD_SUFFIXES, Studio

router = APIRouter(prefix="/api")


@router.get("/options")
def options(request: Request):
    # correct_available: always, the loop ships with the package (state.py imports it)
    return {"garments": {k: v[2] for k, v in GARMENTS.items()}, "sizes": list(SIZE_NAMES),
            "bodies": list_bodies(), "fabrics": list(FABRICS),
            "engines": _engines(), "correct_available": True,
            "max_upload": request.app.state.max_upload, "exports": list(EXPORTS),
            "drag_ops": DRAG_OPS,
            "uploads": {k: list(v) for k, v in UPLOAD_SUFFIXES.items()}}


def _engines() -> list[dict]:
    """Every drape engine: ``usable`` by the studio's sessions, ``installed`` here, and a
    note saying which, for the Engine menu."""
    out = []
    for name, missing in api.list_engines().items():
        usable = name in ENGINES and missing is None
        note = ("the quasi-static solver: drapes to equilibrium" if usable else
                missing or "installed; the studio's design sessions drape with the static "
                           "engine only (use patternfit drape --engine " + name + ")")
        out.append({"name": name, "usable": usable, "installed": missing is None,
                    "note": note})
    return out


@router.get("/state")
async def state(studio: Studio = Depends(studio_of)):
    if studio.summary is None:  # the first request of a new folder makes its session
        await in_worker(studio.ensure)
    return {**studio.summary, "drape": studio.job.as_dict()}


@router.get("/body")
async def body_mesh(request: Request, studio: Studio = Depends(studio_of)):
    payload = await in_worker(lambda: body_payload(studio.ensure().body))
    return payload.response(request)


@router.post("/new")
async def new(req: NewSession = Depends(body(NewSession)),
              studio: Studio = Depends(studio_of)):
    archived = await in_worker(lambda: studio.new(**req.given(), revision=req.revision))
    return {"ok": True, "revision": studio.revision, "archived": archived}


@router.post("/upload")
async def upload(request: Request, kind: str = "pattern", revision: str | None = None,
                 studio: Studio = Depends(studio_of)):
    if revision is not None and not revision.isdigit():
        raise ValueError("revision: expected a whole number")
    seen = None if revision is None else int(revision)
    cap = request.app.state.max_upload
    raw = await read_capped(request, cap + MULTIPART_SLACK, "upload", stated=cap)
    file = await multipart_file(request.headers, raw)
    data = await file.read(cap + 1)
    if len(data) > cap:
        raise HTTPException(413, f"upload: larger than {cap // 1024} KiB")
    result = await in_worker(studio.upload, kind, file.filename or "", data, seen)
    return {"ok": True, "revision": studio.revision, **result}


def _step(studio: Studio, which: str, revision: int | None) -> dict:
    with studio.lock:
        getattr(studio, which)(revision)
        return {"ok": True, "revision": studio.revision}


@router.post("/undo")
async def undo(req: Revisioned = Depends(body(Revisioned)), studio: Studio = Depends(studio_of)):
    return await in_worker(_step, studio, "undo", req.revision)


@router.post("/redo")
async def redo(req: Revisioned = Depends(body(Revisioned)), studio: Studio = Depends(studio_of)):
    return await in_worker(_step, studio, "redo", req.revision)
