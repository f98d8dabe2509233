"""The studio's web application: a JSON API over one design session plus the static page.

Lengths in the API are metres, like everywhere in patternfit; the page shows centimetres.
No path from the client is ever opened: bodies and fabrics are chosen by preset name or
uploaded, uploads are read under names of the studio's choosing inside the session folder,
and each export is written to a fresh folder of its own and sent back.

No other web page can drive the studio (:mod:`.guard`: ``Host``, ``Origin``, the page's
token, JSON-only bodies, capped uploads). The requests live in :mod:`.routes` by topic, their
bodies are pydantic models (:mod:`.requests`); heavy work (meshing, edits, exports, reading
uploads) runs in worker threads, so the server keeps answering ``GET /api/state``
meanwhile. One handler answers every refusal: bad input (``InputError``, ``PatternError``,
``ValueError`` and the tools' ``KeyError``/``IndexError``/``TypeError``) with 400, a change
the session's present state does not allow (a drape running, a stale tab) with 409, each
with a message for the designer.
"""

from __future__ import annotations

import secrets
from pathlib import Path

from fastapi import FastAPI, HTTPException
from fastapi.responses import HTMLResponse, JSONResponse
from fastapi.staticfiles import StaticFiles

from ..constants import limits
from .fabric_lab import FabricLab
from .guard import LOCAL_HOSTS, Guard
from .routes import ROUTERS
from .jobs import Refused
from .state import StaleRevision, Studio
from .words import designer_message

STATIC = Path(__file__).parent / "static"
_TOKEN_SLOT = "__PATTERNFIT_TOKEN__"
#: what a refused request raises; each answers 400 (bad input) unless listed in _CONFLICTS
REFUSALS = (ValueError, KeyError, IndexError, TypeError, Refused, StaleRevision)
#: refusals that mean "not now" rather than "not this": 409
_CONFLICTS = (Refused, StaleRevision)


def create_app(session_dir, *, max_upload: int | None = None,
               allowed_hosts=LOCAL_HOSTS) -> FastAPI:
    """The studio app over the design session kept in ``session_dir`` (created if missing,
    continued if it holds one; a saved session that does not load raises
    :class:`~patternfit.errors.SessionError`). ``max_upload``: upload size limit [bytes]
    (default ``limits.upload_bytes``). ``allowed_hosts``: the host names requests may address
    (tests add the test client's ``"testserver"``). The page's token is ``app.state.token``.
    """
    token = secrets.token_urlsafe(32)
    page = (STATIC / "index.html").read_text(encoding="utf-8").replace(_TOKEN_SLOT, token)
    app = FastAPI(title="patternfit studio", docs_url=None, redoc_url=None, openapi_url=None)
    app.state.studio = Studio(session_dir)
    app.state.token = token
    app.state.max_upload = limits.upload_bytes if max_upload is None else int(max_upload)
    app.state.fabric_lab = FabricLab()
    app.add_middleware(Guard, hosts=allowed_hosts, token=token)

    @app.exception_handler(HTTPException)
    async def http_error(request, exc: HTTPException):
        return JSONResponse({"error": exc.detail}, exc.status_code)

    async def refused(request, exc: Exception):
        if isinstance(exc, StaleRevision):
            # a tab that missed another tab's change: nothing was changed, it must reload
            return JSONResponse({"error": str(exc), "stale": True, "revision": exc.current},
                                409)
        return JSONResponse({"error": designer_message(exc)},
                            409 if isinstance(exc, _CONFLICTS) else 400)

    for kind in REFUSALS:
        app.add_exception_handler(kind, refused)

    @app.exception_handler(Exception)
    async def server_error(request, exc: Exception):
        return JSONResponse({"error": f"internal error: {designer_message(exc)}"}, 500)

    @app.get("/", include_in_schema=False)
    def index():
        # never cached: a page kept from before a restart would carry a stale token; never
        # framed: a foreign page could otherwise lay its own buttons over the studio's
        return HTMLResponse(page, headers={"Cache-Control": "no-store",
                                           "X-Frame-Options": "DENY",
                                           "Content-Security-Policy": "frame-ancestors 'none'"})

    app.mount("/static", StaticFiles(directory=STATIC), name="static")
    for router in ROUTERS:
        app.include_router(router)
    return app
