"""The studio's web application: a JSON API over one design session plus the static page.

Lengths in the API are metres, like everywhere in patternfit; the page shows centimetres.
No path from the client is ever opened: bodies and fabrics are chosen by preset name or
uploaded, uploads are read under names of the studio's choosing inside the session folder,
and each export is written to a fresh folder of its own and sent back.

No other web page can drive the studio: every request must name the studio's own address
in ``Host`` (and in ``Origin``, where the browser sends one), and every request that changes
something, and every export, must carry the random token the page was served with in the
``X-Patternfit-Token`` header. JSON bodies must be sent as ``application/json``, uploads as
``multipart/form-data``. Heavy work (meshing, edits, exports, reading uploads) runs in
worker threads, so the server keeps answering ``GET /api/state`` meanwhile.
"""

from __future__ import annotations

import mimetypes
import secrets
import tempfile
from pathlib import Path

import anyio
import numpy as np
from fastapi import FastAPI, HTTPException, Request
from fastapi.responses import HTMLResponse, JSONResponse, Response
from fastapi.staticfiles import StaticFiles
from starlette.datastructures import Headers, UploadFile
from starlette.formparsers import MultiPartException, MultiPartParser

from ..body.builtin import list_bodies
from ..constants import limits
from ..errors import InputError
from ..files import parse_json_text
from ..fit.colormap import FitScale, vertex_values
from ..fit.export import export_garment
from ..fit.report import fit_report, write_report
from ..pattern.formats import save_any_pattern
from ..pattern.library import GARMENTS
from ..pattern.sizes import SIZE_NAMES
from ..sim.fabrics import FABRICS
from .state import (
    DRAG_OPS,
    ENGINES,
    STRETCH_SCALE,
    UPLOAD_SUFFIXES,
    StaleRevision,
    Studio,
    describe_error,
)

STATIC = Path(__file__).parent / "static"
#: the names the studio answers to (a page from another site reaching 127.0.0.1 through DNS
#: rebinding carries its own host name and is refused)
LOCAL_HOSTS = ("127.0.0.1", "localhost")
#: the header every state-changing request carries the page's token in
TOKEN_HEADER = "X-Patternfit-Token"
#: room for the multipart framing (boundaries, part headers) around an upload [bytes]
MULTIPART_SLACK = 64 * 1024
EXPORTS = {
    "pattern.json": "pattern", "pattern.dxf": "pattern", "pattern.svg": "pattern",
    "pattern.pdf": "pattern", "garment.glb": "garment", "garment.obj": "garment",
    "report.json": "report",
}
_TOKEN_SLOT = "__PATTERNFIT_TOKEN__"


class _Guard:
    """ASGI middleware refusing what no page of the studio's own sends: a foreign ``Host``
    (403), a foreign ``Origin`` (403), a request that changes something (or exports) without
    the token (403), and a body of the wrong type (415)."""

    def __init__(self, app, *, hosts, token: str):
        self.app = app
        self.hosts = tuple(hosts)
        self.token = token

    async def __call__(self, scope, receive, send):
        if scope["type"] == "http":
            refusal = self.refusal(scope)
            if refusal is not None:
                await JSONResponse({"error": refusal[1]}, refusal[0])(scope, receive, send)
                return
        await self.app(scope, receive, send)

    def refusal(self, scope) -> tuple[int, str] | None:
        """``(status, message)`` for a request to refuse, None to let it through."""
        headers = Headers(scope=scope)
        port = (scope.get("server") or (None, None))[1]
        name, _, given = (headers.get("host") or "").partition(":")
        if port is None or name not in self.hosts or (given or "80") != str(port):
            return 403, f"the studio answers only on {self.hosts[0]}"
        # an exact match: a page on another port of this machine is another site
        own = {f"http://{h}:{port}" for h in self.hosts}
        if port == 80:
            own |= {f"http://{h}" for h in self.hosts}
        origin = headers.get("origin")
        if origin is not None and origin not in own:
            return 403, "requests from other sites are refused"
        path, method = scope["path"], scope["method"]
        if method in ("GET", "HEAD") and not path.startswith("/api/export/"):
            return None
        if not secrets.compare_digest(headers.get(TOKEN_HEADER, "").encode(),
                                      self.token.encode()):
            return 403, (f"missing or wrong {TOKEN_HEADER} header (reload the page: the studio "
                         "may have been restarted)")
        if method in ("GET", "HEAD"):
            return None
        kind = headers.get("content-type", "").split(";")[0].strip().lower()
        wanted = "multipart/form-data" if path == "/api/upload" else "application/json"
        # a request without a body (POST /api/drape) needs no type
        if kind != wanted and not (kind == "" and headers.get("content-length") == "0"
                                   and wanted == "application/json"):
            return 415, f"expected a {wanted} body"
        return None


