"""The studio's web application: a JSON API over one design session plus the static page.

Lengths in the API are metres, like everywhere in patternfit; the page shows centimetres.
No path from the client is ever opened: uploads are written under fixed names inside the
session folder, exports are produced under fixed names and sent back.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from fastapi import FastAPI, File, HTTPException, Request, UploadFile
from fastapi.responses import FileResponse, JSONResponse, Response
from fastapi.staticfiles import StaticFiles

from ..fit.colormap import FitScale
from .state import DRAG_OPS, STRETCH_SCALE, Studio, describe_error

STATIC = Path(__file__).parent / "static"
#: largest pattern file the page may upload [bytes]
MAX_UPLOAD = 5 * 1024 * 1024
#: hosts the server answers to (a page from another site reaching 127.0.0.1 through DNS
#: rebinding carries its own host name and is refused)
LOCAL_HOSTS = ("127.0.0.1", "localhost", "testserver")
EXPORTS = {
    "pattern.json": "pattern", "pattern.dxf": "pattern", "pattern.svg": "pattern",
    "pattern.pdf": "pattern", "garment.glb": "garment", "garment.obj": "garment",
    "report.json": "report",
}


def _correct_available() -> bool:
    try:
        from ..loop import correct  # noqa: F401
    except ImportError:
        return False
    return True


def create_app(session_dir, *, max_upload: int = MAX_UPLOAD) -> FastAPI:
    """The studio app over the design session kept in ``session_dir`` (created if missing,
    continued if it holds one). ``max_upload``: upload size limit [bytes]."""
    studio = Studio(session_dir)
    app = FastAPI(title="patternfit studio", docs_url=None, redoc_url=None)
    app.state.studio = studio

    @app.middleware("http")
    async def local_only(request: Request, call_next):
        host = (request.headers.get("host") or "").rsplit(":", 1)[0].strip("[]")
        if host not in LOCAL_HOSTS:
            return JSONResponse({"error": "the studio answers only on 127.0.0.1"}, 403)
        return await call_next(request)

    def refuse(exc: Exception, code: int = 400):
        raise HTTPException(code, describe_error(exc)) from None

    @app.exception_handler(HTTPException)
    async def http_error(request, exc: HTTPException):
        return JSONResponse({"error": exc.detail}, exc.status_code)

    def checked_revision(body: dict) -> str | None:
        rev = body.get("revision")
        if rev is not None and rev != studio.revision:
            return ("the session was changed in another tab; this change was applied on top "
                    "of it (last write wins)")
        return None

    @app.get("/", include_in_schema=False)
    def index():
        return FileResponse(STATIC / "index.html")

    app.mount("/static", StaticFiles(directory=STATIC), name="static")

    @app.get("/api/options")
    def options():
        from ..body.builtin import list_bodies
        from ..pattern.library import GARMENTS
        from ..pattern.sizes import SIZE_NAMES
        from ..sim.fabrics import FABRICS

        return {"garments": {k: v[2] for k, v in GARMENTS.items()}, "sizes": list(SIZE_NAMES),
                "bodies": list_bodies(), "fabrics": list(FABRICS),
                "engines": ["default"], "correct_available": _correct_available(),
                "max_upload": max_upload, "exports": list(EXPORTS), "drag_ops": DRAG_OPS}

    @app.get("/api/state")
    def state():
        try:
            s = studio.ensure()
        except Exception as exc:
            refuse(exc, 500)
        with studio.lock:
            return {"revision": studio.revision, "info": studio.info,
                    "fabric": s.fabric.name, "triangles": s.triangles,
                    "threshold": s.threshold, "position": s.position,
                    "history": [{k: r[k] for k in ("index", "label", "fitting_ratio", "current")}
                                for r in s.summary()],
                    "fitting_ratio": s.state.fitting_ratio, "draped": s.positions is not None,
                    "checks": s.state.checks, "drape": studio.job.as_dict(),
                    "can_undo": s.position > 0, "can_redo": s.position + 1 < len(s.history)}

    @app.get("/api/geometry")
    def geometry():
        with studio.lock:
            s = studio.ensure()
            return _geometry(s)

    @app.get("/api/garment3d")
    def garment3d():
        with studio.lock:
            s = studio.ensure()
            if s.positions is None:
                raise HTTPException(409, "nothing draped yet")
            return _garment3d(s)

    @app.get("/api/body")
    def body():
        b = studio.ensure().body
        return {"name": b.name, "vertices": np.round(b.vertices, 5).ravel().tolist(),
                "faces": b.faces.ravel().tolist()}

    @app.post("/api/new")
    async def new(request: Request):
        body = await request.json()
        try:
            studio.new(**{k: body[k] for k in ("garment", "size", "body", "fabric", "triangles")
                          if k in body})
        except Exception as exc:
            refuse(exc)
        return {"ok": True, "revision": studio.revision}

    @app.post("/api/edit")
    async def edit(request: Request):
        body = await request.json()
        warning = checked_revision(body)
        try:
            result = studio.apply(str(body.get("op")), dict(body.get("args") or {}))
        except Exception as exc:
            refuse(exc)
        return {"ok": True, "warning": warning, "revision": studio.revision, **result}

    @app.post("/api/drag")
    async def drag(request: Request):
        body = await request.json()
        try:
            vertices, moved = studio.drag(str(body.get("op")), dict(body.get("args") or {}))
        except Exception as exc:
            refuse(exc)
        # the preview travels as raw float32 (n, 2): the page maps it straight onto its mesh
        return Response(np.ascontiguousarray(vertices, dtype="<f4").tobytes(),
                        media_type="application/octet-stream",
                        headers={"X-Moved": ",".join(moved)})

    @app.post("/api/drag/basis")
    async def drag_basis(request: Request):
        body = await request.json()
        try:
            basis = studio.drag_basis(str(body.get("op")), dict(body.get("args") or {}))
        except Exception as exc:
            refuse(exc)
        return Response(np.ascontiguousarray(basis, dtype="<f4").tobytes(),
                        media_type="application/octet-stream")

    @app.post("/api/undo")
    async def undo(request: Request):
        body = await request.json() if await request.body() else {}
        warning = checked_revision(body)
        try:
            studio.undo()
        except Exception as exc:
            refuse(exc)
        return {"ok": True, "warning": warning, "revision": studio.revision}

    @app.post("/api/redo")
    async def redo(request: Request):
        body = await request.json() if await request.body() else {}
        warning = checked_revision(body)
        try:
            studio.redo()
        except Exception as exc:
            refuse(exc)
        return {"ok": True, "warning": warning, "revision": studio.revision}

    @app.post("/api/drape")
    def drape():
        try:
            studio.start_drape()
        except Exception as exc:
            refuse(exc, 409)
        return studio.job.as_dict()

    @app.post("/api/correct")
    def correct():
        try:
            studio.start_drape(kind="correct")
        except Exception as exc:
            refuse(exc, 409)
        return studio.job.as_dict()

    @app.get("/api/drape")
    def drape_progress():
        return studio.job.as_dict()

    @app.post("/api/drape/stop")
    def drape_stop():
        studio.stop_drape()
        return studio.job.as_dict()

    @app.post("/api/upload")
    async def upload(file: UploadFile = File(...)):
        from ..pattern.formats import READ_SUFFIXES, load_any_pattern

        # only the ending of the client's file name is used, to pick the reader
        suffix = Path(file.filename or "").suffix.lower()
        if suffix not in READ_SUFFIXES:
            raise HTTPException(400, f"upload: expected a {' or '.join(READ_SUFFIXES)} file")
        data = await file.read(max_upload + 1)
        if len(data) > max_upload:
            raise HTTPException(413, f"upload: larger than {max_upload // 1024} KiB")
        from ..files import atomic_write_bytes

        target = studio.folder / "uploads" / f"upload{suffix}"
        atomic_write_bytes(target, data)
        try:
            pattern = load_any_pattern(target)
            studio.start_from(pattern, source=f"uploaded {Path(file.filename).name}")
        except Exception as exc:
            # the message names the client's file, not the server's folder
            raise HTTPException(400, describe_error(exc).replace(
                str(target), Path(file.filename).name)) from None
        return {"ok": True, "revision": studio.revision, "panels": len(pattern.panels)}

    @app.get("/api/export/{name}")
    def export(name: str):
        if name not in EXPORTS:
            raise HTTPException(404, f"export: one of {', '.join(EXPORTS)}")
        try:
            path = _export(studio, name)
        except Exception as exc:
            refuse(exc, 409)
        return FileResponse(path, filename=path.name)

    return app


def _geometry(s) -> dict:
    """The 2D picture of the current state: pattern outlines, the mesh, fit colours."""
    mesh = s.mesh
    panels = []
    for p in s.pattern.panels:
        loops = [{"name": lp.name, "edges": [{"name": e.name, "kind": e.kind,
                                              "points": np.asarray(e.points).tolist(),
                                              "polyline": e.point_at(np.linspace(0, 1, 24)
                                                                     ).tolist()}
                                             for e in lp.edges]}
                 for lp in p.loops]
        panels.append({"name": p.name, "loops": loops})
    seams = [{"name": sm.name, "a": [sm.a.panel, sm.a.edge], "b": [sm.b.panel, sm.b.edge]}
             for sm in s.pattern.seams]
    out = {"panels": panels, "seams": seams, "panel_names": list(mesh.panel_names),
           "vertices": np.round(mesh.vertices, 6).ravel().tolist(),
           "triangles": mesh.triangles.ravel().tolist(),
           "triangle_panel": mesh.triangle_panel.tolist(), "colors": None}
    if s.positions is not None:
        fit = s.evaluate()
        out["colors"] = _rgb(FitScale().colors(fit.area_change))
        out["area_change"] = np.round(fit.area_change, 5).tolist()
    return out


def _rgb(colors) -> list:
    return np.round(np.asarray(colors) * 255).astype(int).ravel().tolist()


def _garment3d(s) -> dict:
    """The draped garment: positions, triangles, the three fit maps with their colours."""
    fit = s.evaluate()
    scale = FitScale()
    maps = {"area_change": (fit.area_change, scale), "warp": (fit.warp - 1, STRETCH_SCALE),
            "weft": (fit.weft - 1, STRETCH_SCALE)}
    return {"positions": np.round(s.positions, 5).ravel().tolist(),
            "triangles": s.mesh.triangles.ravel().tolist(),
            "fitting_ratio": fit.fitting_ratio,
            "maps": {k: {"values": np.round(v, 5).tolist(), "colors": _rgb(sc.colors(v)),
                         "legend": [{"value": val, "rgb": _rgb(rgb), "label": label}
                                    for val, rgb, label in sc.legend()]}
                     for k, (v, sc) in maps.items()}}


def _export(studio: Studio, name: str) -> Path:
    """Write export ``name`` (a key of ``EXPORTS``) into the session's export folder."""
    from ..fit.colormap import vertex_values
    from ..fit.export import export_garment
    from ..fit.report import fit_report, write_report
    from ..pattern.formats import save_any_pattern

    with studio.lock:
        s = studio.ensure()
        folder = studio.folder / "exports"
        folder.mkdir(exist_ok=True)
        path = folder / name
        kind = EXPORTS[name]
        if kind == "pattern":
            fit = s.evaluate() if s.positions is not None and path.suffix in (".svg", ".pdf") \
                else None
            colours = None if fit is None else (s.mesh.vertices, s.mesh.triangles,
                                                FitScale().colors(fit.area_change),
                                                s.mesh.triangle_panel)
            save_any_pattern(s.pattern, path, fit=colours)
            return path
        if s.positions is None:
            raise RuntimeError("drape the garment first")
        fit = s.evaluate()
        if kind == "garment":
            rgb = FitScale().colors(vertex_values(s.mesh.triangles, fit.area_change,
                                                  s.mesh.n_vertices, weights=fit.area_2d))
            return export_garment(s.positions, s.mesh.triangles, rgb, path)
        return write_report(fit_report(s.mesh, fit, state="draped",
                                       extra={"checks": s.state.checks,
                                              "history": s.summary()}), path)
