"""What keeps other web pages from driving the studio: the ``Host``/``Origin``/token/body-type
middleware, the capped body reader and the multipart reader of uploads.

Every request must name the studio's own address in ``Host`` (and in ``Origin``, where the
browser sends one), and every request that changes something, and every export, must carry
the random token the page was served with in the ``X-Patternfit-Token`` header. JSON bodies
must be sent as ``application/json``, uploads as ``multipart/form-data``.
"""

from __future__ import annotations

import secrets

from fastapi import HTTPException, Request
from fastapi.responses import JSONResponse
from starlette.datastructures import Headers, UploadFile
from starlette.formparsers import MultiPartException, MultiPartParser

#: the names the studio answers to (a page from another site reaching 127.0.0.1 through DNS
#: rebinding carries its own host name and is refused)
LOCAL_HOSTS = ("127.0.0.1", "localhost")
#: the header every state-changing request carries the page's token in
TOKEN_HEADER = "X-Patternfit-Token"
#: room for the multipart framing (boundaries, part headers) around an upload [bytes]
MULTIPART_SLACK = 64 * 1024
#: the request paths that take a multipart body (every other body is JSON)
MULTIPART_PATHS = ("/api/upload",)


class Guard:
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
        wanted = "multipart/form-data" if path in MULTIPART_PATHS else "application/json"
        # a request without a body (POST /api/drape) needs no type: Content-Length 0, or
        # neither it nor Transfer-Encoding (curl -X POST sends no length)
        bodyless = (kind == "" and headers.get("content-length", "0") == "0"
                    and "transfer-encoding" not in headers)
        if kind != wanted and not (bodyless and wanted == "application/json"):
            return 415, f"expected a {wanted} body"
        return None


async def read_capped(request: Request, limit: int, what: str, *,
                      stated: int | None = None) -> bytes:
    """The request body, refused with 413 once it is found larger than ``limit`` bytes: from
    ``Content-Length`` before reading, else while it arrives (nothing beyond is read). The
    refusal states ``stated`` bytes (default ``limit``): the limit the user knows, where
    ``limit`` has room for a wrapping (a multipart upload's headers)."""
    said = f"{what}: larger than {(limit if stated is None else stated) // 1024} KiB"
    declared = request.headers.get("content-length")
    if declared is not None:
        if not declared.isdigit():
            raise HTTPException(400, "Content-Length: not a number")
        if int(declared) > limit:
            raise HTTPException(413, said)
    body = bytearray()
    async for chunk in request.stream():
        body += chunk
        if len(body) > limit:
            raise HTTPException(413, said)
    return bytes(body)


async def multipart_file(headers, raw: bytes) -> UploadFile:
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