async def _read_capped(request: Request, limit: int, what: str) -> bytes:
    """The request body, refused with 413 once it is found larger than ``limit`` bytes: from
    ``Content-Length`` before reading, else while it arrives (nothing beyond is read)."""
    declared = request.headers.get("content-length")
    if declared is not None:
        if not declared.isdigit():
            raise HTTPException(400, "Content-Length: not a number")
        if int(declared) > limit:
            raise HTTPException(413, f"{what}: larger than {limit // 1024} KiB")
    body = bytearray()
    async for chunk in request.stream():
        body += chunk
        if len(body) > limit:
            raise HTTPException(413, f"{what}: larger than {limit // 1024} KiB")
    return bytes(body)


def _json_object(raw: bytes) -> dict:
    """The JSON object of a request body (an empty body is ``{}``); InputError otherwise."""
    if not raw:
        return {}
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise InputError("not UTF-8 text", file="request body") from None
    body = parse_json_text(text, file="request body")
    if not isinstance(body, dict):
        raise InputError("expected a JSON object", file="request body")
    return body


def _edit_request(body: dict) -> tuple[str, dict]:
    """``op`` and ``args`` of an edit or drag request, checked for their JSON types."""
    op, args = body.get("op"), body.get("args", {})
    if not isinstance(op, str):
        raise ValueError("op: expected the name of an editing tool")
    if not isinstance(args, dict):
        raise ValueError("args: expected an object of the tool's arguments")
    if "label" in args:  # the label is the studio's own description of the edit
        raise ValueError("args: 'label' is not an argument of an editing tool")
    return op, args


def _revision(body: dict) -> int | None:
    """The revision the asking tab last saw (None: not given, not checked)."""
    rev = body.get("revision")
    if rev is not None and (isinstance(rev, bool) or not isinstance(rev, int)):
        raise ValueError("revision: expected a whole number")
    return rev


def _query_revision(text: str | None) -> int | None:
    if text is None:
        return None
    if not text.isdigit():
        raise HTTPException(400, "revision: expected a whole number")
    return int(text)


