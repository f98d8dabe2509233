"""The studio's request bodies as pydantic models, the dependency that reads and checks one,
and the worker-thread runner of heavy work.

A body is read capped at ``limits.json_body_bytes`` and parsed by
:func:`patternfit.files.parse_json_text` (finite numbers, bounded nesting) before the model
checks it; a body that fails raises ``ValueError`` naming the field, which the app's one
exception handler answers with 400. Fields a request does not take are ignored (a revision
given is always checked).
"""

from __future__ import annotations

from typing import Annotated, Any

import anyio
from fastapi import HTTPException, Request
from pydantic import (BaseModel, BeforeValidator, ConfigDict, StrictInt, StrictStr,
                      ValidationError, field_validator)

from ..body.builtin import list_bodies
from ..constants import limits
from ..errors import InputError
from ..files import parse_json_text
from ..pattern.library import GARMENTS
from ..pattern.sizes import SIZE_NAMES
from ..sim.fabrics import FABRICS
from .guard import read_capped
from .state import ENGINES, Studio

#: bodies up to this size [bytes] are parsed on the server's loop (microseconds); larger
#: ones, up to ``limits.json_body_bytes``, in a worker thread
INLINE_BODY = 16 * 1024
#: triangle counts a new session may ask for
TRIANGLES = (100, 60000)


def _one_of(known):
    """A check that a given value is one of ``known()`` (names shown in the message); a
    field left out is None and not checked."""
    def check(value):
        names = known()
        if not isinstance(value, str) or value not in names:
            raise ValueError(f"expected one of {', '.join(names)}")
        return value
    return BeforeValidator(check)


class Revisioned(BaseModel):
    """A change from a tab that names the session revision it last saw (None: a script that
    does not say, not checked)."""

    model_config = ConfigDict(extra="ignore")
    revision: StrictInt | None = None


class NewSession(Revisioned):
    """``POST /api/new``: a session on built-in garment, size, body, fabric, engine."""

    garment: Annotated[str | None, _one_of(lambda: list(GARMENTS))] = None
    size: Annotated[str | None, _one_of(lambda: list(SIZE_NAMES))] = None
    body: Annotated[str | None, _one_of(list_bodies)] = None
    fabric: Annotated[str | None, _one_of(lambda: list(FABRICS))] = None
    engine: Annotated[str | None, _one_of(lambda: list(ENGINES))] = None
    triangles: StrictInt | None = None

    @field_validator("triangles")
    @classmethod
    def _triangles(cls, n):
        if n is not None and not TRIANGLES[0] <= n <= TRIANGLES[1]:
            raise ValueError(f"expected a whole number in {TRIANGLES[0]}..{TRIANGLES[1]}")
        return n

    def given(self) -> dict:
        """The fields the request gave (the rest keep the studio's defaults)."""
        return {k: v for k, v in self.model_dump(exclude={"revision"}).items() if v is not None}


class Edit(Revisioned):
    """``POST /api/edit``, ``/api/drag``, ``/api/drag/basis``: an editing tool and its
    arguments (lengths [m])."""

    op: StrictStr
    args: dict[str, Any] = {}

    @field_validator("args")
    @classmethod
    def _no_label(cls, args):
        if "label" in args:  # the label is the studio's own description of the edit
            raise ValueError("'label' is not an argument of an editing tool")
        return args


def _message(exc: ValidationError) -> str:
    """``field: what is wrong`` for the first problem of a model check."""
    err = exc.errors()[0]
    where = ".".join(str(p) for p in err["loc"]) or "request body"
    text = err["msg"].removeprefix("Value error, ")
    if err["type"] == "missing":
        text = "missing"
    return f"{where}: {text}"


def parse_body(raw: bytes, model: type[BaseModel]) -> BaseModel:
    """The request body ``raw`` checked as ``model`` (an empty body is ``{}``); InputError
    or ValueError naming the field otherwise."""
    body = {}
    if raw:
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError:
            raise InputError("not UTF-8 text", file="request body") from None
        body = parse_json_text(text, file="request body")
        if not isinstance(body, dict):
            raise InputError("expected a JSON object", file="request body")
    try:
        return model.model_validate(body)
    except ValidationError as exc:
        raise ValueError(_message(exc)) from None


def body(model: type[BaseModel]):
    """A FastAPI dependency: the request's JSON body checked as ``model``."""
    async def read(request: Request) -> BaseModel:
        raw = await read_capped(request, limits.json_body_bytes, "request body")
        if len(raw) <= INLINE_BODY:  # a drag's few hundred bytes: no thread hop per frame
            return parse_body(raw, model)
        return await in_worker(parse_body, raw, model)
    return read


def studio_of(request: Request) -> Studio:
    """A FastAPI dependency: the app's one :class:`~patternfit.studio.state.Studio`."""
    return request.app.state.studio


async def in_worker(fn, *args):
    """``fn(*args)`` in a worker thread, so the server keeps answering meanwhile. Past
    ``limits.request_seconds`` the client gets 503 (the work itself cannot be interrupted:
    it finishes in the background). Refusals raised by ``fn`` reach the app's handler."""
    try:
        with anyio.fail_after(limits.request_seconds):
            return await anyio.to_thread.run_sync(fn, *args, abandon_on_cancel=True)
    except TimeoutError:
        raise HTTPException(503, f"the request took longer than {limits.request_seconds:g} s; "
                                 "it finishes in the background (reload to see it)") from None