def create_app(session_dir, *, max_upload: int | None = None,
               allowed_hosts=LOCAL_HOSTS) -> FastAPI:
    """The studio app over the design session kept in ``session_dir`` (created if missing,
    continued if it holds one; a saved session that does not load raises
    :class:`~patternfit.errors.SessionError`). ``max_upload``: upload size limit [bytes]
    (default ``limits.upload_bytes``). ``allowed_hosts``: the host names requests may address
    (tests add the test client's ``"testserver"``). The page's token is ``app.state.token``.
    """
    studio = Studio(session_dir)
    max_upload = limits.upload_bytes if max_upload is None else int(max_upload)
    token = secrets.token_urlsafe(32)
    page = (STATIC / "index.html").read_text(encoding="utf-8").replace(_TOKEN_SLOT, token)
    app = FastAPI(title="patternfit studio", docs_url=None, redoc_url=None, openapi_url=None)
    app.state.studio = studio
    app.state.token = token
    app.add_middleware(_Guard, hosts=allowed_hosts, token=token)

    @app.exception_handler(HTTPException)
    async def http_error(request, exc: HTTPException):
        return JSONResponse({"error": exc.detail}, exc.status_code)

    @app.exception_handler(StaleRevision)
    async def stale_revision(request, exc: StaleRevision):
        # a tab that missed another tab's change: nothing was changed, the page must reload
        return JSONResponse({"error": str(exc), "stale": True, "revision": exc.current}, 409)

    @app.exception_handler(Exception)
    async def server_error(request, exc: Exception):
        return JSONResponse({"error": f"internal error: {describe_error(exc)}"}, 500)

    async def in_worker(fn, *args, code: int = 400):
        """``fn(*args)`` in a worker thread, so the server keeps answering meanwhile. Its
        refusals answer ``code``; past ``limits.request_seconds`` the client gets 503 (the
        work itself cannot be interrupted: it finishes in the background)."""
        try:
            with anyio.fail_after(limits.request_seconds):
                return await anyio.to_thread.run_sync(fn, *args, abandon_on_cancel=True)
        except TimeoutError:
            raise HTTPException(503, f"the request took longer than {limits.request_seconds:g} s"
                                     "; it finishes in the background (reload to see it)"
                                ) from None
        except (ValueError, TypeError, KeyError, IndexError, RuntimeError) as exc:
            raise HTTPException(code, describe_error(exc)) from None

    @app.get("/", include_in_schema=False)
    def index():
        # never cached: a page kept from before a restart would carry a stale token; never
        # framed: a foreign page could otherwise lay its own buttons over the studio's
        return HTMLResponse(page, headers={"Cache-Control": "no-store",
                                           "X-Frame-Options": "DENY",
                                           "Content-Security-Policy": "frame-ancestors 'none'"})

    app.mount("/static", StaticFiles(directory=STATIC), name="static")

    @app.get("/api/options")
    def options():
        # correct_available: always, the loop ships with the package (state.py imports it)
        return {"garments": {k: v[2] for k, v in GARMENTS.items()}, "sizes": list(SIZE_NAMES),
                "bodies": list_bodies(), "fabrics": list(FABRICS),
                "engines": list(ENGINES), "correct_available": True,
                "max_upload": max_upload, "exports": list(EXPORTS), "drag_ops": DRAG_OPS,
                "uploads": {k: list(v) for k, v in UPLOAD_SUFFIXES.items()}}

    @app.get("/api/state")
    async def state():
        if studio.summary is None:  # the first request of a new folder makes its session
            await in_worker(studio.ensure, code=500)
        return {**studio.summary, "drape": studio.job.as_dict()}

    def read_geometry():
        with studio.lock:
            return _geometry(studio.ensure())

    @app.get("/api/geometry")
    async def geometry():
        return await in_worker(read_geometry)

    def read_garment3d():
        with studio.lock:
            s = studio.ensure()
            if s.positions is None:
                raise HTTPException(409, "nothing draped yet")
            return _garment3d(s)

    @app.get("/api/garment3d")
    async def garment3d():
        return await in_worker(read_garment3d)

    def read_body():
        b = studio.ensure().body
        return {"name": b.name, "vertices": np.round(b.vertices, 5).ravel().tolist(),
                "faces": b.faces.ravel().tolist()}

    @app.get("/api/body")
    async def body():
        return await in_worker(read_body)

    async def json_body(request: Request) -> bytes:
        return await _read_capped(request, limits.json_body_bytes, "request body")

    def do_new(raw: bytes):
        body = _json_object(raw)
        studio.new(**{k: body[k] for k in ("garment", "size", "body", "fabric", "triangles",
                                           "engine") if k in body},
                   revision=_revision(body))
        return {"ok": True, "revision": studio.revision}

    @app.post("/api/new")
    async def new(request: Request):
        return await in_worker(do_new, await json_body(request))

    def do_edit(raw: bytes):
        body = _json_object(raw)
        op, args = _edit_request(body)
        revision = _revision(body)
        with studio.lock:
            result = studio.apply(op, args, revision)
            return {"ok": True, "revision": studio.revision, **result}

    @app.post("/api/edit")
    async def edit(request: Request):
        return await in_worker(do_edit, await json_body(request))

    def do_drag(raw: bytes):
        vertices, moved = studio.drag(*_edit_request(_json_object(raw)))
        # the preview travels as raw float32 (n, 2): the page maps it straight onto its mesh
        return Response(np.ascontiguousarray(vertices, dtype="<f4").tobytes(),
                        media_type="application/octet-stream",
                        headers={"X-Moved": ",".join(moved)})

    @app.post("/api/drag")
    async def drag(request: Request):
        return await in_worker(do_drag, await json_body(request))

    def do_drag_basis(raw: bytes):
        basis = studio.drag_basis(*_edit_request(_json_object(raw)))
        return Response(np.ascontiguousarray(basis, dtype="<f4").tobytes(),
                        media_type="application/octet-stream")

    @app.post("/api/drag/basis")
    async def drag_basis(request: Request):
        return await in_worker(do_drag_basis, await json_body(request))

    def step(move):
        def run(raw: bytes):
            revision = _revision(_json_object(raw))
            with studio.lock:
                move(revision)
                return {"ok": True, "revision": studio.revision}
        return run

    @app.post("/api/undo")
    async def undo(request: Request):
        return await in_worker(step(studio.undo), await json_body(request))

    @app.post("/api/redo")
    async def redo(request: Request):
        return await in_worker(step(studio.redo), await json_body(request))

    def start(kind: str, revision: int | None):
        studio.start_drape(kind=kind, revision=revision)
        return studio.job.as_dict()

    async def started(kind: str, request: Request):
        revision = await in_worker(lambda raw: _revision(_json_object(raw)),
                                   await json_body(request))  # malformed: 400
        return await in_worker(start, kind, revision, code=409)

    @app.post("/api/drape")
    async def drape(request: Request):
        return await started("drape", request)

    @app.post("/api/correct")
    async def correct(request: Request):
        return await started("correct", request)

    @app.get("/api/drape")
    def drape_progress():
        return studio.job.as_dict()

    @app.post("/api/drape/stop")
    def drape_stop():
        studio.stop_drape()
        return studio.job.as_dict()

    @app.post("/api/upload")
    async def upload(request: Request, kind: str = "pattern", revision: str | None = None):
        seen = _query_revision(revision)
        raw = await _read_capped(request, max_upload + MULTIPART_SLACK, "upload")
        file = await _multipart_file(request.headers, raw)
        data = await file.read(max_upload + 1)
        if len(data) > max_upload:
            raise HTTPException(413, f"upload: larger than {max_upload // 1024} KiB")
        result = await in_worker(studio.upload, kind, file.filename or "", data, seen)
        return {"ok": True, "revision": studio.revision, **result}

    @app.get("/api/export/{name}")
    async def export(name: str):
        if name not in EXPORTS:
            raise HTTPException(404, f"export: one of {', '.join(EXPORTS)}")
        data = await in_worker(_export, studio, name, code=409)
        return Response(data, media_type=mimetypes.guess_type(name)[0] or
                        "application/octet-stream",
                        headers={"Content-Disposition": f'attachment; filename="{name}"'})

    return app


async def _multipart_file(headers, raw: bytes) -> UploadFile:
    """The one file field ``file`` of the multipart body ``raw`` (already size-capped)."""
    async def stream():
        yield raw

    parser = MultiPartParser(headers, stream(), max_files=1, max_fields=4)
    parser.spool_max_size = len(raw)  # the body is in memory already: no copy on disk
    try:
        form = await parser.parse()
    except MultiPartException as exc:
        raise HTTPException(400, f"upload: {exc.message}") from None
    file = form.get("file")
    if not isinstance(file, UploadFile):
        raise HTTPException(400, "upload: expected a multipart field 'file' with the file")
    return file


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


def _export(studio: Studio, name: str) -> bytes:
    """The bytes of export ``name`` (a key of ``EXPORTS``), written into a folder of its own
    under the session's ``exports/`` (removed again): an export running while another one,
    or an edit, writes can never hand out a half-written file."""
    (studio.folder / "exports").mkdir(exist_ok=True)
    with studio.lock, tempfile.TemporaryDirectory(dir=studio.folder / "exports") as tmp:
        s = studio.ensure()
        path = Path(tmp) / name
        kind = EXPORTS[name]
        if kind == "pattern":
            fit = s.evaluate() if s.positions is not None and path.suffix in (".svg", ".pdf") \
                else None
            colours = None if fit is None else (s.mesh.vertices, s.mesh.triangles,
                                                FitScale().colors(fit.area_change),
                                                s.mesh.triangle_panel)
            save_any_pattern(s.pattern, path, fit=colours)
        elif s.positions is None:
            raise RuntimeError("drape the garment first")
        elif kind == "garment":
            fit = s.evaluate()
            rgb = FitScale().colors(vertex_values(s.mesh.triangles, fit.area_change,
                                                  s.mesh.n_vertices, weights=fit.area_2d))
            path = export_garment(s.positions, s.mesh.triangles, rgb, path)
        else:
            path = write_report(fit_report(s.mesh, s.evaluate(), state="draped",
                                           extra={"checks": s.state.checks,
                                                  "history": s.summary()}), path)
        return Path(path).read_bytes()
